"""Gross errors of a recording, found before anything is fitted: data problems, not machine errors.

The reflectors (points) of one axis sit on one rigid side of the machine, so within every pass (axis, station,
round, position, direction) their mutual distances are the same up to the tracker's noise, whatever the machine's
errors, drifts and knocks of the tracker do (those move the side rigidly).  A reading that breaks that rigidity by
far more than the noise is a data problem:

* two labels swapped (exchanging them makes the pass rigid again): "P and Q swapped in Y round 3?";
* one reading far from its nest (misread, mistyped, a reflector from another nest, the tracker locked onto another
  target): "reading of P far from its nest";
* a whole pass far from the same pass of the other rounds (a wrong position or axis label), or readings far from
  where the other rounds read the same reflector (with two rounds only, which round is wrong cannot be told:
  both are left out, unless the other axes of the side or the other stations say which); a station's only round
  far from where the other stations' rounds, agreeing, read the same pass;
* a row repeated exactly (a duplicated export line);
* a clock that is not what it claims (_clock): within one axis' round of one station, written in time order, the
  time goes back from one row to the next, or jumps forward by more than max(JUMP_FLOOR_S, JUMP_FACTOR x the
  round's median step) between two rows; or two rounds of one station overlap in time (one station reads one
  axis' round at a time); or a round's readings lying more than SLOW_STEP_S apart at the median (a column in
  milliseconds called seconds: one problem where every round is so).  The readings stand; the time column does
  not (``Screen.untimed``): what reads the clock -- a drift, a knock at a time, a creep -- is not tested, and
  that is said;
* a round whose direction column has the other sign (_directions): each reading's label against the sign of the
  axis' motion to it from the previous reading of its reflector; a round that says the opposite of the axis'
  other rounds at DIRECTION_AGREE of its readings or more is left out (one export's convention);
* coordinates written too coarsely (_resolution): every x, y and z a multiple of a step of RESOLUTION_MM or more
  (an export set to 2 decimals of a mm): the rounding's error, step / sqrt(12), is above a tracker's noise along
  its beam.  The readings stand (nothing is left out); the noise law, read from their scatter over the rounds,
  holds the rounding only as far as it differs from round to round: mismatches located beside it may be its.

Each is reported naming axis, round, position, points and lines, and the pass is left out with a note (a pass
is the unit every estimator uses).  When the left-out pass held a round's reference reading, that round of that
axis is left out.  When nothing of an axis is left the screen refuses the recording (InputError) rather than
fitting what is left.

Thresholds (mm) are far above any machine error a tracker campaign measures (tens of µm): a pair distance may
differ from its median over the passes by max(RIGID_K x its robust scale, RIGID_FLOOR_MM); a pass may lie
PASS_FLOOR_MM from the median of the same pass in the other rounds.  Smaller inconsistencies (a knocked nest, an
outlier of tens of µm) are left to the diagnosis, which models them.
"""
from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from mtcal.errors import InputError
from mtcal.measurement.passes import group_passes, position_key, reference_position
from mtcal.measurement.recordings import Recording

RIGID_K = 10.0         # robust standard deviations of a pair distance
RIGID_FLOOR_MM = 0.15  # never flag a distance change below this (machine errors and knocked nests are smaller)
PASS_FLOOR_MM = 2.0    # a pass this far from the same pass of the other rounds has a wrong label
SAME_MM = 1e-6         # readings equal to this are one reading repeated
JUMP_FLOOR_S = 3600.0  # a forward step of the clock within one axis' round longer than this ...
JUMP_FACTOR = 100.0    # ... and than this many times the round's median step is a jump of the clock
DIRECTION_AGREE = 0.9  # a round whose labels say the opposite of the other rounds' at this share of its readings
RESOLUTION_MM = 0.005  # coordinates all multiples of this step or a coarser one (mm) are rounded beyond the
# tracker: step / sqrt(12) >= 1.4 um, above the AT960's noise along its beam in a machine's work zone (its MPE
# 0.4 um + 0.3 um/m at k = 2: 0.5 um at 2 m)
RESOLUTION_STEPS_MM = (1.0, 0.5, 0.1, 0.05, 0.01, 0.005)  # the steps an export's number format gives, coarsest first
RESOLUTION_MIN = 20  # coordinates needed before their common step is read (by chance, 4-decimal data: 1 in 50 ** 20)
SLOW_STEP_S = 600.0    # a round whose readings lie further apart than this at the median is not timed in seconds
# (a tracker reads a nest in seconds; the machine moves between positions in seconds to a minute)


