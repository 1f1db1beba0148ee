"""A thermal error model of each displacement channel from the temperatures and the spindle speed's history,
selected and judged out of sample in time.

**Split.** The readings are split once in time: the first ``1 - holdout`` (the training part) and the rest (the
hold-out). Nothing of the hold-out is seen before the model is fixed; rows are never drawn at random.

**Candidates, simple to rich** (``features.Term``): each sensor's dT, its first-order lag for each tau of
``LAGS_S``, the spindle speed's first-order lag (krpm) for each tau, combined linearly with an intercept. Forward
selection adds, one at a time, the term that lowers most the **rolling-origin** RMSE inside the training part:
the model is fitted on the training part up to each origin of ``ORIGINS`` (shares of the training part) and
predicts the next ``ORIGIN_STEP`` of it, the errors of all origins pooled. It stops when the next term lowers that
RMSE by less than ``MIN_GAIN`` (relative) or at ``MAX_TERMS`` terms; zero terms is the constant. A lag longer
than a third of the training part is not a candidate (it cannot be told from a drift in time there).

**Baselines**, fitted on the same training part: the *constant* (the training mean) and the *time-only* warm-up
c + A (1 - exp(-(t - t0)/tau)) (the diagnosis' thermal_drift; tau the best of ``TIME_TAUS_S`` on the training
part).

**The decision: is the channel predictable?** A one-sided test of equal predictive accuracy on the hold-out
against each baseline, in the manner of Diebold and Mariano (1995): the loss differential d_i = e_base,i^2 -
e_model,i^2 of each hold-out reading; null: E[d] <= 0 (the model predicts no better than the baseline),
alternative: E[d] > 0. The error term: d is autocorrelated over hours, so its mean is judged by batch means --
the hold-out cut into ``HOLDOUT_BLOCKS`` contiguous blocks, the blocks' means taken as independent, Student's t
with B - 1 degrees of freedom (assumed: the blocks are longer than the residuals' correlation). The channel is
predictable when both nulls are rejected at ``ALPHA`` (an intersection-union test: each at the full level, no
correction needed). Multiplicity across channels: none -- each channel's decision is its own (its own
compensation), at ALPHA per channel; with m channels up to m ALPHA may be offered wrongly in the worst case. A
channel not predictable gets no compensation. With 8 blocks the test has little power: a model has to win
through most of the hold-out, not in one event.

**Uncertainty of the prediction**: the hold-out RMSE of the model (the standard uncertainty of what is left after
compensation, for conditions like the hold-out's) and the 95th percentile of |e| there; both from one test of one
machine, and from hours that followed the training ones: a different duty cycle can leave more.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from mtcal.errors import InputError
from mtcal.io import file_sha256
from mtcal.thermal.features import SPEED, Term, first_order_lag, temperature_rise, warm_up
from mtcal.thermal.readings import ThermalTest

LAGS_S = (900.0, 1800.0, 3600.0, 7200.0, 14400.0)
ORIGINS = (0.5, 0.6, 0.7, 0.8, 0.9)
ORIGIN_STEP = 0.1
MAX_TERMS = 6
MIN_GAIN = 0.05
TIME_TAUS_S = tuple(float(v) for v in np.geomspace(300.0, 86400.0, 25))
HOLDOUT_BLOCKS = 8
MIN_BLOCK_READINGS = 5
MIN_TRAINING_READINGS = 50
ALPHA = 0.05
KIND = "mtcal thermal model"
log = logging.getLogger("mtcal.thermal")


@dataclass
class ChannelModel:
    """One channel's model, its out-of-sample figures and the decision.

    Attributes
    ----------
    channel, direction : str
        The displacement channel and its direction ('' when not known).
    terms : list of Term
        The inputs chosen (empty: the constant).
    coefficients : list of float
        um per term unit (K, krpm), in the order of ``terms``.
    intercept_um : float
        The model's value when every term is zero.
    rmse_um, r2 : float
        Hold-out RMSE and R^2 (1 - SS_res / SS about the hold-out mean).
    constant_rmse_um, time_only_rmse_um : float
        The baselines' hold-out RMSE (fitted on the same training part).
    time_only_tau_s : float
        The time-only baseline's time constant.
    inner_rmse_um : float
        The rolling-origin RMSE inside the training part that chose the model.
    p_constant, p_time_only : float
        One-sided p-values against each baseline (module docstring).
    predictable : bool
        Both nulls rejected at ``ALPHA``: the model is offered for compensation.
    u_um, u95_um : float
        The prediction's standard uncertainty (hold-out RMSE) and the 95th percentile of |e| on the hold-out.
    reason : str
        The decision in words.
    ranges : list of (float, float)
        Each term's smallest and largest value over the test (what the plausibility guard bounds the offset with).
    """

    channel: str
    direction: str
    terms: list[Term]
    coefficients: list[float]
    intercept_um: float
    rmse_um: float
    r2: float
    constant_rmse_um: float
    time_only_rmse_um: float
    time_only_tau_s: float
    inner_rmse_um: float
    p_constant: float
    p_time_only: float
    predictable: bool
    u_um: float
    u95_um: float
    reason: str
    ranges: list[tuple[float, float]] = field(default_factory=list)
    fitted_um: np.ndarray | None = field(default=None, repr=False)
    baselines_um: dict | None = field(default=None, repr=False)

    @property
    def model(self) -> str:
        return "constant" if not self.terms else " + ".join(t.label for t in self.terms)

    def predict(self, time_s: np.ndarray, rise: dict[str, np.ndarray], rpm: np.ndarray | None = None) -> np.ndarray:
        """The channel's displacement (um) at readings with sensors' dT ``rise`` (K) and spindle speed ``rpm``."""
        out = np.full(len(time_s), self.intercept_um)
        for term, c in zip(self.terms, self.coefficients):
            if term.input == SPEED and rpm is None:
                raise InputError(f"the model of {self.channel} needs the spindle speed")
            if term.input != SPEED and term.input not in rise:
                raise InputError(f"the model of {self.channel} needs temperature {term.input}")
            out += c * term.column(time_s, rise, rpm)
        return out

    def largest_offset_um(self) -> float:
        """The largest |value| the model can give over the ranges its terms took in the test (um)."""
        return abs(self.intercept_um) + sum(abs(c) * max(abs(a), abs(b)) for c, (a, b) in zip(self.coefficients,
                                                                                          self.ranges))

    def to_dict(self) -> dict:
        return {"channel": self.channel, "direction": self.direction, "model": self.model,
                "terms": [t.to_dict() for t in self.terms], "coefficients_um": self.coefficients,
                "intercept_um": self.intercept_um, "rmse_um": self.rmse_um, "r2": self.r2,
                "constant_rmse_um": self.constant_rmse_um, "time_only_rmse_um": self.time_only_rmse_um,
                "time_only_tau_s": self.time_only_tau_s, "inner_rmse_um": self.inner_rmse_um,
                "p_constant": self.p_constant, "p_time_only": self.p_time_only, "predictable": self.predictable,
                "u_um": self.u_um, "u95_um": self.u95_um, "reason": self.reason,
                "ranges": [list(r) for r in self.ranges]}


@dataclass
class ThermalModel:
    """Every channel's model of one thermal test.

    Attributes
    ----------
    source, sha256 : str
        The test file and its hash.
    holdout : float
        The share of the readings held out (the last ones in time).
    split_s : float
        Time of the first hold-out reading.
    reference_c : dict of str to float
        Each sensor's reference temperature (its first reading): dT = T - reference.
    channels : list of ChannelModel
    alpha : float
        The level of each channel's decision.
    notes : list of str
    """

    source: str
    sha256: str
    holdout: float
    split_s: float
    reference_c: dict[str, float]
    channels: list[ChannelModel]
    alpha: float = ALPHA
    notes: list[str] = field(default_factory=list)

    def channel(self, name: str) -> ChannelModel:
        for c in self.channels:
            if c.channel == name:
                return c
        raise InputError(f"the model has no channel {name!r} (it has {', '.join(c.channel for c in self.channels)})")

    def to_dict(self) -> dict:
        return {"kind": KIND, "source": self.source, "sha256": self.sha256, "holdout": self.holdout,
                "split_s": self.split_s, "alpha": self.alpha, "reference_c": self.reference_c,
                "channels": [c.to_dict() for c in self.channels], "notes": self.notes}


def model_from_dict(d: dict, source: str = "model") -> ThermalModel:
    """The model a ``to_dict`` wrote (``mtcal thermal fit -o``)."""
    if not isinstance(d, dict) or d.get("kind") != KIND:
        raise InputError(f"{source}: not a thermal model (no \"kind\": \"{KIND}\"; write one with `mtcal thermal "
                         f"fit FILE -o MODEL.json`)")
    try:
        chans = [ChannelModel(c["channel"], c["direction"], [Term(t["input"], t["tau_s"]) for t in c["terms"]],
                              [float(v) for v in c["coefficients_um"]], float(c["intercept_um"]), c["rmse_um"],
                              c["r2"], c["constant_rmse_um"], c["time_only_rmse_um"], c["time_only_tau_s"],
                              c["inner_rmse_um"], c["p_constant"], c["p_time_only"], bool(c["predictable"]),
                              c["u_um"], c["u95_um"], c["reason"],
                              [(float(a), float(b)) for a, b in c.get("ranges", [])]) for c in d["channels"]]
        return ThermalModel(d["source"], d["sha256"], float(d["holdout"]), float(d["split_s"]),
                            {k: float(v) for k, v in d["reference_c"].items()}, chans, float(d["alpha"]),
                            list(d.get("notes", [])))
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{source}: a thermal model with a missing or bad field ({exc})") from None


def fit_thermal(test: ThermalTest, holdout: float = 0.4, lags_s: tuple[float, ...] | None = None,
                alpha: float = ALPHA) -> ThermalModel:
    """Fit, select and judge a model of every channel of ``test`` (module docstring).

    Parameters
    ----------
    test : ThermalTest
        The readings (mtcal.thermal.readings.read_thermal_test).
    holdout : float, optional
        Share of the readings, the last in time, held out to judge the models (default 0.4).
    lags_s : tuple of float, optional
        Time constants of the lag terms (s); default ``LAGS_S`` (those longer than a third of the training part
        left out, said in the notes); given ones that long are refused.
    alpha : float, optional
        Level of each channel's predictable decision (default 0.05).

    Returns
    -------
    ThermalModel

    Raises
    ------
    mtcal.errors.InputError
        A training part too short, a lag too long for it, a hold-out too short to judge.
    """
    n = len(test)
    n_train = int(round((1.0 - holdout) * n))
    _check_split(test, n_train)
    notes: list[str] = []
    lags = _lags(test, n_train, lags_s, notes)
    ref = {k: float(v[0]) for k, v in test.temperatures.items()}
    rise = {k: temperature_rise(test.time_s, v, ref[k]) for k, v in test.temperatures.items()}
    terms, F = candidates(test.time_s, rise, test.spindle_rpm, lags)
    log.info("%d candidate terms, training on %d readings, judging on %d", len(terms), n_train, n - n_train)
    chans = []
    for name, y in test.channels.items():
        chans.append(_channel(test, name, y, terms, F, n_train, alpha))
        c = chans[-1]
        log.info("%s: %s: RMSE %.3g um out of sample (constant %.3g, time only %.3g): %s", name, c.model, c.rmse_um,
                 c.constant_rmse_um, c.time_only_rmse_um, "predictable" if c.predictable else "not predictable")
    notes.append(f"decision at alpha {alpha:g} per channel against each baseline; hold-out in {HOLDOUT_BLOCKS} "
                 f"blocks of about {(n - n_train) // HOLDOUT_BLOCKS} readings")
    return ThermalModel(test.source, file_sha256(test.source), holdout, float(test.time_s[n_train]), ref, chans,
                        alpha, notes)


def _check_split(test: ThermalTest, n_train: int) -> None:
    n = len(test)
    need = HOLDOUT_BLOCKS * MIN_BLOCK_READINGS
    if n - n_train < need:
        raise InputError(f"hold-out too short to judge: {n - n_train} readings held out, at least {need} needed "
                         f"({HOLDOUT_BLOCKS} blocks of {MIN_BLOCK_READINGS}); a longer test or a larger `holdout`",
                         test.source)
    if n_train < MIN_TRAINING_READINGS:
        raise InputError(f"test too short to fit: {n_train} readings before the hold-out, at least "
                         f"{MIN_TRAINING_READINGS}", test.source)


def _lags(test: ThermalTest, n_train: int, lags_s, notes: list[str]) -> tuple[float, ...]:
    span = float(test.time_s[n_train - 1] - test.time_s[0])
    given = lags_s is not None
    lags = tuple(LAGS_S if lags_s is None else lags_s)
    long = [v for v in lags if 3.0 * v > span]
    if long and given:
        raise InputError(f"test too short for lag {long[0]:g} s: the training part spans {span:g} s, a lag needs "
                         f"three time constants of it (at most {span / 3:g} s)", test.source, test.where(n_train - 1))
    if long:
        notes.append(f"lags {', '.join(f'{v:g}' for v in long)} s left out: longer than a third of the training "
                     f"part ({span:g} s)")
    return tuple(v for v in lags if 3.0 * v <= span)


def candidates(time_s, rise: dict[str, np.ndarray], rpm, lags) -> tuple[list[Term], np.ndarray]:
    """Every candidate term and its column (n, m): the sensors' dT, their lags, the speed's lags."""
    names = list(rise)
    terms = [Term(k) for k in names]
    cols = [np.column_stack([rise[k] for k in names])] if names else []
    for tau in lags:
        if names:
            cols.append(first_order_lag(time_s, cols[0], tau))
            terms += [Term(k, tau) for k in names]
        if rpm is not None and np.ptp(rpm) > 0:
            cols.append(first_order_lag(time_s, rpm / 1000.0, tau)[:, None])
            terms.append(Term(SPEED, tau))
    return terms, (np.column_stack(cols) if cols else np.zeros((len(time_s), 0)))


def _lstsq(X: np.ndarray, y: np.ndarray) -> np.ndarray:
    return np.linalg.lstsq(X, y, rcond=None)[0]


def _design(F: np.ndarray, sel: list[int]) -> np.ndarray:
    return np.column_stack([np.ones(len(F)), F[:, sel]])


def rolling_origin_rmse(F: np.ndarray, y: np.ndarray, sel: list[int], n_train: int) -> float:
    """Pooled RMSE of fitting on the training part up to each origin and predicting the next ORIGIN_STEP."""
    X = _design(F, sel)
    e = []
    for o in ORIGINS:
        a, b = int(round(o * n_train)), int(round(min(o + ORIGIN_STEP, 1.0) * n_train))
        e.append(y[a:b] - X[a:b] @ _lstsq(X[:a], y[:a]))
    return float(np.sqrt(np.mean(np.concatenate(e) ** 2)))


def forward_select(F: np.ndarray, y: np.ndarray, n_train: int) -> tuple[list[int], float]:
    """Forward selection by rolling-origin RMSE (module docstring): the columns chosen and their score."""
    sel, score = [], rolling_origin_rmse(F, y, [], n_train)
    while len(sel) < MAX_TERMS:
        trials = [(rolling_origin_rmse(F, y, sel + [c], n_train), c) for c in range(F.shape[1]) if c not in sel]
        if not trials:
            break
        s, c = min(trials)
        if s > (1.0 - MIN_GAIN) * score:
            break
        sel, score = sel + [c], s
    return sel, score


def time_only(t: np.ndarray, y: np.ndarray, n_train: int) -> tuple[np.ndarray, float]:
    """The time-only baseline c + A warm_up(t - t0, tau) fitted on the training part: its values and tau."""
    best = None
    for tau in TIME_TAUS_S:
        X = np.column_stack([np.ones(len(t)), warm_up(t - t[0], tau)])
        p = _lstsq(X[:n_train], y[:n_train])
        r = float(np.sum((y[:n_train] - X[:n_train] @ p) ** 2))
        if best is None or r < best[0]:
            best = (r, X @ p, tau)
    return best[1], best[2]


def better_than(e_model: np.ndarray, e_base: np.ndarray) -> float:
    """One-sided p-value of 'the model's squared errors are smaller on average' by batch means (module
    docstring)."""
    d = e_base ** 2 - e_model ** 2
    means = np.array([b.mean() for b in np.array_split(d, HOLDOUT_BLOCKS)])
    s = means.std(ddof=1)
    if s == 0:
        return 0.0 if means.mean() > 0 else 1.0
    return float(stats.t.sf(means.mean() / (s / math.sqrt(len(means))), len(means) - 1))


def _channel(test: ThermalTest, name: str, y: np.ndarray, terms: list[Term], F: np.ndarray, n_train: int,
             level: float) -> ChannelModel:
    sel, inner = forward_select(F, y, n_train)
    X = _design(F, sel)
    p = _lstsq(X[:n_train], y[:n_train])
    fitted = X @ p
    const = np.full(len(y), y[:n_train].mean())
    timed, tau = time_only(test.time_s, y, n_train)
    h = slice(n_train, None)
    e, e_c, e_t = y[h] - fitted[h], y[h] - const[h], y[h] - timed[h]
    rmse = lambda r: float(np.sqrt(np.mean(r ** 2)))  # noqa: E731
    pc, pt = (better_than(e, e_c), better_than(e, e_t)) if sel else (1.0, 1.0)
    ok = bool(sel) and pc < level and pt < level
    failed = [f"the {b} (p = {v:.2g})" for b, v in (("constant", pc), ("time-only warm-up", pt)) if v >= level]
    reason = (f"predictable: better out of sample than the constant (p = {pc:.2g}) and the time-only warm-up "
              f"(p = {pt:.2g}), each below {level:.2g}" if ok else
              "not predictable: no term improves the rolling-origin validation on the constant; no compensation "
              "offered" if not sel else
              f"not predictable: not shown better out of sample than {' nor '.join(failed)} at {level:.2g}; "
              f"no compensation offered")
    ss = float(np.sum((y[h] - y[h].mean()) ** 2))
    return ChannelModel(name, test.directions.get(name, ""), [terms[c] for c in sel], [float(v) for v in p[1:]],
                        float(p[0]), rmse(e), 1.0 - float(np.sum(e ** 2)) / ss if ss > 0 else float("nan"),
                        rmse(e_c), rmse(e_t), tau, inner, pc, pt, ok, rmse(e), float(np.quantile(np.abs(e), 0.95)),
                        reason, [(float(F[:, c].min()), float(F[:, c].max())) for c in sel], fitted,
                        {"constant": const, "time only": timed})
