"""Result types of identification: one position (PositionResult), one axis over its rounds (AxisResult), the whole
recording (IdentifyResult).  Errors in mm (E_X?, E_Y?, E_Z?) and rad (E_A?, E_B?, E_C?), in the axis' own frame;
positions in mm or deg."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mtcal import _tails
from mtcal.identify import fitting
from mtcal.model.errormodel import ErrorModel
from mtcal.model.fits import Fit


@dataclass
class PositionResult:
    errors: np.ndarray  # (..., 6) E_X, E_Y, E_Z mm; E_A, E_B, E_C rad
    residuals: np.ndarray  # (..., 3 n) mm
    covariance: np.ndarray | None  # (..., 6, 6) with a tracker position
    names: tuple[str, ...]

    @property
    def residual_rms(self) -> np.ndarray:
        return np.sqrt(np.mean(self.residuals**2, axis=-1))

    def as_dict(self) -> dict[str, np.ndarray]:
        return {n: self.errors[..., i] for i, n in enumerate(self.names)}


# ----------------------------------------------------------------------------- a recording
@dataclass
class AxisResult:
    """Identified errors of one axis: its six error motions at every measured position, per round.

    Statistics over rounds (Type A, the thesis' eqs. 2.45-2.49) are properties: ``mean``, ``std`` (experimental
    standard deviation, eq. 2.47), ``std_mean`` (of the mean, eq. 2.49), ``n`` (rounds per position).

    Attributes
    ----------
    axis : str
        The axis (a name of the machine's axes).
    positions : numpy.ndarray, shape (n_positions,)
        Measured positions, mm or deg.
    rounds : numpy.ndarray of int, shape (n_rounds,)
        The round numbers.
    points : tuple of str
        The reflectors used.
    per_round : numpy.ndarray, shape (n_rounds, n_positions, 6)
        Each round's estimate of the six error motions (``names``), mm and rad; NaN where a round lacks a position.
    residual_rms : numpy.ndarray, shape (n_positions,)
        RMS residual of the readings over all passes, mm.
    sigma_pred : numpy.ndarray, shape (n_positions, 6)
        Predicted standard deviation of one round's value (from the noise law or the residuals), mm and rad.
    names : tuple of str
        ISO 230-1 names of the six error motions, e.g. ``("E_XX", "E_YX", "E_ZX", "E_AX", "E_BX", "E_CX")``.
    reference_position : float
        The position the errors are zero at (closest to zero), mm or deg.
    weighted : bool
        Whether the fit weighted the readings by the tracker's noise law.
    lines : dict
        Reference straight lines of the straightness errors (mtcal.identify.fitting).
    reversal : numpy.ndarray, shape (n_positions, 6), or None
        Mean over rounds of (+ pass) - (- pass) when bidirectional, else None.
    fits : dict of str to mtcal.model.fits.Fit
        The fitted function of each error (what compensation evaluates).
    covariance : numpy.ndarray or None
        Covariance (n_positions * 6, n_positions * 6) of the joint fit's estimate; None for three-point.
    fit_variance_factor : float
        The data's precision relative to ``covariance`` (joint fit: min(1, Birge ratio squared)).
    """

    axis: str
    positions: np.ndarray
    rounds: np.ndarray
    points: tuple[str, ...]
    per_round: np.ndarray
    residual_rms: np.ndarray  # (n_positions,) mm, over all passes
    sigma_pred: np.ndarray  # (n_positions, 6): predicted std of one round's value (noise model or residuals)
    names: tuple[str, ...]
    reference_position: float
    weighted: bool
    lines: dict[str, dict] = field(default_factory=dict)  # reference straight lines of straightness errors
    reversal: np.ndarray | None = None  # (n_positions, 6): mean over rounds of (+ pass) - (- pass), if bidirectional
    fits: dict[str, Fit] = field(default_factory=dict)  # mtcal.model.fits
    covariance: np.ndarray | None = None  # (n_positions * 6, n_positions * 6) of the joint fit's estimate, else None
    # the data's precision relative to ``covariance`` (joint fit: min(1, Birge ratio^2)): the functions are sized by
    # the scatter the readings show, not by the noise law assumed (noise-free readings give the truth back)
    fit_variance_factor: float = 1.0

    @property
    def n(self) -> np.ndarray:
        return np.isfinite(self.per_round[..., 0]).sum(axis=0)

    @property
    def mean(self) -> np.ndarray:
        return np.nanmean(self.per_round, axis=0)

    @property
    def std(self) -> np.ndarray:
        n = self.n[:, None]
        dev = np.where(np.isfinite(self.per_round), self.per_round - self.mean, 0.0)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(n >= 2, np.sqrt((dev**2).sum(axis=0) / (n - 1)), np.nan)

    @property
    def std_mean(self) -> np.ndarray:
        """Type A over rounds (eq. 2.49); for the joint fit its covariance (Birge-scaled), since its rounds may come
        from stations of different precision and share the reflectors' and alignments' estimate."""
        if self.covariance is not None:
            return np.sqrt(np.diagonal(self.covariance).reshape(len(self.positions), 6))
        return self.std / np.sqrt(self.n[:, None])

    @property
    def dof(self) -> np.ndarray:
        """Degrees of freedom of ``std_mean`` per position: n - 1 rounds for the three-point method's Type A;
        infinite for the joint fit, whose covariance comes from the noise law (GUM 6.3.3, G.3)."""
        if self.covariance is not None:
            return np.full(len(self.positions), np.inf)
        return np.where(self.n >= 2, self.n - 1.0, np.nan)

    @property
    def k95(self) -> np.ndarray:
        """Coverage factor per position for a 95 % interval of the mean: Student's t_0.975(dof) (GUM G.3.2; 4.30
        for 3 rounds, 3.18 for 4, where +-2 sigma would cover 82 % and 86 %), 1.96 for the joint fit."""
        with np.errstate(invalid="ignore"):
            return _tails.t_ppf(0.975, self.dof)

    @property
    def u95(self) -> np.ndarray:
        """Expanded uncertainty (n_positions, 6), mm and rad: half-width of the 95 % interval of each mean."""
        return self.k95[:, None] * self.std_mean

    def values(self, name: str, corrected: bool = True) -> np.ndarray:
        """Mean per position of one error; straightness with its reference-line slope removed if ``corrected``."""
        v = self.mean[:, self.names.index(name)]
        if corrected and name in self.lines:
            v = v - self.lines[name]["slope"] * self.positions
        return v

    def to_json(self) -> dict:
        mean, std, sm, u95 = self.mean, self.std, self.std_mean, self.u95
        return {"positions": self.positions.tolist(), "rounds": self.rounds.tolist(), "points": list(self.points),
                "reference_position": self.reference_position, "n": self.n.tolist(),
                "dof": [None if not np.isfinite(d) else float(d) for d in self.dof],
                "k95": [None if not np.isfinite(k) else float(k) for k in self.k95],
                "errors": {nm: {"mean": mean[:, i].tolist(), "std": std[:, i].tolist(), "std_mean": sm[:, i].tolist(),
                                "u95": u95[:, i].tolist()} for i, nm in enumerate(self.names)},
                "residual_rms": self.residual_rms.tolist(),
                "reference_lines": self.lines, "fits": {n: f.to_dict() for n, f in self.fits.items()},
                **({} if self.reversal is None else
                   {"reversal": {nm: self.reversal[:, i].tolist() for i, nm in enumerate(self.names)}})}


@dataclass
class IdentifyResult:
    """What ``identify`` found: per axis the error motions with their statistics, the squareness, and the model.

    Units: mm and rad (errors), mm or deg (positions).  ``to_json()`` is the JSON answer of `mtcal identify`.

    Attributes
    ----------
    axes : dict of str to AxisResult
        Per measured axis, its error motions at every position (per round and their statistics).
    squareness : dict of str to float
        Squareness errors by ISO 230-1 name (``E_C0Y``, ``E_B0Z``, ``E_A0Z``), rad, right-hand convention of
        docs/design.md.
    model : ErrorModel
        The error model (tables, fitted functions, constants); ``model.meta`` says how it was made (method,
        ``tracker_estimated``, ``noise_law``, ``worth``, ``warnings``).
    warnings : list of str
        What the user should know (gross errors left out, a model that may make the machine worse, ...).
    reference : str
        The reference straight-line method (least-squares, end-point, minimum-zone).
    weighted : bool
        Whether the readings were weighted by the tracker's noise law.
    source : str
        The recording's source.
    squareness_stats : dict
        Type A statistics of the squareness over rounds: {name: {rounds, std, std_mean}}.
    method : str
        The estimator used: ``"joint"`` or ``"three-point"``.
    joint : dict or None
        The joint fit's summary (stations, reflectors, chi2, dof), None for three-point.
    data_problems : list of dict
        Gross errors found and left out (mtcal.measurement.screen).
    """

    axes: dict[str, AxisResult]
    squareness: dict[str, float]
    model: ErrorModel
    warnings: list[str]
    reference: str
    weighted: bool
    source: str
    squareness_stats: dict = field(default_factory=dict)  # Type A over rounds: {name: {rounds, std, std_mean}}
    method: str = "three-point"
    joint: dict | None = None  # joint fit: stations (tracker, alignment), reflectors, chi2, dof (JointResult.summary)
    data_problems: list[dict] = field(default_factory=list)  # gross errors left out (mtcal.measurement.screen)

    def to_json(self) -> dict:
        return {"source": self.source, "method": self.method, **({"joint": self.joint} if self.joint else {}),
                "units": {"length": "mm", "angle": "rad", "position": "mm or deg"},
                "weighted": self.weighted, "reference": self.reference,
                "axes": {a: r.to_json() for a, r in self.axes.items()},
                "squareness": self.squareness, "squareness_type_a": self.squareness_stats,
                "squareness_convention": fitting.SQUARENESS_CONVENTION,
                **{k: self.model.meta[k] for k in ("tracker_estimated", "noise_law") if k in self.model.meta},
                **({"data_problems": self.data_problems} if self.data_problems else {}),
                "warnings": self.warnings}
