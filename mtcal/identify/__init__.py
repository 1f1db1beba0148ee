"""Identification from a tracker recording: the three-point method, the joint fit, fitted functions, model
comparison, plots."""
