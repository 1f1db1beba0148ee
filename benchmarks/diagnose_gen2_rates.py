"""Rates of ``mtcal diagnose`` on planted and clean campaigns of a generator we do not control (issue 24 item 5):
`python benchmarks/diagnose_gen2_rates.py [--n 200] [--seed 7] [--json]`.

benchmarks/gen2 was written from the physics and the design contract by a helper that had not read mtcal/diagnose
(benchmarks/gen2/README.md).  Its own mix is used: about 40 % clean campaigns, the rest with one or two distinct
classes among nine physical effects and three gross errors of the export.  Each campaign is diagnosed

* at the defaults: the tracker columns removed (single-station campaigns only: several stations need them), and
* with the tracker given: the CSV as written, when it has tracker_x,y,z columns (every several-station campaign
  and 60 % of the single-station ones),

and each run is judged by :func:`judge` against gen2's truth, through the one table :data:`MAPPING` from gen2's
names to mtcal's: right, stated out of reach, missed, or wrong.  The table's rows are gen2's classes (a run with two
classes counts in both rows, with that class's own verdict; wrong when the run is wrong); the totals count runs.
"""
from __future__ import annotations

import argparse
import csv
import importlib.util
import io
import json
import logging
import re
import subprocess
import sys
import tempfile
import time
from collections import Counter
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from mtcal.diagnose import diagnose  # noqa: E402
from mtcal.diagnose.design import base_design, engine_for, family_degrees, whiten  # noqa: E402
from mtcal.diagnose.prepared import LEVEL, STAGES  # noqa: E402
from mtcal.diagnose.run import MAX_DEGREE  # noqa: E402
from mtcal.errors import InputError  # noqa: E402
from mtcal.measurement.recordings import Recording, parse_recording  # noqa: E402
from mtcal.measurement.screen import RIGID_FLOOR_MM  # noqa: E402

TRACKER_COLUMNS = ("tracker_x", "tracker_y", "tracker_z")
VERDICTS = ("right", "out of reach", "missed", "wrong")
SHORT = {"right": "right", "out of reach": "reach", "missed": "missed", "wrong": "wrong"}
HOWS = ("defaults", "given")


# ------------------------------------------------------------------------------------------ gen2 -> mtcal names
@dataclass(frozen=True)
class Mapping:
    """How a gen2 class is recognised in mtcal's answer.  ``names``: mtcal finding kinds that name it (a kind is
    the finding's name, or "offset (tracker knock)" / "offset (re-seated nest)" for the two offsets); ``match``:
    what the finding must share with the truth ("axis", "reading": axis, round and point, "point": the nest,
    "station": the station when there are several, "any"); ``unexplained``: whether an "unexplained" entry on an
    axis where the effect shows names it; ``problem``: whether a data problem at its axis and round finds it."""

    names: tuple[str, ...]
    match: str
    why: str
    unexplained: bool = True
    problem: bool = False


