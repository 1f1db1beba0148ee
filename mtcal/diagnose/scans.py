"""Scans over the residuals of the diagnosis: where the misfit sits (single factors and pairs of factors), the
best single-reading / bumped-nest displacement (outlier), and the change point of a tracker knock.

Units: residuals whitened (unit variance at the noise model), sizes reported in mm (machine frame).
"""
from __future__ import annotations

import itertools
import math
import weakref
from dataclasses import dataclass, field, fields, replace
from typing import Any, Callable

import numpy as np

from mtcal import _tails
from mtcal.diagnose import effects as fx
from mtcal.diagnose.engine import ALIAS_TOL, Engine
from mtcal.diagnose.prepare import Prepared
from mtcal.diagnose.prepared import LEVEL

FACTORS = ("direction", "round", "position", "point", "time")


@dataclass
class Located:
    """A group of readings (one axis, one level of a factor or of a pair of factors) whose residuals are not
    noise: ``kind`` "mean" (a common shift; ``shift_mm`` its size, mm) or "spread" (a larger scatter)."""

    axis: str
    by: str                 # "direction", ..., or "direction x point"
    where: Any
    score: float            # -log10 p_adjusted
    p_adjusted: float       # Bonferroni over every group x (mean, spread)
    kind: str
    readings: int
    mean_shift_chi2_per_dof: float
    spread_chi2_per_dof: float
    shift_mm: float
    note: str = "located but not explained by any candidate effect"
    shift_sd_mm: float | None = None  # the standard uncertainty of shift_mm, where it is a fit's (a free form's)
    rows: np.ndarray | None = field(default=None, repr=False, compare=False)  # the group's readings (indices)

    def to_dict(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self) if f.name != "rows"}


SEEN = 3.0  # the least size, in its standard deviations, of a displacement's component the data see (seen_z)


def seen_z(columns: int, among: int = 1) -> float:
    """The standardised size beyond which a component of an entry's displacement is one the data see: the two-sided
    normal quantile at the diagnosis' default level (prepared.LEVEL), Bonferroni over the ``columns`` independent
    components of the entry's fit and the ``among`` fits its size was chosen from (a scan's groups), never below
    SEEN: a reported entry is the most extreme of many, and a component as large as the largest of their noise is
    not one the data see."""
    return max(SEEN, math.sqrt(float(_tails.chi2_isf(LEVEL / (max(columns, 1) * max(among, 1)), 1))))


@dataclass
class Beyond:
    """What columns' fit adds beyond another fit (beyond_fit): ``theta`` their coefficients in the whitened fit
    beside it (Frisch-Waugh: what the fit says, e.g. where it moves the readings most); ``coef`` and ``cov`` the
    same columns fitted in mm to the readings' part beyond that fit's columns, and its covariance (the size's
    estimate); ``J`` (n, 3, k) mm per parameter, the columns' displacement beyond what that fit's columns can take
    of it in the machine frame; ``disp`` (n, 3) mm = J coef; ``moved`` (n,) the readings the columns touch;
    ``among`` the fits (a scan's groups) the entry was chosen from (seen_z)."""

    theta: np.ndarray
    coef: np.ndarray
    cov: np.ndarray
    disp: np.ndarray
    J: np.ndarray
    moved: np.ndarray | None = None
    among: int = 1

    def seen(self) -> tuple[np.ndarray, np.ndarray]:
        """((n, 3) mm, (n,) mm^2): the part of every reading's displacement the data determine -- its components,
        in the principal axes of its covariance J cov J^T, larger than seen_z standard deviations (the others are
        the noise of a direction the readings hardly see: across a tracker's beam, a free form's 3-vector is mostly
        that, and its norm is biased up by it) -- and the variance those kept components carry (their noise's
        expected share of its squared norm)."""
        C = np.einsum("nik,kl,njl->nij", self.J, self.cov, self.J)
        lam, V = np.linalg.eigh(C)
        a = np.einsum("nji,nj->ni", V, self.disp)
        keep = np.abs(a) > seen_z(len(self.coef), self.among) * np.sqrt(np.maximum(lam, 0.0))
        return np.einsum("nij,nj->ni", V, np.where(keep, a, 0.0)), np.sum(np.where(keep, lam, 0.0), axis=1)

    def largest(self) -> tuple[int, float, float]:
        """(reading, size mm, its standard uncertainty mm) of the largest displacement the data determine at a
        reading the columns move (``seen``), its noise removed by its expected value: sqrt(|d|^2 - the variance of
        its kept components), the estimate of the true displacement's norm under the fit's error term (a largest
        norm over many readings of a many-column fit is otherwise the largest of its noise).  Where no component
        is seen the size is 0, with the standard uncertainty of the largest displacement: what the data cannot
        see beyond the base is not given a size."""
        d, var = self.seen()
        size2 = np.maximum(np.sum(d ** 2, axis=1) - var, 0.0)
        if self.moved is not None and self.moved.any():  # at the readings the columns move (the base's own
            size2 = np.where(self.moved, size2, 0.0)     # motion spread over the others is not the entry's)
        if not size2.any():
            d = self.disp * (self.moved[:, None] if self.moved is not None and self.moved.any() else 1.0)
            k = int(np.argmax(np.sum(d ** 2, axis=1)))
        else:
            k = int(np.argmax(size2))
        norm = float(np.linalg.norm(d[k]))
        g = d[k] / norm if norm > 0 else np.zeros(3)
        Jk = g @ self.J[k]
        return k, float(math.sqrt(size2[k])), float(math.sqrt(max(Jk @ self.cov @ Jk, 0.0)))