@dataclass
class DataProblem:
    """One gross error: ``kind`` one of "label_swap", "far_reading", "pass_far", "rounds_disagree",
    "round_off_side" (of two rounds that disagree, the one the other axes of its side do not agree with),
    "round_off_station" (of one station's two rounds that disagree, the one the other stations do not agree with;
    or a station's only round, where the other stations' rounds agree and it does not),
    "duplicate_row", "clock" (the time column going back, jumping or overlapping within a station: _clock),
    "direction" (_directions), "resolution" (every coordinate rounded to a coarse step: _resolution)."""

    kind: str
    axis: str
    round: int
    position: float
    points: tuple[str, ...]
    lines: tuple[int, ...]
    size_mm: float
    text: str
    why: str = ""  # what a round's passes are judged by, said once for the round (_merge)

    def to_dict(self) -> dict:
        return {"kind": self.kind, "axis": self.axis, "round": self.round, "position": self.position,
                "points": list(self.points), "lines": list(self.lines), "size_mm": round(self.size_mm, 6),
                "text": self.text}


@dataclass
class Screen:
    """The screen's answer: the problems found, the rows kept (bool per row) and notes on rounds left out because
    their reference readings were."""

    problems: list[DataProblem] = field(default_factory=list)
    keep: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))
    notes: list[str] = field(default_factory=list)
    untimed: bool = False  # the time column is not what it claims (a "clock" problem): not to be used


def screen(rec: Recording, sides: Mapping[str, str] | None = None, machine=None) -> Screen:
    """Find gross errors in ``rec`` (see module docstring); the recording itself is not changed: apply
    ``rec.select(result.keep)``.  ``sides``: axis -> the side its reflectors sit on (the machine's, e.g. "tool",
    "table"): the axes of one side judge each other's reflector distances (_pooled_medians); None: each axis
    alone.  ``machine`` (a mtcal.Machine): a far reading's distance from its own nest is stated (_nest_distance);
    None: how far its distances to the other reflectors are off."""
    out = Screen(keep=np.ones(len(rec), bool))
    _duplicates(rec, out)
    _clock(rec, out)
    _directions(rec, out)
    _resolution(rec, out)
    by_axis = {}
    for axis in rec.axes():
        rows = np.flatnonzero((rec.axis == axis) & out.keep)
        by_axis[axis] = group_passes(rec, rows, rec.direction[rows], axis, by_station=True, repeats="first")
    dist = {a: _pair_distances(rec, p) for a, p in by_axis.items()}
    group = {a: (sides or {}).get(a, f"axis {a}") for a in by_axis}
    medians = {g: _pooled_medians([d for a, d in dist.items() if group[a] == g]) for g in set(group.values())}
    for axis, passes in by_axis.items():
        rigid = _rigidity(rec, axis, passes, dist[axis], medians[group[axis]], out, machine)
        nests = _side_nests(rec, axis, by_axis, group, machine)
        bad = rigid | _cross_round(rec, axis, passes, rigid, out, nests, machine)
        for key in bad:
            out.keep[list(passes[key].values())] = False
        _reference_rounds(rec, axis, out)
    out.problems = _merge(out.problems)
    return out


def _merge(problems: list[DataProblem]) -> list[DataProblem]:
    """One problem per (kind, axis, round, points) over its passes: a swap in every pass of a round is one slip."""
    groups: dict[tuple, list[DataProblem]] = {}
    for p in problems:
        groups.setdefault((p.kind, p.axis, p.round, p.points), []).append(p)
    out = []
    for (kind, axis, rnd, pts), ps in groups.items():
        if len(ps) == 1:
            out.append(ps[0])
            continue
        lines = tuple(sorted({ln for p in ps for ln in p.lines}))
        size = max(p.size_mm for p in ps)
        at = sorted({p.position for p in ps})
        what = (f"{' and '.join(pts)} swapped in {axis} round {rnd}?" if kind == "label_swap" else
                f"readings of {' or '.join(pts)} far from their nest in {axis} round {rnd}" if kind == "far_reading"
                else f"{axis} round {rnd}: passes far from the other rounds'" if kind == "pass_far"
                else f"{axis} round {rnd} disagrees with the other round" if kind == "rounds_disagree"
                else f"{axis} round {rnd}: its nests lie far from where the other axes of its side read them (the "
                     f"axis' other round agrees with them)" if kind == "round_off_side"
                else f"{axis} round {rnd}: its readings lie far from where the other station(s) read the same "
                     f"passes ({ps[0].why})" if kind == "round_off_station"
                else f"duplicated rows of {axis} round {rnd}")
        out.append(DataProblem(kind, axis, rnd, at[0], pts, lines, size,
                               f"{what} ({len(ps)} passes, at {at[0]:g} .. {at[-1]:g}; lines {lines[0]}-{lines[-1]}; "
                               f"up to {size:.3g} mm): left out"))
    return out


