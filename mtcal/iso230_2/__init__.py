"""ISO 230-2 positioning accuracy and repeatability: evaluation (one datum for every run), interferometer
readings, plots."""
from mtcal.iso230_2.evaluation import evaluate, evaluate_runs
from mtcal.iso230_2.readings import read_readings

__all__ = ["evaluate", "evaluate_runs", "read_readings"]