MAPPING: dict[str, Mapping] = {
    "backlash": Mapping(("backlash",), "axis",
                        "gen2 moves the effective position by direction*size/2: a reversal of the positioning "
                        "error, which is mtcal's backlash of that axis (linear or rotary)"),
    "thermal_drift": Mapping(("thermal_drift",), "any",
                             "one side translating with time: mtcal's thermal_drift, of the spindle, the table or "
                             "the tracker (a tracker drift moves every reading alike: the same readings as the "
                             "drifting side while only that side is measured); gen2 writes no temperature, so "
                             "thermal_temperature (always 'not separable' then) is no alternative"),
    "periodic": Mapping(("periodic",), "axis",
                        "an extra angular positioning of B or C with k >= 3 cycles per turn: mtcal's periodic of "
                        "that axis"),
    "scale": Mapping(("scale",), "axis",
                     "a constant extra positioning s*position: mtcal's scale of that axis (without a reference "
                     "model it is part of the fitted E_JJ: 'not separable' is the honest answer)"),
    "growing_scale": Mapping((), "axis",
                             "a scale growing while the axis is measured, no temperature channel: mtcal has no "
                             "name for it (issue 24 item 4: located by position x time), so only 'unexplained' "
                             "on its axis is right"),
    "outlier": Mapping(("outlier",), "reading",
                       "one reading off by 20-100 um: mtcal's outlier at that axis, round and point, or a data "
                       "problem there (a far reading)", problem=True),
    "knocked_nest": Mapping(("nest_knock", "offset (re-seated nest)"), "point",
                            "one nest displaced from t0 on: mtcal's nest_knock of that point; a re-seated nest "
                            "(offset) of the same point is the same step where the campaign shows it in one round "
                            "only (the nest not read again, or the later axes' own rigid motion absorbing it)"),
    "reflector_creep": Mapping(("nest_creep",), "point",
                               "one nest moving at a constant rate: mtcal's nest_creep of that point"),
    "tracker_knock": Mapping(("offset (tracker knock)",), "station",
                             "every reading of one station translated from t0 on: mtcal's offset, variant tracker "
                             "knock (of that station when there are several)"),
    "label_swap": Mapping((), "axis",
                          "a gross error of the export: found when data_problems report a label_swap of the same "
                          "axis, round and two points (as benchmarks/screen_rates.py)",
                          unexplained=False, problem=True),
    "duplicate_row": Mapping((), "axis",
                             "a gross error of the export: found when a data problem names its axis and round",
                             unexplained=False, problem=True),
    "mistyped_reading": Mapping(("outlier",), "reading",
                                "a gross error of the export: found when a data problem names its axis and round, "
                                "or (what it is to the fit: one reading off) an outlier at that reading; below the "
                                f"screen's {RIGID_FLOOR_MM} mm bound only the outlier can find it",
                                unexplained=False, problem=True),
}
# gen2 v3 (benchmarks/gen2/README.md, "v3"): physics outside mtcal's list ("outside_list", judged as one located
# "unexplained" at its place and nothing named beside it) and careless campaigns ("careless", judged as a data
# problem or refusal naming its axis and round, never as physics).  mtcal has no name for any of them.
OUTSIDE = ("table_warming", "spindle_warming", "axis_scatter", "graded_backlash", "thermal_straightness",
           "air_temperature")
SLIPS = ("rotary_radians", "inch_positions", "columns_swapped")  # careless exports: data problems
LOCATED = OUTSIDE + ("tracker_relevel",)  # judged as located (gen2's judge_as "located_unexplained")
for _name in OUTSIDE:
    MAPPING[_name] = Mapping((), "axis", "physics outside mtcal's list: right is an 'unexplained' entry on an axis "
                                         "where it shows, with nothing named beside it and nothing unexplained "
                                         "elsewhere")
# the members of mtcal's grammar of effects (issue 34 item 1, derive/grammar.py) that name five of them: right too,
# at their place (the side that expands, the axis whose lost motion grows or that repeats worse; the air's drift
# scales every station's distances by one law, so any air_index_drift is at its place)
GRAMMAR = {"table_warming": ("side_expansion",), "spindle_warming": ("side_expansion",),
           "graded_backlash": ("backlash_travel",), "axis_scatter": ("axis_scatter",),
           "air_temperature": ("air_index_drift",)}
PLACE = {"table_warming": "side", "spindle_warming": "side", "air_temperature": "any"}  # else the axis
for _name, _names in GRAMMAR.items():
    MAPPING[_name] = Mapping(_names, PLACE.get(_name, "axis"),
                             MAPPING[_name].why + f"; or the grammar's {_names[0]} at its place")
MAPPING["tracker_relevel"] = Mapping(
    ("offset (tracker knock)", "tracker_settling", "tracker_relevel"), "station",
    "the tracker re-levelled under the same station name: a rigid step of that station's frame from t0 (gen2 "
    "calls it careless, judged as located); a tracker knock (of that station) is the translation part of it, so "
    "it or an 'unexplained' entry where it shows is right; a data problem at its round too", problem=True)