def _duplicates(rec: Recording, out: Screen) -> None:
    """Rows repeating an earlier row exactly (same labels, time and reading): the later one is left out.  A reading
    repeated at another time is a second measurement, which the estimators refuse to average silently."""
    seen: dict[tuple, int] = {}
    keys = zip(rec.stations().tolist(), rec.axis.tolist(), rec.round.tolist(), position_key(rec.position).tolist(),
               rec.point.tolist(), rec.direction.tolist())
    for i, key in enumerate(keys):  # the columns read once: this runs before every identification and diagnosis
        j = seen.setdefault(key, i)
        same_time = rec.time_s[i] == rec.time_s[j] or (np.isnan(rec.time_s[i]) and np.isnan(rec.time_s[j]))
        if j != i and same_time and np.abs(rec.xyz[i] - rec.xyz[j]).max() <= SAME_MM:
            out.keep[i] = False
            out.problems.append(DataProblem(
                "duplicate_row", key[1], key[2], key[3], (key[4],), (int(rec.line[j]), int(rec.line[i])), 0.0,
                f"line {int(rec.line[i])} repeats line {int(rec.line[j])} ({key[1]} round {key[2]} at {key[3]:g}, "
                f"point {key[4]}): a duplicated row, left out"))


def _clock(rec: Recording, out: Screen) -> None:
    """The clock's problems (module docstring): one per axis' round of a station, at its first bad line; where
    there is one, ``out.untimed``."""
    t = rec.time_s
    blocks: dict[tuple, list[int]] = {}
    for i, key in enumerate(zip(rec.stations().tolist(), rec.axis.tolist(), rec.round.tolist())):
        if np.isfinite(t[i]) and out.keep[i]:
            blocks.setdefault(key, []).append(i)
    flagged = set()
    for key, rows in blocks.items():
        why = _clock_in_round(rec, rows)
        if why:
            flagged.add(key)
            _clock_problem(rec, out, key, *why)
    flagged |= _slow_rounds(rec, out, {k: r for k, r in blocks.items() if k not in flagged})
    spans = sorted((t[r].min(), t[r].max(), k, r) for k, r in blocks.items() if k not in flagged)
    end: dict[str, tuple] = {}  # station -> (latest end so far, its round's key)
    for lo, hi, key, rows in spans:
        last = end.get(key[0])
        if last is not None and lo < last[0]:
            first = rows[int(np.argmin(t[rows]))]
            _clock_problem(rec, out, key, first, f"its times ({lo:.6g} .. {hi:.6g} s) overlap those of axis "
                           f"{last[1][1]} round {last[1][2]} (to {last[0]:.6g} s), and one station reads one axis' "
                           "round at a time")
            continue
        if last is None or hi > last[0]:
            end[key[0]] = (hi, key)
    out.untimed = bool(flagged) or any(p.kind == "clock" for p in out.problems)


def _clock_in_round(rec: Recording, rows: list[int]) -> tuple[int, str] | None:
    """(the row, the words) where the clock goes back or jumps within one axis' round (``rows`` in file order),
    else None."""
    t = rec.time_s[rows]
    step = np.diff(t)
    back = np.flatnonzero(step < 0)
    if len(back):
        j = int(back[0])
        return rows[j + 1], (f"the time goes back from {t[j]:.6g} s (line {int(rec.line[rows[j]])}) to "
                             f"{t[j + 1]:.6g} s")
    pos = step[step > 0]
    limit = max(JUMP_FLOOR_S, JUMP_FACTOR * float(np.median(pos))) if len(pos) else np.inf
    jump = np.flatnonzero(step > limit)
    if len(jump):
        j = int(jump[0])
        return rows[j + 1], (f"the clock jumps by {step[j]:.6g} s from line {int(rec.line[rows[j]])} (more than "
                             f"{limit:.6g} s: {JUMP_FACTOR:g} times the round's median step, at least "
                             f"{JUMP_FLOOR_S:g} s)")
    return None