def beyond_fit(W: np.ndarray, beside: Engine, G: np.ndarray, sigma: float, among: int = 1) -> Beyond:
    """The displacement the whitened columns ``G`` (3n, k) add beyond the fit ``beside``, in mm (machine frame):
    the columns un-whitened (``W`` (n, 3, 3) the whitening) and taken beyond what ``beside``'s columns can take of
    them (J = (I - P) G_mm, P the least-squares projection in mm on those columns), fitted by least squares in mm
    to the readings' own part beyond those columns ((I - P) y = (I - P) of the whitened fit's residual,
    un-whitened); the covariance the sandwich of that fit under the noise law (sigma^2 W^-1 W^-T per reading,
    ``sigma`` the residual scale).  In mm throughout: the weighted fit is efficient where the columns are the
    physics, but a located group or a free form is a shape near it, and there the weighted fit lets the base trade
    a reading's across-beam position (cheap under the law) for the along-beam misfit of others, and the columns
    carry that trade: gen3 1010/0, an AT960-like tracker 0.6 um along the beam, 17.7 um across it, a cyclic
    distance error of 2.3 um located in groups sized at up to 23 um (10 sigma across the beam, all of it the base's
    trade).  The mm fit is a projection of what the raw readings show beyond the base: it cannot exceed it, and
    its noise is stated (``cov``; ``seen`` keeps what stands out of it).  Columns that move every reading along one
    direction only (_one_direction: a tracker's distance or angle read off) have no freedom across it to carry
    that trade; there the mm fit would only add the noise across the beam to an along-beam estimate (gen3
    1010/9's distance map, seen at p ~ 0, came out "too small to size"), so their coefficients are the whitened
    fit's own, with its covariance, taken beyond the base in mm (J theta).  ``theta``: the whitened fit's
    coefficients (Frisch-Waugh), for what the fit says.  ``among``: the fits the entry is chosen from (Beyond)."""
    n = len(W)
    A = G - beside.project(G)
    theta, *_ = np.linalg.lstsq(A, beside.r, rcond=None)
    moved = np.any(G.reshape(n, 3, -1) != 0, axis=(1, 2))
    Wi = np.linalg.inv(W)
    raw = np.zeros((n, 3, G.shape[1]))
    raw[moved] = np.einsum("nij,njk->nik", Wi[moved], G.reshape(n, 3, -1)[moved])
    U = _mm_basis(Wi, beside)
    on = np.repeat(moved, 3)
    Jf = raw.reshape(3 * n, -1) - U @ (U[on].T @ raw.reshape(3 * n, -1)[on])
    x = np.einsum("nij,nj->ni", Wi, beside.r.reshape(n, 3)).ravel()  # the residual in mm: (I - P) y is its
    coef, *_ = np.linalg.lstsq(Jf, x - U @ (U.T @ x), rcond=None)     # part beyond the columns in mm
    J = Jf.reshape(n, 3, -1)
    if _one_direction(raw[moved]):  # no freedom across it to carry the base's trade: the whitened fit's own
        coef, cov = theta, sigma ** 2 * np.linalg.pinv(A.T @ A)  # coefficients, efficient under the law
    else:
        Hi = np.linalg.pinv(Jf.T @ Jf)
        B = np.einsum("nij,nip->njp", Wi, J).reshape(3 * n, -1)  # W^-T J: J^T Sigma J = B^T B, Sigma = W^-1 W^-T
        cov = sigma ** 2 * Hi @ (B.T @ B) @ Hi
    return Beyond(theta, coef, cov, np.einsum("nik,k->ni", J, coef), J, moved, among)


def _one_direction(G: np.ndarray) -> bool:
    """Whether the columns ``G`` (m, 3, k; mm) move every reading along one direction only (each reading's 3 x k
    block of rank 1: a tracker's distance or angle read off, effects.instrument_map)."""
    if not len(G):
        return False
    lam = np.linalg.eigvalsh(np.einsum("nik,njk->nij", G, G))
    return bool(np.all(lam[:, 1] <= 1e-12 * np.maximum(lam[:, 2], 1e-300)))


_MM_BASES: "weakref.WeakKeyDictionary[Engine, tuple[int, np.ndarray]]" = weakref.WeakKeyDictionary()


def _mm_basis(Wi: np.ndarray, eng: Engine) -> np.ndarray:
    """(3n, P) an orthonormal basis, in mm (machine frame), of the columns of the fit ``eng`` (``Wi`` (n, 3, 3) the
    inverse whitening), kept per engine and its column count: every group a scan locates is sized beside one fit."""
    kept = _MM_BASES.get(eng)
    if kept is None or kept[0] != eng.p:
        kept = eng.p, np.linalg.qr(np.einsum("nij,njp->nip", Wi, eng.full_rows()).reshape(Wi.shape[0] * 3, -1))[0]
        _MM_BASES[eng] = kept
    return kept[1]


