"""Predicted uncertainty of a measurement plan before anything is measured (one station or several)."""
from mtcal.planning.plan import PlanResult, plan_uncertainty

__all__ = ["plan_uncertainty", "PlanResult"]
