"""Issue 34: one axis repeating worse than the others, as gen2 plants it (benchmarks/gen2/README.md, row
``axis_scatter``): every stop (round, direction, position) of one linear axis lands N(0, sigma) off along the
axis and every nest read at that stop shares the draw -- a random effect per stop.  mtcal.diagnose.scatter tests
it by the stops against the nests' scatter within them (law-free), so that

* planted, it is found on its axis with sigma inside the stated interval, and no tracker knock, outlier or
  unexplained entry is named in its place (gen2 seed 3502 campaign 16 of ``--mix outside``: on e58d8c4 the
  defaults named "a tracker knock along -X at t0=1927 s" and, with the tracker given, three tracker knocks);
* on clean campaigns it holds its level under every gen2 noise law: the clean twins of the same plans, an
  isotropic tracker over three stations, and gen2 seed 3502 campaign 5 (2 stations, AT960-like: on e58d8c4 a
  false "axis_scatter Y", 25 um, from the stations' alignment read as round-to-round scatter).
"""
from __future__ import annotations

import json
import logging
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from mtcal.diagnose import diagnose
from mtcal.diagnose.prepare import prepare
from mtcal.measurement.recordings import parse_recording

GEN2 = Path(__file__).resolve().parent.parent / "benchmarks" / "gen2" / "gen2.py"


def _gen2(tmp_path: Path, seed: int, index: int, *args: str):
    """(recording with the tracker columns, truth) of gen2 campaign ``index`` of ``seed``."""
    out = tmp_path / f"g{seed}_{index}_{'_'.join(args).replace('-', '')}"
    subprocess.run([sys.executable, str(GEN2), "--out", str(out), "--n", "1", "--seed", str(seed), "--start",
                    str(index), *args], check=True, capture_output=True)
    csv = out / f"campaign_{index:04d}.csv"
    return parse_recording(csv.read_text(), csv.name), json.loads(csv.with_suffix(".truth.json").read_text())


def _trackers(rec):
    """The given tracker position(s) of a gen2 recording, as diagnose takes them (None: no tracker columns)."""
    if rec.tracker_xyz is None:
        return None
    st = rec.stations()
    if rec.station is None:
        return rec.tracker_xyz[0]
    return {s: rec.tracker_xyz[np.flatnonzero(st == s)[0]] for s in dict.fromkeys(st.tolist())}


def _found(rec, tracker):
    prep = prepare(rec, "dmu50", tracker=tracker)
    return prep.noise.details["axis_scatter"]


@pytest.mark.slow  # a whole diagnosis: 12-27 s on the shared 2-core machine
@pytest.mark.parametrize("told", [False, True], ids=["defaults", "tracker given"])
def test_a_per_stop_scatter_is_found_sized_and_nothing_named_in_its_place(tmp_path, told):
    """gen2 3502/16 (outside mix): Y scatters 2.44 um per stop (realised 2.60 um), two rounds, one station,
    an AT960-like tracker: found on Y with the truth inside its 95 % interval, nothing else significant, nothing
    unexplained (on e58d8c4: tracker knocks named instead)."""
    logging.getLogger("mtcal").setLevel(logging.ERROR)
    rec, truth = _gen2(tmp_path, 3502, 16, "--mix", "outside", "--clean-fraction", "0.3")
    (e,) = truth["effects"]
    assert e["name"] == "axis_scatter" and e["where"]["axis"] == "Y"
    sigma = e["details"]["sigma_um"] * 1e-3
    d = diagnose(rec, tracker=_trackers(rec) if told else None).to_dict()
    f = d["noise_model"]["axis_scatter"]["found"]
    assert f is not None and f["axis"] == "Y", d["noise_model"]["axis_scatter"]
    assert f["interval_95_mm"][0] < sigma < f["interval_95_mm"][1], f
    assert "at every stop" in f["says"] and f["p_adjusted"] < 0.005
    assert not [x["name"] for x in d["effects"] if x.get("significant")], d["effects"]
    assert not d["unexplained"], d["unexplained"]