def group_shift(W: np.ndarray, eng: Engine, idx: np.ndarray, among: int = 1) -> tuple[float, float]:
    """(size, standard uncertainty) mm of a group's common shift beyond the fit ``eng``: a translation of the
    readings ``idx`` as three columns (beyond_fit), its largest displacement at a reading; ``among``: the groups
    it was located among (seen_z)."""
    return beyond_fit(W, eng, translations(W, [idx]), eng.sigma, among).largest()[1:]


def translations(W: np.ndarray, groups: list[np.ndarray]) -> np.ndarray:
    """(3n, 3m) whitened columns (``W`` (n, 3, 3) the whitening): a translation (mm, machine frame) of each of
    the m groups' readings (indices)."""
    G = np.zeros((len(W), 3, 3 * len(groups)))
    for j, idx in enumerate(groups):
        G[idx, :, 3 * j:3 * j + 3] = W[idx]
    return G.reshape(3 * len(W), -1)


def _levels(prep: Prepared, on: np.ndarray) -> dict[str, list[tuple[Any, np.ndarray]]]:
    """The levels of every factor on the readings ``on`` (bool (n,)): (label, mask)."""
    rec, n = prep.rec, len(prep.rec)
    out: dict[str, list[tuple[Any, np.ndarray]]] = {
        "direction": [(d, on & (rec.direction == d)) for d in (1, -1)],
        "round": [(int(r), on & (rec.round == r)) for r in sorted(set(rec.round[on].tolist()))],
        "position": [(float(p), on & (rec.position == p)) for p in sorted(set(rec.position[on].tolist()))],
        "point": [(str(p), on & (rec.point == p)) for p in sorted(set(rec.point[on].tolist()))],
        "time": []}
    ts = rec.time_s[on]
    if np.isfinite(ts).all():
        edges = np.quantile(ts, [0, 1 / 3, 2 / 3, 1])
        for k in range(3):
            sel = on & (rec.time_s >= edges[k]) & ((rec.time_s < edges[k + 1]) if k < 2 else np.ones(n, bool))
            out["time"].append(([round(float(edges[k]), 1), round(float(edges[k + 1]), 1)], sel))
    return {k: [(w, m) for w, m in v if m.any()] for k, v in out.items()}


def _groups(prep: Prepared, pairs: bool):
    """(axis, by, where, mask) of every single factor level and, with ``pairs``, every cell of two factors."""
    for a in prep.axes:
        lv = _levels(prep, prep.rec.axis == a)
        for f in FACTORS:
            for w, m in lv[f]:
                yield a, f, w, m
        if not pairs:
            continue
        for f1, f2 in itertools.combinations(FACTORS, 2):
            if len(lv[f1]) < 2 or len(lv[f2]) < 2:
                continue
            for (w1, m1), (w2, m2) in itertools.product(lv[f1], lv[f2]):
                yield a, f"{f1} x {f2}", [w1, w2], m1 & m2


def locate(prep: Prepared, eng: Engine, level: float, pairs: bool = True) -> list[Located]:
    """Where the studentized residuals concentrate: groups by axis x (direction, round, position, point, time)
    and, with ``pairs``, by axis x every pair of them (patterns that cancel within one factor, e.g. a pitch error
    that reverses with the direction of approach and has opposite signs on reflectors either side of the axis).
    Each group: a chi^2 test of its mean shift and of its spread; Bonferroni over groups x 2.  Every group is
    screened with its readings studentized one by one (3 and 3 n_g dof); a group that screen puts below an
    adjusted p of 1 is tested with its residuals studentized together (_group_tests: their correlations through the
    fit included), and that test decides."""
    n = len(prep.rec)
    r = eng.r.reshape(n, 3)
    Qi = eng.rows()
    IH = np.eye(3) - np.einsum("nip,njp->nij", Qi, Qi)
    s2 = eng.sigma**2
    t2 = np.einsum("ni,ni->n", r, np.linalg.solve(IH + 1e-12 * np.eye(3), r[..., None])[..., 0]) / s2
    groups = [(a, by, where, np.flatnonzero(sel)) for a, by, where, sel in _groups(prep, pairs) if sel.sum() >= 2]
    count = 2 * len(groups)
    Qf, cols = None, {}  # the full rows of Q (computed when first needed) and, per axis, its live columns

    def rows_of(b: str) -> np.ndarray:  # the fit's rows on the columns live on axis b (a group lies within one)
        nonlocal Qf
        if Qf is None:
            Qf = eng.full_rows()
        if b not in cols:
            cols[b] = np.flatnonzero(np.any(Qf[prep.rec.axis == b] != 0, axis=(0, 1)))
        return Qf[:, :, cols[b]]

    out = []
    for a, by, where, idx in groups:
        ng = len(idx)
        mean = r[idx].sum(axis=0)
        tests = [(float(mean @ mean) / (ng * s2), 3), (float(t2[idx].sum()), 3 * ng)]
        if min(_tails.chi2_sf(v, k) for v, k in tests) * count >= 1.0:
            continue
        tests = _group_tests(r[idx], rows_of(a)[idx], s2)
        p_shift = float(_tails.chi2_sf(*tests[0])) if tests[0][1] else 1.0
        p_disp = _spread_p(prep, a, idx, tests[1], r, rows_of, s2, level / count)
        padj = min(1.0, min(p_shift, p_disp) * count)
        if padj < level:
            (T, kt), (S, ks) = tests
            size, sd = group_shift(prep.W, eng, idx, len(groups))
            out.append(Located(a, by, where,
                               float(-math.log10(max(padj, 1e-300))), padj,
                               "mean" if p_shift <= p_disp else "spread", ng, T / max(kt, 1), S / max(ks, 1),
                               size, shift_sd_mm=sd, rows=idx))
    out.sort(key=lambda d: -d.score)
    return out


