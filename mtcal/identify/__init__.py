"""Identification from a tracker recording: ``identify()`` (run), its result types (results), the three-point
method (threepoint), the joint fit (joint), the ISO frame and squareness (frame), fitted functions (fitting),
the model (build), model comparison (compare), plots."""
from mtcal._verb import callable_package
from mtcal.identify.results import AxisResult, IdentifyResult
from mtcal.identify.run import identify

__all__ = ["identify", "IdentifyResult", "AxisResult"]

callable_package(__name__, identify)  # mtcal.identify(...) is the verb even once the package is imported