for _name in ("rotary_radians", "inch_positions", "columns_swapped"):
    MAPPING[_name] = Mapping((), "axis", "a slip of the export (units, columns): right only as a data problem or "
                                         "a refusal naming its axis (and round), never as physics",
                             unexplained=False, problem=True)
CLASSES = tuple(MAPPING) + ("clean",)


# ------------------------------------------------------------------------------------------ the truth
@dataclass(frozen=True)
class Planted:
    """One planted class of a campaign, from gen2's truth: where it is, and the axes where it shows."""

    cls: str
    axis: str
    axes: tuple[str, ...]
    point: str | None = None
    round: int | None = None
    station: str | None = None
    points: tuple[str, ...] = ()
    side: str | None = None


def _shows_after(rec: Recording, t0: float, on) -> tuple[str, ...]:
    """Axes with readings selected by ``on`` (bool mask) at or after t0 (s)."""
    sel = on & (rec.time_s >= t0)
    return tuple(a for a in dict.fromkeys(rec.axis.tolist()) if (sel & (rec.axis == a)).any())


def planted_v3(e: dict, rec: Recording, stations: int) -> Planted:
    """A gen2 v3 entry (kind "outside_list" or "careless", README "Truth records") as Planted: the axes where it
    shows from its ``where`` (a side: the measured axes of that side; an axis; the tracker: every axis it reaches
    from t0 on, of its station)."""
    w, name, d = e["where"], e["name"], e.get("details", {})
    axes = tuple(dict.fromkeys(rec.axis.tolist()))
    if w["place"] in ("table", "tool"):
        side = ("B", "C") if w["place"] == "table" else ("X", "Y", "Z")
        shows = tuple(a for a in axes if a in side)
    elif w["place"] == "axis":
        shows = (w["axis"],)
    else:
        st = w.get("station")
        on = (np.isin(rec.station, [st] if isinstance(st, str) else st) if rec.station is not None and st
              else np.ones(len(rec), bool))
        shows = _shows_after(rec, float(d.get("t0_s", -np.inf)), on)
    station = w.get("station") if stations > 1 and isinstance(w.get("station"), str) else None
    return Planted(name, w.get("axis") or e["axis"], shows or (e["axis"],), round=w.get("round"), station=station,
                   side=w["place"] if w["place"] in ("table", "tool") else None)


def planted_effect(e: dict, rec: Recording, stations: int) -> Planted:
    """A gen2 effect entry as Planted (time effects: every axis it reaches)."""
    if e.get("kind") in ("outside_list", "careless"):
        return planted_v3(e, rec, stations)
    d, name, ax = e["details"], e["name"], e["axis"]
    if name in ("thermal_drift", "reflector_creep"):
        return Planted(name, ax, tuple(d["axes"]), point=d.get("point"))
    if name == "outlier":
        k = d["row_key"]
        return Planted(name, ax, (ax,), point=k["point"], round=k["round"])
    if name == "knocked_nest":
        return Planted(name, ax, _shows_after(rec, d["t0_s"], rec.point == d["point"]), d["point"], d["round"])
    if name == "tracker_knock":
        on = rec.station == d["station"] if rec.station is not None else np.ones(len(rec), bool)
        return Planted(name, ax, _shows_after(rec, d["t0_s"], on), round=d["round"],
                       station=d["station"] if stations > 1 else None)
    return Planted(name, ax, (ax,))


def planted_gross(g: dict) -> Planted:
    key = g.get("row_key", {})
    return Planted(g["name"], g["axis"], (g["axis"],), point=key.get("point"), round=g.get("round", key.get("round")),
                   points=tuple(g.get("points", ())))


def planted_of(truth: dict, rec: Recording) -> list[Planted]:
    stations = len(truth["tracker"]["stations"])
    return ([planted_effect(e, rec, stations) for e in truth["effects"]] +
            [planted_gross(g) for g in truth["gross_errors"]])


# ------------------------------------------------------------------------------------------ the judge
@dataclass
class Verdict:
    verdict: str                                          # one of VERDICTS
    status: dict[str, str] = field(default_factory=dict)  # planted class -> "found" | "stated" | "missed"
    wrong: list[str] = field(default_factory=list)        # what was claimed wrongly


