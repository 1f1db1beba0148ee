"""Each effect written once (issue 12 item 5): the simulator plants an effect as a physical model (the generated
``<effect>_model`` increments of derive/signatures.py, carried to the reflectors by the exact error-inclusive
kinematics, or the generated reading models); the diagnosis' signature is the derivative of the same model.
For every effect on every spec: simulate(effect) - simulate(none) = signature x parameter to first order, and the
remainder is second order (shown: halving the parameter quarters it) or zero (effects linear in the parameter
through a translation: positioning of a linear axis, drift, knocks, tracker scale).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import mtcal
from mtcal.campaign.plans import Plan
from mtcal.campaign.simulate import simulate
from mtcal.diagnose import effects as fx
from mtcal.diagnose import prepare
from mtcal.generated import signatures_numpy as S
from mtcal.kinematics.defaults import default_positions

SPECS = sorted(p.stem for p in (Path(__file__).resolve().parent.parent / "derive" / "machines").glob("*.toml"))
UNIT = {"+X": np.array([1.0, 0, 0]), "+Y": np.array([0, 1.0, 0]), "+Z": np.array([0, 0, 1.0])}


def _plan(m: mtcal.Machine, cross: bool = False) -> Plan:
    """A short campaign; with ``cross`` the first linear axis is measured with the second at 100 mm (else the
    cross_axis effect is invisible) and no other axis is measured."""
    pos = {a: p[::3] if p[::3][-1] == p[-1] else np.append(p[::3], p[-1]) for a, p in default_positions(m).items()}
    lin = m.linear_axes
    if cross:
        return Plan(m, rounds=1, positions={lin[0]: pos[lin[0]]}, at={lin[0]: {lin[1]: 100.0}})
    return Plan(m, rounds=1, positions=pos)


def _cases(m: mtcal.Machine):
    """(effect name, params, parameter vector theta, signature builder g -> G (n, 3, k))."""
    lin = m.linear_axes
    for a in m.axes:
        big = 0.05 if m.kind(a) == "linear" else 1e-3  # mm or rad: large, so that second order shows
        pitch = 120.0 if m.kind(a) == "linear" else 90.0
        pe = m.positioning_errors[a]
        yield "backlash", {"axis": a, "amount": big}, [big], lambda g, a=a: fx.backlash(g, a).G
        yield "scale", {"axis": a, "ppm": 500.0}, [500.0], lambda g, a=a: fx.scale(g, a).G
        # phase 0: zero at q = 0, where the other axes are measured (the signature covers the axis' own readings)
        yield ("periodic", {"axis": a, "amplitude": big, "pitch": pitch, "phase_deg": 0.0}, [big, 0.0],
               lambda g, a=a, p=pitch: fx.periodic(g, a, p, (p, p)).G)
        c2 = big / np.ptp(default_positions(m)[a]) ** 2
        yield ("second_order", {"error": pe, "coefficient": c2}, [c2],
               lambda g, a=a, e=pe: fx.second_order(g, a, e).G)
    for e, (name, _a) in fx.constants(m).items():
        v = 1e-3 if e[2] in "AB" or name == "squareness" else 0.05
        yield name, {"error": e, "value": v}, [v], lambda g, e=e, n=name: fx.constant(g, n, e).G
    cx = f"E_Z{lin[0]}"
    yield ("cross_axis", {"error": cx, "on": lin[1], "coefficient": 1e-6}, [1e-6],
           lambda g: (S.cross_axis_signature(g.col(cx), g.position, 100.0) * (g.axis == lin[0])[:, None])[..., None])
    yield ("thermal_drift", {"amplitude": 0.05, "direction": "+Y", "tau_s": 1800.0, "target": "spindle"},
           0.05 * UNIT["+Y"], lambda g: fx.thermal_drift(g, "spindle", 1800.0, 0.0).G)
    yield "tracker_scale", {"ppm": 200.0}, [200.0], lambda g: fx.tracker_scale(g).G


@pytest.mark.parametrize("name", SPECS)
def test_simulated_effect_is_signature_times_parameter_to_first_order(name):
    m = mtcal.load_machine(name)
    runs = {}
    for cross in (False, True):
        pl = _plan(m, cross)
        clean, _ = simulate(None, plan=pl, noise=False)
        runs[cross] = pl, clean, prepare(clean, m, tracker=pl.tracker).geometry
    seen, second = set(), set()
    for effect, params, theta, sig in _cases(m):
        pl, clean, g = runs[effect == "cross_axis"]
        first = np.einsum("nik,k->ni", sig(g), np.asarray(theta, dtype=float))
        rem = []
        for s in (1.0, 0.5):
            p = {k: (v * s if k in ("amount", "ppm", "amplitude", "coefficient", "value") else v)
                 for k, v in params.items()}
            rec, _ = simulate(None, plan=pl, noise=False, effects=[(effect, p)])
            rem.append(np.abs(rec.xyz - clean.xyz - s * first).max())
        size = np.abs(first).max()
        assert size > 1e-3, (name, effect, params)  # the effect moves the reflectors (mm)
        assert rem[0] < 2e-3 * size, (name, effect, params, rem[0], size)  # first order
        # second order shown: halving the parameter quarters the remainder, or there is none (rounding only)
        assert rem[0] < 1e-10 or 3.6 < rem[0] / rem[1] < 4.4, (name, effect, params, rem)
        seen.add(effect)
        if rem[0] >= 1e-10:
            second.add(effect)
    # rotations (rotary positioning, angular errors, location tilts) leave a genuine second-order remainder
    assert {"backlash", "periodic", "rotary_location"} <= second, second
    assert seen == {"backlash", "scale", "periodic", "second_order", "squareness", "rotary_location", "cross_axis",
                    "thermal_drift", "tracker_scale"}


@pytest.mark.parametrize("name", SPECS)
def test_knocks_and_outliers_are_their_signature_exactly(name):
    """offset (tracker knock) and outlier move readings by the displacement itself: the signature is I3 on the
    displaced readings, and simulate(effect) - simulate(none) equals it to rounding."""
    m = mtcal.load_machine(name)
    pl = _plan(m)
    clean, _ = simulate(None, plan=pl, noise=False)
    g = prepare(clean, m, tracker=pl.tracker).geometry
    rec, truth = simulate(None, plan=pl, noise=False, effects=[("offset", {"size": 0.03, "direction": "+Z"})])
    t0 = truth["effects"][0]["t_from_s"]
    where = {"from_axis": "", "round": 1, "point": "", "position": 0.0, "readings": 0}
    want = np.einsum("nik,k->ni", fx.tracker_knock(g, t0, where).G, 0.03 * UNIT["+Z"])
    assert np.abs(rec.xyz - clean.xyz - want).max() < 1e-12 and np.abs(want).max() == pytest.approx(0.03)
    rec, truth = simulate(None, plan=pl, noise=False, effects=[("outlier", {"size": 0.05, "direction": "+X"})])
    rows = np.flatnonzero(np.abs(rec.xyz - clean.xyz).max(axis=1) > 0)
    on = np.zeros(len(rec))
    on[rows] = 1.0
    assert len(rows) == 1 and np.abs(rec.xyz - clean.xyz - S.outlier_signature(on) @ (0.05 * UNIT["+X"])).max() < 1e-12
