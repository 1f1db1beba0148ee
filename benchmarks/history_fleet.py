"""Issue 38's acceptance on a simulated fleet: several machines (three specs), several calibrations each, changes
planted between some calibrations and none between others; every model identified from its own simulated campaign
(exact kinematics, AT960 noise, tracker given, identify's default estimator), added to a SQLite history and to a
PostgreSQL one (tests/pg_server.py), then `history compare` on each machine.

Reported: every planted change with its size over the u95 of the difference `history compare` gives for it (named
or not; those >= 3 x u95 must all be named); the rate of false changes over the unchanged steps (a step that names
anything; the stated family-wise level is mtcal.history.compare.LEVEL) and over the errors of the changed steps
(a named error that was not planted); the per-test check of the intervals (the share of differences beyond their
own 95 % interval over the unchanged steps, 5 % if the models' intervals are right); and whether SQLite and
PostgreSQL give the same answers.  `python benchmarks/history_fleet.py [--quick]` (about 30 identifications; the
last line is one JSON object).
"""
from __future__ import annotations

import argparse
import datetime as dt
import json
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

# machine ID -> (spec, calibrations, {calibration index k: {error: change}} planted between k-1 and k): a constant's
# change in rad, or ("ramp", mm) for an error function: a change growing linearly from 0 at the reference position
# to mm at the far end of the axis' table (a scale change of a positioning error, a straightness tilting)
FLEET = {
    "dmu50-A": ("dmu50", 4, {2: {"E_C0Y": 90e-6}, 3: {"E_B0Z": -100e-6, "E_A0Z": 80e-6}}),
    "dmu50-B": ("dmu50", 4, {2: {"E_XX": ("ramp", 0.045)}, 3: {"E_C0Y": -70e-6}}),
    "headbc-A": ("headbc", 4, {2: {"E_B0Z": 100e-6}, 3: {"E_YY": ("ramp", -0.025)}}),
    "xyzac-A": ("xyzac", 4, {3: {"E_A0Z": -100e-6, "E_C0Y": 60e-6}}),
    "dmu50-steady": ("dmu50", 8, {}),
    "xyzac-steady": ("xyzac", 6, {}),
}
QUICK = {k: (s, 3, {p: c for p, c in ch.items() if p < 3}) for k, (s, n, ch) in FLEET.items() if "steady" not in k}


def truth_of(spec: str, seed: int):
    """A machine's truth: the spec's synthetic truth (mtcal.data.make_demo_data.build_for) of its own seed."""
    from mtcal.data.make_demo_data import build_for
    from mtcal.kinematics.machine import load_machine
    return build_for(load_machine(spec), seed=seed)


def calibrate(truth, spec: str, seed: int, folder: Path, name: str) -> Path:
    """One calibration: a simulated campaign of the spec's default design, identified; the model file."""
    from mtcal.campaign.simulate import simulate
    from mtcal.identify.run import identify
    from mtcal.model.errormodel import save_model
    rec, planted = simulate(truth, machine=spec, seed=seed)
    model = identify(rec, tracker=planted["tracker"], machine=spec, worth=False).model
    save_model(model, folder / name)
    return folder / name


def build(fleet: dict, folder: Path, dbs: list[str]) -> dict:
    """Every calibration of every machine, added to every database; the planted changes per step."""
    from mtcal.history import add
    planted = {}
    for i, (mid, (spec, n, changes)) in enumerate(fleet.items()):
        truth = truth_of(spec, 1000 + i)
        day = dt.date(2024, 1, 15)
        for k in range(n):
            if k in changes:
                truth = changed(truth, changes[k])
                planted[(mid, k)] = {e: ramp_of(truth, d) if isinstance(d, tuple) else d
                                     for e, d in changes[k].items()}
            f = calibrate(truth, spec, 10_000 * i + k, folder, f"{mid}_{k}.json")
            for db in dbs:
                add(f, mid, day, db)
            day += dt.timedelta(days=120)
        print(f"  {mid}: {n} calibrations", file=sys.stderr)
    return planted


def ramp_of(truth, change: tuple) -> dict:
    """{position: change (mm)} of a ("ramp", mm) change over the positions of ``truth``'s table (filled in by
    ``changed``)."""
    return change[2]


def changed(truth, changes: dict):
    """``truth`` with ``changes`` (FLEET) applied: constants shifted, error functions' tables ramped."""
    from dataclasses import replace

    from mtcal.model.errormodel import ErrorModel
    consts, funcs = dict(truth.constants), dict(truth.functions)
    for e, d in list(changes.items()):
        if isinstance(d, tuple):
            f = funcs[e]
            ref = f.positions[np.argmin(np.abs(f.positions))]
            far = f.positions[np.argmax(np.abs(f.positions - ref))]
            ramp = d[1] * (f.positions - ref) / (far - ref)
            funcs[e] = replace(f, values=f.values + ramp)
            changes[e] = (*d[:2], dict(zip(f.positions.tolist(), ramp.tolist())))
        else:
            consts[e] = consts.get(e, 0.0) + d
    return ErrorModel(truth.machine, consts, funcs, truth.meta)