def _kind(f: dict) -> str:
    """A finding's (or a confounded_with entry's) kind: its name; the two offsets told apart."""
    if f["name"] != "offset":
        return f["name"]
    variant = f.get("variant") or ("tracker knock" if "tracker" in str(f.get("where", "")) else "re-seated nest")
    return f"offset ({variant})"


def _field(f: dict, key: str):
    """A finding's round / point / station: its own key, else read from its "where" (confounded_with entries)."""
    if f.get(key) is not None:
        return f[key]
    m = re.search(rf"\b{key} (\w+)", str(f.get("where", "")))
    return (int(m.group(1)) if key == "round" else m.group(1)) if m else None


def _same(value, truth) -> bool:
    return value is None or truth is None or value == truth


def _at(p: Planted, f: dict) -> bool:
    """Whether finding ``f`` is where ``p`` is (MAPPING's ``match``); a key the finding does not give is no
    contradiction."""
    match = MAPPING[p.cls].match
    if match in ("axis", "reading") and not _same(f.get("axis"), p.axis):
        return False
    if match == "reading":
        return _same(_field(f, "round"), p.round) and _same(_field(f, "point"), p.point)
    if match == "point":
        return _same(_field(f, "point"), p.point)
    if match == "station":
        return _same(_field(f, "station"), p.station)
    if match == "side":
        return _same(f.get("side"), p.side)
    return True


def _names(p: Planted, f: dict) -> bool:
    """``f`` names ``p``: one of its mtcal names, where it is."""
    return _kind(f) in MAPPING[p.cls].names and _at(p, f)


def _accepted(p: Planted, f: dict) -> bool:
    """``f`` names ``p``, or lists it among what it cannot be told apart from (confounded_with): by one of its
    names, or (a class an "unexplained" entry finds) as an unexplained misfit on an axis where it shows."""
    rivals = f.get("confounded_with") or []
    return (_names(p, f) or any(_names(p, c) for c in rivals)
            or MAPPING[p.cls].unexplained and any(c["name"] == "unexplained" and c.get("axis") in p.axes
                                                  for c in rivals))


def _problem_finds(p: Planted, dp: dict) -> bool:
    if not MAPPING[p.cls].problem or dp.get("axis") != p.axis or dp.get("round") != p.round:
        return False
    return p.cls != "label_swap" or (dp.get("kind") == "label_swap" and set(dp.get("points", ())) == set(p.points))


def _problem_explained(p: Planted, dp: dict) -> bool:
    """A data problem that a planted gross error or outlier accounts for (its axis and round)."""
    return MAPPING[p.cls].problem and dp.get("axis") == p.axis and dp.get("round") == p.round


def _scatter_found(answer: dict) -> list[dict]:
    """The axes the noise model found repeating worse than the others (mtcal.diagnose.scatter; noise_model
    .axis_scatter.found), as findings {"name": "axis_scatter", "axis"}."""
    found = ((answer.get("noise_model") or {}).get("axis_scatter") or {}).get("found") or []
    return [{"name": "axis_scatter", "axis": f if isinstance(f, str) else f.get("axis"), "significant": True}
            for f in (found if isinstance(found, list) else [found])]


def _status(p: Planted, answer: dict) -> str:
    sig = [f for f in answer["effects"] if f.get("significant")] + _scatter_found(answer)
    m = MAPPING[p.cls]
    if (any(_accepted(p, f) for f in sig)
            or (m.unexplained and any(u.get("axis") in p.axes for u in answer.get("unexplained", [])))
            or any(_problem_finds(p, dp) for dp in answer.get("data_problems", []))):
        return "found"
    stated = [f for f in answer["effects"] if f.get("not_separable")]
    return "stated" if any(_names(p, f) for f in stated) else "missed"


def _describe(f: dict) -> str:
    return f"{_kind(f)} {f.get('axis') or ''} {str(f.get('where', ''))[:70]}".replace("  ", " ").strip()


