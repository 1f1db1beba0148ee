"""A real spindle thermal drift against the diagnosis' two thermal models, out of sample (issue 24, part 6b).

Data: tests/data/fl_thermal/fl_thermal_2min.csv, an extract of data/data.xlsx of the public repository
CAIVIAC/FL_THERMAL (MIT; tests/data/fl_thermal/README.md): 46.3 h, five displacement channels (um), 16
temperatures (degC), the spindle speed (rpm), one row every 2 min.

Each channel is fitted, on the first 40 % of the run only, by the two models that ``mtcal diagnose`` names for a
drift of the spindle side, their columns taken from the generated signatures (generated/signatures_numpy.py):

* **time only** (``thermal_drift``, mtcal.diagnose.effects.thermal_drift): A (1 - exp(-(t - t0)/tau)),
  ``thermal_drift_signature``; t0 the record's start, tau the best of ``TAUS_S`` then refined in
  [tau/1.5, tau*1.5] within 60 s .. 24 h, as mtcal.diagnose.selection.refine does;
* **temperature** (``thermal_temperature``, mtcal.diagnose.effects.thermal_temperature_drift): c dT (mm/K),
  ``thermal_temperature_drift_signature``; dT = T - T(first reading) of one recorded temperature, as
  mtcal.diagnose.candidates._temperature builds it.

Both have an intercept (the channel's zero; in a campaign the base's alignment unknowns absorb it).  The
signatures are dT I and (1 - exp(-dt/tau)) I (3 x 3): a channel along any direction u gets the same column, so the
column is the signature's x-x entry (the source does not give the channels' directions).  The temperature is
either the sensor that fits the channel best on the training part (chosen there only) or t5, the spindle's
sensor by its response (5-12 K within an hour of each spindle start, back when it stops; the source gives no
sensor positions).

Also measured (not a model of the diagnosis): the same c dT with dT passed through a first-order lag, the
thermal_drift's step response 1 - exp(-dt/tau) (same signature, same ``TAUS_S``) convolved with dT's increments;
sensor and tau chosen on the training part.

Run: ``MPLBACKEND=Agg python benchmarks/real_thermal.py [--splits] [--plot docs/img/fl_thermal.png]``: prints the
tables of docs/guide/real-data-thermal.md (RMS of the residual in um, in sample / out of sample).
"""
from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import optimize

from mtcal.diagnose.effects import TAUS_S
from mtcal.generated import signatures_numpy as S

CSV = Path(__file__).resolve().parents[1] / "tests" / "data" / "fl_thermal" / "fl_thermal_2min.csv"
TRAIN = 0.4          # share of the run (rows, in time order) the models are fitted on
SPINDLE_SENSOR = 4   # t5 (0-based column of the temperatures)
TAU_RANGE = (60.0, 86400.0)  # mtcal.diagnose.effects.thermal_drift: refine_range


@dataclass
class Data:
    t: np.ndarray      # (n,) s
    rpm: np.ndarray    # (n,)
    y: np.ndarray      # (n, 5) mm (the file's um / 1000)
    T: np.ndarray      # (n, 16) degC
    names: list[str]   # channel names
    train: np.ndarray  # (n,) bool: the first TRAIN of the rows


def load(path: Path = CSV, train: float = TRAIN) -> Data:
    header = path.read_text().split("\n", 1)[0].split(",")
    a = np.loadtxt(path, delimiter=",", skiprows=1)
    ch = [i for i, h in enumerate(header) if h.startswith("ch")]
    tc = [i for i, h in enumerate(header) if h.startswith("t") and h.endswith("_c")]
    n = len(a)
    return Data(a[:, header.index("time_s")], a[:, header.index("spindle_rpm")], a[:, ch] / 1000.0, a[:, tc],
                [header[i].removesuffix("_um") for i in ch], np.arange(n) < round(train * n))


def time_column(d: Data, tau: float) -> np.ndarray:
    """thermal_drift: the warm-up from the record's start, d x / d A_x."""
    return S.thermal_drift_signature(d.t - d.t[0], tau)[:, 0, 0]


def temperature_column(dT: np.ndarray) -> np.ndarray:
    """thermal_temperature (drift): d x / d c_x = dT."""
    return S.thermal_temperature_drift_signature(dT)[:, 0, 0]