def _group_tests(rg: np.ndarray, Qg: np.ndarray, s2: float) -> tuple[tuple[float, int], tuple[float, int]]:
    """((T, dof) of the mean shift, (S, dof) of the spread) of one group's whitened residuals ``rg`` (m, 3), with
    ``Qg`` (m, 3, P) their rows of the fit's orthonormal basis, ``s2`` the residual variance.  The residuals of a
    group are correlated through the fit (cov = s2 (I - Q_g Q_g^T)): with two rounds the two readings of a pass are
    mirror images about their mean, and their squares summed as if independent scatter like chi^2 with about half
    the degrees of freedom (gen2 seed 3501 campaign 4, clean: a "spread" at p_adj 0.004 that is 0.03 studentized
    together).  So: S = r^T (I - Q_g Q_g^T)^+ r / s2 (Woodbury on the group's own columns of Q) with 3 m less the
    directions the fit holds exactly, and T = m^T C^+ m / s2 of the group's sum m, C = m I - (sum Q)(sum Q)^T."""
    m = len(rg)
    Q = Qg.reshape(3 * m, -1)
    r = rg.ravel()
    if 3 * m <= Q.shape[1]:  # the group's own space is the smaller: (I - Q Q^T)^+ directly
        lam, V = np.linalg.eigh(np.eye(3 * m) - Q @ Q.T)
        free = lam > GROUP_TOL
        S = float(np.sum((V[:, free].T @ r) ** 2 / lam[free])) / s2
    else:  # Woodbury in the space of Q's columns
        mu, U = np.linalg.eigh(Q.T @ Q)  # the squared singular values of Q_g
        c = U.T @ (Q.T @ r)
        free = 1.0 - mu > GROUP_TOL
        S = (float(r @ r) + float(np.sum(c[free] ** 2 / (1.0 - mu[free])))
             - float(np.sum(c[~free] ** 2 / np.maximum(mu[~free], GROUP_TOL)))) / s2
        free = np.concatenate([free, np.ones(3 * m - len(mu), bool)])
    A = Qg.sum(axis=0)  # (3, P): the rows of the group's sum
    lam, V = np.linalg.eigh(m * np.eye(3) - A @ A.T)
    live = lam > GROUP_TOL * m
    total = rg.sum(axis=0)
    T = float(np.sum((V[:, live].T @ total) ** 2 / lam[live])) / s2
    return (T, int(live.sum())), (max(S, 0.0), int(3 * m - (~free).sum()))


GROUP_TOL = 1e-6  # a direction the fit holds to within this share of its variance carries no residual


def _spread_p(prep: Prepared, axis: str, idx: np.ndarray, spread: tuple[float, int], r: np.ndarray,
              rows_of: Callable[[str], np.ndarray], s2: float, bound: float) -> float:
    """p of a group's spread (``spread``: S and its dof, _group_tests, in the residual variance ``s2``): against the
    law (chi^2) and, where that is below ``bound`` (the level over the tests), also against the scatter of the same
    reflectors' other readings on the axis from the same station(s), an F test (their own S and dof, studentized
    together the same way: ``r`` (n, 3) the whitened residuals, ``rows_of(axis)`` (n, 3, P) the fit's rows on an
    axis' columns); the larger p.  A law estimated from the rounds is wrong nest by nest (its shape, its distance term),
    and a nest whose scatter it understates spreads in every round it is read (gen2 seed 3513 campaign 17, clean, a
    1 : 2.8 tracker read as 1 : 4: nest P8 in round 5 at p_adj 0.0017 against the law, 2.2 times its variance, and
    as much in its other rounds).  The same station, because each station's scale is its own: one whose rounds a
    re-levelled tracker spread is scaled up, which leaves the others' readings spread against the pooled variance
    in every round (gen2 seed 3514 campaign 20, tracker given: station S1's rounds of Y and B at 1.5 to 1.8 times
    it, none beyond the others of S1).  Where the axis has no other readings of those reflectors at the station
    (one round of it there), the station's readings of its other axes are the reference, each axis studentized on
    its own columns (gen2 seed 3543 campaign 18: S3's only round of Z "spread" at 1.55 times the pool, which a
    re-levelled S1 pulled down)."""
    S, k = spread
    if not k:
        return 1.0
    p_law = float(_tails.chi2_sf(S, k))
    if p_law >= bound:
        return p_law
    rec = prep.rec
    inside = np.zeros(len(rec), bool)
    inside[idx] = True
    st = rec.stations()
    here = np.isin(st, st[idx]) & ~inside
    ref = np.flatnonzero((rec.axis == axis) & np.isin(rec.point, rec.point[idx]) & here)
    if len(ref) < 2:
        ref = np.flatnonzero(here)
    S_ref, k_ref = 0.0, 0
    for b in dict.fromkeys(rec.axis[ref].tolist()):
        rb = ref[rec.axis[ref] == b]
        if len(rb) >= 2:
            _, (S_b, k_b) = _group_tests(r[rb], rows_of(b)[rb], s2)
            S_ref, k_ref = S_ref + S_b, k_ref + k_b
    if k_ref < 2 or S_ref <= 0:
        return p_law
    return max(p_law, float(_tails.f_sf((S / k) / (S_ref / k_ref), k, k_ref)))