def _directions(rec: Recording, out: Screen) -> None:
    """Rounds whose direction column has the other sign (module docstring): a "direction" problem at the round's
    first line, its readings left out.  An axis' convention is the majority's over its rounds, mtcal's (the label
    is the sign of the motion) where they split evenly: an axis or a file in the other convention throughout is
    that convention, not a slip; readings with no motion since the last of their reflector, or no label, are not
    counted."""
    if not np.any(rec.direction):
        return
    order = np.where(np.isfinite(rec.time_s), rec.time_s, np.inf)
    keys = list(zip(rec.stations().tolist(), rec.axis.tolist(), rec.round.tolist()))
    blocks: dict[tuple, list[int]] = {}
    for i in np.lexsort((rec.line, order)):
        if out.keep[i]:
            blocks.setdefault(keys[i], []).append(int(i))
    tally = {k: _motion_agreement(rec, rows) for k, rows in blocks.items()}
    for key, (a, n) in tally.items():
        same = [v for k, v in tally.items() if k[1] == key[1]]
        sign = 1 if 2 * sum(x for x, _ in same) >= sum(m for _, m in same) else -1
        off = n - a if sign > 0 else a
        if n >= 3 and off >= DIRECTION_AGREE * n:
            rows = blocks[key]
            first = min(rows, key=lambda i: rec.line[i])
            out.keep[rows] = False
            station, axis, rnd = key
            of = f" of station {station}" if station else ""
            out.problems.append(DataProblem(
                "direction", axis, rnd, float(rec.position[first]), tuple(sorted(set(map(str, rec.point[rows])))),
                (int(rec.line[first]),), 0.0,
                f"line {int(rec.line[first])}: the direction column of axis {axis} round {rnd}{of} says the "
                f"opposite of the axis' motion at {off} of {n} readings, where the other rounds agree with it: "
                "written with the other sign (another export's convention); the round is left out"))


def _resolution(rec: Recording, out: Screen) -> None:
    """A "resolution" problem where every finite coordinate (x, y, z, mm) of the readings kept is a multiple of one
    of RESOLUTION_STEPS_MM (the coarsest such step named); nothing is left out.  Fewer than RESOLUTION_MIN
    coordinates are not read."""
    xyz = rec.xyz[out.keep]
    v = xyz[np.isfinite(xyz)]
    if v.size < RESOLUTION_MIN:
        return
    step = next((q for q in RESOLUTION_STEPS_MM if np.all(np.abs(v / q - np.round(v / q)) < 1e-6)), None)
    if step is None or step < RESOLUTION_MM:
        return
    first = int(np.flatnonzero(out.keep)[np.argmin(rec.line[out.keep])])
    sigma = step / np.sqrt(12.0)
    out.problems.append(DataProblem(
        "resolution", str(rec.axis[first]), int(rec.round[first]), float(rec.position[first]), (),
        (int(rec.line[first]),), float(sigma),
        f"line {int(rec.line[first])} on: every coordinate (x, y, z) is a multiple of {step:g} mm: the export "
        f"rounds to {step:g} mm, an error of {1e3 * sigma:.1f} um (1 sigma) per coordinate, more than the tracker's "
        "noise along its beam; the readings are kept, but the noise law read from their rounds holds the rounding "
        "only where it differs between rounds, so mismatches located beside this may be the rounding's -- "
        "export at least 3 decimals (0.001 mm)"))


def _motion_agreement(rec: Recording, rows: list[int]) -> tuple[int, int]:
    """(readings whose direction label is the sign of the axis' motion to them from the previous reading of their
    reflector, readings with motion and a label) among ``rows`` in time order."""
    last: dict[str, float] = {}
    agree = n = 0
    for i in rows:
        p, q = str(rec.point[i]), float(rec.position[i])
        if p in last and q != last[p] and rec.direction[i] != 0:
            n += 1
            agree += int(np.sign(q - last[p]) == rec.direction[i])
        last[p] = q
    return agree, n


def _slow_rounds(rec: Recording, out: Screen, blocks: dict[tuple, list[int]]) -> set[tuple]:
    """The rounds (``blocks``: key -> rows in file order) whose readings lie more than SLOW_STEP_S apart at the
    median, each a clock problem at its second reading -- one, for the first round in the file, where every round
    with two readings is so (the whole column in another unit).  Returns their keys."""
    med = {k: float(np.median(np.diff(rec.time_s[r]))) for k, r in blocks.items() if len(r) > 1}
    slow = [k for k, m in med.items() if m > SLOW_STEP_S]
    if not slow:
        return set()
    every = len(slow) == len(med)
    for key in sorted(slow, key=lambda k: blocks[k][0])[:1 if every else None]:
        _clock_problem(rec, out, key, blocks[key][1], (
            f"{'the readings of every round' if every else 'its readings'} lie {med[key]:.6g} s apart at the "
            f"median (more than {SLOW_STEP_S:g} s, where a tracker reads a nest in seconds): a time column in "
            "milliseconds or another unit is not one in seconds"))
    return set(slow)


def _clock_problem(rec: Recording, out: Screen, key: tuple, row: int, why: str) -> None:
    """A "clock" problem of the axis' round ``key`` (station, axis, round) at ``row``."""
    station, axis, rnd = key
    of = f" of station {station}" if station else ""
    line = int(rec.line[row])
    out.problems.append(DataProblem(
        "clock", axis, int(rnd), float(rec.position[row]), (str(rec.point[row]),), (line,), 0.0,
        f"line {line}: the time column is not what it claims in axis {axis} round {rnd}{of}: {why}; the readings "
        "are kept, the time column is not used (nothing that reads the clock -- a drift, a knock, a creep -- is "
        "tested)"))


