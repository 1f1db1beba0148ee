"""Verification after compensation: a new recording made on the compensated machine, read against the model that
compensated it.  What the model promised: every error it holds is gone, to within the model's own uncertainty;
what it does not hold is not touched.

For a tracker recording the new recording is identified with the same estimator ``identify`` uses; each error
left is compared with zero at every position it was measured: z = |left| / sqrt(u_left^2 + u_model^2) (the new
identification's standard uncertainty and the model's at that position), within when z <= ``K_VERIFY``.  Of every
error the model holds, the share still there is fitted, left = f * model: f ~ 0 corrected, f ~ 1 not applied,
f ~ 2 applied with the wrong sign, f ~ 0.5 half (a unit or a factor wrong).  An error left that the model does not
hold is named as not covered.  A circular test or R-test recorded after compensation is evaluated against what the
model predicts then (zero from the compensated errors, the prediction's uncertainty from the model)."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mtcal.check.evaluate import after_compensation, constant_sigmas, evaluate_check, uncertainty_columns
from mtcal.check.files import MeasuredCheck
from mtcal.errors import InputError
from mtcal.model.errormodel import ErrorModel

K_VERIFY = 3.0  # coverage factor of "within": a few positions per error, normal to within the t of >= 4 rounds


@dataclass
class ErrorLeft:
    """One error after compensation: its largest |value| left (mm or rad) and where, the largest z, whether
    within, the share of the model's error still there (None when the model does not hold it) and a sentence."""

    name: str
    axis: str | None
    left_max: float
    at: float | None
    z: float
    within: bool
    in_model: bool
    share: float | None
    text: str

    def to_dict(self) -> dict:
        return {"name": self.name, "axis": self.axis, "left_max": self.left_max, "at": self.at, "z": self.z,
                "within": self.within, "in_model": self.in_model, "share_of_model": self.share, "text": self.text}


@dataclass
class Verification:
    """The verdict on a compensation.

    Attributes
    ----------
    source : str
        The measurement made after compensating.
    passed : bool
        Every error left is within K_VERIFY (3) combined standard uncertainties of zero (a recording), or the check
        test agrees with the compensated machine.
    errors : list of ErrorLeft
        Per error (worst first): its largest value left and where, z, within, the share of the model's error still
        there.
    not_covered : list of str
        Errors outside the model that are not within: the compensation did not reach them.
    check : dict or None
        The evaluation of a check test (CheckEvaluation.to_dict()) instead of a recording.
    """

    source: str
    passed: bool
    errors: list[ErrorLeft] = field(default_factory=list)
    not_covered: list[str] = field(default_factory=list)
    check: dict | None = None

    def to_dict(self) -> dict:
        return {"source": self.source, "passed": self.passed, "k": K_VERIFY,
                "errors": [e.to_dict() for e in self.errors], "not_covered": self.not_covered,
                **({"check": self.check} if self.check is not None else {})}


def verify(data, model: ErrorModel, *, covered: set[str] | None = None, machine=None,
           **identify_options) -> Verification:
    """Verify a compensation with ``model`` from a measurement made after it.

    A recording is identified again and every error left is compared with zero within the combined uncertainty of
    both models; a check test is evaluated against the compensated machine (what is left of the model's errors).

    Parameters
    ----------
    data : Recording or MeasuredCheck
        A tracker campaign on the compensated machine, or a circular test / R-test (``read_check``).
    model : ErrorModel
        The model the machine was compensated with.
    covered : set of str, optional
        The errors the compensation acted on (default: all of the model's; a name the model does not hold is
        refused: the compensation cannot have acted on it).
    machine : str or Machine, optional
        The machine measured (default the model's): refused when it is not the model's machine.
    **identify_options
        Passed to ``identify`` for a recording (tracker, method, ...).

    Returns
    -------
    Verification
        ``passed``, and per error what is left.

    Raises
    ------
    mtcal.errors.InputError
        As ``identify`` or ``evaluate_check`` do; an unknown ``covered`` name, another machine than the model's.

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.check import simulate_circular
    >>> from mtcal.data import path
    >>> model = mtcal.load_model(path("demo_truth.json"))
    >>> test = simulate_circular(model, mtcal.CircleSetup("XY", 150.0), seed=1)  # the machine NOT compensated
    >>> mtcal.verify(test, model).passed
    False
    """
    name = getattr(machine, "name", machine)
    if name is not None and name != model.machine:
        raise InputError(f"the model is of machine {model.machine}, not {name} (`machine`): verify a compensation "
                         f"with the model of the machine measured")
    if covered is not None:
        unknown = sorted(set(covered) - set(model.names()))
        if unknown or not covered:
            known = set(model.kinematics.error_names)
            what = ("is not an error of machine " + model.machine if unknown and unknown[0] not in known else
                    "is not held by the model: the compensation cannot have acted on it") if unknown else ""
            raise InputError(f"`covered`: {unknown[0] + ' ' + what if unknown else 'names no error'}; the model "
                             f"holds {', '.join(sorted(model.names())) or 'nothing'}")
    if isinstance(data, MeasuredCheck):
        ev = evaluate_check(data, after_compensation(model, covered), model.kinematics, uncertainty_from=model)
        return Verification(data.source, ev.agrees, check=ev.to_dict())
    from mtcal.identify.run import identify
    new = identify(data, machine=model.kinematics, worth=False, **identify_options).model
    m = model.kinematics
    rows = [_compare(name, new, model, m, covered) for name in sorted(set(new.names()) | set(model.names()))]
    rows = sorted((r for r in rows if r is not None), key=lambda r: -r.z)
    not_covered = [r.name for r in rows if not r.within and not r.in_model]
    return Verification(data.source, all(r.within for r in rows), rows, not_covered)


