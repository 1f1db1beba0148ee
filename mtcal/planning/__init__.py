"""Predicted uncertainty of a measurement plan (one station or several) before anything is measured."""
