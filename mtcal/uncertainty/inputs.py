"""The input quantities of the Monte Carlo (GUM Supplement 1, 6.4): what a trial draws, with its defaults and their
sources.  Lengths in mm, the tracker's law as mtcal.measurement.tracker states it.

* Each reading: the tracker's noise law (radial and transverse, a + b L), about that reading's tracker,
  independent per reading; a reading's PDF is Gaussian centred on the value recorded (GUM-S1 6.4.7).  By default
  (``noise`` None) the law identify weighted by (its model's ``noise_law``: the prior's, the AT960's unless
  `tracker_model` names another, or the data's where the repeated rounds are shaped otherwise), scaled up by the
  joint fit's Birge ratio when the readings scatter more than that law says (as identify's covariance is); the
  ratio comes from thousands of degrees of freedom, so its own uncertainty is left out (mtcal.uncertainty.run).
* The tracker's length scale (per station and trial): the refractive index of air from the air temperature and
  pressure the tracker's weather station reads.  Edlen: dn/dT = -0.93 ppm/K, dn/dp = +0.27 ppm/hPa; a station
  read to u(T) = 0.3 K and u(p) = 0.5 hPa (typical of a tracker's weather station; Leica AT960 data sheet: air
  temperature +-0.3 K, pressure +-1 hPa as rectangular bounds) gives u(scale) = sqrt((0.93 * 0.3)^2 +
  (0.27 * 0.5)^2) ppm = 0.31 ppm about the tracker.
* Reflector centring (per reflector and trial, isotropic): a 1.5" red-ring reflector's centring +-2.5 um (Leica
  RRR 1.5" data sheet; rectangular bound: u = 2.5 / sqrt(3) = 1.44 um per axis) - a constant offset of that
  reflector in every reading.
* Material temperature (per trial): the machine structure's expansion about its origin, alpha u(T), off by
  default (alpha 11.5e-6 /K for steel and u(T) in K to be given: mtcal cannot know the shop).
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

from mtcal.measurement import tracker as trk

EDLEN_PPM_PER_K = 0.93
EDLEN_PPM_PER_HPA = 0.27


@dataclass(frozen=True)
class Inputs:
    """The Monte Carlo's input quantities (module docstring); 0 switches a term off."""

    noise: trk.TrackerSpec | None = None  # None: the law identify used (module docstring)
    noise_how: str = ""
    air_temperature_u_k: float = 0.3
    air_pressure_u_hpa: float = 0.5
    centring_u_um: float = 2.5 / 3 ** 0.5
    alpha_per_k: float = 11.5e-6
    material_temperature_u_k: float = 0.0

    @property
    def scale_u(self) -> float:
        """Standard uncertainty of the tracker's length scale (1), from the weather station's u(T), u(p)."""
        return ((EDLEN_PPM_PER_K * self.air_temperature_u_k) ** 2
                + (EDLEN_PPM_PER_HPA * self.air_pressure_u_hpa) ** 2) ** 0.5 * 1e-6

    def only(self, term: str) -> "Inputs":
        """These inputs with every term but ``term`` ("noise", "scale", "centring", "material") switched off: one
        line of the uncertainty budget (one-at-a-time Monte Carlo)."""
        zero_noise = trk.TrackerSpec(0.0, 0.0, 0.0, 0.0, self.noise.k if self.noise else 2.0)
        return Inputs(self.noise if term == "noise" else zero_noise, self.noise_how if term == "noise" else "",
                      self.air_temperature_u_k if term == "scale" else 0.0,
                      self.air_pressure_u_hpa if term == "scale" else 0.0,
                      self.centring_u_um if term == "centring" else 0.0, self.alpha_per_k,
                      self.material_temperature_u_k if term == "material" else 0.0)

    def to_dict(self) -> dict:
        d = asdict(self)
        d["noise"] = None if self.noise is None else {**self.noise.mpe(), "instrument": self.noise.label}
        d["tracker_scale_u_ppm"] = self.scale_u * 1e6
        return d


TERMS = ("noise", "scale", "centring", "material")
