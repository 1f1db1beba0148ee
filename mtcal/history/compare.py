"""Changes between calibrations of one machine, tested against their uncertainty, and an error's trend.

Each error of two identified models (every position of an error function, every constant) gives a difference
d = v2 - v1 with the standard uncertainty u = sqrt(s1² + s2²), s = u95 / k of each model's own interval (k = 1.96
for the joint fit's covariance, Student's t of n - 1 for the three-point rounds), and the Welch-Satterthwaite
degrees of freedom.  Its 95 % interval is t_0.975(ν) u.  A change is named when its two-sided p-value passes
Holm's step-down procedure over every error and position of the step at the family-wise level ``LEVEL`` (0.01):
on a machine that did not change, the probability that a comparison names anything is at most 1 %, whatever the
correlation between the errors (Holm needs no independence).  An error is named with its largest significant
difference; the words come from the error's ISO/TR 16907 class on the model's machine (mtcal.model.iso_types).

Values inside: mm and rad; the answers in µm and µrad (``unit``).
"""
from __future__ import annotations

import datetime as dt
import math
from dataclasses import dataclass, field

import numpy as np

from mtcal import _tails
from mtcal.errors import InputError
from mtcal.history.results import Z95, Quantity
from mtcal.history.store import Record

LEVEL = 0.01
MULTIPLICITY = "Holm over every error and position of a step"
SHOWN = {"mm": ("µm", 1e3), "rad": ("µrad", 1e6)}

# words a service engineer reads, per ISO/TR 16907 class ({J}: the error's axis, {C}: its component, {K}: the
# axis a squareness is to; {kind} {how}: "an offset in" or "a tilt about" as {C} is a translation or a rotation), and
# what may have caused a change of that class
WORDS = {
    "L-POS": ("a positioning error of {J}", "a scale or pitch change: the machine's temperature, or a re-compensated "
                                            "scale?"),
    "L-STR": ("a straightness of {J} in {C}", "guideway wear, a crash, or the machine re-levelled?"),
    "L-SQU": ("a squareness of {J} to {K}", "a crash, or the machine re-levelled?"),
    "L-ANG": ("an angular error of {J} about {C}", "guideway wear, a crash, or the machine re-levelled?"),
    "R-POS": ("a positioning error of {J}", "an encoder, or the axis re-referenced?"),
    "R-RAX": ("a radial or axial motion of {J} in {C}", "bearing wear, or a crash?"),
    "R-POR": ("{kind} of {J}'s axis {how} {C}", "a crash, or the axis re-mounted?"),
    "R-ANG": ("a tilt motion of {J} about {C}", "bearing wear, or a crash?"),
}


@dataclass
class Change:
    """A named change of one error: ``change`` and its 95 % interval ``u95`` in ``unit`` (µm or µrad), where
    (``axis``, ``position`` mm or deg; None for a constant), the p-value and Holm's threshold, and the sentence."""

    name: str
    change: float
    u95: float
    unit: str
    axis: str | None
    position: float | None
    p: float
    text: str

    def to_dict(self) -> dict:
        return {"name": self.name, "change": self.change, "u95": self.u95, "unit": self.unit, "axis": self.axis,
                "position": self.position, "p": self.p, "text": self.text}


@dataclass
class Step:
    """One comparison: the dates, the changed errors, how many compared errors did not change, the errors that
    could not be compared (no interval in one of the models, or no common position)."""

    date_from: dt.date
    date_to: dt.date
    changed: list[Change] = field(default_factory=list)
    unchanged: int = 0
    tests: int = 0
    not_compared: list[str] = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"from": self.date_from.isoformat(), "to": self.date_to.isoformat(),
                "changed": [c.to_dict() for c in self.changed], "unchanged": self.unchanged, "tests": self.tests,
                "not_compared": self.not_compared}


