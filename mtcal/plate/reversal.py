"""2-D plate reversal (Hocken & Borchardt, NBSIR 79-1752): read a plate file, fit, correct, flag, plot.

Frames and units: coordinates in the file's length unit (any), angles in rad, gamma dimensionless.
Position 1 is the plate aligned with the machine axes, position 2 the plate turned about 90 degrees clockwise
(viewed from the top); optional positions 3 and 4 are the plate turned about 180 and 270 degrees (Reeve-style
redundancy).  Parameters: alpha (axis non-orthogonality), beta (turn minus its nominal value, one per extra
position), gamma (x scale minus y scale), ex, ey (offsets of position 1 from the turned positions).

The maths lives in ``mtcal.generated.plate_numpy`` (derived in derive/plate.py); this module does the
bookkeeping: sums, least squares on generated design matrices, statistics, the gage frame and I/O.
``fit_plate`` returns a :class:`PlateFit` that keeps the design matrix and residuals for diagnosis.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

import numpy as np

from mtcal import _tails
from mtcal.errors import InputError
from mtcal.generated import plate_numpy as G
from mtcal.io import read_csv_rows, save_figure

METRICS = ("split", "x", "y", "none")  # paper options 3, 1, 2, 4
PAPER_OPTION = {"x": 1, "y": 2, "split": 3, "none": 4}
NOMINAL_TURN = (0.0, math.pi / 2, math.pi, 3 * math.pi / 2)  # positions 1..4, clockwise
MAX_TURN_ERROR = math.radians(45.0)  # positions 3, 4: beyond this the turn is not "about 180/270 degrees": refuse
MIN_TURN = math.radians(10.0)  # position 2: the reversal needs a turn at least this far from 0 and 180 degrees
FIRST_ORDER_TURN = math.radians(1.0)  # beyond this deviation from nominal the first-order model is not used
UNIT_RATIOS = (25.4, 1 / 25.4, 1000.0, 1e-3, 10.0, 0.1, 2.54, 1 / 2.54, 12.0, 1 / 12.0)
DATA_DIR = Path(__file__).resolve().parent.parent / "data"


# ----------------------------------------------------------------------------- input
@dataclass
class PlateData:
    """A measured 2-D ball or hole plate: the N points' coordinates in each of 2-4 positions of the plate.

    Made by ``read_plate_csv(path)``, ``plate_from_arrays(ids, pos1, pos2, ...)`` or ``plate_from_pairs``.

    Attributes
    ----------
    ids : list of str
        Point labels, in order.
    positions : list of numpy.ndarray
        ``positions[k]`` is (N, 2) x, y in position k + 1 (k = 0: aligned, 1: turned ~90 deg clockwise, ...), in
        the input's length unit.
    source : str
        Where the data came from (for messages).
    rows : list of int
        The file line of each point (for messages).
    resolution : float
        The last printed digit of the file's coordinates (0: arrays, full precision).
    """

    ids: list[str]
    positions: list[np.ndarray]
    source: str = "<arrays>"
    rows: list[int] = field(default_factory=list)  # file line of each point (for messages)
    resolution: float = 0.0  # the last printed digit of the file's coordinates (0: arrays, full precision)

    @property
    def n(self) -> int:
        return len(self.ids)

    def where(self, i: int) -> str:
        """``FILE:LINE`` of point i (``SOURCE: row N`` for arrays)."""
        return f"{self.source}:{self.rows[i]}" if self.rows else f"{self.source}: row {i + 1}"


def _num(text: str, src: str, line: int, col: str) -> float:
    try:
        val = float(text)
    except ValueError:
        raise InputError(f"{src}:{line}: column {col}: {text.strip()!r} is not a number") from None
    if not math.isfinite(val):
        raise InputError(f"{src}:{line}: column {col}: {text.strip()!r} is not a finite number")
    return val


def read_plate_csv(path: str | os.PathLike) -> PlateData:
    """Read ``point,x1,y1,x2,y2[,x3,y3[,x4,y4]]`` (lines starting with # are comments); validate."""
    src = str(path)
    body = read_csv_rows(path, "plate")
    hline, header = body[0]
    cols = [c.strip().lower() for c in header]
    need = ["point", "x1", "y1", "x2", "y2"]
    missing = [c for c in need if c not in cols]
    if missing:
        raise InputError(f"{src}:{hline}: header lacks column(s) {', '.join(missing)} "
                         f"(expected point,x1,y1,x2,y2 and optionally x3,y3,x4,y4)")
    dup = sorted({c for c in cols if cols.count(c) > 1})
    if dup:
        raise InputError(f"{src}:{hline}: duplicate column(s) {', '.join(dup)}")
    k_max = 2
    for k in (3, 4):
        have = [f"x{k}" in cols, f"y{k}" in cols]
        if any(have) and not all(have):
            raise InputError(f"{src}:{hline}: column x{k} needs y{k} and vice versa")
        if all(have):
            if k != k_max + 1:
                raise InputError(f"{src}:{hline}: columns x{k},y{k} need x{k - 1},y{k - 1}")
            k_max = k
    idx = {c: cols.index(c) for c in cols}
    ids: list[str] = []
    rows: list[int] = []
    pos: list[list[tuple[float, float]]] = [[] for _ in range(k_max)]
    seen: dict[str, int] = {}
    decimals = 0
    for line, rec in body[1:]:
        if len(rec) != len(cols):
            raise InputError(f"{src}:{line}: {len(rec)} fields, header has {len(cols)}")
        pid = rec[idx["point"]].strip()
        if not pid:
            raise InputError(f"{src}:{line}: empty point id")
        if pid in seen:
            raise InputError(f"{src}:{line}: duplicate point id {pid!r} (first on line {seen[pid]})")
        seen[pid] = line
        for k in range(k_max):
            xs, ys = rec[idx[f"x{k + 1}"]], rec[idx[f"y{k + 1}"]]
            if not xs.strip() or not ys.strip():
                raise InputError(f"{src}:{line}: point {pid!r} has no position-{k + 1} values "
                                 f"(x{k + 1},y{k + 1}); every point must be measured in every position")
            pos[k].append((_num(xs, src, line, f"x{k + 1}"), _num(ys, src, line, f"y{k + 1}")))
            decimals = max(decimals, *(_decimals(t) for t in (xs, ys)))
        ids.append(pid)
        rows.append(line)
    data = PlateData(ids, [np.array(q, dtype=float).reshape(-1, 2) for q in pos], src, rows, 10.0 ** -decimals)
    validate(data)
    return data


def _decimals(text: str) -> int:
    """Digits printed after the decimal point (``1.250`` -> 3, ``2e-3`` -> 3, ``12`` -> 0)."""
    t = text.strip().lower()
    mant, _, exp = t.partition("e")
    d = len(mant.split(".", 1)[1]) if "." in mant else 0
    return max(0, d - (int(exp) if exp.lstrip("+-").isdigit() else 0))


def plate_from_arrays(ids: Sequence, *positions, source: str = "<arrays>") -> PlateData:
    """Build and validate a plate from point ids and 2..4 arrays (N, 2), one per position."""
    if not 2 <= len(positions) <= 4:
        raise InputError(f"{source}: need 2 to 4 positions, got {len(positions)}")
    ids = [str(i) for i in ids]
    seen: dict[str, int] = {}
    for i, pid in enumerate(ids):
        if pid in seen:
            raise InputError(f"{source}: row {i + 1}: duplicate point id {pid!r} (first in row {seen[pid] + 1})")
        seen[pid] = i
    arrs = []
    for k, p in enumerate(positions):
        a = np.asarray(p, dtype=float)
        if a.ndim != 2 or a.shape[1] != 2 or a.shape[0] != len(ids):
            raise InputError(f"{source}: position {k + 1} has shape {a.shape}, expected ({len(ids)}, 2) "
                             "(one row per point id, same order in every position)")
        bad = np.argwhere(~np.isfinite(a))
        if bad.size:
            i = int(bad[0, 0])
            raise InputError(f"{source}: row {i + 1}: point {ids[i]!r}: position {k + 1} value is not finite")
        arrs.append(a)
    data = PlateData(ids, arrs, source)
    validate(data)
    return data


def plate_from_pairs(pos1: dict, pos2: dict, source: str = "<arrays>") -> PlateData:
    """Plate from two mappings id -> (x, y); the id sets must match."""
    a, b = set(map(str, pos1)), set(map(str, pos2))
    if a != b:
        only1, only2 = sorted(a - b), sorted(b - a)
        raise InputError(f"{source}: point ids differ between positions: only in position 1: {only1}, "
                         f"only in position 2: {only2}")
    ids = sorted(a, key=lambda s: (len(s), s))
    m1 = {str(k): v for k, v in pos1.items()}
    m2 = {str(k): v for k, v in pos2.items()}
    return plate_from_arrays(ids, [m1[i] for i in ids], [m2[i] for i in ids], source=source)


MAX_COORDINATE = 1e7  # no plate is this large in any length unit: a misreading (an exponent, a pasted id)
FAR_FROM_CENTRE = 5.0  # a point this many times the median distance from the plate centre: a misreading


def validate(data: PlateData) -> None:
    """Refuse what the fit cannot use: < 3 points, coordinates no plate has, a point far off the plate, collinear
    points, mixed units."""
    src = data.source
    if data.n < 3:
        raise InputError(f"{src}: {data.n} point(s); the plate fit needs at least 3 non-collinear points")
    for k, p in enumerate(data.positions):
        big = np.flatnonzero(np.abs(p).max(axis=1) > MAX_COORDINATE)
        if len(big):
            i = int(big[0])
            raise InputError(f"{data.where(i)}: point {data.ids[i]!r}: position {k + 1} coordinate "
                             f"{np.abs(p[i]).max():.3g} is beyond {MAX_COORDINATE:g}: no plate is that large (a "
                             f"misreading?)")
    for k, p in enumerate(data.positions):
        c = p - p.mean(axis=0)
        s = np.linalg.svd(c, compute_uv=False)
        if s[0] == 0 or s[1] <= 1e-9 * s[0]:
            raise InputError(f"{src}: position {k + 1}: the {data.n} points are collinear "
                             "(all on one line); a 2-D plate needs points off that line")
    # mixed units: rotation keeps distances, so each point's distance from the (robust) centre must agree
    c1 = _spatial_median(data.positions[0])
    r1 = np.hypot(*(data.positions[0] - c1).T)
    for k in range(1, len(data.positions)):
        pk = data.positions[k]
        rk = np.hypot(*(pk - _spatial_median(pk)).T)
        ok = r1 > 0.05 * np.median(r1[r1 > 0]) if np.any(r1 > 0) else r1 > 0
        ratio = np.where(ok, rk / np.where(ok, r1, 1.0), 1.0)
        med = float(np.median(ratio[ok])) if np.any(ok) else 1.0
        if abs(med - 1) > 0.02:
            raise InputError(f"{src}: position {k + 1} is {med:.4g} times the size of position 1 "
                             f"(mixed units?{_unit_hint(med)}); all positions must use one length unit")
        # distances from the coordinate origin too, when both positions share it (normalised to the
        # plate origin, as the paper does): a row typed in other units scales its coordinates
        o1, ok_o = np.hypot(*data.positions[0].T), None
        nz = o1 > 0.05 * (np.max(o1) or 1.0)
        if np.any(nz) and _turned_about_origin(data.positions[0], pk):
            ratio_o = np.where(nz, np.hypot(*pk.T) / np.where(nz, o1, 1.0), 1.0)
            if abs(float(np.median(ratio_o[nz])) - 1) < 0.02:
                ok_o = ratio_o
        for i in range(data.n):
            for q, where in ((ratio[i] if ok[i] else 1.0, "the plate centre"),
                             (ok_o[i] if ok_o is not None and nz[i] else 1.0, "the coordinate origin")):
                if abs(q - 1) > 0.02 and any(abs(q / u - 1) < 0.05 for u in UNIT_RATIOS):
                    raise InputError(f"{data.where(i)}: point {data.ids[i]!r}: position {k + 1} lies "
                                     f"{q:.4g} times as far from {where} as in position 1 "
                                     f"(mixed units?{_unit_hint(q)})")
    for k, p in enumerate(data.positions):  # a whole row in another unit or misread: far off the plate
        r = np.hypot(*(p - _spatial_median(p)).T)
        med = float(np.median(r))
        if med > 0 and r.max() > FAR_FROM_CENTRE * med:
            i = int(np.argmax(r))
            q = float(r[i] / med)
            raise InputError(f"{data.where(i)}: point {data.ids[i]!r} lies {q:.3g} times as far from the plate "
                             f"centre as the median point in position {k + 1} (a row in another unit?"
                             f"{_unit_hint(q)}; or a misreading)")


def _spatial_median(p: np.ndarray, iterations: int = 100) -> np.ndarray:
    """Geometric median of points (N, 2) (Weiszfeld): robust to a mistyped point and, unlike the coordinate-wise
    median, turns with the plate, so distances from it are kept by a turn of any angle."""
    c = np.median(p, axis=0)
    for _ in range(iterations):
        d = np.maximum(np.hypot(*(p - c).T), 1e-12 * (1.0 + np.abs(p).max()))
        c_new = (p / d[:, None]).sum(axis=0) / (1.0 / d).sum()
        if np.allclose(c_new, c, rtol=0, atol=1e-13 * (1.0 + np.abs(p).max())):
            return c_new
        c = c_new
    return c


def _turned_about_origin(p1: np.ndarray, pk: np.ndarray) -> bool:
    """True when position k is (mostly) position 1 turned about the coordinate origin: then each point's distance
    from the origin must be kept, whatever the turn angle (a plate turned about another centre moves them)."""
    s = G.procrustes_terms(p1, pk).sum(axis=0)
    t = math.atan2(s[0], s[1])
    c, sn = math.cos(t), math.sin(t)
    pred = p1 @ np.array([[c, -sn], [sn, c]])  # clockwise turn by t (B(t) applied to row vectors)
    size = float(np.median(np.hypot(*p1.T))) or 1.0
    return float(np.median(np.hypot(*(pk - pred).T))) < 0.02 * size


def _unit_hint(q: float) -> str:
    for u, name in ((25.4, "mm vs inch"), (1000.0, "um vs mm"), (10.0, "mm vs cm"), (12.0, "inch vs ft")):
        if abs(q / u - 1) < 0.05 or abs(q * u - 1) < 0.05:
            return f" the ratio is close to {u:g}: {name}"
    return ""


# ----------------------------------------------------------------------------- fit
@dataclass
class PlateFit:
    """Result of :func:`fit_plate`.  Lengths in the input unit, angles in rad.

    ``value(name)`` and ``stderr(name)`` read one parameter; ``to_dict()`` is the JSON answer of `mtcal plate`.

    Attributes
    ----------
    data : PlateData
        The data fitted.
    metric : str
        Where gamma goes in the corrected coordinates (x, y, split, none).
    offsets : bool
        Whether the plate's offsets ex, ey were fitted (False: ALBE2).
    method : str
        ``"first_order"`` (closed form / linear least squares) or ``"exact"`` (Gauss-Newton).
    names : list of str
        The fitted parameters: ``alpha``, ``beta`` (rad), ``gamma`` (1), ``ex``, ``ey`` (length), in order.
    values : numpy.ndarray
        Their values.
    covariance : numpy.ndarray
        Their covariance.
    sigma : float
        Residual standard deviation of one coordinate, input unit.
    dof : int
        Degrees of freedom of the fit.
    residuals : numpy.ndarray, shape (N, m)
        Per point the m = 2 (K - 1) observation rows' residuals (x, y of position 1 predicted from each turned
        position).
    design : numpy.ndarray, shape (N, m, p)
        The design rows of those observations; ``names`` label the p columns.
    turn_deg : list of float
        Measured clockwise turn of positions 2.. relative to position 1, deg (Procrustes).
    corrected : numpy.ndarray, shape (N, 2)
        The plate's corrected coordinates in the gage frame.
    origin : str
        The point at (0, 0) of the gage frame.
    align : str
        The point on the ``align_axis`` axis.
    align_axis : str
        ``"x"`` or ``"y"``.
    flagged : list of dict
        Points whose residuals are too large at the family-wise level.
    flag_rule : str
        How they were flagged.
    notes : list of str
        What the user should know (a scale left out, the exact model used, ...).
    """

    data: PlateData
    metric: str
    offsets: bool
    method: str  # "first_order" (closed form / linear least squares) or "exact" (Gauss-Newton)
    names: list[str]
    values: np.ndarray
    covariance: np.ndarray
    sigma: float
    dof: int
    residuals: np.ndarray
    design: np.ndarray
    turn_deg: list[float]  # measured clockwise turn of positions 2.. relative to position 1 (Procrustes)
    corrected: np.ndarray  # (N, 2) gage frame
    origin: str
    align: str
    align_axis: str
    flagged: list[dict]
    flag_rule: str
    notes: list[str]

    def value(self, name: str) -> float:
        return float(self.values[self.names.index(name)]) if name in self.names else 0.0

    def stderr(self, name: str) -> float:
        if name not in self.names:
            return 0.0
        i = self.names.index(name)
        return float(math.sqrt(max(self.covariance[i, i], 0.0)))

    def to_dict(self) -> dict:
        """The JSON answer of ``mtcal plate`` (docs/design.md)."""
        d = {"file": self.data.source, "scale_fitted": "gamma" in self.names,
             "units": {"length": "input unit", "angle": "rad", "gamma": "1"},
             "metric": self.metric, "paper_option": PAPER_OPTION[self.metric], "offsets": self.offsets,
             "method": self.method, "n_points": self.data.n, "n_positions": len(self.data.positions),
             "dof": self.dof}
        for n in ("alpha", "beta", "gamma", "ex", "ey"):
            d[n] = self.value(n)
        d["sigma"] = self.sigma
        d["standard_errors"] = {n: self.stderr(n) for n in self.names}
        extra = {n: self.value(n) for n in self.names if n not in ("alpha", "beta", "gamma", "ex", "ey")}
        if extra:
            d["parameters_extra"] = extra
        d["turn_deg"] = self.turn_deg
        d["gage_frame"] = {"origin": self.origin, "align": self.align, "axis": self.align_axis}
        d["corrected"] = [{"point": pid, "x": float(x), "y": float(y)}
                          for pid, (x, y) in zip(self.data.ids, self.corrected)]
        d["residuals"] = [{"point": pid, "r": [float(v) for v in r]}
                          for pid, r in zip(self.data.ids, self.residuals)]
        d["flag_rule"] = self.flag_rule
        d["flagged"] = self.flagged
        d["notes"] = self.notes
        return d


def _param_layout(k_positions: int, offsets: bool, scale: bool = True) -> tuple[list[str], np.ndarray]:
    """Names of the fitted parameters and, per turned position, the indices of the generated columns
    (alpha, beta, gamma, ex, ey) in that list (-1: not fitted, held at 0)."""
    names = ["alpha", "beta"] + (["gamma"] if scale else [])
    ig = 2 if scale else -1
    if offsets:
        names += ["ex", "ey"]
    cols = [[0, 1, ig, len(names) - 2 if offsets else -1, len(names) - 1 if offsets else -1]]
    for k in range(3, k_positions + 1):
        names.append(f"beta{k}")
        b = len(names) - 1
        if offsets:
            names += [f"ex{k}", f"ey{k}"]
            cols.append([0, b, ig, b + 1, b + 2])
        else:
            cols.append([0, b, ig, -1, -1])
    return names, np.array(cols)


def _position_params(values: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """(K-1, 5) generated-parameter vectors (alpha, beta_k, gamma, ex_k, ey_k) for each turned position."""
    v = np.append(values, 0.0)  # index -1 -> 0
    return v[cols]


def measured_turns(data: PlateData) -> list[float]:
    """Clockwise turn (rad) of each position k >= 2 relative to position 1, from centred coordinates."""
    p1 = data.positions[0] - data.positions[0].mean(axis=0)
    out = []
    for pk in data.positions[1:]:
        s = G.procrustes_terms(p1, pk - pk.mean(axis=0)).sum(axis=0)
        out.append(math.atan2(s[0], s[1]))
    return out


def nominal_turns(turns: list[float], notes: list[str]) -> tuple[float, ...]:
    """The nominal turn of each position (rad, clockwise): the paper's 0, 90, 180, 270 deg, or, when position 2
    was turned counter-clockwise, 0, -90, -180, -270 deg (said in ``notes``); alpha, beta, gamma keep their
    meaning (beta: the turn's deviation from this nominal)."""
    sense = 1.0 if turns and _wrap(turns[0]) >= 0 else -1.0
    nom = [sense * t for t in NOMINAL_TURN[:len(turns) + 1]]
    if turns and sense < 0:
        notes.append(f"position 2 is turned counter-clockwise ({math.degrees(turns[0]):.3f} deg clockwise = "
                     f"{-math.degrees(turns[0]):.3f} deg counter-clockwise), not clockwise as the paper's: fitted "
                     f"with the turn the data show")
    return tuple(nom)


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def _closed_form(data: PlateData, offsets: bool) -> np.ndarray:
    """ALBE3 (offsets: centred sums) or ALBE2 (raw sums) via the generated closed-form normal equations."""
    p1, p2 = data.positions[0], data.positions[1]
    y = G.reduced_observation(p1, p2, math.pi / 2)  # (N, 2): u = x1 + y2, v = y1 - x2 (to 1e-16)
    if offsets:
        p2c, yc = p2 - p2.mean(axis=0), y - y.mean(axis=0)
    else:
        p2c, yc = p2, y
    x, yy = p2c[:, 0], p2c[:, 1]
    u, v = yc[:, 0], yc[:, 1]
    sums = np.array([x @ x, yy @ yy, x @ yy, x @ u, yy @ u, x @ v, yy @ v])
    abg = G.normal_solve(sums)
    if not offsets:
        return abg
    full = np.concatenate([abg, [0.0, 0.0]])
    # eps = mean(reduced obs) - J(mean p2) (alpha, beta, gamma): the prediction is linear in the data
    eps = y.mean(axis=0) - (G.predict_first_order(p2.mean(axis=0), full, math.pi / 2)
                            - G.predict_first_order(p2.mean(axis=0), np.zeros(5), math.pi / 2))
    return np.concatenate([abg, eps])


def _linear_system(data: PlateData, names: list[str], cols: np.ndarray, nom: tuple = NOMINAL_TURN
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Stacked first-order design (N, m, p) and reduced observations (N, m) over positions 2..K."""
    n, kk = data.n, len(data.positions)
    J = np.zeros((n, 2 * (kk - 1), len(names)))
    Y = np.zeros((n, 2 * (kk - 1)))
    for k in range(1, kk):
        d = G.design_first_order(data.positions[k], nom[k])  # (N, 2, 5)
        Y[:, 2 * (k - 1):2 * k] = G.reduced_observation(data.positions[0], data.positions[k], nom[k])
        for g, j in enumerate(cols[k - 1]):
            if j >= 0:
                J[:, 2 * (k - 1):2 * k, j] += d[:, :, g]
    return J, Y


def _exact_system(data: PlateData, values: np.ndarray, cols: np.ndarray, w: float, nom: tuple = NOMINAL_TURN
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Exact residuals (N, m) and their Jacobian (N, m, p) at ``values``."""
    n, kk = data.n, len(data.positions)
    R = np.zeros((n, 2 * (kk - 1)))
    J = np.zeros((n, 2 * (kk - 1), len(values)))
    pp = _position_params(values, cols)
    for k in range(1, kk):
        args = (data.positions[0], data.positions[k], pp[k - 1], nom[k], w)
        R[:, 2 * (k - 1):2 * k] = G.residual_exact(*args)
        d = G.jacobian_exact(*args)
        for g, j in enumerate(cols[k - 1]):
            if j >= 0:
                J[:, 2 * (k - 1):2 * k, j] += d[:, :, g]
    return R, J


def _gauss_newton(data: PlateData, start: np.ndarray, cols: np.ndarray, w: float, nom: tuple = NOMINAL_TURN,
                  max_iter: int = 50) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least squares on the exact model with the generated residual and Jacobian (Gauss-Newton)."""
    x = start.copy()
    for _ in range(max_iter):
        R, J = _exact_system(data, x, cols, w, nom)
        step, *_ = np.linalg.lstsq(J.reshape(-1, len(x)), -R.ravel(), rcond=None)
        x = x + step
        if np.max(np.abs(step)) < 1e-15 * max(1.0, np.max(np.abs(x))):
            break
    R, J = _exact_system(data, x, cols, w, nom)
    return x, R, J


def _statistics(J: np.ndarray, R: np.ndarray, ids: list[str], level: float
                ) -> tuple[float, int, np.ndarray, list[dict], str]:
    """sigma (eq. 16), covariance, and points flagged by externally studentised residuals.

    For point i with residual block r_i (m rows) and hat block H_ii = J_i (J'J)^-1 J_i', the deletion
    statistic Q_i = r_i' (I - H_ii)^-1 r_i compares with s_(i)^2 = (SSR - Q_i) / (dof - m):
    F_i = Q_i / (m s_(i)^2) ~ F(m, dof - m) if the point is consistent; Bonferroni over the N points.
    """
    n, m, p = J.shape
    A = J.reshape(-1, p)
    r = R.ravel()
    dof = A.shape[0] - p
    ssr = float(r @ r)
    sigma = math.sqrt(ssr / dof) if dof > 0 else float("nan")
    M = np.linalg.inv(A.T @ A)
    cov = M * (sigma**2 if dof > 0 else np.nan)
    rule = (f"externally studentised point residuals, F(m={m}, dof-m) test, Bonferroni over {n} points, "
            f"flag if adjusted p < {level:g}")
    flagged: list[dict] = []
    if dof - m <= 0:
        return sigma, dof, cov, flagged, rule + f" (not applicable: dof {dof} <= {m})"
    H = np.einsum("nip,pq,njq->nij", J, M, J)
    V = np.eye(m) - H
    ok = np.linalg.det(V) > 1e-12
    Vs = np.where(ok[:, None, None], V, np.eye(m))
    Q = np.einsum("ni,ni->n", R, np.linalg.solve(Vs, R[..., None])[..., 0])
    s2 = (ssr - Q) / (dof - m)
    with np.errstate(divide="ignore", invalid="ignore"):
        F = np.where(ok & (s2 > 0), Q / (m * s2), 0.0)
    pval = _tails.f_sf(F, m, dof - m)
    padj = np.minimum(1.0, pval * n)
    for i in np.argsort(padj, kind="stable"):
        if ok[i] and padj[i] < level:
            flagged.append({"point": ids[i], "F": float(F[i]), "p_bonferroni": float(padj[i]),
                            "residual": [float(v) for v in R[i]]})
    return sigma, dof, cov, flagged, rule


def _gage_frame(est: np.ndarray, ids: list[str], origin: str | None, align: str | None, axis: str,
                translate: bool = True) -> tuple[np.ndarray, str, str, str]:
    """Translate so ``origin`` is (0, 0) and turn so ``align`` lies on the x (or y) axis; translate=False
    turns about the coordinate origin instead (as the ALBE2 listing of Table A1 does)."""
    lookup = {pid: i for i, pid in enumerate(ids)}
    for name, val in (("origin", origin), ("align", align)):
        if val is not None and str(val) not in lookup:
            raise InputError(f"{name} point {val!r} is not in the plate (ids: {', '.join(ids[:10])}...)")
    if axis not in ("x", "y"):
        raise InputError(f"gage-frame axis must be 'x' or 'y', got {axis!r}")
    io = lookup[str(origin)] if origin is not None else 0
    q = est - est[io] if translate else est.copy()
    if align is None:  # default: the point farthest along +x (else along -x) from the origin
        ia = int(np.argmax(q[:, 0])) if np.max(q[:, 0]) > 0 else int(np.argmax(np.abs(q[:, 0])))
        axis = "x"
    else:
        ia = lookup[str(align)]
    if ia == io or not np.any(q[ia]):
        raise InputError("the align point must differ from the origin point")
    ang = math.atan2(q[ia, 1], q[ia, 0])
    targets = (0.0, math.pi, -math.pi) if axis == "x" else (math.pi / 2, -math.pi / 2)
    target = min(targets, key=lambda t: abs(_wrap(ang - t)))
    psi = _wrap(ang - target)  # turn clockwise by psi: B(psi) = estimate with beta = -psi, alpha = gamma = 0
    q = G.estimate_exact(q, np.array([0.0, -psi, 0.0, 0.0, 0.0]), 0.0, 0.0)
    if translate:
        q[io] = 0.0
    q[ia, 1 if axis == "x" else 0] = 0.0
    return q, (ids[io] if translate else "(coordinate origin)"), ids[ia], axis


def _check_turns(data: PlateData, turns: list[float], exact: bool | None, nom: tuple = NOMINAL_TURN) -> None:
    """Position 2 may be turned by any angle the reversal can use (exact fit): not within MIN_TURN of 0 or
    180 deg, where C = A B^-1 A^-1 no longer depends on the machine metric A; the optional positions 3 and 4
    (Reeve-style redundancy) must be about 180 and 270 deg; a forced first-order fit needs a turn near nominal."""
    for k, t in enumerate(turns, start=2):
        dev = _wrap(t - nom[k - 1])
        where = f"position {k} is turned {math.degrees(t) % 360:.3f} deg clockwise from position 1"
        if k == 2 and abs(math.sin(t)) < math.sin(MIN_TURN):
            raise InputError(f"{where}: a reversal needs a turn away from 0 and 180 deg (at least "
                             f"{math.degrees(MIN_TURN):g} deg away; about 90 deg is best) to separate the machine's "
                             "non-orthogonality from the plate's", data.source)
        if (k > 2 and abs(dev) > MAX_TURN_ERROR) or (exact is False and abs(dev) > FIRST_ORDER_TURN):
            raise InputError(f"{where}; expected about {math.degrees(nom[k - 1]):.0f} deg (clockwise, viewed "
                             f"from the top){' for the first-order fit (use the exact fit)' if k == 2 else ''}",
                             data.source)


def _exact_needed(data: PlateData, turns, nom, offsets: bool, sigma1: float, notes: list[str]) -> bool:
    """Whether the exact model is needed (``exact=None``): a turn more than FIRST_ORDER_TURN from nominal, or the
    first-order model's neglected terms (beta^2 R / 2) above half of sigma; the reason goes into ``notes``."""
    if any(abs(_wrap(t - nom[k])) > FIRST_ORDER_TURN for k, t in enumerate(turns, 1)):
        notes.append(f"turn(s) {', '.join(f'{math.degrees(t):.3f}' for t in turns)} deg are more than "
                     f"{math.degrees(FIRST_ORDER_TURN):g} deg from nominal: exact fit used")
        return True
    worst = 0.0
    for k in range(1, len(data.positions)):
        pk = data.positions[k]
        rad = np.max(np.hypot(*(pk - (pk.mean(axis=0) if offsets else 0.0)).T))
        beta = _wrap(turns[k - 1] - nom[k])
        worst = max(worst, 0.5 * beta**2 * rad)
    if worst > 0.5 * sigma1:
        notes.append(f"first-order model error beta^2 R / 2 = {worst:.3g} exceeds sigma / 2 = "
                     f"{0.5 * sigma1:.3g} (turn off 90 deg by "
                     f"{math.degrees(abs(_wrap(turns[0] - nom[1]))) * 3600:.1f} "
                     "arcsec; the paper asks for about 10 arcsec): exact fit used")
        return True
    return False


def _estimate(data: PlateData, pp: np.ndarray, metric: str, method: str, nom, w: float) -> np.ndarray:
    """The corrected coordinates (eq. 20): the mean of the estimates from every position (``pp``: each position's
    parameters); gamma not applied for metric "none"."""
    if metric == "none":
        pp[:, 2] = 0.0
    est_fn = G.estimate_exact if method == "exact" else G.estimate_first_order
    p1par = pp[0].copy()
    p1par[1] = 0.0
    est = est_fn(data.positions[0], p1par, 0.0, w)
    for k in range(1, len(data.positions)):
        est = est + est_fn(data.positions[k], pp[k - 1], nom[k], w)
    return est / len(data.positions)


def fit_plate(data: PlateData, metric: str = "split", offsets: bool = True, exact: bool | None = None,
              origin: str | None = None, align: str | None = None, align_axis: str = "x",
              level: float = 0.01, translate: bool = True, scale: bool = True) -> PlateFit:
    """Fit the machine's alpha, beta, gamma (and the plate's ex, ey) to a plate measured in 2-4 positions.

    The Hocken-Borchardt reversal (NBSIR 79-1752): the plate's own errors cancel between positions; what is left is
    the machine's squareness (beta), scale difference (gamma) and the plate's set-up (alpha, ex, ey).

    Parameters
    ----------
    data : PlateData
        The measured plate (``read_plate_csv``, ``plate_from_arrays``).
    metric : {"split", "x", "y", "none"}, optional
        Where gamma goes in the corrected coordinates (paper options x = 1, y = 2, split = 3, none = 4; the fit
        does not depend on it to first order, Appendix B).  Default ``"split"``.
    offsets : bool, optional
        Fit the offsets ex, ey (False: ALBE2).  Default True.
    exact : bool, optional
        None: first order unless its neglected terms (beta^2 R / 2) exceed half of sigma, then exact; True: the
        exact model (any turn); False: first order always.
    origin : str, optional
        The point that goes to (0, 0) of the gage frame (default: the first point), unless ``translate=False``.
    align : str, optional
        The point that goes onto the ``align_axis`` axis (default: the point farthest along +x).
    align_axis : {"x", "y"}, optional
        Default ``"x"``.
    level : float, optional
        Family-wise level at which points are flagged (default 0.01).
    translate : bool, optional
        Move ``origin`` to (0, 0) (default True).
    scale : bool, optional
        False holds gamma at 0 (the metric of eq. 2, Reeve's): it reproduces Reeve's alpha and beta of Tables 1
        and 2.  Default True.

    Returns
    -------
    PlateFit
        The parameters with their covariance, residuals, corrected coordinates, flagged points, notes.

    Raises
    ------
    mtcal.errors.InputError
        Fewer than 2 positions, turns that are not about 90/180/270 deg, too few points, a bad option.

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.data import path
    >>> from mtcal.plate.reversal import read_plate_csv
    >>> fit = mtcal.fit_plate(read_plate_csv(path("nbs_table1.csv")))  # NBSIR 79-1752, Table 1
    >>> fit.names
    ['alpha', 'beta', 'gamma', 'ex', 'ey']
    >>> print(", ".join(f"{n} {fit.value(n) * 1e6:.2f}" for n in ("alpha", "beta", "gamma")), "(x1e-6)")
    alpha 4.53, beta -131.01, gamma 13.48 (x1e-6)
    """
    if metric not in METRICS:
        raise InputError(f"unknown metric {metric!r}; choose one of {', '.join(METRICS)}")
    kk = len(data.positions)
    notes: list[str] = []
    turns = measured_turns(data)
    nom = nominal_turns(turns, notes)
    _check_turns(data, turns, exact, nom)
    names, cols = _param_layout(kk, offsets, scale)
    w = float(G.METRIC_SHARE[metric])

    # first order: closed form for the paper's two positions, linear least squares otherwise
    J, Y = _linear_system(data, names, cols, nom)
    if kk == 2 and scale and nom[1] == NOMINAL_TURN[1]:
        values = _closed_form(data, offsets)
    else:
        values, *_ = np.linalg.lstsq(J.reshape(-1, len(names)), Y.ravel(), rcond=None)
    R = Y - np.einsum("nmp,p->nm", J, values)
    dof = J.shape[0] * J.shape[1] - len(names)
    sigma1 = math.sqrt(float(np.sum(R**2)) / dof) if dof > 0 else 0.0
    method = "first_order"
    if exact is None:
        exact = _exact_needed(data, turns, nom, offsets, sigma1, notes)
    if exact:
        start = values.copy()
        for k in range(1, kk):  # start each beta at the measured turn (first order is wrong for large beta)
            start[cols[k - 1][1]] = _wrap(turns[k - 1] - nom[k])
        if offsets:
            start[[c for k in range(kk - 1) for c in cols[k][3:]]] = 0.0
        values, R, J = _gauss_newton(data, start, cols, w, nom)
        method = "exact"
    sigma, dof, cov, flagged, rule = _statistics(J, R, data.ids, level)
    floor = data.resolution or 1e-12 * float(max(np.abs(p).max() for p in data.positions))
    flagged = [f for f in flagged if max(abs(v) for v in f["residual"]) > floor]  # not numerical / rounding noise
    rule += f"; and a residual above the data's resolution ({floor:.3g})"

    est = _estimate(data, _position_params(values, cols), metric, method, nom, w)
    corrected, o, a, ax = _gage_frame(est, data.ids, origin, align, align_axis, translate)
    return PlateFit(data, metric, offsets, method, names, values, cov, sigma, dof, R, J,
                    [math.degrees(t) for t in turns], corrected, o, a, ax, flagged, rule, notes)


def load_example(name: str = "nbs_table2_corrected") -> PlateData:
    """A bundled plate file from mtcal/data (e.g. nbs_table1, nbs_table1_corrected, nbs_table2)."""
    return read_plate_csv(DATA_DIR / f"{name}.csv")


# ----------------------------------------------------------------------------- plot
def plot_plate(fit: PlateFit, path: str | os.PathLike, magnify: float | None = None) -> float:
    """PNG of the corrected plate with residual vectors magnified; returns the magnification used."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    c = fit.corrected
    res = fit.residuals.reshape(fit.data.n, -1, 2).mean(axis=1)  # mean over turned positions
    size = float(np.max(np.ptp(c, axis=0))) or 1.0
    big = float(np.max(np.hypot(*res.T))) or 1.0
    if magnify:
        mag = magnify
    else:  # the largest arrow about 12 % of the plate, magnification rounded down to 1, 2, 5 x 10^k
        raw = 0.12 * size / big
        e = 10 ** math.floor(math.log10(raw))
        mag = max(m * e for m in (1, 2, 5) if m * e <= raw)
    fig, ax = plt.subplots(figsize=(6.5, 6.5))
    ax.plot(c[:, 0], c[:, 1], "o", color="0.3", ms=5)
    ax.quiver(c[:, 0], c[:, 1], res[:, 0] * mag, res[:, 1] * mag, angles="xy", scale_units="xy", scale=1,
              color="tab:blue", width=0.004)
    flagged = {f["point"] for f in fit.flagged}
    for pid, (x, y) in zip(fit.data.ids, c):
        ax.annotate(pid, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8,
                    color="tab:red" if pid in flagged else "0.2")
        if pid in flagged:
            ax.plot(x, y, "o", mfc="none", mec="tab:red", ms=14, mew=2)
    ax.set_aspect("equal")
    ax.set_xlabel("x (gage frame, input unit)")
    ax.set_ylabel("y (gage frame, input unit)")
    ax.set_title(f"{Path(fit.data.source).name}: residuals x{mag:g}, sigma = {fit.sigma:.3g}, "
                 f"alpha = {fit.value('alpha'):.3g} rad\nred: flagged ({len(flagged)})", fontsize=9)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)
    return mag