def lagged(d: Data, dT: np.ndarray, tau: float) -> np.ndarray:
    """dT through a first-order lag: each increment of dT followed by the thermal_drift step response."""
    dt = np.maximum(d.t[:, None] - d.t[None, :], 0.0)          # (reading, increment)
    u, inv = np.unique(dt, return_inverse=True)                  # the signature once per distinct delay
    step = S.thermal_drift_signature(u, tau)[:, 0, 0][inv].reshape(dt.shape)
    inc = np.diff(dT, prepend=dT[:1], axis=0)
    return step @ inc


@dataclass
class Fit:
    rms_in_um: float
    rms_out_um: float
    params: np.ndarray
    residual_um: np.ndarray


def fit(d: Data, col: np.ndarray, y: np.ndarray) -> Fit:
    """Least squares of y on [1, col] over the training rows; RMS of the residual in and out of sample (um)."""
    X = np.column_stack([np.ones(len(y)), col])
    p, *_ = np.linalg.lstsq(X[d.train], y[d.train], rcond=None)
    r = (y - X @ p) * 1000.0
    return Fit(float(np.sqrt(np.mean(r[d.train] ** 2))), float(np.sqrt(np.mean(r[~d.train] ** 2))), p, r)


def time_model(d: Data, y: np.ndarray) -> tuple[float, Fit]:
    """The time-only drift: tau scanned over TAUS_S, then refined as the diagnosis does (training rows only)."""
    tau = min(TAUS_S, key=lambda v: fit(d, time_column(d, v), y).rms_in_um)
    a, b = max(TAU_RANGE[0], tau / 1.5), min(TAU_RANGE[1], tau * 1.5)
    res = optimize.minimize_scalar(lambda lv: fit(d, time_column(d, math.exp(lv)), y).rms_in_um,
                                   bounds=(math.log(a), math.log(b)), method="bounded", options={"xatol": 1e-3})
    scanned, refined = fit(d, time_column(d, tau), y), fit(d, time_column(d, math.exp(res.x)), y)
    return (math.exp(res.x), refined) if refined.rms_in_um < scanned.rms_in_um else (tau, scanned)


def rise(d: Data, k: int) -> np.ndarray:
    return d.T[:, k] - d.T[0, k]


def temperature_model(d: Data, y: np.ndarray, sensor: int | None = None) -> tuple[int, Fit]:
    """c dT of one sensor: the given one, or the one with the least training RMS."""
    ks = range(d.T.shape[1]) if sensor is None else [sensor]
    k = min(ks, key=lambda k: fit(d, temperature_column(rise(d, k)), y).rms_in_um)
    return k, fit(d, temperature_column(rise(d, k)), y)


def lagged_model(d: Data, y: np.ndarray) -> tuple[int, float, Fit]:
    """c (dT lagged by tau): sensor and tau (TAUS_S) with the least training RMS."""
    best = None
    for tau in TAUS_S:
        L = lagged(d, d.T - d.T[0], tau)
        for k in range(d.T.shape[1]):
            f = fit(d, temperature_column(L[:, k]), y)
            if best is None or f.rms_in_um < best[2].rms_in_um:
                best = (k, tau, f)
    return best


def run(d: Data | None = None) -> list[dict]:
    d = d or load()
    rows = []
    for j, name in enumerate(d.names):
        y = d.y[:, j]
        tau, ft = time_model(d, y)
        k, fT = temperature_model(d, y)
        _, f5 = temperature_model(d, y, SPINDLE_SENSOR)
        kl, taul, fl = lagged_model(d, y)
        const = fit(d, np.zeros(len(y)), y)
        rows.append(dict(channel=name, time=ft, tau_s=tau, temp=fT, sensor=k, t5=f5, lag=fl, lag_sensor=kl,
                         lag_tau_s=taul, const=const))
    return rows


def pooled(rows: list[dict], key: str, part: str) -> float:
    return float(np.sqrt(np.mean([getattr(r[key], part) ** 2 for r in rows])))


def table(rows: list[dict]) -> str:
    out = ["| channel | time only (tau) | c dT, best sensor on training | c dT, t5 | lagged c dT (sensor, tau) | "
           "constant |", "|---|---|---|---|---|---|"]

    def io(f: Fit) -> str:
        return f"{f.rms_in_um:.2f} / {f.rms_out_um:.2f}"

    for r in rows:
        out.append(f"| {r['channel']} | {io(r['time'])} ({r['tau_s']:.0f} s) | {io(r['temp'])} (t{r['sensor'] + 1}) "
                   f"| {io(r['t5'])} | {io(r['lag'])} (t{r['lag_sensor'] + 1}, {r['lag_tau_s']:.0f} s) "
                   f"| {io(r['const'])} |")
    out.append("| all five (RMS) | " + " | ".join(
        f"{pooled(rows, k, 'rms_in_um'):.2f} / {pooled(rows, k, 'rms_out_um'):.2f}"
        for k in ("time", "temp", "t5", "lag", "const")) + " |")
    out.append("| out of sample / time only | 1 | " + " | ".join(
        " / ".join(f"{r[k].rms_out_um / r['time'].rms_out_um:.2f}" for r in rows)
        for k in ("temp", "t5", "lag", "const")) + " |")
    return "\n".join(out)


