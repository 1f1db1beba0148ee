"""Laser-tracker noise laws: the AT960's (the default and the prior), the other named instruments whose published
maximum permissible errors (MPE) were found, and laws given as numbers; the basis of weighting, simulation and
planning.

A law is MPE = a + b L along the beam (radial: the interferometer or absolute distance meter, ADM) and across it
(transverse: the angle encoders, as a length), in um and um/m, L the distance to the tracker.  One standard
deviation is MPE / k, k = 2 unless set otherwise (the usual reading of a specification as a 95 % bound).  Angular
noise acts perpendicular to the beam, so the covariance of a measured point depends on where the tracker stands
(thesis ch. 5).

Named instruments (``TRACKER_MODELS``; ``tracker_model`` parses a name or numbers):
* AT960: interferometer +-(0.4 um + 0.3 um/m) along, angle encoders +-(15 um + 6 um/m) across: the project's law
  from the start (Leica Absolute Tracker AT960 data sheet, as the project took it; the search made when the other
  instruments were added did not find that data sheet to check the radial term again; the transverse term is the
  Leica family's, the same in the AT500 manual below).
* AT500: ADM e_ADM +-(10 um + 0.3 um/m), transverse e_T +-(15 um + 6 um/m): Leica Absolute Tracker AT500 User
  Manual, 2.8.2 "Laser Tracker Subsystem Specifications" (per ISO 10360-10:2021, Annex D, so 2021 or later), as
  published on manualslib.com (manual 2861259, p. 39).  An ADM-only tracker: radial : transverse about 1 : 2.6 at
  2 m, 11 times the AT960's ratio.
Not included, because no published MPE could be found to cite: Leica AT930, FARO Vantage (S/E, S6/E6), API
Radian.  Give their data sheets' numbers as ``a_r,b_r,a_t,b_t`` instead.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from mtcal.errors import InputError


@dataclass(frozen=True)
class TrackerSpec:
    """MPE terms in um and um/m; ``k`` converts MPE to one standard deviation (sigma = MPE / k).  ``name``: the
    instrument whose published law this is ("" for numbers given or estimated), ``source``: where it is
    published; neither takes part in comparisons."""

    radial_um: float = 0.4
    radial_um_per_m: float = 0.3
    transverse_um: float = 15.0
    transverse_um_per_m: float = 6.0
    k: float = 2.0
    name: str = field(default="", compare=False)
    source: str = field(default="", compare=False, repr=False)

    @property
    def label(self) -> str:
        """The instrument's name, or "given numbers"."""
        return self.name or "given numbers"

    @property
    def whose(self) -> str:
        """The law in words: "the AT960's", or "the given law's"."""
        return f"the {self.name or 'given law'}'s"

    def sigmas(self, distance_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(sigma along the beam, sigma across the beam) in mm at the given distance in mm."""
        r_m = np.asarray(distance_mm, dtype=float) / 1000.0
        s_r = (self.radial_um + self.radial_um_per_m * r_m) / self.k * 1e-3
        s_t = (self.transverse_um + self.transverse_um_per_m * r_m) / self.k * 1e-3
        return s_r, s_t

    def scaled(self, radial: float, transverse: float) -> "TrackerSpec":
        """This law with its sigmas along and across the beam multiplied by ``radial`` and ``transverse``: numbers
        estimated from data (unnamed), the distance law a : b of each direction kept."""
        return TrackerSpec(self.radial_um * radial, self.radial_um_per_m * radial, self.transverse_um * transverse,
                           self.transverse_um_per_m * transverse, self.k)

    def mpe(self) -> dict:
        """The law's MPE terms (um, um/m) and k, as the JSON answers report them."""
        return {"radial_um": self.radial_um, "radial_um_per_m": self.radial_um_per_m,
                "transverse_um": self.transverse_um, "transverse_um_per_m": self.transverse_um_per_m, "k": self.k}


AT960 = TrackerSpec(name="AT960", source="Leica Absolute Tracker AT960 data sheet: interferometer, angle encoders")
AT500 = TrackerSpec(10.0, 0.3, 15.0, 6.0, name="AT500",
                    source="Leica Absolute Tracker AT500 User Manual, 2.8.2 Laser Tracker Subsystem Specifications "
                           "(ISO 10360-10:2021 Annex D): e_ADM, e_T")
TRACKER_MODELS = {s.name: s for s in (AT960, AT500)}  # the named instruments (module docstring: sources)
# what a laser tracker's law can be, MPE at 1 m (um): far outside it, the numbers are in another unit (mm, nm)
PLAUSIBLE_RADIAL_UM = (0.05, 1000.0)
PLAUSIBLE_TRANSVERSE_UM = (1.0, 1000.0)
NUMBERS_FORM = "four numbers a_r,b_r,a_t,b_t (MPE along and across the beam, um and um/m) and an optional k"


def tracker_model(text: str, what: str | None = "`tracker_model`") -> TrackerSpec:
    """A tracker's noise law from a name of ``TRACKER_MODELS`` (case-insensitive) or "a_r,b_r,a_t,b_t[,k]": MPE
    along the beam a_r um + b_r um/m, across it a_t um + b_t um/m, sigma = MPE / k (k > 0, default 2).  Anything
    else is refused with one line (``what`` prefixes it), numbers whose MPE at 1 m is not a laser tracker's too
    (PLAUSIBLE_RADIAL_UM, PLAUSIBLE_TRANSVERSE_UM: mm or nm given as um)."""
    say = (f"{what}: " if what else "")
    names = ", ".join(TRACKER_MODELS)
    key = "".join(str(text).split()).upper().replace("-", "").replace("_", "")
    for name, spec in TRACKER_MODELS.items():
        if key == name.upper():
            return spec
    try:
        v = [float(t) for t in str(text).split(",")]
    except ValueError:
        v = []
    if len(v) not in (4, 5):
        raise InputError(f"{say}expected an instrument ({names}) or {NUMBERS_FORM}, got {text!r}")
    if not all(math.isfinite(x) for x in v) or min(v[:4]) < 0 or (len(v) == 5 and v[4] <= 0):
        raise InputError(f"{say}the terms must be finite and >= 0 and k > 0, got {text!r}")
    at_1m = v[0] + v[1], v[2] + v[3]
    (rl, rh), (tl, th) = PLAUSIBLE_RADIAL_UM, PLAUSIBLE_TRANSVERSE_UM
    if not (rl <= at_1m[0] <= rh and tl <= at_1m[1] <= th):
        raise InputError(f"{say}{text!r} gives an MPE at 1 m of {at_1m[0]:.3g} um along and {at_1m[1]:.3g} um "
                         f"across the beam, not a laser tracker's ({rl:g} to {rh:g} um along, {tl:g} to {th:g} um "
                         f"across): the terms are in um and um/m (not mm or nm)")
    return TrackerSpec(*v)


def as_tracker_model(value, what: str = "`tracker_model`") -> TrackerSpec:
    """A library caller's ``tracker_model``: None (the AT960's law), a TrackerSpec, or text for ``tracker_model``."""
    if value is None:
        return AT960
    if isinstance(value, TrackerSpec):
        return value
    if isinstance(value, str):
        return tracker_model(value, what)
    raise InputError(f"{what}: expected an instrument name, numbers or a TrackerSpec, got {value!r}")


def law_report(used: TrackerSpec, prior: TrackerSpec, source: str, why: str = "",
               obtained_from: str = "the repeated rounds") -> dict:
    """How the JSON answers report the law that weights the readings (diagnose ``noise_model.law``, identify
    ``noise_law``): its MPE terms (um, um/m; sigma = MPE / k), the prior's instrument (its name or "given
    numbers"), ``source`` "prior" (the prior's law as it is) or "data" (estimated from the repeated rounds, the
    prior's shape rejected; ``obtained_from``: from what, in words, tracker_position.ShapeEstimate.source), and how
    it was obtained, in words (+ ``why``)."""
    if source == "prior":
        how = (f"the {prior.name}'s published MPE ({prior.source})" if prior.name else
               "the numbers given (`tracker_model`)")
    else:
        how = f"estimated from {obtained_from}: {prior.whose} shape does not fit them"
    return {**{k: round(float(v), 6) for k, v in used.mpe().items()}, "instrument": prior.label,
            "source": source, "obtained": how + (f"; {why}" if why else "")}


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
    return draw(covariance(points, tracker, spec), rng)


def draw(cov: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """One noise draw (..., 3) mm of the covariances ``cov`` (..., 3, 3) mm^2 (``sample``'s, or a diagnosis' law:
    mtcal.diagnose.calibrate)."""
    return np.einsum("...ij,...j->...i", np.linalg.cholesky(cov), rng.standard_normal(np.shape(cov)[:-1]))


def parse_xyz(text: str, what: str | None = "tracker position") -> np.ndarray:
    """'x,y,z' in mm (CLI --tracker) -> array (3,) of finite numbers; ``what`` prefixes the message."""
    try:
        v = np.array([float(t) for t in text.split(",")])
    except ValueError:
        v = np.array([])
    if v.shape != (3,) or not np.isfinite(v).all():
        raise InputError((f"{what}: " if what else "") + f"expected three numbers x,y,z in mm, got {text!r}")
    return v
