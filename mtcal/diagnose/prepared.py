"""The data the diagnosis works on, as types only (no behaviour that needs the other modules): the weights of every
reading (NoiseModel, mtcal.diagnose.noise) and a recording prepared for the fits (Prepared,
mtcal.diagnose.prepare).  Units: mm, rad; machine frame."""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from mtcal.diagnose import effects as fx
from mtcal.kinematics.machine import Machine
from mtcal.measurement.recordings import Recording
from mtcal.measurement.tracker import AT960, TrackerSpec, covariance, law_report

LEVEL = 0.005  # the default family-wise level: it bounds the rate of false findings on a clean campaign by design,
#              so it sits at half the 1 % the project promises (issue 24), the rest left to the noise model's error
#              (gen2 at 0.01: findings of clean campaigns at p_adj 0.0057-0.0073, as often as the level allows)
STAGES = 3  # the stages that claim something on their own -- the per-stop scatter (a noise model re-weighted), the
#            selection of effects and the located misfits left beside them -- each test at level / STAGES
#            (Bonferroni), so that the level bounds the whole diagnosis' false alarms, not each stage's: at 0.005
#            each, gen2's clean campaigns were flagged 11 times in 916, 3-4 by each stage (docs/guide/diagnose.md);
#            mtcal.diagnose.run applies them, the stages take their share


@dataclass
class NoiseModel:
    """Whitening W (n, 3, 3) with W^T W = covariance^-1 (1/mm), and how it was obtained."""

    W: np.ndarray
    kind: str                          # "AT960 (given tracker)", "AT960 (estimated tracker)", "isotropic"
    how: str
    tracker: list[float] | None = None  # mm, machine frame
    details: dict = field(default_factory=dict)
    law: dict | None = None            # the tracker law that weights the readings (``law_report``); None: isotropic

    @property
    def weighted(self) -> bool:
        return self.kind != "isotropic"

    @classmethod
    def isotropic(cls, n: int, how: str = "") -> "NoiseModel":
        return cls(np.broadcast_to(np.eye(3), (n, 3, 3)).copy(), "isotropic", how)

    @classmethod
    def at960(cls, xyz: np.ndarray, tracker: np.ndarray, kind: str, how: str, spec: TrackerSpec = AT960,
              law: dict | None = None, **details) -> "NoiseModel":
        """Readings weighted by the covariance of ``spec``'s law (default the AT960's) about ``tracker`` (mm);
        ``law``: how it is reported (``law_report``; default: ``spec`` as the prior)."""
        return cls(_whitening(xyz, tracker, spec), kind, how, [float(v) for v in tracker], dict(details),
                   law if law is not None else law_report(spec, spec, "prior"))

    @classmethod
    def stations(cls, xyz: np.ndarray, station: np.ndarray, trackers: dict[str, np.ndarray],
                 spec: TrackerSpec = AT960, law: dict | None = None, specs: dict[str, TrackerSpec] | None = None,
                 **details) -> "NoiseModel":
        """The covariance of ``spec``'s law (default the AT960's; ``specs``: a station's own where given) of every
        reading about its own station's tracker (several stations); ``law``: how it is reported (``law_report``;
        default: ``spec`` as the prior, its shape not checked)."""
        W = np.empty((len(xyz), 3, 3))
        for label, t in trackers.items():
            on = station == label
            W[on] = _whitening(xyz[on], t, (specs or {}).get(label, spec))
        data = bool(law) and law.get("source") == "data"
        name = "tracker law estimated" if data else spec.name or "given law"
        return cls(W, f"{name} (given trackers, per station)",
                   f"each reading weighted by {'the estimated law' if data else spec.whose} covariance about its own "
                   "station's tracker (the recording's station and tracker_x,y,z columns)"
                   + (", each station's sigmas scaled to its own scatter (per_station)" if specs else ""), None,
                   {"trackers": {k: [float(v) for v in t] for k, t in trackers.items()}, **details},
                   law if law is not None else law_report(spec, spec, "prior", "the shape is not checked"))

    def to_dict(self) -> dict:
        return {"kind": self.kind, "how": self.how, "tracker": self.tracker, "law": self.law, **self.details}


def _whitening(xyz: np.ndarray, tracker: np.ndarray, spec: TrackerSpec = AT960) -> np.ndarray:
    """W (n, 3, 3), W^T W = the inverse covariance (``spec``'s law, default AT960) of the readings xyz (n, 3) mm
    about ``tracker`` (3,)."""
    return np.linalg.inv(np.linalg.cholesky(covariance(xyz, tracker, spec)))


@dataclass
class Prepared:
    rec: Recording
    machine: Machine
    geometry: fx.Geometry
    y: np.ndarray            # (n, 3) readings minus nominal (incl. the given model), mm
    axes: list[str]
    q_ref: dict[str, float]
    seq: np.ndarray          # (n,) index of the (axis, round, point) sequence of each reading
    seq_keys: list[tuple]    # (axis, round, point) per sequence
    order: np.ndarray        # (n,) reading order within the recording (time, else file line)
    given_model: bool
    Aoff: np.ndarray         # (n, 3, 3) d nominal / d point position (rigid motion of the reflector)
    point_group: np.ndarray  # (n,) index of the reflector position of each reading (shared by tied axes)
    local: np.ndarray        # (n, 3) the reflector's position from the reference readings, mm, the side's frame
    noise: NoiseModel        # the weights: W (n, 3, 3), W^T W = covariance^-1 (1/mm), and how they were obtained

    @property
    def W(self) -> np.ndarray:
        return self.noise.W

    @property
    def weighted(self) -> bool:
        return self.noise.weighted

    @cached_property
    def stop(self) -> np.ndarray:
        """(n,) index of every reading's stop: consecutive readings (in time) of one station, axis, round, position
        and direction -- the machine stood still while the nests were read in turn (the per-stop scatter test,
        the stops' free form, an outlier shared by its stop)."""
        rec = self.rec
        key = list(zip(rec.stations().tolist(), rec.axis.tolist(), rec.round.tolist(), rec.position.tolist(),
                       rec.direction.tolist()))
        ids = np.empty(len(rec), int)
        last, k = None, -1
        for i in np.argsort(self.order, kind="stable"):
            if key[i] != last:
                k, last = k + 1, key[i]
            ids[i] = k
        return ids

    @property
    def stations(self) -> list[str]:
        """The station labels of a multi-station recording (each with its own alignment unknowns), else []."""
        return list(self.geometry.trackers or {})
