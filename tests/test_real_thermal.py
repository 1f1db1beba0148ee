"""Issue 24, part 6b: the diagnosis' temperature-driven drift (c dT) against its drift in time alone, on a real
46 h spindle thermal drift, out of sample.

Data: tests/data/fl_thermal/fl_thermal_2min.csv (1 390 rows, every 8th row of data/data.xlsx of the public
repository CAIVIAC/FL_THERMAL at 9fa40bd, MIT; tests/data/fl_thermal/README.md).  Each of the five displacement
channels is fitted on rows 0-555 (t < 18.5 h, the first 40 %) and judged on rows 556-1389 (18.5-46.3 h) by:
* time only, A (1 - exp(-(t - t0)/tau)): generated ``thermal_drift_signature``, tau scanned over the diagnosis'
  TAUS_S and refined as it does (mtcal.diagnose.effects.thermal_drift);
* temperature, c dT: generated ``thermal_temperature_drift_signature``, dT = T - T(first row) of one sensor
  (mtcal.diagnose.effects.thermal_temperature_drift), the sensor with the least training RMS (chosen on rows
  0-555 only), or t5 (the spindle's, by its response).
The models and the fits are benchmarks/real_thermal.py's (which prints the table of
docs/guide/real-data-thermal.md); the figures asserted are the page's, with their margins.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from mtcal.diagnose.effects import TAUS_S
from mtcal.generated import signatures_numpy as S

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import real_thermal as R  # noqa: E402


@pytest.fixture(scope="module")
def data():
    return R.load()


@pytest.fixture(scope="module")
def rows(data):
    return {r["channel"]: r for r in R.run(data)}


def ratio(r: dict, key: str) -> float:
    return r[key].rms_out_um / r["time"].rms_out_um


def test_the_extract_is_what_its_readme_says(data):
    here = Path(R.CSV).parent
    assert data.y.shape == (1390, 5) and data.T.shape == (1390, 16)
    assert np.all(np.diff(data.t) == 120.0) and data.t[0] == 0.0 and data.t[-1] == 166680.0
    assert int(data.train.sum()) == 556 and data.t[~data.train][0] == 66720.0  # 18.5 h
    assert set(np.unique(data.rpm)) == {0, 500, 1250, 1500, 2500, 3500, 3750, 4500, 5000}
    assert "Copyright (c) 2024 CAIVIAC" in (here / "LICENSE").read_text()
    assert "9fa40bd4c3d8a67b802c19719ff9b20bbba085d7" in (here / "README.md").read_text()
    assert R.CSV.stat().st_size < 300_000


def test_the_columns_are_the_generated_signatures(data):
    """The two design columns are the diagnosis' generated signatures (any channel direction: both are scalar x I)."""
    dT = data.T[:, 3] - data.T[0, 3]
    u = np.array([0.6, 0.0, 0.8])  # a channel along any unit direction sees the same column
    np.testing.assert_allclose(S.thermal_temperature_drift_signature(dT) @ u @ u, R.temperature_column(dT))
    np.testing.assert_allclose(R.temperature_column(dT), dT)
    tau = TAUS_S[3]
    np.testing.assert_allclose(S.thermal_drift_signature(data.t, tau) @ u @ u, R.time_column(data, tau))
    # the lag's step response is the same signature: a step of 1 K at t_i gives 1 - exp(-(t - t_i)/tau) after it
    step = np.where(data.t >= data.t[100], 1.0, 0.0)
    L = R.lagged(data, step[:, None], tau)[:, 0]
    np.testing.assert_allclose(L, np.where(data.t >= data.t[100], 1 - np.exp(-(data.t - data.t[100]) / tau), 0.0),
                               atol=1e-12)


@pytest.mark.slow
def test_temperature_beats_time_alone_on_the_large_channels(rows):
    """ch3 and ch4 (range -71..+20 um): c dT of t4 (chosen on the training rows) leaves 18.5 and 18.1 um RMS out
    of sample where the time-only drift leaves 32.1 and 32.0 (0.58x, 0.56x); in sample 6.7 / 6.4 against 10.3 /
    10.2.  Over all five channels 14.0 against 21.1 um (0.66x)."""
    for ch in ("ch3", "ch4"):
        r = rows[ch]
        assert r["sensor"] == 3, (ch, r["sensor"])           # t4
        assert r["temp"].rms_out_um < 0.65 * r["time"].rms_out_um, (ch, ratio(r, "temp"))
        assert r["temp"].rms_in_um < 0.7 * r["time"].rms_in_um
        assert r["temp"].rms_out_um < 20.0                     # of a channel whose test part is 30 um RMS
    assert R.pooled(list(rows.values()), "temp", "rms_out_um") < 0.72 * R.pooled(list(rows.values()), "time",
                                                                                 "rms_out_um")


@pytest.mark.slow
def test_one_linear_temperature_is_not_enough_on_the_other_channels(rows):
    """The limitation the page states: on ch1, ch2 and ch5 the best training sensor's c dT is worse out of sample
    than the drift in time alone (1.24x, 1.22x, 1.50x) -- and worse than a constant -- and what it leaves on ch3/ch4
    (18 um) is still more than half of what a constant leaves there (30 um)."""
    for ch in ("ch1", "ch2", "ch5"):
        r = rows[ch]
        assert ratio(r, "temp") > 1.1, (ch, ratio(r, "temp"))
        assert r["temp"].rms_out_um > r["const"].rms_out_um
    for ch in ("ch3", "ch4"):
        assert rows[ch]["temp"].rms_out_um > 0.5 * rows[ch]["const"].rms_out_um


@pytest.mark.slow
def test_the_spindle_sensor_helps_the_spindle_channels(rows):
    """t5 chosen a priori (not on the data): 0.85x, 0.85x, 0.88x of the time-only RMS out of sample on ch3, ch4,
    ch5; 1.19x, 1.17x on ch1, ch2."""
    for ch in ("ch3", "ch4", "ch5"):
        assert ratio(rows[ch], "t5") < 0.92, (ch, ratio(rows[ch], "t5"))
    for ch in ("ch1", "ch2"):
        assert ratio(rows[ch], "t5") > 1.1, (ch, ratio(rows[ch], "t5"))


def test_a_lag_on_the_temperature_helps_where_the_temperature_does(rows):
    """Not a model of the diagnosis: c dT with dT through a first-order lag (the thermal_drift step response, tau
    from TAUS_S, chosen on the training rows) leaves 13.7 / 13.4 um on ch3 / ch4 (t4, 1800 s: 0.43x, 0.42x of the
    time-only drift, against 0.58x, 0.56x unlagged); it does not help ch1, ch2, ch5."""
    for ch in ("ch3", "ch4"):
        r = rows[ch]
        assert (r["lag_sensor"], r["lag_tau_s"]) == (3, 1800.0)
        assert r["lag"].rms_out_um < 0.5 * r["time"].rms_out_um
        assert r["lag"].rms_out_um < 0.8 * r["temp"].rms_out_um
    for ch in ("ch1", "ch2", "ch5"):
        assert ratio(rows[ch], "lag") > 1.1
