"""Measurement uncertainty at full rigour: a GUM Supplement 1 Monte Carlo through the whole estimator (``run``:
``monte_carlo``), its input quantities with their defaults and sources (``inputs``), one trial (``trials``); on
Dask, a local cluster or an existing one."""
from mtcal.uncertainty.inputs import Inputs
from mtcal.uncertainty.run import UncertaintyResult, intervals, monte_carlo

__all__ = ["monte_carlo", "Inputs", "UncertaintyResult", "intervals"]