def _clean_claims(answer: dict) -> list[str]:
    return ([_describe(f) for f in answer["effects"] + _scatter_found(answer) if f.get("significant")] +
            [f"unexplained {u['axis']} by {u['by']} {u['where']}" for u in answer.get("unexplained", [])] +
            [f"data problem: {dp.get('text', dp.get('kind'))}" for dp in answer.get("data_problems", [])])


def _refused(answer: dict, planted: list[Planted]) -> Verdict:
    named = [p for p in planted if MAPPING[p.cls].problem and f"axis {p.axis}" in answer["refused"]]
    if named and all(p.cls in SLIPS for p in planted):  # a slip refused, naming its axis: the right answer
        return Verdict("right", {p.cls: "found" for p in planted})
    if named:
        return Verdict("out of reach", {p.cls: "stated" if p in named else "missed" for p in planted})
    return Verdict("wrong", {p.cls: "missed" for p in planted}, [f"refused: {answer['refused'][:120]}"])


def judge(answer: dict, planted: list[Planted]) -> Verdict:
    """The verdict on one diagnosis (``answer``: ``Diagnosis.to_dict()``, or ``{"refused": message}`` when the
    recording was refused) against what gen2 planted.

    * Clean (nothing planted): right when the answer claims nothing -- no significant finding, nothing
      unexplained, no data problem; anything claimed is a false alarm (wrong).
    * A planted class is *found* when a significant finding names it (one of its MAPPING names, at its place:
      axis, reading, nest or station as MAPPING says), or a significant finding lists such a name in its
      ``confounded_with``, or an ``unexplained`` entry lies on an axis where it shows (not for gross errors; also
      as a ``confounded_with`` entry of a significant finding), or a
      data problem at its axis and round reports it (gross errors, outliers; a label swap: the same two points).
      It is *stated* out of reach when a ``not_separable`` entry carries one of its names (on its axis), else
      *missed*.
    * Wrong claims: a significant finding naming nothing planted (neither itself nor through confounded_with), or
      a data problem at no planted gross error's or outlier's axis and round.  A refusal is stated out of reach
      when it names a planted gross error's axis, else wrong.
    * The run: wrong if anything is claimed wrongly, else missed if any class is missed, else out of reach if any
      is stated, else right.
    """
    if "refused" in answer:
        return _refused(answer, planted)
    if not planted:
        claims = _clean_claims(answer)
        return Verdict("wrong" if claims else "right", {}, claims)
    status = {p.cls: _status(p, answer) for p in planted}
    wrong = [_describe(f) for f in answer["effects"] + _scatter_found(answer)
             if f.get("significant") and not any(_accepted(p, f) for p in planted)]
    wrong += [f"data problem: {dp.get('text', dp.get('kind'))}" for dp in answer.get("data_problems", [])
              if not any(_problem_explained(p, dp) for p in planted)]
    if any(p.cls in LOCATED for p in planted):  # one located entry: nothing unexplained where nothing shows
        shows = {a for p in planted if MAPPING[p.cls].unexplained for a in p.axes}
        wrong += [f"unexplained {u['axis']} by {u['by']} (nothing planted shows there)"
                  for u in answer.get("unexplained", []) if u.get("axis") not in shows]
    states = set(status.values())
    verdict = ("wrong" if wrong else "missed" if "missed" in states else
               "out of reach" if "stated" in states else "right")
    return Verdict(verdict, status, wrong)


# ------------------------------------------------------------------------------------------ running
def without_tracker(text: str) -> str:
    rows = list(csv.reader(io.StringIO(text)))
    keep = [i for i, h in enumerate(rows[0]) if h not in TRACKER_COLUMNS]
    return "\n".join(",".join(r[i] for i in keep) for r in rows) + "\n"


def cases(text: str) -> list[tuple[str, str]]:
    """(how, CSV text): the defaults (single station) and the tracker given (when the CSV has its columns)."""
    header = text.splitlines()[0].split(",")
    out = [] if "station" in header else [("defaults", without_tracker(text))]
    return out + ([("given", text)] if "tracker_x" in header else [])


