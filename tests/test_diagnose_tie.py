"""Reflector positions shared across axes measured from the same reference pose (mtcal.diagnose.prepare, design):
the tie rule, the engine's shared base columns against plain least squares, and what the tie makes visible (a
nest creeping 10 um/h: missed with per-axis positions, F about 3)."""
from __future__ import annotations

import campaigns as C
import numpy as np
import pytest
from diagnose_judge import judge
from scipy import stats

from mtcal.campaign.plans import Plan
from mtcal.campaign.simulate import simulate_campaign
from mtcal.diagnose import diagnose
from mtcal.diagnose.design import base_design, engine_for, whiten
from mtcal.diagnose.engine import Engine
from mtcal.diagnose.prepare import prepare

POS = Plan().positions


def _campaign(at=None):
    axes = {a: {"positions": POS[a][::4].tolist()} for a in "XYZBC"}
    for a, v in (at or {}).items():
        axes[a]["at"] = v
    return simulate_campaign(seed=3, plan={"axes": axes, "rounds": 2}, rounds=None)


def _groups(prep):
    """{frozenset of axes sharing a position: point labels}, read off the prepared readings."""
    out = {}
    rec = prep.rec
    for k in np.unique(prep.point_group):
        on = prep.point_group == k
        (label,) = set(rec.point[on].tolist())
        out.setdefault(frozenset(rec.axis[on].tolist()), set()).add(label)
    return out


def test_axes_share_positions_only_at_one_reference_pose_and_side():
    # default plan: every axis measured with the others at zero, references at 0 -> X, Y, Z (tool side) share
    # their reflectors, B and C (table side) theirs; never across sides
    g = _groups(prepare(_campaign(), tracker=Plan().tracker))
    assert set(g) == {frozenset("XYZ"), frozenset("BC")}
    # Y measured with X parked at 250 mm: Y's reference pose differs from X's and Z's -> Y keeps its own
    rec = _campaign(at={"Y": {"X": 250.0}})
    assert rec.other_positions is not None and "X" in rec.other_positions
    g = _groups(prepare(rec, tracker=Plan().tracker))
    assert set(g) == {frozenset("XZ"), frozenset("Y"), frozenset("BC")}
    # the option off: one position per (axis, reflector)
    g = _groups(prepare(_campaign(), tracker=Plan().tracker, tie_positions=False))
    assert all(len(axes) == 1 for axes in g)


def test_shared_columns_equal_plain_least_squares():
    """Engine(blocks, y, shared) against numpy.linalg.lstsq on the full design written here: same RSS, p, F of a
    candidate, estimate and leverages (rows, full_rows); copy_base keeps the shared columns."""
    rng = np.random.default_rng(5)
    n = 240
    ia, ib = np.arange(0, 120), np.arange(120, 240)
    xa, xb = rng.normal(size=(120, 3)), rng.normal(size=(120, 2))
    s = rng.normal(size=(n, 2))
    g = rng.normal(size=(n, 1))
    y = rng.normal(size=n) + 0.4 * g[:, 0]
    full = np.zeros((n, 5))
    full[ia, :3], full[ib, 3:] = xa, xb
    full = np.hstack([full, s])

    def rss(x):
        return float(np.sum((y - x @ np.linalg.lstsq(x, y, rcond=None)[0]) ** 2))
    rss0, rss1 = rss(full), rss(np.hstack([full, g]))
    dof = n - 7 - 1
    eng = Engine([(ia, xa), (ib, xb)], y, s)
    assert eng.p == 7 and eng.rss == pytest.approx(rss0, rel=1e-12)
    sc = eng.score(g)
    assert sc.dof == dof and sc.F == pytest.approx((rss0 - rss1) / (rss1 / dof), rel=1e-10)
    assert sc.logp == pytest.approx(stats.f.logsf(sc.F, 1, dof), rel=1e-9)
    theta, _ = eng.estimate([g])
    assert theta[0] == pytest.approx(np.linalg.lstsq(np.hstack([full, g]), y, rcond=None)[0][-1], rel=1e-10)
    hat = np.einsum("ij,ji->i", full, np.linalg.pinv(full))          # leverages of the plain design
    for Q in (Engine([(ia, xa), (ib, xb)], np.zeros(n), s).full_rows(), eng.rows()):
        # the engine's rows group the readings by three; here every "reading" is one scalar row
        assert np.allclose(np.sum(Q.reshape(n, -1) ** 2, axis=1), hat, atol=1e-10)
    eng.add(g)
    base = eng.copy_base()
    assert base.p == 7 and base.rss == pytest.approx(rss0, rel=1e-12)