def _pair_distances(rec: Recording, passes: dict) -> dict[tuple[str, str], dict[tuple, float]]:
    out: dict[tuple[str, str], dict[tuple, float]] = {}
    for key, g in passes.items():
        for a, b in itertools.combinations(sorted(g), 2):
            out.setdefault((a, b), {})[key] = float(np.linalg.norm(rec.xyz[g[a]] - rec.xyz[g[b]]))
    return out


def _pooled_medians(axes_dist: list[dict]) -> dict[tuple[str, str], float]:
    """The median distance (mm) of every pair of reflectors over the passes of the axes of one side that read both
    (``axes_dist``: each axis' _pair_distances): a label names one nest throughout a file, and the side is rigid,
    so one axis with two rounds (half its passes wrong when one round has two labels swapped) is judged by the
    other axes' passes too."""
    pooled: dict[tuple[str, str], list[float]] = {}
    for dist in axes_dist:
        for ab, v in dist.items():
            pooled.setdefault(ab, []).extend(v.values())
    return {ab: float(np.median(v)) for ab, v in pooled.items() if len(v) >= 3}


def _rigidity(rec: Recording, axis: str, passes: dict, dist: dict, median: dict, out: Screen,
              machine=None) -> set[tuple]:
    """Passes whose reflectors are not where the passes of every axis of the side (``median``: _pooled_medians)
    put them relative to each other; ``dist``: the axis' own _pair_distances."""
    dev = np.array([d - median[ab] for ab, v in dist.items() if ab in median for d in v.values()])
    if not len(dev):
        return set()
    scale = 1.4826 * float(np.median(np.abs(dev - np.median(dev))))
    limit = max(RIGID_K * scale, RIGID_FLOOR_MM)
    bad: set[tuple] = set()
    for key, g in passes.items():
        pairs = _bad_pairs(rec, g, median, limit)
        if not pairs:
            continue
        bad.add(key)
        out.problems.append(_explain(rec, axis, key, g, median, limit, pairs, (passes, machine)))
    return bad


def _bad_pairs(rec: Recording, g: dict[str, int], median: dict, limit: float) -> list[tuple[str, str, float]]:
    found = []
    for a, b in itertools.combinations(sorted(g), 2):
        if (a, b) in median:
            d = float(np.linalg.norm(rec.xyz[g[a]] - rec.xyz[g[b]])) - median[(a, b)]
            if abs(d) > limit:
                found.append((a, b, d))
    return found


def _explain(rec: Recording, axis: str, key: tuple, g: dict[str, int], median: dict, limit: float,
             pairs: list, context: tuple = ({}, None)) -> DataProblem:
    """A swap when exchanging two labels makes the pass rigid, else the reading(s) in the most bad pairs, with
    their distance from their own nest (``context``: the axis' passes and the machine, _nest_distance)."""
    _, rnd, q, _ = key
    where = f"{axis} round {rnd} at {q:g}"
    for a, b in itertools.combinations(sorted(g), 2):
        swapped = dict(g, **{a: g[b], b: g[a]})
        if not _bad_pairs(rec, swapped, median, limit):
            return DataProblem("label_swap", axis, rnd, q, (a, b), (int(rec.line[g[a]]), int(rec.line[g[b]])),
                               max(abs(p[2]) for p in pairs),
                               f"{a} and {b} swapped in {where}? (lines {int(rec.line[g[a]])}, "
                               f"{int(rec.line[g[b]])}; exchanging them makes the reflectors rigid again): pass "
                               f"left out")
    count: dict[str, int] = {}
    for a, b, _ in pairs:
        count[a] = count.get(a, 0) + 1
        count[b] = count.get(b, 0) + 1
    worst = max(count.values())
    pts = tuple(sorted(p for p, c in count.items() if c == worst))
    lines = tuple(int(rec.line[g[p]]) for p in pts)
    off = [_nest_distance(rec, axis, key, g[p], p, *context) for p in pts]
    if all(d is not None for d in off):
        size = max(off)
        how = (f"{' and '.join(f'{d:.4g}' for d in off)} mm from where its nest is (the commanded motion from the "
               f"other passes' readings of it)")
    else:
        size = max(abs(p[2]) for p in pairs)
        how = f"off by up to {size:.3g} mm in its distances to the other reflectors"
    return DataProblem("far_reading", axis, rnd, q, pts, lines, size,
                       f"reading of {' or '.join(pts)} in {where} (line(s) {', '.join(map(str, lines))}) is {how}: "
                       f"{_cause(rec, [g[p] for p in pts])}: pass left out")