MAX_LEVELS = 3  # located levels of one factor on one axis beyond which they are one entry (collapsed)


def collapsed(located: list[Located]) -> list[Located]:
    """One entry per (axis, factor) where more than MAX_LEVELS levels of that factor are located: a recording whose
    every pose (round) is displaced its own way holds one mismatch -- a motion from one level to the next that the
    model does not hold -- not one per level (icelinker: 40 of 1000 robot poses).  The entry keeps the largest
    shift (mm), the smallest adjusted p, the readings of every level, and lists the levels in ``where``."""
    groups: dict[tuple[str, str], list[Located]] = {}
    for u in located:
        groups.setdefault((u.axis, u.by), []).append(u)
    out = []
    for (axis, by), us in groups.items():
        if len(us) <= MAX_LEVELS:
            out += us
            continue
        top = max(us, key=lambda u: u.score)
        big = max(us, key=lambda u: u.shift_mm)
        note = (f"{len(us)} levels of {by} of axis {axis} are displaced, each its own way (largest "
                f"{big.shift_mm * 1e3:.1f} um at {by} {big.where}): the readings move from one {by} to the next "
                "in a way the model does not hold (a motion shared by the reflectors, e.g. of the stand or the "
                "structure they sit on)")
        out.append(Located(axis, by, {"levels": [u.where for u in us]}, top.score,
                           top.p_adjusted, top.kind, sum(u.readings for u in us), top.mean_shift_chi2_per_dof,
                           top.spread_chi2_per_dof, big.shift_mm, note, big.shift_sd_mm,
                           np.unique(np.concatenate([u.rows for u in us if u.rows is not None] or [[]])).astype(int)))
    out.sort(key=lambda d: -d.score)
    return out


SHAPE_NOTE = ("the error functions tabulated at the measured positions explain it: a quasi-static shape beyond "
              "the family's degree, not a left-out effect")


def beyond_the_family(prep: Prepared, eng: Engine, located: list[Located],
                      w: Callable[[fx.Candidate], np.ndarray], level: float) -> tuple[list[Located], list[Located]]:
    """Split ``located`` (found on ``eng``) into what is still located with every error motion of its axis free at
    every measured position (fx.tabulated: a compensation table's worth of quasi-static error) and what that
    explains: a shape of the error function the family's polynomials (degree 7) do not hold -- repeatable, the same
    in every round -- reported with the base, not as unexplained (gen2 seed 19 campaign 183: a 1 : 70 tracker, 0.15
    um along the beam, saw 0.7-2.5 um of Y's smooth error function beyond degree 7 at 10 positions).  ``w``
    maps a candidate to its whitened columns (selection.Columns)."""
    axes = sorted({u.axis for u in located})
    if not axes:
        return located, []
    tab = eng.copy()
    for a in axes:
        tab.add(tab.residualized(w(fx.tabulated(prep.geometry, a))))
    still = {(u.axis, u.by, repr(u.where)) for u in locate(prep, tab, level)}
    keep = [u for u in located if (u.axis, u.by, repr(u.where)) in still]
    return keep, [replace(u, note=SHAPE_NOTE) for u in located if (u.axis, u.by, repr(u.where)) not in still]


MAX_ENTRIES = 8  # located entries taken one at a time (one_at_a_time); the rest follow as located beside them


