"""Multi-station campaigns (docs/design.md: several tracker stations): the same campaign measured from each station
in turn, every station with its own small alignment error.

Each station's readings are ``rigid_point(exact reflector position, a_s) + AT960 noise from that station``
(derive/threepoint.py ``rigid_point``: a_s = tx, ty, tz mm and rotations about x, y, z rad, drawn from
N(0, alignment_um) and N(0, alignment_urad), seeded); the exact reflector positions come from the machine's
error-inclusive kinematics (mtcal.campaign.simulate, noise off).  Rounds are numbered across stations (a round belongs
to one station); times continue from station to station with ``station_change_s`` for moving and re-aligning
the tracker.  The truth sidecar lists every station's tracker position, alignment error and planted effects
(``effects`` planted in every station's campaign, ``station_effects`` in one station's).
"""
from __future__ import annotations

from dataclasses import replace
from typing import Iterable, Mapping, Sequence

import numpy as np

from mtcal.campaign.plans import as_plan
from mtcal.campaign.simulate import simulate
from mtcal.errors import InputError
from mtcal.generated import threepoint_numpy as tp
from mtcal.kinematics.machine import Machine, load_machine
from mtcal.measurement import tracker as trk
from mtcal.measurement.recordings import Recording, make_recording
from mtcal.model.errormodel import ErrorModel

ALIGNMENT_UM = 20.0  # default 1-sigma station alignment error: translation (um) and rotation (urad)
ALIGNMENT_URAD = 30.0
STATION_CHANGE_S = 1800.0  # move the tracker, warm up, re-align (s)


def simulate_stations(model: ErrorModel | None, stations: Sequence, *, machine: str | Machine | None = None,
                      rounds: int = 1, seed: int | None = 0, effects: Iterable = (), noise: bool = True, plan=None,
                      alignment_um: float = ALIGNMENT_UM, alignment_urad: float = ALIGNMENT_URAD,
                      spec: trk.TrackerSpec = trk.AT960, temperature=None,
                      station_effects: Mapping[str, Iterable] | None = None,
                      extrapolate: str = "error") -> tuple[Recording, dict]:
    """(recording, truth) of a campaign measured from each of ``stations`` ((3,) mm positions or
    (label, (3,)) pairs, machine frame) with ``rounds`` rounds each; ``temperature`` as in ``simulate``;
    ``effects`` are planted in every station's campaign (their times from that station's start),
    ``station_effects`` (label -> effects) in that station's only (e.g. a knock of one tracker); ``extrapolate`` as
    in ``simulate``."""
    if machine is None:
        machine = model.machine if model is not None else None
    m = machine if isinstance(machine, Machine) else load_machine(*([machine] if machine else []))
    pl = as_plan(plan, m)
    named = [(s if isinstance(s, tuple) and isinstance(s[0], str) else (f"S{i + 1}", s))
             for i, s in enumerate(stations)]
    if not named:
        raise InputError("a multi-station campaign needs at least one station")
    extra = sorted(set(station_effects or {}) - {label for label, _ in named})
    if extra:
        raise InputError(f"station_effects: no station {extra[0]!r} (stations: {', '.join(k for k, _ in named)})")
    effects = list(effects)
    rng = np.random.default_rng(seed)
    align = np.column_stack([rng.normal(0, alignment_um * 1e-3, (len(named), 3)),
                             rng.normal(0, alignment_urad * 1e-6, (len(named), 3))])
    align[:, :3] -= align[:, :3].mean(axis=0)  # the gauge of docs/design.md: translations sum to zero (see module doc)
    parts, st_truth, t0, held = [], [], 0.0, {}
    for k, (label, pos) in enumerate(named):
        t = np.asarray(pos, dtype=float).reshape(3)
        if not np.isfinite(t).all():
            raise InputError(f"station {label}: tracker position must be finite, got {pos!r}")
        rec, truth = simulate(model, machine=m, plan=replace(pl, tracker=tuple(t), rounds=int(rounds)),
                              rounds=None, seed=None, effects=[*effects, *(station_effects or {}).get(label, ())],
                              noise=False, temperature=temperature, extrapolate=extrapolate)
        a = align[k]
        xyz = tp.rigid_point(rec.xyz, a)
        if noise:
            xyz = xyz + trk.sample(xyz, t, rng, spec)
        parts.append((label, t, rec, xyz, k * int(rounds), t0))
        t0 += float(rec.time_s.max()) + STATION_CHANGE_S
        for name, n in truth.pop("model_held", {}).items():
            held[name] = held.get(name, 0) + n
        st_truth.append({"label": label, "tracker": t.tolist(), "alignment": a.tolist(), "rounds": int(rounds),
                         "effects": truth.get("effects", [])})
    cat = lambda f: np.concatenate([f(p) for p in parts])  # noqa: E731
    out = make_recording(cat(lambda p: p[2].axis), cat(lambda p: p[2].round + p[4]), cat(lambda p: p[2].position),
                         cat(lambda p: p[2].point), cat(lambda p: p[3]), cat(lambda p: p[2].time_s + p[5]),
                         cat(lambda p: p[2].direction), cat(lambda p: p[2].temperature_c))
    out.station = cat(lambda p: np.full(len(p[2]), p[0], dtype=object))
    out.tracker_xyz = cat(lambda p: np.tile(p[1], (len(p[2]), 1)))
    if parts[0][2].other_positions:
        out.other_positions = {a: np.concatenate([p[2].other_positions[a] for p in parts])
                               for a in parts[0][2].other_positions}
    truth = {**truth, "tracker": None, "noise": bool(noise), "seed": seed, "rounds": int(rounds) * len(named),
             "stations": st_truth,
             "alignment_convention": "reading = rigid_point(true point, alignment): Trans(tx, ty, tz mm) "
                                     "Rz(c) Ry(b) Rx(a) (rad), derive/threepoint.py",
             "alignment_sigma": {"um": alignment_um, "urad": alignment_urad}, **({"model_held": held} if held else {})}
    out.truth = truth
    return out, truth