def _nest_distance(rec: Recording, axis: str, key: tuple, row: int, point: str, passes: dict,
                   machine) -> float | None:
    """Distance (mm) of reading ``row`` from where its nest is in its pass ``key``: the median of the point's
    readings in the axis' other passes of the same station, each carried to this pass' position by the nominal
    motion (machine errors, tens of um, are far below a far reading); None without a machine or another pass."""
    other = [(g[point], k[2]) for k, g in passes.items() if k != key and k[0] == key[0] and point in g]
    if machine is None or not other:
        return None
    local = _local(rec, axis, np.array([j for j, _ in other]), np.array([q for _, q in other]), machine)
    t, r = machine.rigid_motion(axis, machine.axis_vector({axis: key[2]}))
    nest = np.median(local @ r.T + t, axis=0)
    return float(np.linalg.norm(rec.xyz[row] - nest))


def _cause(rec: Recording, rows: list[int]) -> str:
    """What a far reading looks like: no target (a tracker writes 0, 0, 0 when it found none), else a misread,
    mistyped or other reflector."""
    if all(not np.any(rec.xyz[i]) for i in rows):
        return "no target (the tracker wrote 0, 0, 0)"
    return "misread, mistyped or another reflector"


def _local(rec: Recording, axis: str, rows: np.ndarray, q: np.ndarray, machine) -> np.ndarray:
    """The readings ``rows`` of ``axis`` at positions ``q`` carried back to their side's frame by the nominal
    motion (x = b + R local): where the nests sit on the side, the same for every axis of that side (mm)."""
    b, R = machine.rigid_motion(axis, machine.axis_vector({axis: q}))
    return np.einsum("nji,nj->ni", R, rec.xyz[rows] - b)


def _side_nests(rec: Recording, axis: str, by_axis: dict, group: dict, machine) -> dict[tuple, np.ndarray]:
    """{(station, point): where the nest sits on the side (mm, _local)} from the passes of the other axes of
    ``axis``' side (the median over them): what tells which of two rounds that disagree holds the slip (a
    machine's geometric errors, tens of um, are far below PASS_FLOOR_MM).  Empty without a machine or sides."""
    others = [a for a in by_axis if a != axis and group[a] == group[axis] and not group[a].startswith("axis ")]
    if machine is None or not others:
        return {}
    seen: dict[tuple, list[np.ndarray]] = {}
    for a in others:
        keys = [(k[0], p, i, k[2]) for k, g in by_axis[a].items() for p, i in g.items()]
        if not keys:
            continue
        rows = np.array([i for *_, i, _ in keys])
        local = _local(rec, a, rows, np.array([q for *_, q in keys]), machine)
        for (st, p, _, _), v in zip(keys, local):
            seen.setdefault((st, p), []).append(v)
    return {k: np.median(v, axis=0) for k, v in seen.items()}


def _cross_round(rec: Recording, axis: str, passes: dict, skip: set[tuple], out: Screen,
                 nests: dict[tuple, np.ndarray] | None = None, machine=None) -> set[tuple]:
    """Passes whose readings are far (> PASS_FLOOR_MM) from the same reflectors in the same pass of the other
    rounds: two labels swapped (exchanging them brings both back), the whole pass moved (a wrong position or axis
    label), or single readings far off.  With two rounds only, the median cannot say which round is wrong: where
    the other axes of the side put the pass' nests (``nests``, _side_nests) one of the two agrees with and the
    other does not, the other is left out; else, where the other stations read the same pass and one of the two
    agrees with them (_off_the_stations), the other; else both, as rounds that disagree.  A station's only round
    of the axis is judged by the other stations' rounds of the same pass where they agree (_lone_round)."""
    groups: dict[tuple, list[tuple]] = {}
    for key in passes:
        if key not in skip:
            groups.setdefault((key[0], key[2], key[3]), []).append(key)
    bad: set[tuple] = set()
    for keys in groups.values():
        if len(keys) < 2:
            problem = _lone_round(rec, axis, keys[0], passes, skip, nests or {}, machine)
            if problem is not None:
                bad.add(keys[0])
                out.problems.append(problem)
            continue
        ref = {p: np.median([rec.xyz[passes[k][p]] for k in keys if p in passes[k]], axis=0)
               for p in {p for k in keys for p in passes[k]}}
        far = [k for k in keys if max(float(np.linalg.norm(rec.xyz[i] - ref[p])) for p, i in passes[k].items())
               > PASS_FLOOR_MM]
        off, by = None, ""
        if len(keys) == 2:  # two rounds: the median cannot say which is wrong, the referees may
            off, by = _off_the_side(rec, axis, far, passes, nests or {}, machine), "side"
            if off is None:
                off, by = _off_the_stations(rec, far, passes, skip), "station"
        for k in far:
            dev = {p: float(np.linalg.norm(rec.xyz[i] - ref[p])) for p, i in passes[k].items()}
            if off is None:
                bad.add(k)
                out.problems.append(_cross_explain(rec, axis, k, passes[k], ref, dev, len(keys)))
            elif k in off:
                bad.add(k)
                out.problems.append(_off_explain(rec, axis, k, passes[k], off[k], by))
    return bad