def test_two_stations_eight_rounds_sized_on_x(tmp_path):
    """gen2 3502/14: X scatters 4.35 um per stop over 8 rounds at 2 stations (a 1 : 4 tracker, its law rejected by
    the rounds): found on X, 4.35 um inside the interval (on e58d8c4: not tested, and the diagnosis named an
    'unexplained Y by time')."""
    rec, truth = _gen2(tmp_path, 3502, 14, "--mix", "outside", "--clean-fraction", "0.3")
    sigma = truth["effects"][0]["details"]["sigma_um"] * 1e-3
    sc = _found(rec, _trackers(rec))
    assert sc["found"] is not None and sc["found"]["axis"] == "X", sc
    lo, hi = sc["found"]["interval_95_mm"]
    assert lo < sigma < hi and hi < 2 * sigma, sc["found"]
    # compared with the linear axes tested, not with the rotary ones this design does not test
    assert sc["found"]["says"].startswith("X repeats worse than Y and Z: ") and "B, C: rotary" in sc["not_tested"]


CLEAN = [
    (3502, 5, ("--mix", "outside", "--clean-fraction", "0.3"), "at960_like"),   # 2 stations, 8 rounds
    (3502, 16, ("--only", "none"), "at960_like"),                               # the twin of the case above
    (9000, 0, ("--only", "none"), "isotropic"),                                 # 3 stations, 8 rounds
    (9000, 26, ("--only", "none"), "isotropic"),                                # 1 station, 4 rounds
    (9000, 1, ("--only", "none"), "ratio_1_4"),                                 # 1 station, 4 rounds
]


def _quiet(rec, tracker):
    sc = _found(rec, tracker)
    assert sc["found"] is None, sc
    linear = [a for a in ("X", "Y", "Z") if a in set(rec.axis.tolist())]
    assert {t["axis"] for t in sc["tested"]} == set(linear), sc
    assert all(t["p_adjusted"] > 0.005 for t in sc["tested"])


@pytest.mark.parametrize("seed,index,args,law", CLEAN)
def test_clean_campaigns_do_not_fire_it_under_any_law(tmp_path, seed, index, args, law):
    """Nothing planted, the tracker given: no axis found; the linear axes are tested (not skipped), the rotary
    ones said not tested.  3502/5 is the false 'axis_scatter Y' (25 um) of e58d8c4."""
    rec, truth = _gen2(tmp_path, seed, index, *args)
    assert truth["clean"] and truth["tracker"]["noise"]["instrument"] == law
    _quiet(rec, _trackers(rec))


@pytest.mark.slow  # the station estimated from the rounds' scatter: 5-30 s each on the shared machine
@pytest.mark.parametrize("seed,index,args,law", [c for c in CLEAN if c[:2] != (3502, 5) and c[:2] != (9000, 0)])
def test_clean_single_station_campaigns_do_not_fire_it_at_the_defaults(tmp_path, seed, index, args, law):
    """The same single-station campaigns with the tracker columns removed (the noise model then estimated)."""
    rec, _ = _gen2(tmp_path, seed, index, *args)
    _quiet(rec, None)


def test_a_tracker_knock_is_not_read_as_scatter(tmp_path):
    """A knock is a persistent step: it cancels in the differences of the pairs of stops after it and lands in
    one pair only, which the trim drops -- the test stays at its level (gen2 9002/7: a 25.7 um tracker knock
    during X, 7 rounds, AT960-like; with a per-reading projection C^-1 g the beam turning square to X between
    142 and 214 mm read it as a jump there and X was 'found', 8.9 um)."""
    rec, truth = _gen2(tmp_path, 9002, 7, "--only", "tracker_knock")
    assert [e["name"] for e in truth["effects"]] == ["tracker_knock"]
    sc = _found(rec, _trackers(rec))
    assert sc["found"] is None and sc["tested"], sc


@pytest.mark.slow  # two whole diagnoses of three stations: 10-20 s
def test_the_level_bounds_the_whole_diagnosis_not_each_stage(tmp_path):
    """gen2 seed 3530 campaign 33 (clean; three stations given, the 1 : 70 tracker): the per-stop test reads Z at
    p_adj 0.0045.  On 4814652 it tested at a fixed 0.005 whatever the level, beside a selection and a location each
    at the level, and "Z repeats worse than B and C: 0.65 um" was this clean campaign's claim (gen2's clean runs:
    11 of 916 flagged, 3-4 by each stage).  Each stage now tests at level / 3 (mtcal.diagnose.run.STAGES): nothing
    at the default 0.005, Z at 0.015 (each stage at the former 0.005) -- the user's level reaches the scatter test."""
    rec, truth = _gen2(tmp_path, 3530, 33, "--mix", "outside", "--clean-fraction", "0.3")
    assert truth["effects"] == []
    d = diagnose(rec).to_dict()
    assert d["noise_model"]["axis_scatter"]["found"] is None, d["noise_model"]["axis_scatter"]
    assert not [x["name"] for x in d["effects"] if x.get("significant")] and not d["unexplained"]
    (t,) = d["noise_model"]["axis_scatter"]["tested"]
    assert 0.005 / 3 < t["p_adjusted"] < 0.005, t
    loose = diagnose(rec, level=0.015).to_dict()["noise_model"]["axis_scatter"]["found"]
    assert loose is not None and loose["axis"] == "Z", loose


