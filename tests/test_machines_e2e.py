"""Machines are data, end to end (issue 12): every spec in derive/machines/ goes through simulate -> identify ->
compensate (checked with the exact kinematics of the true machine) -> diagnose -> plan with no code of its own.

The true machine of each spec is a smooth error model written here (positioning, straightness and angular errors
of every linear axis; radial, axial-free and positioning errors of every rotary axis), sized like the thesis'
DMU 50 results (~10 um, ~30 urad).  Campaigns are the spec's defaults (derive/machines/<name>.toml [campaign]),
shortened where the test only needs the path to work.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import mtcal
from mtcal.campaign.plans import Plan
from mtcal.campaign.simulate import simulate
from mtcal.compensate.solver import Compensator
from mtcal.diagnose import diagnose
from mtcal.identify.run import identify
from mtcal.kinematics.defaults import default_positions
from mtcal.kinematics.machine import available_machines
from mtcal.model.errormodel import ErrorFunction, ErrorModel
from mtcal.planning.plan import plan_uncertainty

SPECS = sorted(p.stem for p in (Path(__file__).resolve().parent.parent / "derive" / "machines").glob("*.toml"))


def test_every_shipped_spec_is_generated():
    assert SPECS == available_machines() and {"dmu50", "xyzac", "headbc"} <= set(SPECS)


def true_model(m: mtcal.Machine) -> ErrorModel:
    """Smooth errors vanishing at each axis' reference position (the position closest to zero)."""
    funcs = {}
    for a, pos in default_positions(m).items():
        q = np.linspace(pos.min(), pos.max(), 41)
        q0 = pos[np.argmin(np.abs(pos))]
        if m.kind(a) == "linear":
            s = (q - q0) / np.ptp(pos)
            pe = m.positioning_errors[a]
            straight = next(n for n in m.error_motions(a)[:3] if n != pe)
            funcs[pe] = ErrorFunction(a, q, 0.012 * s**2)
            funcs[straight] = ErrorFunction(a, q, 0.006 * np.sin(np.pi * s))
            funcs[f"E_A{a}"] = ErrorFunction(a, q, 25e-6 * s)
        else:
            t = np.radians(q - q0)
            funcs[f"E_X{a}"] = ErrorFunction(a, q, 0.008 * (1 - np.cos(t)))
            funcs[f"E_Y{a}"] = ErrorFunction(a, q, 0.005 * np.sin(t))
            funcs[m.positioning_errors[a]] = ErrorFunction(a, q, 40e-6 * np.sin(t))
    return ErrorModel(m.name, {}, funcs)


def short_plan(m: mtcal.Machine, rounds: int, step: int = 1) -> Plan:
    pos = {a: p[::step] if p[::step][-1] == p[-1] else np.append(p[::step], p[-1]) for a, p in
           default_positions(m).items()}
    return Plan(m, rounds=rounds, positions=pos)


@pytest.fixture(scope="module", params=SPECS)
def identified(request):
    m = mtcal.load_machine(request.param)
    truth = true_model(m)
    rec, _ = simulate(truth, plan=Plan(m, rounds=1), noise=False)
    return m, truth, identify(rec, machine=m)


def test_identify_recovers_the_true_machine(identified):
    """Noise-free campaign: the three-point method is exact to first order; the error motions (E_XJ .. E_CJ of
    every axis, including a head axis measured with reflectors on the spindle) come back within 1 nm / 1 nrad
    (second-order terms of 25 urad over 150 mm lever arms: < 0.1 nm)."""
    m, truth, res = identified
    assert set(res.axes) == set(m.axes)
    for a, ar in res.axes.items():
        tv = truth.errors_at(m, m.axis_vector({a: ar.positions}))
        for i, n in enumerate(ar.names):
            assert np.abs(ar.mean[:, i] - tv[:, m.error_names.index(n)]).max() < 1e-6, (m.name, n)


def test_compensation_checked_with_the_exact_kinematics_of_the_true_machine(identified):
    """Random targets inside the measured ranges: the identified model's first-order correction takes the
    true machine's tool-tip error (exact error-inclusive forward kinematics) from ~10 um to below 2 % of it."""
    m, truth, res = identified
    rng = np.random.default_rng(3)
    lo = {a: p.min() for a, p in default_positions(m).items()}
    hi = {a: p.max() for a, p in default_positions(m).items()}
    q_nom = np.column_stack([rng.uniform(lo[a], hi[a], 400) for a in m.axes])
    q_cmd = Compensator(res.model, m).correct(q_nom)
    target = m.forward(q_nom)[:, :3]
    before = np.linalg.norm(m.forward(q_nom, truth.errors_at(m, q_nom))[:, :3] - target, axis=1)
    after = np.linalg.norm(m.forward(q_cmd, truth.errors_at(m, q_cmd, "clamp"))[:, :3] - target, axis=1)
    assert before.mean() > 5e-3  # the true machine is ~10 um off (mm)
    assert after.max() < 0.02 * before.max(), (m.name, before.max(), after.max())


