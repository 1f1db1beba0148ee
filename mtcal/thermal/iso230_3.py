"""ISO 230-3 evaluations of a thermal test, as this module understands the standard's text (ISO 230-3:2007,
"Determination of thermal effects"; the 2020 edition's clause numbers were not checked here).

* **Clause 6, thermal distortion caused by rotating spindles.** The relative displacement between the spindle
  (a test mandrel) and the table is measured in X, Y and Z over the test while the spindle runs at its speed
  profile; with two sensors per radial direction a distance l apart along the mandrel, the tilts follow from
  their difference over l. Each direction's **thermal drift** is its displacement from the first reading, d(t) -
  d(t0); reported: the **range** over the test (max - min), the drift **at the end**, the largest |drift|, and the
  same **per spindle-speed stage** (a run of readings at one speed: the drift's range within it and at its end).
  The direction's drift is that of the sensor nearer the spindle nose (X1, Y1); the tilt in the ZX plane (about Y)
  is (X1 - X2) / l, in the YZ plane (about X) (Y1 - Y2) / l, in urad (um / mm * 1000). Unsure: which sensor of a
  pair the standard's figure takes and its sign convention for the tilts -- stated here as used.
* **Clause 5, environmental temperature variation error (ETVE).** A test with the machine at rest (no spindle
  speed, or zero throughout) over the environment's temperature cycle: the ETVE of each direction is the largest
  range of the relative displacement over the test, max - min; the range of each temperature beside it.
  Unsure: whether the standard takes the range per direction over the whole test or per period of the
  environment's cycle; the whole test is used.

Without directions each channel is its own direction and no tilt is evaluated (said in the notes).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mtcal.thermal.readings import PAIRS, ThermalTest

CLAUSE_SPINDLE = "ISO 230-3:2007 clause 6 (thermal distortion caused by rotating spindles)"
CLAUSE_ETVE = "ISO 230-3:2007 clause 5 (environmental temperature variation error, ETVE)"


@dataclass
class Stage:
    """One spindle-speed stage: readings [first, last] at one speed."""

    rpm: float
    start_s: float
    end_s: float
    first: int
    last: int


@dataclass
class Iso230_3Result:
    """The evaluation of one thermal test.

    Attributes
    ----------
    source : str
    kind : {"spindle", "etve"}
        Clause 6 (a spindle runs) or clause 5 (the machine at rest).
    clause : str
    drift_um : dict of str to ndarray
        Each direction's (or channel's) drift from the first reading, um.
    tilt_urad : dict of str to ndarray
        Each tilt's change from the first reading, urad ("B (ZX)" from X1, X2; "A (YZ)" from Y1, Y2).
    figures : dict of str to dict
        Per direction and tilt: range, at_end, max_abs (um or urad); per stage in ``stages``; ``etve`` for clause 5.
    stages : list of Stage
    temperature_range_c : dict of str to float
    notes : list of str
    """

    source: str
    kind: str
    clause: str
    time_s: np.ndarray
    drift_um: dict[str, np.ndarray]
    tilt_urad: dict[str, np.ndarray]
    figures: dict[str, dict]
    stages: list[Stage]
    temperature_range_c: dict[str, float]
    notes: list[str] = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"source": self.source, "kind": self.kind, "clause": self.clause,
                "duration_s": float(self.time_s[-1] - self.time_s[0]), "figures": self.figures,
                "stages": [{"rpm": s.rpm, "start_s": s.start_s, "end_s": s.end_s} for s in self.stages],
                "temperature_range_c": self.temperature_range_c, "notes": self.notes,
                "units": {"drift": "um", "tilt": "urad", "time": "s", "temperature": "degC"}}


def stages(test: ThermalTest) -> list[Stage]:
    """The runs of readings at one spindle speed (one stage for a test without a speed column)."""
    n = len(test)
    rpm = test.spindle_rpm if test.spindle_rpm is not None else np.zeros(n)
    cuts = np.concatenate([[0], np.flatnonzero(np.diff(rpm) != 0) + 1, [n]])
    return [Stage(float(rpm[a]), float(test.time_s[a]), float(test.time_s[b - 1]), int(a), int(b - 1))
            for a, b in zip(cuts[:-1], cuts[1:])]


def directions(test: ThermalTest) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray], list[str]]:
    """(drift per direction in um, tilt per plane in urad, notes) from the channels and their directions."""
    notes = []
    if not test.directions:
        notes.append("the channels' directions are not given (`directions`): each channel is evaluated as its own "
                     "direction, no tilt")
        return {c: v - v[0] for c, v in test.channels.items()}, {}, notes
    by = {d: test.channels[c] for c, d in test.directions.items()}
    drift = {}
    for axis in ("X", "Y", "Z"):
        src = by.get(axis, by.get(f"{axis}1", by.get(f"{axis}2")))
        if src is not None:
            drift[axis] = src - src[0]
    tilt = {}
    for axis, (near, far) in PAIRS.items():
        if near in by and far in by:
            if not test.spacing_mm:
                notes.append(f"{near}, {far}: no sensor spacing (`spacing_mm`), no tilt")
                continue
            a = (by[near] - by[far]) / test.spacing_mm * 1000.0
            tilt["B (ZX)" if axis == "X" else "A (YZ)"] = a - a[0]
    return drift, tilt, notes


def _figures(v: np.ndarray, st: list[Stage]) -> dict:
    return {"range": float(v.max() - v.min()), "at_end": float(v[-1]), "max_abs": float(np.abs(v).max()),
            "stages": [{"rpm": s.rpm, "range": float(np.ptp(v[s.first:s.last + 1])), "at_end": float(v[s.last])}
                       for s in st]}


def evaluate_iso230_3(test: ThermalTest) -> Iso230_3Result:
    """The ISO 230-3 figures of ``test`` (module docstring): clause 6 when the spindle runs, else clause 5.

    Parameters
    ----------
    test : ThermalTest
        The readings (mtcal.thermal.readings.read_thermal_test), with directions and spacing if known.

    Returns
    -------
    Iso230_3Result
    """
    st = stages(test)
    drift, tilt, notes = directions(test)
    at_rest = test.spindle_rpm is None or not np.any(test.spindle_rpm)
    kind, clause = ("etve", CLAUSE_ETVE) if at_rest else ("spindle", CLAUSE_SPINDLE)
    figures = {k: _figures(v, st) for k, v in {**drift, **tilt}.items()}
    if at_rest:
        for k in figures:
            figures[k]["etve"] = figures[k]["range"]
        notes.append("no spindle speed (or zero throughout): an ETVE test (clause 5)")
    temps = {k: float(np.ptp(v)) for k, v in test.temperatures.items()}
    return Iso230_3Result(test.source, kind, clause, test.time_s, drift, tilt, figures, st, temps, test.notes + notes)