def one_at_a_time(prep: Prepared, eng: Engine, located: list[Located],
                  w: Callable[[fx.Candidate], np.ndarray], level: float) -> list[Located]:
    """The located entries, taken one at a time while the fit still locates any of ``located``'s groups (found on
    ``eng``, collapsed).  A misfit at one place leaks through the base's shared freedoms -- a reflector's position
    fitted from every axis it is read on, an axis' error motions from every nest -- into the readings of other
    places, at times more strongly than it shows where it is: freed where it is, the leak goes with it, which
    freeing the leak does not do.  So the places tried at each step are the groups located on the current fit and
    every reflector as read on each axis (its readings there); each is freed in every cell (fx.by_cell: a nest at a
    pose and direction, pooled over rounds) with the base refitted beside it, and the one that explains the misfit
    with the strongest evidence (the smallest p of that F test) is taken; the groups are then located again on the
    fit with it.

    Tests: an entry taken from the located groups keeps locate's test on the fit with the entries before it (null:
    the group's readings have no mean shift and no extra spread beyond that fit; alternative: they have; error
    term: the fit's residual, studentized; Bonferroni over the groups x 2).  A reflector taken on an axis enters
    with its free form's F test (null: its readings on that axis add no mean at any cell beyond the fit; error
    term: the fit's residual), Bonferroni over the places tried; it is taken only where that is below ``level``.
    The steps stop where nothing of ``located`` is located any more (a shape beyond the family stays a shape); after
    MAX_ENTRIES steps what is still located beside them follows as it is."""
    keys = {(u.axis, u.by, repr(u.where)) for u in located}
    rec, g = prep.rec, prep.geometry
    nests = [((a, p), fx.by_cell(g, rows), rows) for a in prep.axes
             for p in sorted(set(rec.point[rec.axis == a].tolist()))
             for rows in [np.flatnonzero((rec.axis == a) & (rec.point == p))]]  # each freed once, whitened once
    out: list[Located] = []
    e, todo = eng, [u for u in located if u.rows is not None and len(u.rows)]
    while todo and len(out) < MAX_ENTRIES:
        tried = [(u, fx.by_cell(g, u.rows), u.rows) for u in todo] + [
            n for n in nests if not any(u.axis == n[0][0] and u.by == "point" and u.where == n[0][1]
                                        for u in todo + out)]
        scores = [e.score(w(free)) for _, free, _ in tried]
        logp = [sc.logp if sc.separable else 0.0 for sc in scores]
        j = min((i for i, (u, _, _) in enumerate(tried)
                 if isinstance(u, Located) or logp[i] + math.log(len(tried)) < math.log(level)),
                key=lambda i: logp[i])
        (u, free, rows), padj = tried[j], min(1.0, math.exp(logp[j]) * len(tried))
        if not isinstance(u, Located):
            size, sd = group_shift(prep.W, e, rows, len(tried))
            u = Located(u[0], "point", u[1], float(-math.log10(max(padj, 1e-300))), padj, "mean", len(rows),
                        scores[j].F, 0.0, size, shift_sd_mm=sd, rows=rows,
                        note="located where freeing the reflector's readings on this axis explains what was "
                             "located on the fit (it leaks from here through the base's shared freedoms)")
        out.append(u)
        e = e.copy()
        e.add(e.residualized(w(free)))
        taken = {(x.axis, x.by, repr(x.where)) for x in out}
        todo = [x for x in collapsed([x for x in locate(prep, e, level) if (x.axis, x.by, repr(x.where)) in keys])
                if (x.axis, x.by, repr(x.where)) not in taken and x.rows is not None and len(x.rows)]
    return out + todo + [x for x in located if x.rows is None or not len(x.rows)]


def outlier_scan(prep: Prepared, eng: Engine) -> tuple[dict, int]:
    """Best single-reading and bumped-nest (rest of the round) displacement; returns (best, family size)."""
    n = len(prep.rec)
    W = prep.W
    r = eng.r.reshape(n, 3)
    Qi = eng.rows()
    # one reading: span of the three whitened unit columns
    M = np.eye(3) - np.einsum("nip,njp->nij", Qi, Qi)
    ok = np.linalg.eigvalsh(M)[:, 0] > ALIAS_TOL**2
    delta = np.zeros(n)
    delta[ok] = np.einsum("ni,ni->n", r[ok], np.linalg.solve(M[ok], r[ok][..., None])[..., 0])
    i = int(np.argmax(delta))
    best = {"delta": float(delta[i]), "rows": np.array([i]), "mode": "reading"}
    count = int(ok.sum())
    # bumped nest: readings s.. of one (axis, round, point) sequence in time order
    for s in range(len(prep.seq_keys)):
        idx = np.flatnonzero(prep.seq == s)
        idx = idx[np.argsort(prep.order[idx])]
        if len(idx) < 3:
            continue
        Wi = W[idx]
        A = np.cumsum((Wi.transpose(0, 2, 1) @ Wi)[::-1], axis=0)[::-1]          # sum W^T W
        B = np.cumsum(np.einsum("npk,nkj->npj", Qi[idx].transpose(0, 2, 1), Wi)[::-1], axis=0)[::-1]  # Q^T G
        b = np.cumsum(np.einsum("nki,nk->ni", Wi, r[idx])[::-1], axis=0)[::-1]   # G^T r
        # every start j = 1 .. len - 2 at once
        GpGp = A[1:-1] - np.einsum("jpi,jpk->jik", B[1:-1], B[1:-1])
        ok = np.linalg.eigvalsh(GpGp)[:, 0] > ALIAS_TOL**2 * np.linalg.eigvalsh(A[1:-1])[:, -1]
        if not ok.any():
            continue
        bj = b[1:-1][ok]
        d = np.einsum("ji,ji->j", bj, np.linalg.solve(GpGp[ok], bj[..., None])[..., 0])
        count += int(ok.sum())
        k = int(np.argmax(d))
        if d[k] > best["delta"]:
            best = {"delta": float(d[k]), "rows": idx[1 + np.flatnonzero(ok)[k]:], "mode": "bump"}
    return best, count


def knock_scan(prep: Prepared, eng: Engine, among: np.ndarray | None = None,
               frame: np.ndarray | None = None) -> tuple[dict | None, int]:
    """Change point of a knock: every reading from t0 on (all axes, all reflectors; of the readings ``among``, bool
    (n,), e.g. one tracker station's or one nest's, else all) shifted by one vector (machine frame; with ``frame``
    (n, 3, 3), the rotation of each reading's local frame, one vector in that frame: a knocked nest turns with its
    side).  The step_scan of those three columns; returns (best {"delta", "t0", "rows", "before_s", "after_s"},
    number of separable change points scanned)."""
    rows = np.ones(len(prep.rec), bool) if among is None else among
    return step_scan(prep, eng, rows, prep.W if frame is None else prep.W @ frame)


