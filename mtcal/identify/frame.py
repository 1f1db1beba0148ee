"""The ISO frame of the linear axes and squareness: least-squares (or end-point) reference lines of the
straightness errors give the squareness constants (ISO 230-1, right-hand convention, docs/design.md), and the
readings are turned into the frame where X runs along the X motion and Y lies in the plane of X and Y."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from mtcal.generated import threepoint_numpy as tp
from mtcal.identify import fitting
from mtcal.identify.results import AxisResult
from mtcal.kinematics.machine import Machine
from mtcal.measurement.recordings import Recording


def reference_lines(results: dict[str, AxisResult], m: Machine, reference: str) -> dict[str, dict[str, dict]]:
    """The reference straight line of every straightness of the linear axes, {axis: {E_IJ: {"method",
    "intercept" (mm), "slope" (mm/mm)}}} (``AxisResult.lines``): their slopes define the ISO frame (docs/design.md
    gauge) and the squareness."""
    out: dict[str, dict[str, dict]] = {}
    for axis, ar in results.items():
        if m.kind(axis) != "linear":
            continue
        for nm in ar.names[:3]:
            if nm == m.positioning_errors[axis]:
                continue  # positioning error: no reference line
            a, b = fitting.reference_line(ar.positions, ar.mean[:, ar.names.index(nm)], reference)
            out.setdefault(axis, {})[nm] = {"method": reference, "intercept": a, "slope": b}
    return out


def iso_frame_rotation(m: Machine, slopes: dict[str, float]) -> np.ndarray:
    """Small rotation (rx, ry, rz) rad that turns the measuring frame into the ISO frame of the linear axes
    (docs/design.md gauge: x along the motion of the linear axis that moves along x, y in the plane of the x and y
    motions), from the straightness reference-line slopes ``slopes`` (mm/mm).  A linear axis moving along
    (1, s_y, s_z) is turned onto x by rz = -s_y, ry = +s_z; the y-moving axis' z slope s_z' by rx = -s_z'.
    Slopes that are missing count as zero (that part of the frame stays the measuring frame's)."""
    along = {m.error_motions(a).index(m.positioning_errors[a]): m.error_motions(a)
             for a in m.axes if m.kind(a) == "linear"}
    phi = np.zeros(3)
    if 0 in along:
        phi[2] = -slopes.get(along[0][1], 0.0)
        phi[1] = slopes.get(along[0][2], 0.0)
    if 1 in along:
        phi[0] = -slopes.get(along[1][2], 0.0)
    return phi


def _in_iso_frame(rec: Recording, tracker, m: Machine, slopes: dict[str, float]):
    """The recording (and the tracker position) with every reading turned about the machine origin into the ISO
    frame of the linear axes, so that the rotary axes' errors are identified in the frame the linear axes'
    reference lines put those in (three-point path; the joint fit holds that frame by its gauge)."""
    phi = np.concatenate([np.zeros(3), iso_frame_rotation(m, slopes)])
    def turn(v):
        return None if v is None else tp.rigid_point(np.asarray(v, dtype=float).reshape(-1, 3), phi)
    turned = replace(rec, xyz=turn(rec.xyz), tracker_xyz=turn(rec.tracker_xyz))
    return turned, (None if tracker is None else turn(tracker)[0])


def _squareness_type_a(results: dict[str, AxisResult], m: Machine, reference: str, sq: dict) -> dict:
    """Squareness of each round (rounds matched by number across axes) -> {name: {"rounds", "std", "std_mean"}}."""
    out = {}
    common = None
    for axis, ar in results.items():
        if m.axis_kinds[m.axes.index(axis)] == "linear":
            common = set(ar.rounds.tolist()) if common is None else common & set(ar.rounds.tolist())
    if not sq or not common or len(common) < 2:
        return out
    per = []
    for r in sorted(common):
        slopes = {}
        for axis, ar in results.items():
            if m.axis_kinds[m.axes.index(axis)] != "linear":
                continue
            k = int(np.flatnonzero(ar.rounds == r)[0])
            for nm in ar.lines:
                v = ar.per_round[k, :, ar.names.index(nm)]
                ok = np.isfinite(v)
                if ok.sum() >= 2:
                    slopes[nm] = fitting.reference_line(ar.positions[ok], v[ok], reference)[1]
        per.append(fitting.squareness(slopes))
    for name in sq:
        v = np.array([p[name] for p in per if name in p])
        if len(v) >= 2:
            s = float(v.std(ddof=1))
            out[name] = {"rounds": v.tolist(), "std": s, "std_mean": s / np.sqrt(len(v))}
    return out


def squareness_sigma(results: dict[str, AxisResult], reference: str) -> dict[str, float]:
    """Standard deviation (rad) of each squareness from the joint covariance of the straightness slopes it sums
    (in the ISO frame the slopes it pairs with are zero by the gauge, so the axes' slopes are independent)."""
    var: dict[str, float] = {}
    for ar in results.values():
        if ar.covariance is None:
            return {}
        g = fitting.slope_weights(ar.positions, reference)
        for nm in ar.lines:
            i = ar.names.index(nm)
            var[nm] = float(g @ ar.covariance[i::6, i::6] @ g)
    return {k: float(np.sqrt(var[a] + var[b])) for k, ((a, b), _) in fitting.SQUARENESS_PAIRS.items()
            if a in var and b in var}