def diagnosis_of(text: str, name: str) -> tuple[dict, object]:
    """(answer, Diagnosis): mtcal's answer as a dict, and the Diagnosis itself (None where it refused)."""
    try:
        d = diagnose(parse_recording(text, name))
    except InputError as exc:
        return {"refused": str(exc)}, None
    return d.to_dict(), d


def answer_of(text: str, name: str) -> dict:
    return diagnosis_of(text, name)[0]


RANDOM = {"axis_scatter"}  # variance components: the planted displacement is the draws themselves, which no test
#                            knows; a test of it as a known shape would claim far more reach than the data give


def _clean_fraction(mix: str) -> float:
    """gen2's --clean-fraction as :func:`generate` passes it: 0.3 in the outside mix, else gen2's default 0.4."""
    return 0.3 if mix == "outside" else 0.4


def _gen2_module(gen2: Path):
    """The generator ``gen2`` imported as a module (its planted_displacement), None if it has none."""
    spec = importlib.util.spec_from_file_location("gen2_generator", gen2)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod if hasattr(mod, "planted_displacement") else None


def planted_reach(diagnosis, truth: dict, gen2) -> float | None:
    """p of the planted physics' own F test: gen2's noise-free displacement of every reading by what was planted
    (``planted_displacement``), whitened by the diagnosis' weights and added as one known column to the tests' null
    (the quasi-static family at its largest degrees, mtcal.diagnose.run) -- the most any test of that shape can see.
    Above the diagnosis' stage level (LEVEL / STAGES) the data cannot show it beside the base even knowing its
    shape: a miss there is beyond the data, below it within reach.  None: no diagnosis, no generator function, or
    a reading not matched to gen2's rows (by axis, round, nest and time), or a random effect planted (RANDOM)."""
    if diagnosis is None or gen2 is None or diagnosis.prep is None or RANDOM & {e["name"] for e in truth["effects"]}:
        return None
    mix = truth.get("mix", "v2")
    only = mix[len("only:"):].split(",") if mix.startswith("only:") else None  # then any v3 mix draws the same
    keys, delta = gen2.planted_displacement(truth["seed"], truth["index"], _clean_fraction(mix),
                                            "outside" if only else mix, only)
    row = {(k["axis"], int(k["round"]), k["point"], float(k["time_s"])): i for i, k in enumerate(keys)}
    prep = diagnosis.prep
    rec = prep.rec
    at = [row.get((a, int(r), pt, float(t))) for a, r, pt, t in zip(rec.axis, rec.round, rec.point, rec.time_s)]
    if any(i is None for i in at):
        return None
    eng = engine_for(prep, base_design(prep, family_degrees(prep, MAX_DEGREE)), whiten(prep.W, prep.y))
    s = eng.score(whiten(prep.W, delta[at])[:, None])
    return float(np.exp(s.logp)) if s.separable and s.k else 1.0


GEN2 = HERE / "gen2" / "gen2.py"


def generate(directory: str, n: int, seed: int, start: int = 0, mix: str = "v2", gen2: Path = GEN2,
             only: str | None = None) -> list[Path]:
    """gen2's campaigns ``start`` .. ``start + n - 1`` of ``seed`` in ``mix`` (v2: the original classes; v3 and
    outside: with the physics outside mtcal's list and the careless campaigns) into ``directory``; ``only``: gen2's
    --only (class names planted in every campaign, or "none" for clean ones)."""
    subprocess.run([sys.executable, str(gen2), "--out", directory, "--n", str(n), "--seed",
                    str(seed), "--start", str(start)] + (["--mix", mix] if mix != "v2" else []) +
                   ["--clean-fraction", str(_clean_fraction(mix))] + (["--only", only] if only else []),
                   check=True, capture_output=True)
    return sorted(Path(directory).glob("campaign_*.csv"))


def _missed_outside(verdict: str, status: dict[str, str]) -> bool:
    """A run not wrong in which a class outside mtcal's list was missed (the runs :func:`planted_reach` judges)."""
    return verdict != "wrong" and any(status.get(c) == "missed" for c in OUTSIDE)


