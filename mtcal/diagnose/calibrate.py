"""The whole diagnosis' level calibrated by simulation from its fitted null: a parametric bootstrap
(`mtcal diagnose --calibrate N`; docs/design.md, "Diagnosis", the calibrated level).

The diagnosis bounds its family-wise rate of false claims by a nominal level (``LEVEL``, Bonferroni over its
STAGES), under assumptions a recording can break: the noise law's shape and scale, whitened residuals treated as
independent, the scans' and change-point searches' null distributions.  This module measures the rate it has on
the recording's own design instead.

* Null H0: the readings are the fitted null -- the reported base (the machine's smooth error functions at the
  degrees the diagnosis chose, the reflectors' positions, every station's alignment; or the given model with its
  offsets) -- plus noise of the law the diagnosis weighted the readings by (its along/across-beam shape about each
  station's tracker, any station's or axis' own scale, ``Prepared.W``) times the base's sigma ratio (the fitted
  null's scale).  Alternative: the diagnosis' own (whatever departure it claims).  On these campaigns every
  claim -- an effect named, a located or unexplained entry, a shape located beyond the quasi-static family, an axis
  repeating worse than the others -- is a false alarm.
* Simulated: N campaigns at exactly the recording's plan (the rows the screen kept: the same poses, order, times,
  temperatures, stations, directions and missing readings), each the fitted readings plus one draw of that law
  (mtcal.measurement.tracker.draw, the simulator's draw).  Held fixed: the fitted null itself (not re-drawn from
  its uncertainty), the plan, the options of the diagnosis.  Each campaign is diagnosed with the same options;
  the noise law, the station and everything else are estimated again from it, as from the recording.
* Reported: the share of campaigns with any claim -- the calibrated family-wise false-alarm rate at the level
  used -- with its one-sided 95 % Clopper-Pearson upper bound, and per kind (and per effect name) the campaigns
  that claimed it; data problems of the screen (its own thresholds, not the level) are counted beside, not in.
* Limits: the null is the fitted model.  A law the model lacks (correlated noise, a drift of the air, a heavy
  tail) is not simulated, so the calibration cannot see a false alarm it would cause; a base fitted to an effect
  it absorbed carries that absorption into every null campaign.  N campaigns bound the rate to about 3 / N at
  zero alarms: 20 campaigns (the default) say "below 14 %", 300 "below 1 %".
"""
from __future__ import annotations

import contextlib
import dataclasses
import logging
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np

from mtcal.diagnose.prepared import LEVEL
from mtcal.diagnose.report import Diagnosis
from mtcal.diagnose.run import diagnose
from mtcal.measurement.recordings import Recording
from mtcal.measurement.tracker import draw

CAMPAIGNS = 20  # the default count of null campaigns (--calibrate bare): a rate bound of 14 % at zero alarms
CONFIDENCE = 0.95  # the one-sided Clopper-Pearson bound of the calibrated rate
NOMINAL = ("nominal, not calibrated: it bounds the false alarms where the noise law and the fitted model hold "
           "(use --calibrate N)")
KINDS = ("named", "located", "unexplained", "beyond_family", "axis_scatter")  # what a diagnosis claims at the level


@dataclass
class NullFit:
    """The diagnosis' fitted null: the readings the base predicts ``xyz`` (n, 3) mm, the law's covariance factor
    ``chol`` (n, 3, 3) mm (the inverse of the whitening ``Prepared.W``), its ``scale`` (the base's sigma ratio)
    and the recording of the rows the diagnosis kept (its plan)."""

    rec: Recording
    xyz: np.ndarray
    chol: np.ndarray
    scale: float


@dataclass
class Calibration:
    """The calibrated level (module docstring): ``alarms`` of ``campaigns`` null campaigns claimed something;
    ``claims`` per kind and ``named`` per effect name the campaigns that claimed it; ``screen`` the campaigns with
    a data problem; CPU and wall seconds of the simulations and their diagnoses."""

    level: float
    campaigns: int
    seed: int
    alarms: int
    claims: dict[str, int]
    named: dict[str, int]
    screen: int
    readings: int
    scale: float
    cpu_s: float
    wall_s: float

    @property
    def rate(self) -> float:
        return self.alarms / self.campaigns

    @property
    def upper(self) -> float:
        return clopper_pearson_upper(self.alarms, self.campaigns, CONFIDENCE)

    def says(self) -> str:
        names = f" ({', '.join(f'{k} {v}' for k, v in sorted(self.named.items()))})" if self.named else ""
        kinds = [f"{k} {v}" + (names if k == "named" else "") for k, v in self.claims.items() if v]
        what = f"; claimed (campaigns): {', '.join(kinds)}" if kinds else ""
        return (f"calibrated: claims in {self.alarms} of {self.campaigns} campaigns simulated from the fitted null "
                f"(seed {self.seed}): false-alarm rate {self.rate:.3g}, one-sided {CONFIDENCE * 100:g} % upper bound "
                f"{self.upper:.3g} (Clopper-Pearson){what}; {self.cpu_s:.0f} CPU-s")

    def to_dict(self) -> dict:
        return {"level": self.level, "calibrated": True, "says": self.says(), "campaigns": self.campaigns,
                "seed": self.seed, "campaigns_with_claims": self.alarms, "rate": self.rate, "upper_95": self.upper,
                "claims": dict(self.claims), "named": dict(self.named), "screen_data_problems": self.screen,
                "readings": self.readings, "noise_scale": self.scale, "cpu_s": self.cpu_s, "wall_s": self.wall_s,
                "null": "the reported base (error functions, reflector positions, station alignments) plus the law "
                        "the readings were weighted by, times the base's sigma ratio",
                "simulated": "the readings at the recording's plan (the rows the screen kept), one draw of the law "
                             "each; the diagnosis run again with the same options",
                "held_fixed": "the fitted null (not re-drawn from its uncertainty), the plan, the options"}