def splits(d: Data, shares=(0.3, 0.4, 0.5, 0.6)) -> str:
    """The out-of-sample ratios (c dT / time only) for other training shares (no lag: quick)."""
    out = ["| trained on | c dT, best sensor on training: ch1 .. ch5 (sensor) | c dT, t5: ch1 .. ch5 | "
           "all five (best; t5) |", "|---|---|---|---|"]
    for share in shares:
        dd = Data(d.t, d.rpm, d.y, d.T, d.names, np.arange(len(d.t)) < round(share * len(d.t)))
        best, t5, tm = [], [], []
        for j in range(len(d.names)):
            _, ft = time_model(dd, d.y[:, j])
            k, fT = temperature_model(dd, d.y[:, j])
            _, f5 = temperature_model(dd, d.y[:, j], SPINDLE_SENSOR)
            tm.append(ft.rms_out_um)
            best.append((fT.rms_out_um, k))
            t5.append(f5.rms_out_um)
        pool = [float(np.sqrt(np.mean(np.square(v)))) for v in (tm, [b for b, _ in best], t5)]
        out.append(f"| first {share:.0%} | " + " / ".join(f"{b / t:.2f} (t{k + 1})" for (b, k), t in zip(best, tm))
                   + " | " + " / ".join(f"{b / t:.2f}" for b, t in zip(t5, tm))
                   + f" | {pool[1] / pool[0]:.2f}; {pool[2] / pool[0]:.2f} |")
    return "\n".join(out)


def plot(rows: list[dict], d: Data, path: str) -> None:
    import matplotlib.pyplot as plt

    h = d.t / 3600.0
    split = h[d.train][-1]
    fig, ax = plt.subplots(3, 1, figsize=(9, 8), sharex=True, height_ratios=[3, 3, 2])
    for a, j in zip(ax[:2], (2, 0)):
        r = rows[j]
        y = d.y[:, j] * 1000.0
        a.plot(h, y, "k", lw=1.2, label=f"{r['channel']} measured")
        a.plot(h, y - r["time"].residual_um, lw=1, label=f"time only (tau {r['tau_s']:.0f} s)")
        a.plot(h, y - r["temp"].residual_um, lw=1, label=f"c dT (t{r['sensor'] + 1})")
        a.plot(h, y - r["lag"].residual_um, lw=1, ls="--",
               label=f"c dT lagged (t{r['lag_sensor'] + 1}, {r['lag_tau_s']:.0f} s)")
        a.axvline(split, color="grey", ls=":")
        a.set_ylabel("displacement (um)")
        a.legend(fontsize=7, loc="best")
        a.grid(alpha=0.3)
    ax[0].set_title("FL_THERMAL: fitted on the first 40 % (left of the dotted line), judged on the rest", fontsize=9)
    b = ax[2].twinx()
    ax[2].step(h, d.rpm, "grey", lw=0.8, where="post")
    ax[2].set_ylabel("spindle (rpm)")
    for k in (3, 4):
        b.plot(h, rise(d, k), lw=1, label=f"t{k + 1} - start")
    b.set_ylabel("dT (K)")
    b.legend(fontsize=7, loc="upper left")
    ax[2].set_xlabel("time (h)")
    fig.tight_layout()
    fig.savefig(path, dpi=80)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--plot", help="write the figure (PNG) here")
    ap.add_argument("--splits", action="store_true", help="also the ratios for training shares 30 .. 60 %%")
    args = ap.parse_args()
    d = load()
    rows = run(d)
    print(f"{CSV.name}: {len(d.t)} rows, fitted on the first {int(d.train.sum())} "
          f"(t < {d.t[~d.train][0] / 3600:.1f} h), judged on the other {int((~d.train).sum())}; "
          "RMS of the residual, um, in sample / out of sample")
    print(table(rows))
    if args.splits:
        print()
        print(splits(d))
    if args.plot:
        plot(rows, d, args.plot)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
