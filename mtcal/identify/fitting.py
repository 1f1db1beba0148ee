"""From identified errors per position to error functions: ISO 230-1 reference straight lines, squareness,
and continuous fits whose complexity is chosen by the values' covariance (the rounds' scatter or the joint fit's).

Units follow the data: positions in mm (linear) or deg (rotary), values in mm or rad.  Slopes of straightness
lines are mm/mm = rad.  Squareness uses the right-hand convention of docs/design.md (ISO 230-1): the actual Y
direction is Rz(E_C0Y) y = (-E_C0Y, 1, 0), the actual Z direction is Ry(E_B0Z) Rx(E_A0Z) z = (E_B0Z, -E_A0Z, 1),
X is the datum.  (The thesis' eq. 3.16 prints +y E_C0Y and +z E_A0Z, i.e. the opposite signs of E_C0Y, E_A0Z.)
"""
from __future__ import annotations

import numpy as np

from mtcal.errors import InputError
from mtcal.model.fits import Harmonic, Polynomial

REFERENCE_METHODS = ("least-squares", "end-point", "minimum-zone")
SQUARENESS_CONVENTION = ("right-hand (ISO 230-1, design.md): actual Y = (-E_C0Y, 1, 0), actual Z = (E_B0Z, -E_A0Z, 1), "
                         "X is the datum; the thesis' eq. 3.16 prints the opposite signs of E_C0Y and E_A0Z")