def _compare(name: str, new: ErrorModel, model: ErrorModel, m, covered: set[str] | None) -> ErrorLeft | None:
    """One error: what is left (the new identification) against zero within the combined uncertainty."""
    in_model = name in model.names() and (covered is None or name in covered)
    unit = "urad" if name[2] in "ABC" else "um"
    scale = 1e6 if unit == "urad" else 1e3
    if name in new.constants or (name not in new.functions and name in model.constants):
        left = float(new.constants.get(name, 0.0))
        u_new = constant_sigmas(new).get(name, 0.0)
        u_mod = constant_sigmas(model).get(name, 0.0)
        z = abs(left) / max(np.hypot(u_new, u_mod), 1e-15)
        share = left / model.constants[name] if in_model and model.constants.get(name) else None
        return _row(name, None, abs(left), None, z, in_model, share, unit, scale)
    if name not in new.functions:
        return None  # held by the model, not measured again: nothing to say
    f = new.functions[name]
    q = np.zeros((len(f.positions), len(m.axes)))
    q[:, m.index(f.axis)] = f.positions
    left = f.values
    u_new = np.nan_to_num(np.asarray(f.extra.get("std_mean", np.zeros_like(left)), dtype=float))
    k = m.error_names.index(name)
    u_mod = np.sqrt((uncertainty_columns(model, m, q)[:, k, :] ** 2).sum(axis=1))
    z = np.abs(left) / np.maximum(np.hypot(u_new, u_mod), 1e-15)
    i = int(np.argmax(z))
    share = None
    if in_model and name in model.functions:
        mv = model.functions[name](f.positions, "hold")
        share = float(left @ mv / (mv @ mv)) if mv @ mv > 0 else None
    return _row(name, f.axis, float(np.abs(left).max()), float(f.positions[i]), float(z[i]), in_model, share, unit,
                scale)


def _row(name, axis, left, at, z, in_model, share, unit, scale) -> ErrorLeft:
    within = z <= K_VERIFY
    where = "" if at is None else f" at {axis} = {at:g}"
    if within:
        text = f"{name}: {left * scale:.2f} {unit} left, within its uncertainty"
    elif not in_model:
        text = f"{name}: {left * scale:.2f} {unit} left{where} (z = {z:.1f}): not covered by the compensation"
    else:
        text = f"{name}: {left * scale:.2f} {unit} left{where} (z = {z:.1f}); {_share_words(share)}"
    return ErrorLeft(name, axis, left, at, float(z), within, in_model, share, text)


def _share_words(share: float | None) -> str:
    if share is None:
        return "the model held it: the compensation did not remove it"
    if abs(share - 1) < 0.25:
        return f"{share:.2f} of the model's error is still there: the compensation was not applied"
    if abs(share - 2) < 0.35:
        return f"{share:.2f} of the model's error: applied with the wrong sign"
    if 0.25 <= share <= 0.75:
        return f"{share:.2f} of the model's error is still there: applied in part (a unit or factor wrong?)"
    return f"{share:.2f} of the model's error: the machine has changed, or the model missed this error"