def _off_the_side(rec: Recording, axis: str, far: list[tuple], passes: dict, nests: dict, machine
                  ) -> dict[tuple, float] | None:
    """Of the two passes ``far`` of two rounds that disagree: {the one whose nests lie more than PASS_FLOOR_MM
    from where the other axes of the side put them: that distance, mm}, when the other lies within it; else None
    (the side cannot tell: both are left out as rounds that disagree)."""
    if len(far) != 2 or not nests:
        return None
    off = {}
    for k in far:
        pts = [p for p in passes[k] if (k[0], p) in nests]
        if not pts:
            return None
        local = _local(rec, axis, np.array([passes[k][p] for p in pts]), np.full(len(pts), k[2]), machine)
        off[k] = max(float(np.linalg.norm(v - nests[(k[0], p)])) for p, v in zip(pts, local))
    return _the_one_off(off)


def _off_the_stations(rec: Recording, far: list[tuple], passes: dict, skip: set[tuple]) -> dict[tuple, float] | None:
    """Of the two passes ``far`` of one station's two rounds that disagree: {the one whose readings lie more than
    PASS_FLOOR_MM from the same pass read from the other stations (their median; every station's readings are in
    the machine's frame, their alignments tens of um apart): that distance, mm}, when the other lies within it;
    else None (no other station reads the pass, or it cannot tell)."""
    if len(far) != 2:
        return None
    _, ref = _other_stations(rec, far[0], passes, skip)
    off = {}
    for k in far:
        pts = [p for p in passes[k] if p in ref]
        if not pts:
            return None
        off[k] = max(float(np.linalg.norm(rec.xyz[passes[k][p]] - ref[p])) for p in pts)
    return _the_one_off(off)


def _other_stations(rec: Recording, key: tuple, passes: dict, skip: set[tuple]) -> tuple[list[tuple], dict]:
    """(the passes of the other stations at ``key``'s position and direction, not left out; per point they read,
    the median of their readings, mm): the referee that the other stations are (every station's readings in the
    machine's frame, their alignments tens of um apart)."""
    others = [k for k in passes if k[0] != key[0] and k[2:] == key[2:] and k not in skip]
    ref = {p: np.median([rec.xyz[passes[k][p]] for k in others if p in passes[k]], axis=0)
           for p in {p for k in others for p in passes[k]}}
    return others, ref


def _lone_round(rec: Recording, axis: str, key: tuple, passes: dict, skip: set[tuple], nests: dict, machine
                ) -> DataProblem | None:
    """The pass ``key``, its station's only round of it, judged by the other stations' rounds of the same pass
    (every station's readings in the machine's frame): where two or more agree within PASS_FLOOR_MM and it lies
    farther from them (their median), it is off (round_off_station); where one other station's only round reads
    the pass and the two disagree, the other axes of the side say which (round_off_side), else neither can be told
    (rounds_disagree: each is left out by its own station's check).  Columns exchanged in a round are a
    reflection: the distances keep, and no round of its own station disagrees (gen2 seed 3577 campaign 6)."""
    others, ref = _other_stations(rec, key, passes, skip)
    pts = [p for p in passes[key] if p in ref]
    if not pts:
        return None
    dev = {p: float(np.linalg.norm(rec.xyz[passes[key][p]] - ref[p])) for p in pts}
    if max(dev.values()) <= PASS_FLOOR_MM:
        return None
    if len(others) == 1:
        if sum(k[2:] == key[2:] and k[0] == others[0][0] for k in passes) > 1:
            return None  # the other station reads the pass in several rounds: its own check judges it
        off = _off_the_side(rec, axis, [key, others[0]], passes, nests, machine)
        if off is None:
            return _cross_explain(rec, axis, key, {p: passes[key][p] for p in pts}, ref, dev, 2)
        return _off_explain(rec, axis, key, passes[key], off[key], "side") if key in off else None
    if max(float(np.linalg.norm(rec.xyz[passes[k][p]] - ref[p])) for k in others for p in pts
           if p in passes[k]) > PASS_FLOOR_MM:
        return None  # the other stations' rounds do not agree among themselves: no referee
    return _off_explain(rec, axis, key, passes[key], max(dev.values()), "stations")