def run_campaign(path: Path, gen2=None) -> list[dict]:
    """Every run of one campaign: {campaign, how, classes, stations, instrument, verdict, status, wrong, claims
    (everything the answer claims: significant findings, unexplained, data problems), seconds, reach_p (where a
    class outside mtcal's list was missed: :func:`planted_reach` with ``gen2``, the generator as a module)}."""
    truth = json.loads(path.with_suffix(".truth.json").read_text())
    text = path.read_text()
    planted = planted_of(truth, parse_recording(text, path.name))
    tracker, out = truth["tracker"], []
    for how, t in cases(text):
        t0 = time.perf_counter()
        answer, diagnosis = diagnosis_of(t, path.name)
        v = judge(answer, planted)
        missed = _missed_outside(v.verdict, v.status)
        out.append({"campaign": path.stem, "how": how, "classes": [p.cls for p in planted] or ["clean"],
                    "stations": len(tracker["stations"]), "instrument": tracker["noise"]["instrument"],
                    **asdict(v), "claims": [] if "refused" in answer else _clean_claims(answer),
                    "seconds": round(time.perf_counter() - t0, 2),
                    "reach_p": planted_reach(diagnosis, truth, gen2) if missed else None})
    return out


def run(n: int = 200, seed: int = 7, start: int = 0, progress: bool = True, mix: str = "v2",
        gen2: Path = GEN2, only: str | None = None) -> list[dict]:
    logging.getLogger("mtcal").setLevel(logging.ERROR)  # data problems are in the answers
    runs: list[dict] = []
    module = _gen2_module(gen2) if mix != "v2" or only else None
    with tempfile.TemporaryDirectory() as d:
        for path in generate(d, n, seed, start, mix, gen2, only):
            for r in run_campaign(path, module):
                runs.append(r)
                if progress:
                    print(f"{r['campaign']} {r['how']:<8} {'+'.join(r['classes']):<32} {r['verdict']:<12} "
                          f"{r['seconds']:5.1f} s {'; '.join(r['wrong'])[:100]}"
                          + (f"planted shape's own p {r['reach_p']:.2g}" if r.get("reach_p") is not None else ""),
                          file=sys.stderr, flush=True)
    return runs


# ------------------------------------------------------------------------------------------ the table
def row_verdict(r: dict, cls: str) -> str:
    """The verdict of run ``r`` for one of its classes: wrong when the run is; else that class's own status."""
    if r["verdict"] == "wrong" or cls == "clean":
        return r["verdict"]
    return {"found": "right", "stated": "out of reach", "missed": "missed"}[r["status"][cls]]


def tally(runs: list[dict]) -> dict:
    """{row: {how: Counter(verdict)}} for every class and the totals (planted runs, clean runs, all runs)."""
    t: dict = {c: {h: Counter() for h in HOWS} for c in CLASSES + ("all planted", "all")}
    for r in runs:
        for cls in r["classes"]:
            t[cls][r["how"]][row_verdict(r, cls)] += 1
        if r["classes"] != ["clean"]:
            t["all planted"][r["how"]][r["verdict"]] += 1
        t["all"][r["how"]][r["verdict"]] += 1
    return t


def _cells(c: Counter, pct: bool) -> str:
    total = sum(c.values())
    if not pct:
        return " ".join(f"{c[v]:>6}" for v in VERDICTS) + f" {total:>5}"
    return " ".join(f"{100 * c[v] / max(total, 1):>5.1f}%" for v in VERDICTS) + f" {total:>5}"


def table(runs: list[dict]) -> str:
    t = tally(runs)
    rows = CLASSES + ("all planted", "all")
    w = max(18, max(len(r) for r in rows) + 5)  # the v3 classes' names are longer than the v2 ones
    head = " ".join(f"{SHORT[v]:>6}" for v in VERDICTS) + "  runs"
    lines = [f"{'':<{w}}| {'defaults (tracker columns removed)':<35}| tracker given",
             f"{'planted class':<{w}}| {head} | {head}"]
    for row in rows:
        if row in ("all planted",):
            lines.append("-" * len(lines[1]))
        lines.append(f"{row:<{w}}| " + " | ".join(_cells(t[row][h], False) for h in HOWS))
    for row in ("clean", "all planted", "all"):
        lines.append(f"{row + ' (%)':<{w}}| " + " | ".join(_cells(t[row][h], True) for h in HOWS))
    return "\n".join(lines)


