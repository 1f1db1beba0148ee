"""The error model from identified positions: continuous functions sized by the values' covariance (BIC,
mtcal.identify.fitting), squareness constants, and the notes on fits that miss their table."""
from __future__ import annotations

import numpy as np

from mtcal.identify import fitting
from mtcal.identify.results import AxisResult
from mtcal.kinematics.machine import Machine
from mtcal.model.errormodel import ErrorFunction, ErrorModel
from mtcal.model.fits import Fit
from mtcal.model.plausibility import FIT_LEAVES_K  # the same bound refuses such a model on export


def build_model(results: dict[str, AxisResult], sq: dict[str, float], m: Machine, max_degree: int,
                max_harmonics: int, source: str, reference: str, weighted: bool,
                warnings: list[str]) -> tuple[ErrorModel, dict[str, dict[str, Fit]]]:
    """(the error model, the fits by axis (``AxisResult.fits``)): every error's table (mean over rounds) and its
    fitted function; a fit that leaves a significant part of its table adds a warning to ``warnings``."""
    funcs, fits = {}, {}
    for axis, ar in results.items():
        fits[axis] = {}
        rotary = m.axis_kinds[m.axes.index(axis)] == "rotary"
        periodic = rotary and fitting.is_periodic(ar.positions)
        std, sm, u95 = ar.std, ar.std_mean, ar.u95
        for i, nm in enumerate(ar.names):
            vals = ar.values(nm)
            pr = ar.per_round[..., i]
            if nm in ar.lines:
                pr = pr - ar.lines[nm]["slope"] * ar.positions
            if len(ar.positions) < 2:
                continue
            cov = _value_covariance(ar, i, nm, reference)
            fit = (fitting.fit_harmonic(ar.positions, pr, 360.0, max_harmonics, ar.reference_position, cov) if periodic
                   else fitting.fit_polynomial(ar.positions, pr, max_degree, ar.reference_position, cov))
            if "covariance" in fit.info:  # reported at the noise law's level (the factor only sized the function)
                fit.info["covariance"] = (np.asarray(fit.info["covariance"]) / ar.fit_variance_factor).tolist()
            warnings += _fit_leaves(nm, i >= 3, ar, pr, cov, ErrorFunction(axis, ar.positions, vals, fit))
            extra = {"std": std[:, i].tolist(), "std_mean": sm[:, i].tolist(), "u95": u95[:, i].tolist(),
                     "n": ar.n.tolist()}
            if nm in ar.lines:
                extra["reference_line"] = ar.lines[nm]
            funcs[nm] = ErrorFunction(axis, ar.positions.copy(), vals, fit, extra)
            fits[axis][nm] = fit
    meta = {"identified_from": source, "method": "three-point (Zhang & Hu), least squares over all equations",
            "weighted": weighted, "reference_line": reference,
            "squareness_convention": fitting.SQUARENESS_CONVENTION}
    return ErrorModel(m.name, dict(sq), funcs, meta), fits


def _fit_leaves(name: str, angular: bool, ar: AxisResult, per_round: np.ndarray, cov, f: ErrorFunction) -> list[str]:
    """A warning where the fitted function misses a significant part of the table (compensation and every
    exporter evaluate the fit, so what it leaves is not corrected): the largest |table - fit| beyond
    ``FIT_LEAVES_K`` standard deviations of the table value (the rounds' scatter, or the joint covariance)."""
    if cov is None:
        cov = fitting.rounds_covariance(per_round)
    var = np.zeros(per_round.shape[1]) if cov is None else np.diagonal(cov)
    table = np.nanmean(per_round, axis=0)
    miss = np.abs(table - f(ar.positions))
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(var > 0, miss / np.sqrt(var), 0.0)
    if not np.nanmax(z, initial=0.0) > FIT_LEAVES_K:
        return []
    k = int(np.nanargmax(z))
    scale, unit = (1e6, "urad") if angular else (1e3, "um")
    return [f"{name}: the fitted function misses the table by {miss[k] * scale:.2f} {unit} ({z[k]:.1f} sigma) at "
            f"{ar.axis} = {ar.positions[k]:g}: compensation evaluates the fit, so that part is not corrected "
            f"(more rounds, or `max_degree` / `max_harmonics`)"]


def _value_covariance(ar: AxisResult, i: int, name: str, reference: str) -> np.ndarray | None:
    """Covariance (n_pos, n_pos) of error ``i``'s values as fitted (reference-line slope removed) from the
    joint fit's covariance; None for the per-position method."""
    if ar.covariance is None:
        return None
    c = ar.covariance[i::6, i::6] * ar.fit_variance_factor
    if name in ar.lines:
        t = np.eye(len(ar.positions)) - np.outer(ar.positions, fitting.slope_weights(ar.positions, reference))
        c = t @ c @ t.T
    return c