def _the_one_off(off: dict[tuple, float]) -> dict[tuple, float] | None:
    """{the one pass of two farther than PASS_FLOOR_MM from its referee: that distance, mm} (``off``: each pass'
    largest distance from where the referee puts its readings), when the other lies within it; else None."""
    wrong = [k for k, d in off.items() if d > PASS_FLOOR_MM]
    return {wrong[0]: off[wrong[0]]} if len(wrong) == 1 else None


def _off_explain(rec: Recording, axis: str, key: tuple, g: dict[str, int], size: float, by: str) -> DataProblem:
    """A pass of two rounds that disagree, the one the other axes of its side (``by`` "side") or the other stations
    (``by`` "station") do not agree with; or a station's only round of it, off the other stations' rounds that
    agree (``by`` "stations", _lone_round)."""
    _, rnd, q, _ = key
    lines = tuple(sorted(int(rec.line[i]) for i in g.values()))
    whom = {"side": "the other axes of its side read the same nests", "station": "the other station(s) read the "
            "same pass", "stations": "the other stations' rounds read the same pass"}[by]
    why = ("its station reads the axis once, the other stations' rounds agree" if by == "stations"
           else "the axis' other round agrees with them")
    kind = "round_off_side" if by == "side" else "round_off_station"
    return DataProblem(kind, axis, rnd, q, tuple(sorted(g)), lines, size,
                       f"{axis} round {rnd} at {q:g}: its readings are {size:.3g} mm from where {whom} (lines "
                       f"{lines[0]}-{lines[-1]}; {why}): a wrong label, a unit or columns slip?: pass left out", why)


def _cross_explain(rec: Recording, axis: str, key: tuple, g: dict[str, int], ref: dict, dev: dict,
                   n_rounds: int) -> DataProblem:
    _, rnd, q, _ = key
    lines = tuple(sorted(int(rec.line[i]) for i in g.values()))
    size = max(dev.values())
    where = f"{axis} round {rnd} at {q:g}"
    if n_rounds == 2:
        return DataProblem("rounds_disagree", axis, rnd, q, tuple(sorted(g)), lines, size,
                           f"{where}: its readings are {size:.3g} mm from the other round's (lines {lines[0]}-"
                           f"{lines[-1]}); with two rounds it cannot be told which is wrong (a label swap or a "
                           f"wrong label?): both left out")
    for a, b in itertools.combinations(sorted(g), 2):
        if max(np.linalg.norm(rec.xyz[g[a]] - ref[b]), np.linalg.norm(rec.xyz[g[b]] - ref[a])) <= PASS_FLOOR_MM:
            return DataProblem("label_swap", axis, rnd, q, (a, b), (int(rec.line[g[a]]), int(rec.line[g[b]])), size,
                               f"{a} and {b} swapped in {where}? (lines {int(rec.line[g[a]])}, "
                               f"{int(rec.line[g[b]])}; exchanging them puts both where the other rounds read them):"
                               f" pass left out")
    shift = np.array([rec.xyz[i] - ref[p] for p, i in g.items()])
    if np.linalg.norm(shift - shift.mean(axis=0), axis=1).max() <= PASS_FLOOR_MM:
        return DataProblem("pass_far", axis, rnd, q, tuple(sorted(g)), lines, size,
                           f"{where} lies {size:.3g} mm from the same pass of the other rounds (lines {lines[0]}-"
                           f"{lines[-1]}): a wrong position or axis label?: pass left out")
    pts = tuple(sorted(p for p, d in dev.items() if d > PASS_FLOOR_MM))
    return DataProblem("far_reading", axis, rnd, q, pts, tuple(int(rec.line[g[p]]) for p in pts), size,
                       f"reading of {' and '.join(pts)} in {where} is {size:.3g} mm from where the other rounds "
                       f"read it: {_cause(rec, [g[p] for p in pts])}: pass left out")


def _reference_rounds(rec: Recording, axis: str, out: Screen) -> None:
    """Leave out the rounds of ``axis`` that lost every reading at their reference position; refuse the axis
    when fewer than two rounds are left."""
    rows = np.flatnonzero(rec.axis == axis)
    rounds = sorted(set(rec.round[rows].tolist()))
    kept_rounds = []
    for r in rounds:
        ri = rows[rec.round[rows] == r]
        q0 = reference_position(rec.position[ri])
        at = ri[(position_key(rec.position[ri]) == q0) & out.keep[ri]]
        if len(at) == 0 and out.keep[ri].any():
            out.keep[ri] = False
            out.notes.append(f"{axis} round {r}: every reading at its reference position {q0:g} was left out, so "
                             f"the round has no reference: left out")
        if out.keep[ri].any():
            kept_rounds.append(r)
    if not kept_rounds and rounds:
        raise InputError(f"{rec.source}: axis {axis}: no round is left after the gross-error screen "
                         f"({'; '.join(p.text for p in out.problems if p.axis == axis)[:400]})")