def judge(fleet: dict, planted: dict, db: str) -> dict:
    """The acceptance figures of one database (module docstring)."""
    from mtcal.history import compare_history, show
    from mtcal.history.compare import LEVEL
    out = {"planted": [], "unchanged_steps": 0, "false_steps": 0, "changed_steps_errors_compared": 0,
           "false_errors_in_changed_steps": 0, "tests_unchanged": 0, "beyond_own_u95_unchanged": 0}
    answers = {}
    for mid in fleet:
        comp = compare_history(mid, db=db)
        answers[mid] = comp.to_dict()
        recs = [r for r in show(mid, db) if r.kind == "model"]
        for k, step in enumerate(comp.steps, 1):
            named = {c.name: c for c in step.changed}
            want = planted.get((mid, k), {})
            if not want:
                out["unchanged_steps"] += 1
                out["false_steps"] += bool(named)
                z = _z_scores(recs[k - 1], recs[k])
                out["tests_unchanged"] += len(z)
                out["beyond_own_u95_unchanged"] += int(np.sum(np.abs(z) > 1.959964))
            else:
                out["changed_steps_errors_compared"] += step.unchanged + len(named)
                out["false_errors_in_changed_steps"] += len(set(named) - set(want))
            for e, d in want.items():
                if isinstance(d, dict):  # a ramp: its largest change over the u95 at that position, in um
                    pos, size, u95 = max(((x, v, _u95_of(recs[k - 1], recs[k], e, x)) for x, v in d.items()
                                          if _u95_of(recs[k - 1], recs[k], e, x)), key=lambda t: abs(t[1]) / t[2])
                    size, u95, unit = size * 1e3, u95 * 1e3, "um"
                else:
                    pos, size, u95, unit = None, d * 1e6, _u95_of(recs[k - 1], recs[k], e) * 1e6, "urad"
                out["planted"].append({"machine": mid, "step": k, "error": e, "position": pos, "planted": size,
                                       "u95": u95, "unit": unit, "ratio": abs(size) / u95, "named": e in named,
                                       "estimate": named[e].change if e in named else None})
    must = [p for p in out["planted"] if p["ratio"] >= 3]
    out.update({"level": LEVEL, "planted_ge_3u95": len(must), "planted_ge_3u95_named": sum(p["named"] for p in must),
                "false_step_rate": out["false_steps"] / max(out["unchanged_steps"], 1),
                "share_beyond_own_u95": out["beyond_own_u95_unchanged"] / max(out["tests_unchanged"], 1)})
    return out, answers


def _u95_of(a, b, name: str, position: float | None = None) -> float | None:
    """The 95 % half-width of the difference of an error (at ``position``) between two records (normal: the
    joint fit); None where one has no interval (the reference position)."""
    def one(r):
        return next((q for q in r.quantities if q.name == name and (q.position is None if position is None else
                                                                  q.position is not None and
                                                                  abs(q.position - position) < 1e-6)), None)
    qa, qb = one(a), one(b)
    if qa is None or qb is None or not qa.u95 or not qb.u95:
        return None
    return 1.959964 * math.hypot(qa.u95 / 1.959964, qb.u95 / 1.959964)


def _z_scores(a, b) -> np.ndarray:
    """Differences over their standard uncertainty of every common error and position with an interval (joint
    fit: k = 1.96)."""
    qa = {(q.name, q.position): q for q in a.quantities if q.u95}
    z = []
    for q in b.quantities:
        p = qa.get((q.name, q.position))
        if q.u95 and p is not None:
            z.append((q.value - p.value) / math.hypot(q.u95 / 1.959964, p.u95 / 1.959964))
    return np.asarray(z)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="four machines, three calibrations each")
    args = ap.parse_args()
    fleet = QUICK if args.quick else FLEET
    from pg_server import fresh_database, private_server
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp, private_server() as (pg, why):
        folder = Path(tmp)
        dbs = [str(folder / "fleet.db")] + ([fresh_database(pg, "mtcal_fleet")] if pg else [])
        planted = build(fleet, folder, dbs)
        result, answers = judge(fleet, planted, dbs[0])
        if pg:
            result["postgresql_same_answers"] = judge(fleet, planted, dbs[1])[1] == answers
        else:
            result["postgresql_same_answers"] = f"not run: {why}"
    result["seconds"] = time.perf_counter() - t0
    for p in result["planted"]:
        where = "" if p["position"] is None else f" at {p['position']:g}"
        print(f"  {p['machine']} step {p['step']}: {p['error']}{where} {p['planted']:+.1f} {p['unit']} = "
              f"{p['ratio']:.1f} x u95 {p['u95']:.1f}: {'named' if p['named'] else 'NOT named'}"
              + (f" ({p['estimate']:+.1f})" if p["named"] else ""))
    print(json.dumps(result))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