def nominal(level: float) -> dict:
    """The ``level`` field of a diagnosis not calibrated."""
    return {"level": level, "calibrated": False, "says": NOMINAL}


def clopper_pearson_upper(k: int, n: int, confidence: float = CONFIDENCE) -> float:
    """The one-sided upper confidence bound of a binomial rate of ``k`` in ``n`` (Clopper and Pearson 1934)."""
    from scipy.stats import beta

    return 1.0 if k >= n else float(beta.ppf(confidence, k + 1, n - k))


def null_fit(d: Diagnosis) -> NullFit:
    """The fitted null of a diagnosis (module docstring): the kept readings less the base's residuals, and the
    law the readings were weighted by, scaled by the base's sigma ratio."""
    prep = d.prep
    n = len(prep.rec)
    raw = np.linalg.solve(prep.W, d.residuals_before.reshape(n, 3)[..., None])[..., 0]
    return NullFit(prep.rec, prep.rec.xyz - raw, np.linalg.inv(prep.W), float(d.base_sigma_ratio))


def null_campaign(null: NullFit, rng: np.random.Generator, label: str = "null campaign") -> Recording:
    """One campaign of the fitted null at the recording's plan: the fitted readings plus one draw of the law."""
    cov = null.scale**2 * np.einsum("nij,nkj->nik", null.chol, null.chol)
    return dataclasses.replace(null.rec, xyz=null.xyz + draw(cov, rng), truth=None,
                               source=f"{null.rec.source} ({label})")


def claims(d: Diagnosis) -> dict[str, list[str]]:
    """What a diagnosis claims at its level, per kind (KINDS): the effect names, the located and unexplained
    entries' axes, the shapes located beyond the quasi-static family (``base_model.shape_beyond_family``), an axis
    found repeating worse."""
    found = (d.noise.details.get("axis_scatter") or {}).get("found")
    return {"named": [e["name"] for e in d.effects if e["significant"]],
            "located": [str(x.axis) for x in d.located], "unexplained": [str(x.axis) for x in d.unexplained],
            "beyond_family": [str(u.get("axis")) for u in d.base.get("shape_beyond_family", [])],
            "axis_scatter": [str(found.get("axis", ""))] if found else []}


def calibrate(d: Diagnosis, campaigns: int = CAMPAIGNS, *, seed: int = 0, level: float | None = None,
              progress: Callable[[int], None] | None = None, **options) -> Calibration:
    """The diagnosis' level calibrated by ``campaigns`` null campaigns (module docstring).

    Parameters
    ----------
    d : Diagnosis
        The diagnosis of the recording (``mtcal.diagnose``).
    campaigns : int, optional
        Null campaigns to simulate and diagnose (default 20).
    seed : int, optional
        Campaign k draws from numpy's ``default_rng((seed, k))`` (default 0): the same seed, the same campaigns.
    level : float, optional
        The family-wise level the diagnosis used (default ``LEVEL``); passed on to every diagnosis.
    progress : callable, optional
        Called with 1 after every campaign.
    **options
        The other options the diagnosis was run with (``model``, ``machine``, ``tracker``, ``tracker_model``,
        ...), passed on unchanged.

    Returns
    -------
    Calibration
        The campaigns with claims, the rate and its upper bound, the claims per kind, the cost.

    Raises
    ------
    KeyboardInterrupt
        Interrupted: its message says how many campaigns were done and what they claimed (nothing is written).
    """
    level = LEVEL if level is None else level
    null, t0, c0 = null_fit(d), time.perf_counter(), time.process_time()
    tally = {"alarms": 0, "screen": 0, "claims": dict.fromkeys(KINDS, 0), "named": {}}
    done = 0
    try:
        with _quiet():
            for k in range(campaigns):
                sim = null_campaign(null, np.random.default_rng((seed, k)), f"null campaign {k}")
                _tally(tally, diagnose(sim, level=level, **options))
                done += 1
                if progress:
                    progress(1)
    except KeyboardInterrupt:
        raise KeyboardInterrupt(f"{done} of {campaigns} null campaigns diagnosed, {tally['alarms']} with claims; "
                                "no rate reported") from None
    return Calibration(level, campaigns, seed, tally["alarms"], tally["claims"], tally["named"], tally["screen"],
                       len(null.rec), null.scale, time.process_time() - c0, time.perf_counter() - t0)


def _tally(tally: dict, d: Diagnosis) -> None:
    """Count one null campaign's claims into ``tally``."""
    said = claims(d)
    tally["alarms"] += any(said.values())
    tally["screen"] += bool(d.data_problems)
    for kind, what in said.items():
        tally["claims"][kind] += bool(what)
    for name in set(said["named"]):
        tally["named"][name] = tally["named"].get(name, 0) + 1


@contextlib.contextmanager
def _quiet():
    """The null campaigns' own lines (degrees, warnings) kept off stderr: what they claim is counted instead."""
    lg = logging.getLogger("mtcal.diagnose")
    old = lg.level
    lg.setLevel(logging.ERROR)
    try:
        yield
    finally:
        lg.setLevel(old)
