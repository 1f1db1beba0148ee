"""The thermal vocabulary: the inputs every thermal model of mtcal is built from, once.

* ``temperature_rise(time_s, T)``: dT = T - T(first reading in time), K -- what ``mtcal diagnose`` calls the
  temperature rise of a tracker recording's ``temperature_c`` (thermal_temperature);
* ``warm_up(dt_s, tau_s)``: the warm-up step response 1 - exp(-dt/tau), the generated
  ``thermal_drift_signature`` (derive/; the diagnosis' thermal_drift);
* ``first_order_lag(time_s, x, tau_s)``: x through a first-order lag of time constant tau, each reading held over
  the interval that ends at it and followed by ``warm_up`` (what a controller that reads the input once a period
  and updates its state does): y_i = y_(i-1) + w(t_i - t_(i-1)) (x_i - y_(i-1)), y_0 = x_0 -- the body warming
  towards the temperature a sensor reads, or towards the heat the spindle speed puts in;
* ``recording_rise(rec)``: a tracker recording's (mtcal.measurement.recordings) ``temperature_c`` as dT, the input
  a thermal model (or the diagnosis' thermal_temperature) reads it with;
* ``Term``: one input column of a model: a sensor's dT, its lag, or the lagged spindle speed (krpm).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mtcal.errors import InputError
from mtcal.generated import signatures_numpy as S

SPEED = "spindle"  # the input name of the spindle speed


def warm_up(dt_s: np.ndarray, tau_s: float) -> np.ndarray:
    """1 - exp(-dt/tau): the generated warm-up step response (thermal_drift_signature, any direction)."""
    return S.thermal_drift_signature(np.asarray(dt_s, float), float(tau_s))[..., 0, 0]


def temperature_rise(time_s: np.ndarray, temperature_c: np.ndarray, reference_c: float | None = None) -> np.ndarray:
    """dT = T - T_ref (K), T_ref the reading first in time unless given; non-finite readings refused."""
    T = np.asarray(temperature_c, float)
    if not np.isfinite(T).all():
        raise InputError("a temperature reading is not finite")
    ref = T[int(np.argmin(time_s))] if reference_c is None else reference_c
    return T - ref


def recording_rise(rec, reference_c: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(time_s, dT in K) of a tracker recording's ``temperature_c``, dT = T - T_ref: T_ref the first reading in
    time (the diagnosis' dT), or a model's ``reference_c`` of that sensor (to compensate with it); refused, naming
    the first reading without one, when a reading has no time or no temperature."""
    t, T = np.asarray(rec.time_s, float), np.asarray(rec.temperature_c, float)
    bad = np.flatnonzero(~(np.isfinite(t) & np.isfinite(T)))
    if bad.size:
        raise InputError("a thermal model needs time_s and temperature_c on every reading", rec.source,
                         int(rec.line[bad[0]]))
    return t, temperature_rise(t, T, reference_c)


def first_order_lag(time_s: np.ndarray, x: np.ndarray, tau_s: float, start: float | None = None) -> np.ndarray:
    """x (n, ...) through a first-order lag of time constant ``tau_s`` (module docstring); ``start`` the lag's
    state at the first reading (default: x_0, in equilibrium)."""
    t = np.asarray(time_s, float)
    w = warm_up(np.diff(t), tau_s)
    x = np.asarray(x, float)
    w = w.reshape((-1,) + (1,) * (x.ndim - 1))
    y = np.empty_like(x)
    y[0] = x[0] if start is None else start
    for i in range(1, len(x)):
        y[i] = y[i - 1] + w[i - 1] * (x[i] - y[i - 1])
    return y


@dataclass(frozen=True)
class Term:
    """One input column: ``dT`` of a sensor (tau None), its first-order lag (tau s), or the spindle speed's lag
    (input ``SPEED``, krpm)."""

    input: str
    tau_s: float | None = None

    @property
    def label(self) -> str:
        what = "speed (krpm)" if self.input == SPEED else f"dT {self.input} (K)"
        return what if self.tau_s is None else f"{what} lagged {self.tau_s:g} s"

    def column(self, time_s: np.ndarray, rise: dict[str, np.ndarray], rpm: np.ndarray | None) -> np.ndarray:
        """The column over readings: ``rise`` the sensors' dT, ``rpm`` the spindle speed."""
        x = rpm / 1000.0 if self.input == SPEED else rise[self.input]
        return x if self.tau_s is None else first_order_lag(time_s, x, self.tau_s)

    def to_dict(self) -> dict:
        return {"input": self.input, "tau_s": self.tau_s}