@dataclass
class Comparison:
    """``history compare``'s answer: the machine, the steps, the level and how multiplicity is controlled."""

    machine: str
    steps: list[Step]
    level: float = LEVEL

    def to_dict(self) -> dict:
        return {"machine": self.machine, "level": self.level, "multiplicity": MULTIPLICITY,
                "interval": "95 % of the difference (Welch-Satterthwaite)", "steps": [s.to_dict() for s in self.steps]}


def words(name: str, spec: str | None) -> tuple[str, str]:
    """(what the error is, what may have changed it) from its ISO/TR 16907 class on machine ``spec``."""
    from mtcal.kinematics.machine import load_machine
    from mtcal.model.iso_types import iso_16907_types
    if spec:
        for cls, members in iso_16907_types(load_machine(spec)).items():
            if name in members:
                what, cause = WORDS[cls]
                j, c = name[-1], name[2]
                lin = "XYZ"[("ABC".index(c))] if c in "ABC" else c
                k = "".join(a for a in "XYZ" if a not in (j, lin))[:1]
                kind = ("an offset", "in") if c in "XYZ" else ("a tilt", "about")
                return what.format(J=j, C=c if c in "XYZ" else lin, K=k, kind=kind[0], how=kind[1]), cause
    return f"the error {name}", "what changed on the machine?"


def _p_value(d: float, s: float, nu: float) -> float:
    z = abs(d) / s
    return float(2 * _tails.t_sf(z, nu))


def _key(q: Quantity) -> tuple:
    return q.name, None if q.position is None else round(q.position, 6)


def compare_pair(a: Record, b: Record, spec: str | None, level: float = LEVEL) -> Step:
    """The step from calibration ``a`` to ``b`` (module docstring)."""
    qa = {_key(q): q for q in a.quantities if q.u95}
    qb = {_key(q): q for q in b.quantities if q.u95}
    names = sorted({q.name for q in a.quantities} | {q.name for q in b.quantities})
    tests = []
    for key in sorted(set(qa) & set(qb), key=lambda k: (k[0], -math.inf if k[1] is None else k[1])):
        x, y = qa[key], qb[key]
        sx, sy = x.u95 / _k(x.dof), y.u95 / _k(y.dof)
        s = math.hypot(sx, sy)
        if s <= 0:
            continue
        nu = _welch(sx, x.dof, sy, y.dof)
        d = y.value - x.value
        tests.append((key, d, s, nu, _p_value(d, s, nu), y))
    compared = {t[0][0] for t in tests}
    step = Step(a.date, b.date, tests=len(tests), not_compared=[n for n in names if n not in compared])
    rejected = _holm([t[4] for t in tests], level)
    best: dict[str, tuple] = {}
    for t, r in zip(tests, rejected):
        if r and (t[0][0] not in best or abs(t[1]) / t[2] > abs(best[t[0][0]][1]) / best[t[0][0]][2]):
            best[t[0][0]] = t
    for name, (_, d, s, nu, p, y) in sorted(best.items(), key=lambda kv: kv[1][4]):
        unit, f = SHOWN.get(y.unit, (y.unit, 1.0))
        half = _k(nu) * s
        step.changed.append(Change(name, d * f, half * f, unit, y.axis, y.position, p,
                                   _sentence(name, d * f, half * f, unit, y, a.date, b.date, spec)))
    step.unchanged = len(compared) - len(best)
    return step


def _sentence(name: str, d: float, half: float, unit: str, q: Quantity, d1: dt.date, d2: dt.date,
              spec: str | None) -> str:
    what, cause = words(name, spec)
    where = "" if q.position is None else f" at {q.axis} = {q.position:g}"
    digits = 0 if half >= 10 else 1 if half >= 1 else 2
    return (f"{name} changed by {d:+.{digits}f} ± {half:.{digits}f} {unit}{where} between {d1.isoformat()} and "
            f"{d2.isoformat()}: {what} — {cause}")


def _k(dof: float | None) -> float:
    """The 95 % coverage factor of ``dof`` degrees of freedom (Student's t; normal where infinite or unknown)."""
    if dof is None or not math.isfinite(dof):
        return Z95
    return float(_tails.t_ppf(0.975, dof))


