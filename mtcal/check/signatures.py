"""What a circular test's residual shows (measured minus predicted): the classic ballbar signatures fitted together
by least squares on the trace (theta, direction), each with its size and t-value (coefficient over its standard
error: the noise estimated from what the fit leaves and the model's own uncertainty); reported when
|t| > T_SIGNIFICANT and its radial effect is at least SIZE_FLOOR_MM.

Quasi-static (a geometric error the model should hold): squareness (an oval along 45 deg, the same in both
directions: -R E/2 sin 2theta with the design contract's E_C0Y sign), scale mismatch of the two axes (an oval along
the axes: R (s_a - s_b)/2 cos 2theta), backlash of either axis (a step of b at the quadrants where that axis
reverses: the lost motion is +b/2 in the direction of travel), cyclic errors (harmonics 3..8).  Dynamic, outside
the quasi-static model: servo mismatch (the two axes' following errors differ: an oval along 45 deg whose sign
flips with the direction of travel) - a quasi-static model cannot hold it, so it is named as dynamic, never as a
squareness or a model error; a test of one direction cannot tell it from a squareness (it is not fitted then).
The centre and radius terms (set-up, ballbar length) are fitted and not reported."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

T_SIGNIFICANT = 5.0  # |t| above which a signature is reported (~20 columns on hundreds of points: no chance hits)
SIZE_FLOOR_MM = 5e-5  # and a radial effect of at least 0.05 um: half a ballbar's resolution (0.1 um)
HARMONICS = range(3, 9)


@dataclass
class Signature:
    """One fitted signature: ``name``, ``size`` (its natural unit: mm, or rad for squareness, or mm/mm for scale),
    ``size_mm`` (its largest radial effect, mm), ``t``, ``quasi_static`` and a sentence."""

    name: str
    size: float
    unit: str
    size_mm: float
    t: float
    quasi_static: bool
    text: str

    def to_dict(self) -> dict:
        return {"signature": self.name, "size": self.size, "unit": self.unit, "size_mm": self.size_mm,
                "t": self.t, "quasi_static": self.quasi_static, "text": self.text}


def _columns(theta_deg: np.ndarray, direction: np.ndarray, plane: str) -> tuple[list[str], np.ndarray]:
    th = np.radians(theta_deg)
    d = direction.astype(float)
    a, b = plane[0], plane[1]
    cols = {"radius": np.ones_like(th), "centre_a": np.cos(th), "centre_b": np.sin(th),
            "squareness": np.sin(2 * th), "scale": np.cos(2 * th), "servo": d * np.sin(2 * th),
            f"backlash_{a}": 0.5 * np.cos(th) * np.sign(-d * np.sin(th)),
            f"backlash_{b}": 0.5 * np.sin(th) * np.sign(d * np.cos(th))}
    for k in HARMONICS:
        cols[f"cos{k}"], cols[f"sin{k}"] = np.cos(k * th), np.sin(k * th)
    if len(np.unique(d)) < 2:  # one direction: a servo mismatch is the squareness column; it cannot be told apart
        del cols["servo"]
    return list(cols), np.column_stack(list(cols.values()))


def fit_signatures(theta_deg: np.ndarray, resid: np.ndarray, direction: np.ndarray, plane: str, radius_mm: float,
                   prediction: np.ndarray | None = None) -> tuple[list[Signature], float]:
    """(significant signatures, noise sd (mm) of what the fit leaves) of a circular test's residual.
    ``prediction`` (n, k): the prediction's uncertainty as k independent standard-uncertainty columns (each an
    error's sigma times its sensitivity, mm): each coefficient's standard error holds both the test's noise and
    what the model's own uncertainty puts into that signature, so a model error within what the model states is
    not reported (a direction-dependent signature, backlash or servo mismatch, gets nothing from it: no
    quasi-static model depends on the direction of travel)."""
    names, A = _columns(theta_deg, direction, plane)
    scale = np.linalg.norm(A, axis=0)
    P = np.linalg.pinv(A / scale)  # (p, n): coefficients (scaled) from the residual
    coef = P @ resid
    left = resid - (A / scale) @ coef
    s = float(np.sqrt(left @ left / max(len(resid) - len(names), 1)))
    var = s**2 * np.einsum("ij,ij->i", P, P)
    if prediction is not None:
        var = var + ((P @ prediction) ** 2).sum(axis=1)
    coef, se = coef / scale, np.sqrt(var) / scale
    t = np.where(se > 0, coef / np.where(se > 0, se, 1), 0.0)
    return _named(names, coef, t, plane, radius_mm), s


def _named(names: list[str], coef: np.ndarray, t: np.ndarray, plane: str, r: float) -> list[Signature]:
    c = dict(zip(names, coef))
    tv = dict(zip(names, t))
    out = []
    a, b = plane[0], plane[1]
    if abs(tv["squareness"]) > T_SIGNIFICANT:
        e = -2 * c["squareness"] / r
        out.append(Signature("squareness", e, "rad", abs(c["squareness"]) * 2, tv["squareness"], True,
                             f"squareness of {b} to {a}: {e * 1e6:+.1f} urad (an oval along 45 deg, the same in both "
                             f"directions)"))
    if abs(tv["scale"]) > T_SIGNIFICANT:
        ds = 2 * c["scale"] / r
        out.append(Signature("scale_mismatch", ds, "mm/mm", abs(c["scale"]) * 2, tv["scale"], True,
                             f"scale mismatch of {a} against {b}: {ds * 1e6:+.1f} um/m (an oval along the axes)"))
    for ax in (a, b):
        k = f"backlash_{ax}"
        if abs(tv[k]) > T_SIGNIFICANT:
            out.append(Signature(f"backlash_{ax}", c[k], "mm", abs(c[k]), tv[k], True,
                                 f"backlash of {ax}: {c[k] * 1e3:+.2f} um (steps where {ax} reverses)"))
    cyc = [(np.hypot(c[f"cos{k}"], c[f"sin{k}"]), k) for k in HARMONICS
           if max(abs(tv[f"cos{k}"]), abs(tv[f"sin{k}"])) > T_SIGNIFICANT]
    if cyc:
        amp, k = max(cyc)
        out.append(Signature("cyclic", amp, "mm", amp, max(abs(tv[f"cos{k}"]), abs(tv[f"sin{k}"])), True,
                             f"cyclic error: {amp * 1e3:.2f} um at {k} waves per revolution"))
    if abs(tv.get("servo", 0.0)) > T_SIGNIFICANT:
        out.append(Signature("servo_mismatch", c["servo"], "mm", abs(c["servo"]) * 2, tv["servo"], False,
                             f"servo mismatch: an oval along 45 deg that flips with the direction of travel "
                             f"({abs(c['servo']) * 2e3:.2f} um): the axes' following errors differ; dynamic, outside "
                             f"the quasi-static model (match the axes' gains or feed forward, or test slower)"))
    return sorted((f for f in out if f.size_mm >= SIZE_FLOOR_MM), key=lambda s: -abs(s.t))
