"""Fitted error functions as types: a polynomial on a domain, a harmonic (Fourier) series of one period, or the
table itself (piecewise linear).  Each is called on axis positions (mm or deg) and returns the error (mm or rad);
``to_dict`` / ``fit_from_dict`` are the model JSON's "fit" object (docs/design.md, "Files"):

* {"kind": "polynomial", "coefficients": [c0, c1, ...], "domain": [lo, hi], ...}: numpy.polynomial.Polynomial
  with that domain (x mapped to [-1, 1]);
* {"kind": "harmonic", "period": 360, "a0": v, "cos": [a1, ...], "sin": [b1, ...], ...}:
  a0 + sum_h a_h cos(h w) + b_h sin(h w), w = 2 pi x / period;
* {"kind": "table"}: the function's own table, piecewise linear.

Keys beyond these (how the size was chosen: degree or harmonics, criterion, scores, rms, covariance of the
coefficients) are kept in ``info`` in their order and written back as they came.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar, Union

import numpy as np

from mtcal.errors import InputError


def _nonzero(*arrays) -> bool:
    return any(np.any(np.asarray(a, dtype=float) != 0) for a in arrays)


def uncertainty_columns(fit, x, domain=None) -> np.ndarray | None:
    """The fitted value's uncertainty at ``x`` as independent columns: basis(x) times a square root of the
    coefficients' covariance (``info["covariance"]``, the identification's), so that their outer product is the
    values' covariance with its correlations across positions (a slope's error keeps its sign).

    Parameters
    ----------
    fit : Polynomial, Harmonic or Table
        The fitted function.
    x : array_like
        Axis positions, mm or deg.
    domain : sequence of float, optional
        A polynomial's domain when it has none of its own (the table's range).

    Returns
    -------
    numpy.ndarray, shape (..., k), or None
        The columns (mm or rad); None without a covariance (a table, or a fit made elsewhere).
    """
    c = fit.info.get("covariance") if isinstance(fit, (Polynomial, Harmonic)) else None
    if c is None:
        return None
    b = fit.basis(x, domain) if isinstance(fit, Polynomial) else fit.basis(x)
    c = np.asarray(c, dtype=float)
    if c.shape != (b.shape[-1],) * 2:
        return None
    w, v = np.linalg.eigh((c + c.T) / 2)
    return b @ (v * np.sqrt(np.maximum(w, 0.0)))


@dataclass
class Polynomial:
    """A polynomial c0 + c1 u + ... with u the position mapped from ``domain`` (mm or deg) to [-1, 1].

    Attributes
    ----------
    coefficients : list of float
        c0, c1, ... (mm or rad).
    domain : list of float or None
        [lo, hi] mm or deg; None: the table's range.
    info : dict
        How the size was chosen (degree, criterion, scores, rms, covariance of the coefficients), kept as it came.
    """

    coefficients: list[float]
    domain: list[float] | None = None
    info: dict[str, Any] = field(default_factory=dict)
    kind: ClassVar[str] = "polynomial"

    @property
    def degree(self) -> int:
        return int(self.info.get("degree", len(self.coefficients) - 1))

    def __call__(self, x, domain=None) -> np.ndarray:
        dom = self.domain if self.domain is not None else domain
        return np.polynomial.Polynomial(self.coefficients, domain=dom)(np.asarray(x, dtype=float))

    def basis(self, x, domain=None) -> np.ndarray:
        """d value / d coefficients at ``x`` (..., k): the powers of the mapped position."""
        dom = self.domain if self.domain is not None else domain
        u = np.polynomial.polyutils.mapdomain(np.asarray(x, dtype=float), dom, [-1, 1]) if dom else np.asarray(x)
        return u[..., None] ** np.arange(len(self.coefficients))

    def is_zero(self) -> bool:
        return not _nonzero(self.coefficients)

    def to_dict(self) -> dict:
        out = {"kind": self.kind, "coefficients": self.coefficients}
        if self.domain is not None:
            out["domain"] = self.domain
        return {**out, **self.info}


@dataclass
class Harmonic:
    """A harmonic series a0 + sum_h a_h cos(h w) + b_h sin(h w), w = 2 pi x / period (x and period in deg, or mm).

    Attributes
    ----------
    period : float
        The period, deg (or mm).
    a0 : float
        The constant term (mm or rad).
    cos : list of float
        a_1, a_2, ...
    sin : list of float
        b_1, b_2, ...
    info : dict
        How the size was chosen (harmonics, criterion, scores, covariance), kept as it came.
    """

    period: float
    a0: float
    cos: list[float]
    sin: list[float]
    info: dict[str, Any] = field(default_factory=dict)
    kind: ClassVar[str] = "harmonic"

    @property
    def harmonics(self) -> int:
        return int(self.info.get("harmonics", min(len(self.cos), len(self.sin))))

    def __call__(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        w = 2 * np.pi * x / float(self.period)
        out = np.full(x.shape, float(self.a0))
        for h, (a, b) in enumerate(zip(self.cos, self.sin), start=1):
            out = out + a * np.cos(h * w) + b * np.sin(h * w)
        return out

    def basis(self, x) -> np.ndarray:
        """d value / d [a0, a1, b1, a2, b2, ...] at ``x`` (..., k)."""
        w = 2 * np.pi * np.asarray(x, dtype=float)[..., None] / float(self.period)
        h = np.arange(1, min(len(self.cos), len(self.sin)) + 1)
        return np.concatenate([np.ones(w.shape), np.stack([np.cos(h * w), np.sin(h * w)], -1).reshape(
            w.shape[:-1] + (-1,))], axis=-1)

    def is_zero(self) -> bool:
        return not _nonzero([self.a0], self.cos, self.sin)

    def to_dict(self) -> dict:
        return {"kind": self.kind, "period": self.period, "a0": self.a0, "cos": self.cos, "sin": self.sin,
                **self.info}


@dataclass
class Table:
    """The function's own table, piecewise linear between its positions (evaluated by the function).

    Attributes
    ----------
    info : dict
        Anything else the JSON's "fit" object held, kept as it came.
    """

    info: dict[str, Any] = field(default_factory=dict)
    kind: ClassVar[str] = "table"

    def is_zero(self) -> bool:
        return True

    def to_dict(self) -> dict:
        return {"kind": self.kind, **self.info}


Fit = Union[Polynomial, Harmonic, Table]
KINDS: dict[str, type] = {"polynomial": Polynomial, "harmonic": Harmonic, "table": Table}
FIT_KEYS = {"polynomial": ("coefficients", "domain"), "harmonic": ("period", "a0", "cos", "sin"), "table": ()}


def fit_from_dict(d: dict | Fit | None) -> Fit | None:
    """A fit from the model JSON's "fit" object (checked by mtcal.model.errormodel when read from a file).

    Parameters
    ----------
    d : dict, Polynomial, Harmonic, Table or None
        The "fit" object (``{"kind": "polynomial" | "harmonic" | "table", ...}``), or a fit (returned as it is).

    Returns
    -------
    Polynomial, Harmonic, Table or None

    Raises
    ------
    mtcal.errors.InputError
        An unknown kind.

    Examples
    --------
    >>> from mtcal.model.fits import fit_from_dict
    >>> f = fit_from_dict({"kind": "harmonic", "period": 360, "a0": 0.0, "cos": [0.001], "sin": [0.0]})
    >>> float(f(0.0)), f.to_dict()["kind"]
    (0.001, 'harmonic')
    """
    if d is None or isinstance(d, (Polynomial, Harmonic, Table)):
        return d
    kind = d.get("kind")
    if kind not in KINDS:
        raise InputError(f"unknown fit kind {kind!r}")
    own = ("kind", *FIT_KEYS[kind])
    info = {k: v for k, v in d.items() if k not in own}
    if kind == "polynomial":
        return Polynomial(d["coefficients"], d.get("domain"), info)
    if kind == "harmonic":
        return Harmonic(d.get("period", 360.0), d.get("a0", 0.0), d.get("cos", []), d.get("sin", []), info)
    return Table(info)
