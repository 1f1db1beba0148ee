"""Laser-tracker noise model (Leica AT960), the basis of weighting, simulation and planning.

Maximum permissible errors (MPE) of the AT960: interferometer/ADM along the beam +-(0.4 um + 0.3 um/m),
angle encoders across the beam +-(15 um + 6 um/m).  One standard deviation is MPE/2 unless set otherwise
(the usual reading of a specification as a 95 % bound).  Angular noise acts perpendicular to the beam, so
the covariance of a measured point depends on where the tracker stands (thesis ch. 5).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mtcal.errors import InputError


@dataclass(frozen=True)
class TrackerSpec:
    """MPE terms in um and um/m; ``k`` converts MPE to one standard deviation (sigma = MPE / k)."""

    radial_um: float = 0.4
    radial_um_per_m: float = 0.3
    transverse_um: float = 15.0
    transverse_um_per_m: float = 6.0
    k: float = 2.0

    def sigmas(self, distance_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(sigma along the beam, sigma across the beam) in mm at the given distance in mm."""
        r_m = np.asarray(distance_mm, dtype=float) / 1000.0
        s_r = (self.radial_um + self.radial_um_per_m * r_m) / self.k * 1e-3
        s_t = (self.transverse_um + self.transverse_um_per_m * r_m) / self.k * 1e-3
        return s_r, s_t


AT960 = TrackerSpec()


def covariance(points, tracker, spec: TrackerSpec = AT960) -> np.ndarray:
    """Covariance (..., 3, 3) in mm^2 of points (..., 3) mm measured from the tracker position (3,) mm."""
    d = np.asarray(points, dtype=float) - np.asarray(tracker, dtype=float)
    r = np.linalg.norm(d, axis=-1)
    if np.any(r < 1.0):
        raise InputError("a measured point is closer than 1 mm to the tracker position")
    u = d / r[..., None]
    s_r, s_t = spec.sigmas(r)
    uu = u[..., :, None] * u[..., None, :]
    return (s_r**2)[..., None, None] * uu + (s_t**2)[..., None, None] * (np.eye(3) - uu)


def sample(points, tracker, rng: np.random.Generator, spec: TrackerSpec = AT960) -> np.ndarray:
    """One noise draw (..., 3) mm with the covariance of ``covariance``."""
    cov = covariance(points, tracker, spec)
    return np.einsum("...ij,...j->...i", np.linalg.cholesky(cov), rng.standard_normal(np.shape(points)))


def parse_xyz(text: str, what: str | None = "tracker position") -> np.ndarray:
    """'x,y,z' in mm (CLI --tracker) -> array (3,) of finite numbers; ``what`` prefixes the message."""
    try:
        v = np.array([float(t) for t in text.split(",")])
    except ValueError:
        v = np.array([])
    if v.shape != (3,) or not np.isfinite(v).all():
        raise InputError((f"{what}: " if what else "") + f"expected three numbers x,y,z in mm, got {text!r}")
    return v