def named(r: dict) -> bool:
    return any(not w.startswith("unexplained") for w in r["wrong"])


def wrong(r: dict) -> bool:
    return r["verdict"] == "wrong"


def _share(runs: list[dict], how: str, hit) -> str:
    on = [r for r in runs if r["how"] == how]
    return f"{sum(map(hit, on))} of {len(on)}"


def breakdown(runs: list[dict]) -> list[str]:
    """Two looks behind the totals: clean false alarms by benchmarks/diagnose_gen2.py's rule (significant findings
    and data problems only, no "unexplained"), and wrong runs by the number of stations."""
    clean = [r for r in runs if r["classes"] == ["clean"]]
    one, several = ([r for r in runs if (r["stations"] > 1) == k] for k in (False, True))
    return [*_reach(runs), f"clean false alarms by a named finding or data problem (not unexplained only): defaults "
            f"{_share(clean, 'defaults', named)}, tracker given {_share(clean, 'given', named)}",
            f"wrong runs, one station: defaults {_share(one, 'defaults', wrong)}, tracker given "
            f"{_share(one, 'given', wrong)}; two or three stations (tracker given): {_share(several, 'given', wrong)}"]


def _reach(runs: list[dict]) -> list[str]:
    """The missed runs of physics outside mtcal's list split by :func:`planted_reach`: within the data's reach (the
    planted displacement's own test below the stage level) or beyond it."""
    level = LEVEL / STAGES
    out = []
    for how in HOWS:
        ps = [r["reach_p"] for r in runs if r["how"] == how and "reach_p" in r
              and _missed_outside(r["verdict"], r["status"])]
        if ps:
            known = [p for p in ps if p is not None]
            out.append(f"missed runs of physics outside the list, {how}: {len(ps)}; within the data's reach (the "
                       f"planted displacement's own F test, its shape known, p < {level:.2g} beside the tests' null) "
                       f"{sum(p < level for p in known)}, beyond it {sum(p >= level for p in known)}"
                       + (f", not judged {len(ps) - len(known)}" if len(known) < len(ps) else ""))
    return out


def wrong_runs(runs: list[dict]) -> list[str]:
    return [f"{r['campaign']} {r['how']:<8} {r['stations']} st. {r['instrument']:<10} planted "
            f"{'+'.join(r['classes'])}: {'; '.join(r['wrong'])}" for r in runs if r["verdict"] == "wrong"]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--start", type=int, default=0, help="first campaign index (gen2 --start)")
    ap.add_argument("--mix", default="v2", choices=("v2", "v3", "outside"), help="gen2's mix (README)")
    ap.add_argument("--gen2", type=Path, default=GEN2, help="the generator (gen2.py with the v3 mixes)")
    ap.add_argument("--only", help="gen2's --only: class names planted in every campaign, or 'none' (clean)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    t0 = time.perf_counter()
    runs = run(args.n, args.seed, args.start, progress=not args.json, mix=args.mix, gen2=args.gen2, only=args.only)
    seconds = time.perf_counter() - t0
    if args.json:
        print(json.dumps({"n": args.n, "seed": args.seed, "start": args.start, "seconds": round(seconds, 1),
                          "table": {k: {h: dict(c) for h, c in v.items()} for k, v in tally(runs).items()},
                          "runs": runs}))
        return 0
    print(f"gen2 seed {args.seed}, campaigns {args.start}..{args.start + args.n - 1}: {len(runs)} diagnoses in "
          f"{seconds:.0f} s (rows: a run counts under each planted class with that class's verdict, wrong if the "
          f"run is; totals count runs)")
    print(table(runs))
    print("\n".join(breakdown(runs)))
    print("wrong runs:")
    for line in wrong_runs(runs):
        print("  " + line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