def test_base_design_shares_columns_and_per_axis_design_stays_per_axis():
    prep = prepare(_campaign(), tracker=Plan().tracker)
    wy = whiten(prep.W, prep.y)
    base = base_design(prep, {a: 1 for a in prep.axes})
    labels = {s: sorted(set(prep.rec.point[prep.geometry.side == s].tolist())) for s in ("tool", "table")}
    assert base.shared.shape[-1] == 3 * (len(labels["tool"]) + len(labels["table"]))
    # X alone (the per-axis BIC degree selection): its own positions, no shared columns, no rigid motion
    one = base_design(prep, {"X": 1}, ["X"])
    assert one.shared.shape[-1] == 0 and one.blocks["X"].shape[-1] == 6 + 3 * len(labels["tool"])
    # tied: shared positions + a free rigid motion (6) per axis, one rigid motion per side being the shared
    # positions' own: per side of k axes and m reflectors, 3 m + 6 k - 6 parameters instead of 3 m k
    flat = prepare(_campaign(), tracker=Plan().tracker, tie_positions=False)
    per_axis = engine_for(flat, base_design(flat, {a: 1 for a in flat.axes}), whiten(flat.W, flat.y))
    tied = engine_for(prep, base, wy)
    saved = sum(3 * (len(labels[s]) - 2) * (k - 1) for s, k in (("tool", 3), ("table", 2)))
    assert saved > 0 and per_axis.p - tied.p == saved


@pytest.mark.slow
def test_nest_creep_of_10_um_per_hour_is_found():
    """docs "Campaigns we did not make": 15 um over the 1.5 h record; per-axis positions absorbed it (F about 3,
    missed in 15 of 16 of these campaigns), the shared positions show it: found in 15 of 16 (seeds 500-507, the
    tracker told and not) at the level 0.01, 13 of 16 at the level 0.005 (issue 24: p_adj 0.009 on seed 501 told),
    12 of 16 at the default level 0.005 since it bounds the whole diagnosis (each stage at a third of it,
    mtcal.diagnose.run.STAGES), never anything else named alone: a creep the data cannot tell from a change at
    another place that fits alike is one located misfit listing it (selection._tied; since ba9d6f8 also beside
    rivals not significant themselves: 4 of the 13 found here), which names nothing in its place.  11 of 16 since
    the station is placed from the rounds' scatter less each round's mean (station_scatter): seed 556 (untold)
    names a false re-seated nest K in round 1 either way, with the creep listed as its rival at p_adj 0.00092
    before and just above the level after (a hair's verdict: the station moved 15 mm)."""
    found = 0
    for seed in range(500, 508):
        for told in (True, False):
            c = C.nest_creep(seed + (0 if told else 50), rate_um_h=10.0)
            c = c if told else C.without_tracker(c)
            d = diagnose(c.recording, c.model, machine=c.design.machine, tracker=c.tracker)
            ok, msg = judge(d, c.expect)
            found += ok
            names = [f.name for f in d.effects if f.significant]
            listed = any(u.by == "effects fitting alike" and "nest_creep" in u.where for u in d.unexplained)
            assert not names or "nest_creep" in names or listed, (seed, told, names)
    assert found >= 11, found


def test_cli_per_axis_positions(tmp_path, capsys):
    import json

    from mtcal.cli import main
    from mtcal.measurement.recordings import write_recording
    path = tmp_path / "r.csv"
    write_recording(_campaign(), path)
    out = {}
    for flag in ([], ["--per-axis-positions"]):
        assert main(["diagnose", str(path), "--tracker", "250,-1475,150", "--json", *flag]) == 0
        out[bool(flag)] = json.loads(capsys.readouterr().out)["base_model"]
    assert "shared by X, Y, Z and by B, C" in out[False]["basis"], out[False]["basis"]
    assert "shared" not in out[True]["basis"], out[True]["basis"]
    # 3 reflectors per side: X, Y, Z save 3 (3 - 2) (3 - 1) = 6 parameters, B, C 3 (3 - 2) (2 - 1) = 3
    assert out[True]["parameters"] - out[False]["parameters"] == 9