def reference_line(x, y, method: str = "least-squares") -> tuple[float, float]:
    """ISO 230-1 reference straight line y ~ a + b x of a straightness record: (intercept a, slope b).

    least-squares: minimum sum of squared deviations; end-point: through the first and last point (by x);
    minimum-zone: the mean line of the narrowest zone of two parallel lines containing all points (minimax fit).
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    if len(x) < 2 or np.ptp(x) == 0:
        raise InputError("a reference straight line needs at least two distinct positions")
    xm, ym = x.mean(), y.mean()
    xc = x - xm
    if method == "least-squares":
        b = float(np.dot(xc, y - ym) / np.dot(xc, xc))
    elif method == "end-point":
        i, j = int(np.argmin(x)), int(np.argmax(x))
        b = float((y[j] - y[i]) / (x[j] - x[i]))
        return float(y[i] - b * x[i]), b
    elif method == "minimum-zone":
        from scipy.optimize import linprog
        s = np.abs(xc).max()
        u = xc / s  # scaled for conditioning; unknowns (a', b', t): minimise t, |y - ym - a' - b' u| <= t
        r = y - ym
        a_ub = np.block([[-np.ones((len(u), 1)), -u[:, None], -np.ones((len(u), 1))],
                         [np.ones((len(u), 1)), u[:, None], -np.ones((len(u), 1))]])
        b_ub = np.concatenate([-r, r])
        res = linprog([0, 0, 1], A_ub=a_ub, b_ub=b_ub, bounds=[(None, None)] * 3, method="highs")
        if not res.success:  # pragma: no cover - an LP of this form is always feasible
            raise InputError(f"minimum-zone line failed: {res.message}")
        b = float(res.x[1] / s)
        return float(ym + res.x[0] - b * xm), b
    else:
        raise InputError(f"reference line method must be one of {REFERENCE_METHODS}, got {method!r}")
    return float(ym - b * xm), b


def slope_weights(x, method: str = "least-squares") -> np.ndarray:
    """Weights g (n,) with slope = g . y of ``reference_line`` (least-squares and end-point exactly; the
    minimum-zone line, piecewise linear in y, is propagated with the least-squares weights)."""
    x = np.asarray(x, dtype=float)
    g = np.zeros(len(x))
    if method == "end-point":
        i, j = int(np.argmin(x)), int(np.argmax(x))
        g[[i, j]] = np.array([-1.0, 1.0]) / (x[j] - x[i])
        return g
    xc = x - x.mean()
    return xc / np.dot(xc, xc)


SQUARENESS_PAIRS = {"E_C0Y": (("E_XY", "E_YX"), -1.0), "E_B0Z": (("E_XZ", "E_ZX"), 1.0),
                    "E_A0Z": (("E_YZ", "E_ZY"), -1.0)}  # squareness = sign * (sum of the two slopes)


def squareness(slopes: dict[str, float]) -> dict[str, float]:
    """Squareness errors (rad) from the slopes of the straightness reference lines, X as the datum.

    ``slopes[E_IJ]`` is the slope (mm/mm) of the reference line of straightness E_IJ over the travel of J.
    E_C0Y = -(s_XY + s_YX), E_B0Z = s_XZ + s_ZX, E_A0Z = -(s_YZ + s_ZY); a name is left out when a slope it
    needs is missing.  A tilt of the measuring frame alone cancels from each sum.
    """
    out = {}
    for name, ((a, b), sign) in SQUARENESS_PAIRS.items():
        if a in slopes and b in slopes:
            out[name] = sign * (slopes[a] + slopes[b])
    return out


# ----------------------------------------------------------------------------- continuous functions
def _poly_design(x: np.ndarray, deg: int, domain: tuple[float, float], x_ref: float | None = None) -> np.ndarray:
    """Columns u^k on the domain mapped to [-1, 1]; with ``x_ref``, u^k - u_ref^k for k >= 1 (zero at x_ref)."""
    lo, hi = domain

    def u(v):
        return (2 * v - (lo + hi)) / (hi - lo) if hi > lo else np.zeros_like(v)
    a = np.polynomial.polynomial.polyvander(u(x), deg)
    if x_ref is None:
        return a
    return a[:, 1:] - np.polynomial.polynomial.polyvander(u(np.array([x_ref], dtype=float)), deg)[:, 1:]


def _harm_design(x: np.ndarray, h: int, period: float, x_ref: float | None = None) -> np.ndarray:
    """Columns 1, cos(k w), sin(k w); with ``x_ref``, the same minus their value at x_ref, without the constant."""
    w = 2 * np.pi * x / period
    cols = [] if x_ref is not None else [np.ones_like(x)]
    w0 = 2 * np.pi * (x_ref or 0.0) / period
    for k in range(1, h + 1):
        if x_ref is None:
            cols += [np.cos(k * w), np.sin(k * w)]
        else:
            cols += [np.cos(k * w) - np.cos(k * w0), np.sin(k * w) - np.sin(k * w0)]
    return np.stack(cols, axis=-1) if cols else np.zeros((len(x), 0))


def _lstsq(a: np.ndarray, y: np.ndarray) -> np.ndarray:
    ok = np.isfinite(y)
    if a.shape[1] == 0:
        return np.zeros(0)
    return np.linalg.lstsq(a[ok], y[ok], rcond=None)[0]


SHRINK_DOF = 2.0  # degrees of freedom of the pooled variance that each position's own variance is shrunk towards


def rounds_covariance(per_round: np.ndarray) -> np.ndarray | None:
    """Covariance (n_positions, n_positions) of the mean over rounds that the rounds' scatter shows, or None when
    the rounds show none (one round; noise-free readings).

    A round's values share its reference reading, so their noise has a part common to the round's positions
    beside an independent part: cov = diag(s_i^2) + s_c^2 (common), s_c^2 the mean covariance of two positions'
    deviations from their means over the rounds (>= 0), s_i^2 each position's remaining variance shrunk towards
    the pooled one (``SHRINK_DOF``); over the number of rounds.  Positions whose rounds agree exactly (the
    reference, zero by definition) get no variance and no covariance."""
    ok = np.isfinite(per_round)
    n = ok.sum(axis=0)
    d = np.where(ok, per_round - np.nanmean(np.where(ok, per_round, np.nan), axis=0), 0.0) if ok.any() else None
    if d is None or per_round.shape[0] < 2:
        return None
    live = (n >= 2) & (np.sum(d**2, axis=0) > 0)
    if live.sum() < 2:
        return None
    pairs = ok.T.astype(float) @ ok.astype(float)  # rounds each pair of positions shares
    s = (d.T @ d) / np.maximum(pairs - 1, 1)
    sub = s[np.ix_(live, live)]
    common = max(0.0, float((sub.sum() - np.trace(sub)) / (len(sub) * (len(sub) - 1))))
    own = np.maximum(np.diagonal(s) - common, 0.0)
    nu = np.maximum(n - 1, 0) * live
    pooled = float(np.sum(nu * own) / nu.sum())
    var = (nu * own + SHRINK_DOF * pooled) / (nu + SHRINK_DOF)
    if not pooled + common > 0:
        return None
    cov = (np.diag(var) + common) / np.sqrt(np.outer(np.maximum(n, 1), np.maximum(n, 1)))
    return cov * np.outer(live, live)


def _select(x: np.ndarray, per_round: np.ndarray, sizes: list[int], design) -> tuple[int, list[float], str]:
    """Index into ``sizes`` chosen by AICc on the mean: for data whose rounds show no scatter (one round;
    noise-free readings), which are then fitted as closely as the sizes allow.  Returns (index, scores,
    criterion)."""
    mean = np.nanmean(per_round, axis=0)
    n = int(np.isfinite(mean).sum())
    scores = []
    for k in sizes:
        a = design(x, k)
        p = a.shape[1]
        if n - p - 1 <= 0:
            scores.append(np.inf)
            continue
        rss = float(np.nansum((mean - a @ _lstsq(a, mean)) ** 2))
        scores.append(n * np.log(max(rss, 1e-300) / n) + 2 * p + 2 * p * (p + 1) / (n - p - 1))
    return int(np.argmin(scores)), scores, "AICc on the mean (the rounds show no scatter)"


# Size selection with the values' covariance: chi^2 + p ln(n) (BIC).  Measured against AIC (chi^2 + 2 p) over 54
# simulated campaigns of a known truth (benchmarks/identify_truth.py): median model error 8.75 vs 9.78 um (joint fit),
# 15.3 vs 16.7 um (three-point, weighted); campaigns made worse by compensating 0 % vs 2 % (joint).
CRITERION = "BIC with the values' covariance (chi^2 + p ln n; the rounds' scatter or the joint fit's)"


def _gls(x: np.ndarray, mean: np.ndarray, cov: np.ndarray, sizes: list[int], design, x_ref: float | None):
    """Generalised least squares with the values' covariance ``cov`` (n, n) (the joint fit's, or the rounds'
    ``rounds_covariance``): the size chosen by ``CRITERION`` (the reference position, zero by definition and without
    variance, is left out of the chi^2; directions the gauge holds exactly, e.g. a straightness slope of the ISO
    frame, get a variance 1e-6 of the mean variance so the fit keeps them).  Returns (index, scores, criterion,
    coefficients, their covariance)."""
    keep = np.isfinite(mean) & (np.diagonal(cov) > 0)
    if x_ref is not None:
        keep &= x != x_ref
    c = cov[np.ix_(keep, keep)]
    chol = np.linalg.cholesky(c + 1e-6 * np.trace(c) / len(c) * np.eye(len(c)))
    yw = np.linalg.solve(chol, mean[keep])
    scores, sols = [], []
    for k in sizes:
        a = design(x, k)
        if a.shape[1] == 0:
            scores.append(float(yw @ yw))
            sols.append((np.zeros(0), np.zeros((0, 0))))
            continue
        aw = np.linalg.solve(chol, a[keep])
        c, *_ = np.linalg.lstsq(aw, yw, rcond=None)
        r = yw - aw @ c
        scores.append(float(r @ r) + np.log(len(yw)) * a.shape[1])
        sols.append((c, np.linalg.pinv(aw.T @ aw)))
    pick = int(np.argmin(scores))
    return pick, scores, CRITERION, *sols[pick]


def fit_polynomial(x, per_round, max_degree: int = 7, x_ref: float | None = None, cov=None) -> Polynomial:
    """Polynomial fit of the mean over rounds, degree chosen by ``_gls`` with the rounds' covariance
    (``rounds_covariance``, or ``cov``), by ``_select`` when the rounds show no scatter (0 .. min(max_degree, n - 2)).

    With ``x_ref`` (the reference position) the function is constrained to 0 there, as the errors are
    measured relative to the reference reading; degree 0 is then the zero function.

    ``per_round`` (n_rounds, n_positions), NaN where a round lacks a position.  Returns a
    mtcal.model.fits.Polynomial (coefficients on ``domain``) whose ``info`` holds degree, criterion, scores and
    rms.  With ``cov`` (n_positions, n_positions; the joint fit's covariance of the mean values) the fit is
    generalised least squares (``_gls``) and ``info`` adds "covariance" of the coefficients.
    """
    x = np.asarray(x, dtype=float)
    per_round = np.atleast_2d(np.asarray(per_round, dtype=float))
    dom = (float(x.min()), float(x.max()))
    top = max(0, min(max_degree, len(x) - 2))
    sizes = list(range(top + 1))
    design = lambda xx, d: _poly_design(xx, d, dom, x_ref)  # noqa: E731
    mean = np.nanmean(per_round, axis=0)
    ccov = None
    cov = rounds_covariance(per_round) if cov is None else np.asarray(cov, dtype=float)
    if cov is None:
        pick, scores, how = _select(x, per_round, sizes, design)
        a = design(x, sizes[pick])
        coef = _lstsq(a, mean)
    else:
        pick, scores, how, coef, ccov = _gls(x, mean, cov, sizes, design, x_ref)
        a = design(x, sizes[pick])
    rms = float(np.sqrt(np.nanmean((mean - a @ coef) ** 2)))
    if x_ref is not None:  # back to plain coefficients on the domain: c0 = -sum_k c_k u_ref^k
        u_ref = (2 * x_ref - sum(dom)) / (dom[1] - dom[0]) if dom[1] > dom[0] else 0.0
        g = np.vstack([-u_ref ** np.arange(1, len(coef) + 1), np.eye(len(coef))])
        coef = g @ coef
        ccov = None if ccov is None else g @ ccov @ g.T
    info = {"degree": sizes[pick], "criterion": how, "scores": [float(s) for s in scores], "rms": rms}
    if ccov is not None:
        info["covariance"] = ccov.tolist()
    return Polynomial(coef.tolist(), list(dom), info)


def fit_harmonic(x, per_round, period: float = 360.0, max_harmonics: int = 6, x_ref: float | None = None,
                 cov=None) -> Harmonic:
    """Fourier series a0 + sum a_h cos(h w) + b_h sin(h w), w = 2 pi x / period, number of harmonics chosen as
    in ``fit_polynomial`` (0 .. min(max_harmonics, (n - 2) // 2)); a mtcal.model.fits.Harmonic.
    With ``x_ref`` the series is constrained to 0 at the reference position (a0 follows from the others).
    With ``cov`` as in ``fit_polynomial`` (GLS, "covariance" of [a0, a1, b1, a2, b2, ...] added)."""
    x = np.asarray(x, dtype=float)
    per_round = np.atleast_2d(np.asarray(per_round, dtype=float))
    top = max(0, min(max_harmonics, (len(x) - 2) // 2))
    sizes = list(range(top + 1))
    design = lambda xx, h: _harm_design(xx, h, period, x_ref)  # noqa: E731
    mean = np.nanmean(per_round, axis=0)
    ccov = None
    cov = rounds_covariance(per_round) if cov is None else np.asarray(cov, dtype=float)
    if cov is None:
        pick, scores, how = _select(x, per_round, sizes, design)
        c = _lstsq(design(x, sizes[pick]), mean)
    else:
        pick, scores, how, c, ccov = _gls(x, mean, cov, sizes, design, x_ref)
    h = sizes[pick]
    a = design(x, h)
    rms = float(np.sqrt(np.nanmean((mean - a @ c) ** 2)))
    if x_ref is not None:  # a0 = -sum_h (a_h cos(h w_ref) + b_h sin(h w_ref))
        w0 = 2 * np.pi * x_ref / period * np.arange(1, h + 1)
        g = np.vstack([-np.ravel(np.column_stack([np.cos(w0), np.sin(w0)])), np.eye(2 * h)])
        c = g @ c
        ccov = None if ccov is None else g @ ccov @ g.T
    info = {"harmonics": h, "criterion": how, "scores": [float(s) for s in scores], "rms": rms}
    if ccov is not None:
        info["covariance"] = ccov.tolist()
    return Harmonic(float(period), float(c[0]), c[1::2].tolist(), c[2::2].tolist(), info)


def is_periodic(positions, period: float = 360.0) -> bool:
    """Whether rotary positions cover (nearly) a full turn, so a periodic (harmonic) function fits."""
    p = np.sort(np.mod(np.asarray(positions, dtype=float), period))
    if len(p) < 5:
        return False
    gaps = np.diff(np.concatenate([p, [p[0] + period]]))
    return bool(gaps.max() <= 3 * np.median(gaps) and np.ptp(p) >= 0.75 * period)