def _welch(sx: float, nx: float | None, sy: float, ny: float | None) -> float:
    """Welch-Satterthwaite degrees of freedom of the difference (inf when both are infinite)."""
    terms = [s**4 / n for s, n in ((sx, nx), (sy, ny)) if n is not None and math.isfinite(n) and n > 0]
    if not terms:
        return math.inf
    return (sx**2 + sy**2) ** 2 / sum(terms)


def _holm(p: list[float], level: float) -> list[bool]:
    """Holm's step-down rejections at family-wise ``level``."""
    m = len(p)
    out = [False] * m
    for rank, i in enumerate(np.argsort(p, kind="stable")):
        if p[i] > level / (m - rank):
            break
        out[i] = True
    return out


def compare(records: list[Record], machine: str, spec: str | None, date_from: dt.date | None = None,
            date_to: dt.date | None = None, level: float = LEVEL) -> Comparison:
    """Consecutive calibrations (identified models, ``records`` oldest first), or the two of ``date_from`` and
    ``date_to`` (the last model of each date), compared (module docstring).  Fewer than two models, or a date
    without one, is an InputError."""
    models = [r for r in records if r.kind == "model"]
    by_date: dict[dt.date, Record] = {}
    for r in models:
        by_date[r.date] = r  # the last one of a date
    dates = sorted(by_date)
    if len(dates) < 2:
        raise InputError(f"the history of {machine} holds {len(dates)} calibration date(s) with an identified model; "
                         "a comparison needs two")
    for d in (date_from, date_to):
        if d is not None and d not in by_date:
            raise InputError(f"no identified model of {machine} dated {d.isoformat()} (dates: "
                             f"{', '.join(x.isoformat() for x in dates)})")
    if date_from or date_to:
        lo, hi = date_from or dates[0], date_to or dates[-1]
        if not lo < hi:
            raise InputError(f"--from {lo.isoformat()} must be before --to {hi.isoformat()}")
        pairs = [(by_date[lo], by_date[hi])]
    else:
        pairs = [(by_date[x], by_date[y]) for x, y in zip(dates, dates[1:])]
    return Comparison(machine, [compare_pair(a, b, spec, level) for a, b in pairs], level)


@dataclass
class Trend:
    """An error's values over time: ``points`` [{"date", "value", "u95"}] in ``unit`` (µm, µrad), at ``position``
    of ``axis`` for an error function (None for a constant)."""

    machine: str
    name: str
    unit: str
    axis: str | None
    position: float | None
    points: list[dict]
    note: str = ""

    def to_dict(self) -> dict:
        return {"machine": self.machine, "error": self.name, "unit": self.unit, "axis": self.axis,
                "position": self.position, "points": self.points, "note": self.note}


def trend(records: list[Record], machine: str, name: str, position: float | None = None) -> Trend:
    """``name``'s value and 95 % interval at every identified model of the history (an error function: at
    ``position``, by default where its latest value is largest in size)."""
    models = [r for r in records if r.kind == "model"]
    found = [q for r in models for q in r.quantities if q.name == name]
    if not found:
        known = sorted({q.name for r in models for q in r.quantities})
        raise InputError(f"no error {name!r} in the identified models of {machine} (errors: {', '.join(known)})")
    note = ""
    if found[0].position is not None and position is None:
        last = [q for q in models[-1].quantities if q.name == name] or found
        position = max(last, key=lambda q: abs(q.value)).position
        note = f"at {found[0].axis} = {position:g}, where the latest value is largest in size"
    unit, f = SHOWN.get(found[0].unit, (found[0].unit, 1.0))
    points = []
    for r in models:
        for q in r.quantities:
            if q.name == name and (q.position is None or abs(q.position - position) < 1e-6):
                points.append({"date": r.date.isoformat(), "value": q.value * f,
                               "u95": None if q.u95 is None else q.u95 * f})
    if not points:
        raise InputError(f"{name} has no value at {found[0].axis} = {position:g} in the history of {machine}")
    return Trend(machine, name, unit, found[0].axis, position, points, note)