def return_scan(prep: Prepared, eng: Engine, rows: np.ndarray, pattern: np.ndarray) -> tuple[dict | None, int]:
    """Second change point of a step along its own motion: the step_scan of one column, the readings ``rows`` (bool
    (n,), the step's place) from t1 on moved by ``pattern`` ((n, 3) mm, machine frame: the step's fitted motion at
    every reading), one amount, scored on ``eng`` (the step fitted).  Returns (best, change points scanned)."""
    return step_scan(prep, eng, rows, np.einsum("nij,nj->ni", prep.W, pattern)[:, :, None])


def step_scan(prep: Prepared, eng: Engine, rows: np.ndarray, Gw: np.ndarray) -> tuple[dict | None, int]:
    """The best change point of a step of a place: of the readings ``rows`` (bool (n,)) in time order, every one
    from t0 on moved by the per-reading whitened columns ``Gw`` ((n, 3, p): W_i times the place's motion per
    parameter at reading i), one amount per column.  t0 is scanned over the gaps between distinct reading times;
    each step's reduction of the residual sum of squares on ``eng`` (Frisch-Waugh: G^T G, Q^T G and G^T r) is
    formed by running sums in time order, across the base blocks.  A change point whose columns lie within
    ALIAS_TOL of the fit (sin^2 of the smallest angle, relative to G^T G: as Engine.score), or that spans fewer
    directions than G has columns (G^T G's smallest eigenvalue below RANK_TOL of its largest), is not counted.
    Returns (best {"delta", "t0", "rows": the readings from t0 on, "before_s", "after_s"}, number of separable
    change points scanned), (None, 0) where none is."""
    rec = prep.rec
    n = len(rec)
    o = np.argsort(prep.order)
    o = o[rows[o]]
    if len(o) < 3 or not np.isfinite(rec.time_s[o]).all():
        return None, 0
    r = eng.r.reshape(n, 3)
    t = rec.time_s[o]
    Go = Gw[o]
    A = np.cumsum((Go.transpose(0, 2, 1) @ Go)[::-1], axis=0)[::-1]                          # G^T G
    B = np.cumsum(np.einsum("nkp,nkj->npj", eng.full_rows()[o], Go)[::-1], axis=0)[::-1]     # Q^T G
    b = np.cumsum(np.einsum("nki,nk->ni", Go, r[o])[::-1], axis=0)[::-1]                     # G^T r
    j = np.flatnonzero(np.diff(t) > 0) + 1       # the step starts at reading j (distinct times only)
    if len(j) == 0:
        return None, 0
    M = A[j] - np.einsum("npi,npj->nij", B[j], B[j])
    lam, V = np.linalg.eigh(A[j])   # A^(-1/2) M A^(-1/2): the step's share outside the fit, per direction
    Li = V / np.sqrt(np.where(lam > 0, lam, 1.0))[:, None, :]
    mu = np.linalg.eigvalsh(np.einsum("nji,njk,nkl->nil", Li, M, Li))
    ok = (lam[:, 0] > RANK_TOL * lam[:, -1]) & (mu[:, 0] > ALIAS_TOL**2)  # as Engine.score: a direction of G
    # below RANK_TOL of its largest is none (the readings from a late t0 on may not move in every direction)
    if not ok.any():
        return None, 0
    delta = np.full(len(j), -np.inf)
    delta[ok] = np.einsum("ni,ni->n", b[j][ok], np.linalg.solve(M[ok], b[j][ok][..., None])[..., 0])
    k = int(np.argmax(delta))
    jj = int(j[k])
    return {"delta": float(delta[k]), "t0": 0.5 * float(t[jj - 1] + t[jj]), "rows": o[jj:],
            "before_s": float(t[jj - 1]), "after_s": float(t[jj])}, int(ok.sum())


RANK_TOL = 1e-12  # step_scan: G^T G's eigenvalues below this share of its largest are nil

K_MAX = 4  # change points a place's search goes up to (its own step and three more)


@dataclass
class ChangePoints:
    """A place's change points found by change_points: for each, in the order found, ``rows`` (the place's readings
    from it on), ``t0`` (s, mid-gap), ``scanned`` (change points scanned for it) and ``logp_adj`` (its test's log p
    times that multiplicity); ``theta`` (k, p) their amplitudes fitted together beside the fit searched on;
    ``drift``: the score of the place's smooth path beside the k steps where it is still needed (the place moving
    smoothly, the steps only sampling it), else None."""

    rows: list[np.ndarray]
    t0: list[float]
    scanned: list[int]
    logp_adj: list[float]
    theta: np.ndarray
    drift: Any = None

    @property
    def k(self) -> int:
        return len(self.rows)


