"""ISO 230-2 positioning accuracy and repeatability: evaluation, interferometer readings, plots."""
