"""Hocken-Borchardt 2-D plate reversal (NBSIR 79-1752): alpha, beta, gamma, offsets from two plate positions."""
from mtcal.plate.reversal import PlateFit, fit_plate, read_plate_csv

__all__ = ["fit_plate", "read_plate_csv", "PlateFit"]
