"""The error model: ErrorModel and its error functions by ISO 230-1 name (mm, rad), typed fits, the JSON
schema, the plausibility guard of what reaches a machine."""
from mtcal.model.errormodel import ErrorEvaluator, ErrorFunction, ErrorModel, load_model, save_model
from mtcal.model.fits import Fit, Harmonic, Polynomial, Table

__all__ = ["ErrorModel", "ErrorFunction", "ErrorEvaluator", "load_model", "save_model", "Fit", "Polynomial", "Harmonic",
           "Table"]