@pytest.mark.parametrize("name", SPECS)
@pytest.mark.slow
def test_diagnose_finds_a_planted_backlash_and_keeps_a_clean_campaign_clean(name):
    """The physical simulator plants a 50 urad reversal on the machine's tilt axis (on the head for headbc);
    diagnosis names it on that axis within 3 sigma; the same campaign without it reports nothing."""
    m = mtcal.load_machine(name)
    pl = short_plan(m, rounds=3, step=2)
    axis = m.ik_info["tilt_axis"]
    amount = 50e-6
    clean, _ = simulate(None, plan=pl, seed=11)
    planted, _ = simulate(None, plan=pl, seed=12, effects=[("backlash", {"axis": axis, "amount": amount})])
    d0 = diagnose(clean, machine=m, tracker=pl.tracker).to_dict()
    assert not [e for e in d0["effects"] if e["significant"]], name
    d1 = diagnose(planted, machine=m, tracker=pl.tracker).to_dict()
    found = [e for e in d1["effects"] if e["significant"]]
    assert [(e["name"], e["axis"]) for e in found] == [("backlash", axis)], (name, found)
    assert abs(found[0]["estimate"] - amount) < 3 * found[0]["uncertainty"]


@pytest.mark.parametrize("name", SPECS)
def test_plan_covers_every_axis_of_the_spec(name):
    m = mtcal.load_machine(name)
    r = plan_uncertainty(machine=m).to_dict()
    assert list(r["axes"]) == list(m.axes) and r["machine"] == name
    for a, sig in r["axes"].items():
        assert list(sig) == list(m.error_motions(a))
        assert all(0 < v < 0.05 for v in sig.values())  # mm / rad: finite, positive, plausible


def test_nc_program_compensated_on_every_machine(identified, tmp_path):
    """`mtcal compensate` on G-code written with the machine's own axis words (X Y Z A C on the trunnion, the
    head's B on headbc), scope full (position and orientation, FOR through a head axis): the written program,
    read back and run on the true machine (exact kinematics), reaches the targets; another machine's axis word
    is refused with its line."""
    from mtcal.compensate.program import ProgramCompensator
    from mtcal.errors import InputError
    from mtcal.nc.gcode import read_moves
    m, truth, res = identified
    rng = np.random.default_rng(5)
    lo = {a: p.min() for a, p in default_positions(m).items()}
    hi = {a: p.max() for a, p in default_positions(m).items()}
    q = np.column_stack([rng.uniform(lo[a], hi[a], 60) for a in m.axes])
    q[:, m.index(m.ik_info["tilt_axis"])] = np.clip(q[:, m.index(m.ik_info["tilt_axis"])], 10, None)  # off B = 0
    src, dst = tmp_path / "p.nc", tmp_path / "out.nc"
    src.write_text("G90 G21\n" + "".join("G1 " + " ".join(f"{a}{v:.4f}" for a, v in zip(m.axes, row)) + "\n"
                                         for row in q))
    # tolerance 1 mm: no subdivision of the long random moves, so the written lines are the program's end points
    comp = Compensator(truth, m, "full", iterations=2)
    ProgramCompensator(comp, tolerance=1.0, precision=6).run(src, dst)
    q_nom, q_cmd = read_moves(src, machine=m), read_moves(dst, machine=m)
    assert len(q_cmd) == len(q_nom) == 60
    want = m.forward(q_nom)
    got = m.forward(q_cmd, truth.errors_at(m, q_cmd, "hold"))
    before = m.forward(q_nom, truth.errors_at(m, q_nom, "hold"))
    assert np.linalg.norm(before[:, :3] - want[:, :3], axis=1).max() > 5e-3  # ~10 um off uncompensated (mm)
    assert np.linalg.norm(got[:, :3] - want[:, :3], axis=1).max() < 1e-4  # mm: exact iterations, 6 decimals
    full = comp.weight(q_nom) >= 1  # orientation corrected in full outside the singular cones (blended inside)
    assert full.sum() > 40 and np.linalg.norm(got[full, 3:] - want[full, 3:], axis=1).max() < 2e-6  # rad
    foreign = next(c for c in "ABUVW" if c not in m.axes)
    bad = tmp_path / "bad.nc"
    bad.write_text(f"G1 X1 Y2 Z3\nG1 {foreign}5\n")
    with pytest.raises(InputError, match=rf"bad.nc, line 2: axis word '{foreign}5'"):
        ProgramCompensator(Compensator(truth, m)).run(bad, tmp_path / "bad_out.nc")