@pytest.mark.slow  # a whole diagnosis: 10-20 s
def test_a_backlash_is_named_beside_stops_landing_off_only_against_their_scatter(tmp_path):
    """gen2 seed 3542 campaign 30 (outside mix, tracker given): X repeats worse, 4.4 um per stop, in two rounds of
    six positions -- too few pairs of stops for the per-stop test (3 degrees of freedom), so the selection locates
    X's stops landing off (rounds 1 and 2).  On 3883bd9 "backlash X" was named beside them (F = 17.5 against the
    tracker's noise): the difference of the two directions' stops, which scatter 4.4 um each.  An effect that moves
    whole stops of a linear axis is tested against the scatter of that axis' stops where they scatter (the
    split-plot F test: the stops' free form beside it is the denominator), and a backlash of 24 random stops is
    not significant there: the stops are located, nothing named beside them.  Since a step of the tracker's frame is
    tested against the stops' scatter along its own direction (selection._split_plot), the stops located first take
    the backlash's fit too: it is not even significant beside them (p_adj 1), where it was significant and then
    rejected against the stops."""
    logging.getLogger("mtcal").setLevel(logging.ERROR)
    rec, truth = _gen2(tmp_path, 3542, 30, "--mix", "outside", "--clean-fraction", "0.3")
    (e,) = truth["effects"]
    assert e["name"] == "axis_scatter" and e["where"]["axis"] == "X"
    d = diagnose(rec, tracker=_trackers(rec)).to_dict()
    assert not [x["name"] for x in d["effects"] if x.get("significant")], d["effects"]
    assert d["unexplained"] and {u["axis"] for u in d["unexplained"]} == {"X"}, d["unexplained"]
    (bl,) = [x for x in d["effects"] if x["name"] == "backlash" and x.get("axis") == "X"]
    assert not bl["significant"] and ("stops" in (bl.get("inadequate") or "")
                                      or bl["evidence"]["p_adjusted"] > 0.005), bl


@pytest.mark.slow  # a whole diagnosis of two stations: 10-20 s
def test_stops_landing_off_early_in_a_round_are_not_a_step_of_the_tracker(tmp_path):
    """gen2 seed 3540 campaign 35 (outside mix, two stations given): X repeats worse, 2.9 um per stop.  The first
    stops of X's first round land off the rest, which a tracker knock of S1 at t0 = 106.1 s fits; the knock's place
    (the rigid step of S1's frame, turning about the tracker) is needed beside it, and on 3883bd9 that step was
    reported, its largest displacement on C (12.7 um, where nothing was planted).  Its 7 stops of X landing off fit
    more (chi^2 348 on 7 columns against 305 on 6), and the rigid step adds nothing beside them (F = 0.37): the
    mismatch is located on X's stops, nowhere else.  The second station's knock in X's second round (t0 = 8236.9 s),
    tested against the stops' scatter along its own direction (F = 9.7, not significant at its multiplicity; it was
    against every rigid motion of the stops pooled, F = 13.7), gives way: its misfit is located on X as well, as
    one that a drift of S2 or that knock fit alike."""
    logging.getLogger("mtcal").setLevel(logging.ERROR)
    rec, truth = _gen2(tmp_path, 3540, 35, "--mix", "outside", "--clean-fraction", "0.3")
    (e,) = truth["effects"]
    assert e["name"] == "axis_scatter" and e["where"]["axis"] == "X"
    d = diagnose(rec).to_dict()  # the stations' tracker columns
    assert not [x["name"] for x in d["effects"] if x.get("significant")], d["effects"]
    assert d["unexplained"] and d["unexplained"][0]["by"] == "round x position", d["unexplained"]
    kinds = {(u["axis"], u["by"]) for u in d["unexplained"]}
    assert kinds <= {("X", "round x position"), ("X", "effects fitting alike")}, d["unexplained"]