def change_points(prep: Prepared, eng: Engine, rows: np.ndarray, G: np.ndarray, level: float,
                  k_max: int = K_MAX, given: list[np.ndarray] = (),
                  against: Callable[[Engine, np.ndarray, np.ndarray, Any], float | None] | None = None,
                  smooth: np.ndarray | None = None) -> ChangePoints:
    """The change points of one place, one penalised search over their number k = 0, 1, 2, ...: the readings
    ``rows`` (bool (n,), the place's: a station's frame, one nest) step k times in time, each step moving them by
    the place's own motion ``G`` ((n, 3, p) mm per parameter, machine frame: a translation; a turn about the tracker
    and a translation; a nest's translation in its side's frame) with its own free amplitude (a step and back is
    k = 2, the second amplitude free).  ``given``: change points already fitted (their readings from t0 on, each
    a step of G), counted in k.

    Search: greedy (binary segmentation along the fit): the best change point on the fit so far (step_scan, every
    gap between reading times), added where it enters; the k-th enters when its F test beside the fit and the k-1
    before it (Engine.score: null, no step there; alternative, a step of G's p columns; error term, the fit's
    residual mean square -- or, with ``against``, the caller's: it returns the step's log p against another
    stratum, e.g. the scatter of the stops it moves, or None for the usual test) has a log p that, multiplied by
    the m_k change points scanned for it (Bonferroni: the max of the scanned statistics), is below log ``level``.
    Equivalently k-hat minimises, along the greedy path, -2 ln L + sum_j q_j with q_j the critical value of the
    j-th change point's test at level/m_j: the scan's own max-statistic calibration as the penalty, so that no
    step enters on noise at more than ``level`` per place.  The search stops at ``k_max`` or at the first change
    point that does not enter.  A drift instead of steps: with ``smooth`` ((n, 3, q) mm, the place moving smoothly
    in the order of the readings, places.frame_path / nest_path) is the other model of the place: beside the given
    steps, significant itself (F test at ``level``, one per place, no location scanned) and ahead of the k-hat
    steps found in the same penalised likelihood (_drift: each term's reduction of the residual sum of squares
    less its critical value), it sets ``drift``: steps cannot hold a smooth motion, which a greedy search samples
    with as many steps as it is allowed.  What the k steps are (a knock, a re-seated nest,
    displaced for a while and back, stepping again and again, a drift sampled by steps) is read by the caller
    from k-hat, the amplitudes and the place, never by a rule per effect name."""
    n = len(prep.rec)
    e = eng.copy()
    Gw = np.einsum("nij,njk->nik", prep.W, G)
    cols = []

    def step(on: np.ndarray) -> np.ndarray:
        X = np.zeros_like(Gw)
        X[on] = Gw[on]
        return X.reshape(3 * n, -1)

    given = [np.flatnonzero(on) if on.dtype == bool else on for on in given]  # readings from t0 on, indices
    for on in given:
        cols.append(step(on))
        e.add(cols[-1])
    start, gains = e.copy(), []
    out = ChangePoints([*given], [float(np.min(prep.rec.time_s[on])) for on in given], [0] * len(given),
                       [-math.inf] * len(given), np.zeros((0, G.shape[2])))
    while out.k < k_max:
        found, m = step_scan(prep, e, rows, Gw)
        if found is None:
            break
        X = step(found["rows"])
        sc = e.score(X)
        if not sc.separable:
            break
        logp = against(e, X, found["rows"], sc) if against is not None else None
        logp = sc.logp if logp is None else logp
        if logp + math.log(m) >= math.log(level):
            break
        e.add(X)
        cols.append(X)
        gains.append((sc.delta, sc.k))
        out.rows.append(found["rows"])
        out.t0.append(found["t0"])
        out.scanned.append(m)
        out.logp_adj.append(logp + math.log(m))
    if cols:
        A = np.hstack(cols)
        theta = np.linalg.lstsq(A - eng.project(A), eng.r, rcond=None)[0]
        out.theta = theta.reshape(len(cols), -1)
    if smooth is not None:
        out.drift = _drift(start, e, np.einsum("nij,njk->nik", prep.W, smooth).reshape(3 * n, -1), out, gains,
                           level)
    return out


def _drift(start: Engine, steps: Engine, P: np.ndarray, cp: ChangePoints, gains: list[tuple[float, int]],
           level: float):
    """The score of the smooth path ``P`` (whitened columns) beside the given steps (``start``) where the path
    model beats the k-hat steps found (``steps``, their reductions and columns ``gains``) in the penalised
    likelihood of change_points -- the reduction of the residual sum of squares less each term's critical value at
    its level (the path: F test at ``level``, one per place; a change point: at level over those scanned for it),
    both in the residual mean square of the better of the two fits -- and is significant itself; else None."""
    sc = start.score(P)
    if not sc.separable or sc.logp >= math.log(level):
        return None
    s2 = min(steps.rss / steps.dof, (start.rss - sc.delta) / sc.dof)
    pen = sum(k * float(_tails.f_ppf(1.0 - min(level / m, 0.5), k, steps.dof))
              for (_, k), m in zip(gains, cp.scanned[len(cp.scanned) - len(gains):]))
    path = sc.delta / s2 - sc.k * float(_tails.f_ppf(1.0 - level, sc.k, sc.dof))
    return sc if path > sum(d for d, _ in gains) / s2 - pen else None


def where_of(prep: Prepared, rows: np.ndarray) -> dict:
    rec = prep.rec
    i = rows[np.argmin(prep.order[rows])]
    return {"round": int(rec.round[i]), "position": float(rec.position[i]), "point": str(rec.point[i]),
            "approach": int(rec.direction[i]), "line": int(rec.line[i]), "readings": int(len(rows))}
