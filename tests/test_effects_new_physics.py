"""Issue 13's new physics (reversal_angular, nest_creep, tracker_settling, thermal_temperature), each planted by the
simulator as a physical model through the exact kinematics, and its signature derived from the same model in
derive/signatures.py.  On every shipped spec: simulate(effect) - simulate(none) = signature x parameter to first
order, with the second-order remainder shown (halving the parameter quarters it) or none (models that are a
translation, linear in the parameter).  The signatures are assembled here from the generated functions and the
Machine's point Jacobians only (no diagnosis code).  Plus the backlash sign convention against ISO 230-2.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import mtcal
from mtcal.campaign.plans import Plan, schedule
from mtcal.campaign.simulate import simulate
from mtcal.cli import main
from mtcal.generated import signatures_numpy as S
from mtcal.iso230_2 import evaluation as iso230_2
from mtcal.kinematics.defaults import default_positions
from mtcal.measurement.recordings import read_recording

SPECS = sorted(p.stem for p in (Path(__file__).resolve().parent.parent / "derive" / "machines").glob("*.toml"))


def _plan(m: mtcal.Machine, rounds: int = 1) -> Plan:
    pos = {a: p[::3] if p[::3][-1] == p[-1] else np.append(p[::3], p[-1]) for a, p in default_positions(m).items()}
    return Plan(m, rounds=rounds, positions=pos)


class Geo:
    """What the signatures need, from the schedule of the plan (rows in the recording's order)."""

    def __init__(self, m: mtcal.Machine, pl: Plan, clean):
        self.m, self.rows, self.xyz = m, schedule(pl), clean.xyz
        r = self.rows
        self.J = np.empty((len(r), 3, len(m.error_names)))
        self.R = np.empty((len(r), 3, 3))
        for side in ("tool", "table"):
            on = r.side == side
            self.J[on] = m.point_jacobian_errors(side, r.axes[on], r.local[on])
            self.R[on] = m.rigid_motion(side, r.axes[on])[1]
        self.tracker = np.asarray(pl.tracker, dtype=float)
        # the default warm-up of the temperature channel, written independently: 2 K (1 - exp(-t / 1800 s)),
        # referred to the first reading
        rise = 2.0 * (1 - np.exp(-r.time_s / 1800.0))
        self.dT = rise - rise[0]

    def col(self, e: str) -> np.ndarray:
        return self.J[:, :, self.m.error_names.index(e)]

    def on(self, axis: str) -> np.ndarray:
        return (self.rows.axis == axis)[:, None, None]


def _cases(m: mtcal.Machine):
    """(effect, params, theta, signature builder Geo -> G (n, 3, k)); big parameters so that second order shows."""
    lin = m.linear_axes
    for a in lin:
        for c in ("ABC" if a == lin[0] else "B"):
            e = f"E_{c}{a}"
            yield ("reversal_angular", {"error": e, "amount": 1e-3}, [1e-3],
                   lambda g, e=e, a=a: S.reversal_angular_signature(g.col(e), g.rows.direction)[..., None] * g.on(a))
        yield ("thermal_temperature", {"axis": a, "ppm_per_k": 100.0}, [100.0],
               lambda g, a=a: S.thermal_temperature_signature(g.col(m.positioning_errors[a]),
                                                              g.rows.axes[:, m.index(a)], g.dT)[..., None])
    u = np.array([0.0, 0.6, 0.8])
    for side in ("tool", "table"):
        pt = m.campaign["reflectors"][side][1][0]
        yield ("nest_creep", {"point": pt, "side": side, "rate_mm_s": 2e-5, "direction": "0;0.6;0.8"}, 2e-5 * u,
               lambda g, pt=pt, side=side: S.nest_creep_signature(g.R.reshape(-1, 9), g.rows.time_s)
               * ((g.rows.point == pt) & (g.rows.side == side))[:, None, None])
    for target, side in (("spindle", "tool"), ("table", "table")):
        yield ("thermal_temperature", {"ppm_per_k": 0.0, "drift_mm_per_k": 0.01, "direction": "-Y",
                                       "target": target}, [0.0, -0.01, 0.0],
               lambda g, side=side: S.thermal_temperature_drift_signature(g.dT) * (g.rows.side == side)[:, None, None])
    settle = lambda g, u: S.tracker_settling_signature(g.xyz, g.tracker, u, g.rows.time_s, 1200.0)  # noqa: E731
    yield ("tracker_settling", {"angle_rad": 1e-3, "tau_s": 1200.0, "about": "+X"}, [0.0, 1e-3],
           lambda g: settle(g, np.array([1.0, 0, 0])))
    yield ("tracker_settling", {"angle_rad": 0.0, "rate_rad_s": 1e-7, "tau_s": 1200.0, "about": "1;1;0"},
           [1e-7, 0.0], lambda g: settle(g, np.array([1.0, 1.0, 0]) / math.sqrt(2)))


SCALED = ("amount", "ppm_per_k", "drift_mm_per_k", "rate_mm_s", "angle_rad", "rate_rad_s")


@pytest.mark.parametrize("name", SPECS)
def test_new_effects_are_signature_times_parameter_to_first_order(name):
    m = mtcal.load_machine(name)
    pl = _plan(m)
    clean, _ = simulate(None, plan=pl, noise=False)
    g = Geo(m, pl, clean)
    second, seen = set(), set()
    for effect, params, theta, sig in _cases(m):
        first = np.einsum("nik,k->ni", sig(g), np.asarray(theta, dtype=float))
        rem = []
        for s in (1.0, 0.5):
            p = {k: (v * s if k in SCALED else v) for k, v in params.items()}
            rec, _ = simulate(None, plan=pl, noise=False, effects=[(effect, p)])
            rem.append(np.abs(rec.xyz - clean.xyz - s * first).max())
        size = np.abs(first).max()
        assert size > 1e-3, (name, effect, params)  # the effect moves the reflectors (mm)
        assert rem[0] < 2e-3 * size, (name, effect, params, rem[0], size)  # first order
        assert rem[0] < 1e-10 or 3.6 < rem[0] / rem[1] < 4.4, (name, effect, params, rem)  # second order shown
        seen.add(effect)
        if rem[0] >= 1e-10:
            second.add(effect)
    # rotations (an angle of a linear axis, the tracker's tilt) leave a genuine second-order remainder; the
    # creep of a nest, an axis' expansion and a side's drift are translations linear in the parameter
    assert second == {"reversal_angular", "tracker_settling"}, second
    assert seen == {"reversal_angular", "nest_creep", "tracker_settling", "thermal_temperature"}


def test_reversal_angular_differs_by_the_amount_between_approaches():
    """E_BX = +40 urad approached in +, -40 urad in -: a point 100 mm above the X guide (z) moves by
    +-z E_BX along x (Delta x = z E_BX, docs/design.md); checked on the readings of X, which no other axis sees."""
    m = mtcal.load_machine("dmu50")
    pts = {"A": (0.0, 0.0, 100.0), "B": (50.0, 0.0, 100.0), "C": (0.0, 50.0, 100.0)}
    pl = Plan(m, rounds=1, positions={"X": np.array([0.0, 250.0, 500.0])}, tool_points=pts)
    clean, _ = simulate(None, plan=pl, noise=False)
    rec, truth = simulate(None, plan=pl, noise=False, effects=["reversal_angular:error=E_BX,amount=80e-6"])
    d = rec.xyz - clean.xyz
    # first order z E_BX = 4 um; the second order x E_BX^2 / 2 <= 50 mm x (40 urad)^2 / 2 = 4e-8 mm
    np.testing.assert_allclose(d[:, 0], 100.0 * 40e-6 * rec.direction, rtol=0, atol=5e-8)
    assert np.abs(d[:, 0]).min() > 0.00399
    assert truth["effects"][0] == {"name": "reversal_angular", "params": {"error": "E_BX", "amount": 80e-6},
                                   "error": "E_BX", "axis": "X", "reversal": 80e-6}


def test_nest_creep_moves_one_reflector_linearly_in_time():
    m = mtcal.load_machine("dmu50")
    rec0, _ = simulate(None, noise=False)
    rec, truth = simulate(None, noise=False, effects=["nest_creep:point=Q,side=tool,rate_mm_s=2.7778e-6,direction=X"])
    d = rec.xyz - rec0.xyz
    q = (rec.point == "Q") & np.isin(rec.axis, [a for a in m.axes if m.side(a) == "tool"])
    # spindle side of the DMU 50 only translates: the creep is along machine x, 2.7778e-6 mm/s x t
    np.testing.assert_allclose(d[q], np.c_[2.7778e-6 * rec.time_s[q], 0 * rec.time_s[q], 0 * rec.time_s[q]],
                               atol=1e-12)
    np.testing.assert_allclose(d[~q], 0, atol=1e-12)
    e = truth["effects"][0]
    assert e["rate_um_h"] == pytest.approx(10.0, rel=1e-4)
    assert e["displacement_mm"] == pytest.approx(2.7778e-6 * rec.time_s[q].max(), rel=1e-12)


def test_tracker_settling_keeps_distances_to_the_tracker():
    """A rotation about an axis through the tracker: every reading keeps its distance to the tracker (exactly),
    and the readings turn by the angle of the law w t + a (1 - exp(-t / tau)) (written here independently)."""
    rec0, t0 = simulate(None, noise=False)
    rec, truth = simulate(None, noise=False, effects=["tracker_settling:angle_rad=50e-6,tau_s=900,rate_rad_s=1e-9"])
    T = np.asarray(t0["tracker"])
    r0, r1 = rec0.xyz - T, rec.xyz - T
    np.testing.assert_allclose(np.linalg.norm(r1, axis=1), np.linalg.norm(r0, axis=1), rtol=1e-13)
    ang = np.arctan2(np.linalg.norm(np.cross(r0, r1), axis=1), np.einsum("ij,ij->i", r0, r1))
    want = 1e-9 * rec.time_s + 50e-6 * (1 - np.exp(-rec.time_s / 900))
    # about +X: the angle seen is the full angle for points in the plane perpendicular to X through the tracker,
    # less for others: |r x X| / |r| of it
    frac = np.linalg.norm(np.cross(r0, [1.0, 0, 0]), axis=1) / np.linalg.norm(r0, axis=1)
    np.testing.assert_allclose(ang, want * frac, rtol=1e-6)
    assert truth["effects"][0]["angle_at_end_rad"] == pytest.approx(want[-1], rel=1e-9)


def test_thermal_temperature_follows_the_recorded_channel():
    """10 ppm/K expansion of X: E_XX = 1e-6 k (T - T_first) q, with T the written warm-up channel."""
    rec0, _ = simulate(None, noise=False)
    rec, truth = simulate(None, noise=False, effects=["thermal_temperature:axis=X,ppm_per_k=10"],
                          temperature="rise_c=3,tau_s=1200")
    T = 20.0 + 3.0 * (1 - np.exp(-rec.time_s / 1200.0))
    np.testing.assert_allclose(rec.temperature_c, T, atol=1e-12)
    x = rec.axis == "X"
    np.testing.assert_allclose((rec.xyz - rec0.xyz)[x, 0], 10e-6 * (T[x] - T[0]) * rec.position[x], atol=1e-12)
    np.testing.assert_allclose((rec.xyz - rec0.xyz)[~x], 0, atol=1e-12)  # X at zero elsewhere
    assert truth["temperature"] == {"start_c": 20.0, "rise_c": 3.0, "tau_s": 1200.0, "t0_s": 0.0}
    assert truth["effects"][0]["delta_t_range_k"][1] == pytest.approx(T.max() - T[0], rel=1e-12)
    # without the option the default warm-up is written; without the effect the channel stays constant
    assert simulate(None, noise=False, effects=["thermal_temperature"])[0].temperature_c.max() > 21.9
    assert np.all(rec0.temperature_c == 20.0)


@pytest.mark.parametrize("args, message", [
    (["--effect", "reversal_angular:error=E_XX"], "must be one of E_AX"),
    (["--effect", "reversal_angular:error=E_BC"], "must be one of E_AX"),
    (["--effect", "reversal_angular:amount=0.5"], "amount='0.5': must lie in [-0.01, 0.01] (rad)"),
    (["--effect", "nest_creep:point=W"], "point must be one of P, Q, K"),
    (["--effect", "nest_creep:rate_mm_s=-1e-6"], "must lie in [0, 0.001]"),
    (["--effect", "nest_creep:direction=0;0;0"], "not all zero"),
    (["--effect", "nest_creep:side=head"], "must be one of tool, table"),
    (["--effect", "tracker_settling:tau_s=0"], "tau_s='0': must lie in [1, 1e+07]"),
    (["--effect", "tracker_settling:angle_rad=inf"], "must be finite"),
    (["--effect", "tracker_settling:about=1;2"], "three finite numbers"),
    (["--effect", "thermal_temperature:axis=C"], "axis must be one of X, Y, Z"),
    (["--effect", "thermal_temperature:ppm_per_k=nan"], "not a number"),
    (["--temperature", "rise_c=50"], "rise_c must be a number in [-20, 20]"),
    (["--temperature", "tau=5"], "unknown key(s) ['tau']"),
])
def test_cli_new_effects_bad_input(tmp_path, capsys, args, message):
    assert main(["simulate", "-o", str(tmp_path / "r.csv"), *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal simulate: error:") and message in err, err
    assert not (tmp_path / "r.csv").exists()


def test_cli_new_effects_round_trip(tmp_path, capsys):
    out = tmp_path / "rec.csv"
    assert main(["simulate", "-o", str(out), "--rounds", "1", "--no-noise", "--json", "--temperature",
                 "--effect", "nest_creep:point=K,side=table,rate_mm_s=1e-5", "--effect", "tracker_settling",
                 "--effect", "reversal_angular:error=E_CY,amount=5e-5",
                 "--effect", "thermal_temperature:drift_mm_per_k=0.002,direction=0;1;1"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert [e["name"] for e in summary["effects"]] == ["nest_creep", "tracker_settling", "reversal_angular",
                                                       "thermal_temperature"]
    truth = json.loads((tmp_path / "rec.truth.json").read_text())
    assert truth["effects"][3]["params"]["direction"] == pytest.approx([0, 2 ** -0.5, 2 ** -0.5])
    assert truth["temperature"]["rise_c"] == 2.0
    rec = read_recording(out)
    assert rec.temperature_c.max() - rec.temperature_c.min() > 1.0


# ----------------------------------------------------------------------------- backlash sign vs ISO 230-2
def _sense(m: mtcal.Machine, axis: str) -> float:
    """+1 when a positive command of the rotary axis turns its side about +z of the axis' stator frame (the
    sense of a positive E_C<axis>), else -1: from the nominal motion of a reflector by +1 deg, computed here."""
    local = np.array(m.campaign["reflectors"][m.side(axis)][0][1])
    a0, a1 = m.axis_vector({}), m.axis_vector({axis: 1.0})
    p0, p1 = m.points(axis, a0, local), m.points(axis, a1, local)
    R, o = m.axis_frame(axis, a0)
    return float(np.sign(np.cross(R[:, 2], p0 - o) @ (p1 - p0)))


@pytest.mark.parametrize("name", SPECS)
def test_backlash_b_is_the_iso_230_2_reversal_value(name):
    """ISO 230-2: B_i = mean(deviation up) - mean(deviation down), deviation = actual - target in the axis'
    commanded sense.  The planted backlash b adds + d b / 2 to the positioning error, so on a linear axis (whose
    positioning error is along its motion in every shipped spec) B = b; on a rotary axis B = s b with s = +1 when
    a positive command turns about +z of the stator (the sense of E_C<axis>), -1 otherwise -- DMU 50's C
    (T_0^w = ... Rz(-C)): s = -1, so b = +20 urad reads B = -20 urad = -4.125 arcsec."""
    m = mtcal.load_machine(name)
    pl = _plan(m, rounds=2)
    effects = [("backlash", {"axis": a, "amount": 0.004 if m.kind(a) == "linear" else 20e-6}) for a in m.axes]
    rec, _ = simulate(None, plan=pl, noise=False, effects=effects)
    ev = iso230_2.evaluate(rec, machine=m, angle_unit="urad")
    for a in m.axes:
        p = ev.axes[a].parameters
        want = 4.0 if m.kind(a) == "linear" else _sense(m, a) * 20.0  # um or urad
        assert p["B_mean"] == pytest.approx(want, abs=1e-4), (a, p["B_mean"])
        assert p["B"] == pytest.approx(abs(want), abs=1e-4)
    if name == "dmu50":
        assert _sense(m, "C") == -1.0 and _sense(m, "B") == 1.0
        c = iso230_2.evaluate(rec, "C", machine=m, angle_unit="arcsec").axes["C"].parameters["B_mean"]
        assert c == pytest.approx(-4.125, abs=1e-3)  # 20 urad = 4.125 arcsec, a lag
