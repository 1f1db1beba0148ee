"""One axis repeating worse than the others: a variance component of the readings, not a displacement (issue 34,
the grammar's member ``axis_scatter``: one axis x scatter).

The physics: every stop of the axis (one round, direction and position: the machine stands still while the nests
are read in turn) lands a random N(0, s^2) off along the axis, and every nest read at that stop shares the draw --
a random effect per stop whose signature is the axis' positioning column in each reading, one free parameter per
stop.  Two tests, by the design of the recording:

* **several nests per stop** (the usual tracker campaign; gen2's): per reading the axis' positioning error seen,
  d = h' y with h = C_m^-1 g / g' C_m^-1 g (g the positioning column, C_m the noise law's covariance averaged over
  the axis' readings at the station: with an anisotropic tracker mostly the beam's component of g is seen; one h
  per station, so that a translation shared by the readings is the same d at every position -- a per-reading
  C^-1 g turns with the beam and, where the beam crosses the axis square, reads a knock as a jump between stops).
  *Within* a stop the nests' d differ only by the tracker's noise (and by what is fixed per nest and position, or
  slow per nest: taken out by nest x cell and nest x time terms): their weighted scatter is the law's scale k at
  that station, whatever the law's shape.  *Between* stops: the stop means D of two consecutive stops of a round (a
  pair: seconds apart, so a drift, a knock after them, a re-seated nest or a re-levelled tracker cancel in the
  difference), less the pair's mean over rounds (every error that repeats) and a per-round slope and bow along the
  travel (a scale or straightness that changes between rounds: a warming axis, a re-levelled tracker).  Nothing
  planted, the between scatter is k too; a per-stop scatter adds 2 s^2.  The pair with the largest contribution is
  dropped (a knock or an outlier between the two stops of one pair), and the statistic's null distribution -- the
  same fit and trim on normal draws, k from its own chi^2 per station -- is simulated (fixed seed), one-sided,
  Bonferroni over the axes tested.  The law's scale and shape cancel, so the test holds its level whatever the
  tracker (measured on gen2's clean campaigns, docs/guide/diagnose.md).  Linear axes only: a rotary axis' per-stop
  angle is not told from a table drift seen through the turning tangents by this design.
* **one nest per stop** (mtcal's own plans read each nest in its own pass): the draw is per reading, and the
  round-to-round scatter along each axis' motion is compared with the other axes' through the law (``_by_axes``).

Found, the readings of the axis are re-weighted by C + m s^2 g g' (m the nests read at the reading's stop: the stop
mean then carries its s^2), so that the scans that follow (outliers, knocks, steps) are not fooled by the scatter.
Units: mm (the positioning of a linear axis)."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from mtcal import _tails
from mtcal.diagnose.prepared import LEVEL as DIAGNOSIS_LEVEL
from mtcal.diagnose.prepared import STAGES, NoiseModel, Prepared

LEVEL = DIAGNOSIS_LEVEL / STAGES  # family-wise over the axes tested: the diagnosis' share of its default level
MIN_DOF = 10   # degrees of freedom an axis' round scatter needs to be tested (one nest per stop)
MIN_PAIR_DOF = 4  # degrees of freedom the pairs of stops need, after the trim (several nests per stop)
DRAWS = 4000   # null draws of the per-stop test (fixed seed: the same answer every run)
NOT_TESTED = ("the rounds reject the given tracker's law and the law was estimated from the same round scatter (or "
              "is isotropic): the axes' scatter along their motions is compared through that law's shape, which "
              "then decides it -- on gen2's seed 3501 a 1 : 70 and an isotropic tracker made X and C 'repeat "
              "worse' on 3 of 25 runs with the tracker given where nothing repeated worse; give the instrument "
              "(--tracker-model) whose shape the rounds confirm")


def axis_scatter(prep: Prepared, level: float = LEVEL) -> NoiseModel:
    """``prep``'s noise model, re-weighted where one axis' stops scatter along its motion (module docstring), with
    the test of every axis in ``details["axis_scatter"]`` (``test``, ``tested``, ``found``); unchanged (and no key)
    when the recording has nothing to compare.

    Parameters
    ----------
    prep : Prepared
        The prepared recording (its noise model, geometry and reference positions).
    level : float, optional
        Family-wise level over the axes tested (default 0.005 / 3: the diagnosis' default, a third to each of its
        stages, mtcal.diagnose.prepared.STAGES).

    Returns
    -------
    NoiseModel
        The noise model to weight the readings by.
    """
    stop = prep.stop
    nests = np.bincount(stop)[stop]
    if np.median(nests) < 2:
        return _by_axes(prep, level)
    linear = [a for a in prep.axes if prep.machine.kind(a) == "linear"]
    return _by_stops(prep, stop, nests, linear, level)


def _by_axes(prep: Prepared, level: float) -> NoiseModel:
    """One nest per stop: the round-to-round scatter along each axis' motion against the other axes' (module
    docstring)."""
    rec, noise = prep.rec, prep.noise
    if noise.kind == "isotropic" or noise.kind.startswith("tracker law estimated (given"):
        return replace(noise, details={**noise.details, "axis_scatter": {"tested": [], "found": None,
                                                                         "not_tested": NOT_TESTED}})
    u = _motion(prep)
    C = np.linalg.inv(np.einsum("nji,njk->nik", noise.W, noise.W))   # covariance (n, 3, 3), mm^2
    sig2 = np.einsum("ni,nij,nj->n", u, C, u)                       # variance along the motion, mm^2
    tables = {a: _round_scatter(prep, a) for a in prep.axes}
    tables = {a: t for a, t in tables.items() if t[1] >= MIN_DOF}
    if len(tables) < 2:
        return noise
    z2 = {a: float(np.sum(np.einsum("ni,ni->n", u[rows], e) ** 2 / sig2[rows])) for a, (rows, _, e) in tables.items()}
    dof = {a: t[1] for a, t in tables.items()}
    tested = []
    for a in tables:
        dj, do = dof[a], sum(v for b, v in dof.items() if b != a)
        k = sum(v for b, v in z2.items() if b != a) / do           # the law's common scale, from the others
        F = (z2[a] / dj) / k
        p = float(_tails.f_sf(F, dj, do))
        tested.append({"axis": a, "F": F, "dof": [dj, do], "p_value": p,
                       "p_adjusted": min(1.0, p * len(tables)), "scale": k})
    best = min(tested, key=lambda t: t["p_value"])
    out = {"test": "round-to-round scatter along each axis' motion against the other axes' (F, one-sided, "
                   "Bonferroni over the axes)", "tested": tested, "found": None}
    if best["p_adjusted"] >= level:
        return replace(noise, details={**noise.details, "axis_scatter": out})
    found = _found(prep, best, tables[best["axis"]][0], sig2)
    out["found"] = found
    W = noise.W.copy()
    on = rec.axis == best["axis"]
    s2 = found["extra_sd_mm"] ** 2
    W[on] = np.linalg.inv(np.linalg.cholesky(C[on] + s2 * np.einsum("ni,nj->nij", u[on], u[on])))
    return replace(noise, W=W, how=f"{noise.how}; the readings of {best['axis']} re-weighted for its extra scatter "
                                   f"along its motion ({found['extra_sd_mm'] * 1e3:.2g} um)",
                   details={**noise.details, "axis_scatter": out})


def _found(prep: Prepared, t: dict, rows: np.ndarray, sig2: np.ndarray) -> dict:
    """The extra scatter (sd, mm) of axis ``t["axis"]`` along its motion with its 95 % interval, in words."""
    a, (dj, do), F, k = t["axis"], t["dof"], t["F"], t["scale"]
    base = k * float(np.mean(sig2[rows]))                           # the law's variance along the motion, mm^2
    lo, hi = F / _tails.f_ppf(0.975, dj, do), F / _tails.f_ppf(0.025, dj, do)
    sd = [math.sqrt(max(r - 1.0, 0.0) * base) for r in (F, lo, hi)]
    others = [b for b in prep.axes if b != a]
    names = " and ".join([", ".join(others[:-1]), others[-1]] if len(others) > 1 else others)
    return {"axis": a, "extra_sd_mm": sd[0], "interval_95_mm": [sd[1], sd[2]], "law_sd_mm": math.sqrt(base),
            "F": F, "p_adjusted": t["p_adjusted"], "readings_reweighted": int(np.sum(prep.rec.axis == a)),
            "says": f"{a} repeats worse than {names}: {sd[0] * 1e3:.2g} um of extra scatter along {a} (95 %: "
                    f"{sd[1] * 1e3:.2g} to {sd[2] * 1e3:.2g} um, beside the tracker's {math.sqrt(base) * 1e3:.2g} "
                    "um there); its readings re-weighted"}


def _motion(prep: Prepared) -> np.ndarray:
    """(n, 3) unit direction of motion of every reading's reflector: its axis' positioning error column."""
    g = prep.geometry
    u = np.zeros((len(prep.rec), 3))
    for a in prep.axes:
        on = prep.rec.axis == a
        c = g.col(prep.machine.positioning_errors[a])[on]
        n = np.linalg.norm(c, axis=1, keepdims=True)
        u[on] = np.where(n > 0, c / np.where(n > 0, n, 1.0), 0.0)
    return u


def _round_scatter(prep: Prepared, axis: str) -> tuple[np.ndarray, int, np.ndarray]:
    """(rows, degrees of freedom, residuals (len(rows), 3) mm) of ``axis``' readings less their cell means
    (position, direction) and their round means, per reflector: the complete cells x rounds tables only."""
    rec = prep.rec
    rows_all, res, dof = [], [], 0
    on = rec.axis == axis
    for p in sorted(set(rec.point[on].tolist())):
        sel = np.flatnonzero(on & (rec.point == p))
        rounds = sorted(set(rec.round[sel].tolist()))
        cells: dict[tuple, dict[int, int]] = {}
        for i in sel:
            cells.setdefault((float(rec.position[i]), int(rec.direction[i])), {}).setdefault(int(rec.round[i]), i)
        full = [c for c in cells.values() if len(c) == len(rounds)]
        if len(rounds) < 2 or len(full) < 2:
            continue
        idx = np.array([[c[r] for r in rounds] for c in full])         # (cells, rounds)
        x = rec.xyz[idx]                                                # (C, R, 3)
        e = x - x.mean(axis=1, keepdims=True) - x.mean(axis=0, keepdims=True) + x.mean(axis=(0, 1))
        rows_all.append(idx.reshape(-1))
        res.append(e.reshape(-1, 3))
        dof += (len(full) - 1) * (len(rounds) - 1)
    if not rows_all:
        return np.zeros(0, int), 0, np.zeros((0, 3))
    return np.concatenate(rows_all), dof, np.concatenate(res)


# ------------------------------------------------------------------ several nests per stop
def _by_stops(prep: Prepared, stop: np.ndarray, nests: np.ndarray, axes: list[str], level: float) -> NoiseModel:
    """Several nests per stop: each linear axis' stops against its nests' scatter within the stops (module
    docstring); the axis with the smallest p re-weighted when it is below ``level`` after Bonferroni."""
    noise, rec = prep.noise, prep.rec
    C = np.linalg.inv(np.einsum("nji,njk->nik", noise.W, noise.W))   # covariance (n, 3, 3), mm^2
    tested, fits = [], {}
    for a in axes:
        fit = _stop_fit(prep, stop, C, a)
        if fit is not None:
            fits[a] = fit
            tested.append({"axis": a, "T": fit["T"], "null_mean": fit["m0"], "dof": [fit["nu"], fit["nu_w"]],
                           "p_value": fit["p"], "pairs": fit["pairs"], "dropped_pair": fit["dropped"]})
    for t in tested:
        t["p_adjusted"] = min(1.0, t["p_value"] * len(tested))
    out = {"test": "stops of each linear axis (pairs of consecutive stops, over rounds) against the scatter of the "
                   "nests within the stops (simulated null, largest pair dropped, Bonferroni over the axes)",
           "tested": tested, "found": None}
    rotary = [b for b in prep.axes if b not in axes]
    few = [b for b in axes if b not in fits]
    why = ([f"{', '.join(rotary)}: rotary (a per-stop angle is not told from a drift of the table seen through "
            "the turning tangents by this design)"] if rotary else []) + (
        [f"{', '.join(few)}: fewer than {MIN_PAIR_DOF} degrees of freedom in the pairs of stops over rounds"]
        if few else [])
    if why:
        out["not_tested"] = "; ".join(why)
    if not tested:
        return replace(noise, details={**noise.details, "axis_scatter": out})
    best = min(tested, key=lambda t: t["p_value"])
    if best["p_adjusted"] >= level:
        return replace(noise, details={**noise.details, "axis_scatter": out})
    a = best["axis"]
    found = _stop_found(prep, {**fits[a], "tested": [t["axis"] for t in tested]}, best)
    out["found"] = found
    on = rec.axis == a
    g = fits[a]["g"][on]
    s2 = found["extra_sd_mm"] ** 2
    W = noise.W.copy()
    W[on] = np.linalg.inv(np.linalg.cholesky(C[on] + (nests[on] * s2)[:, None, None]
                                             * np.einsum("ni,nj->nij", g, g)))
    return replace(noise, W=W, how=f"{noise.how}; the readings of {a} re-weighted for its stops' extra scatter "
                                   f"along its motion ({found['extra_sd_mm'] * 1e3:.2g} um per stop)",
                   details={**noise.details, "axis_scatter": out})


def _stop_fit(prep: Prepared, stop: np.ndarray, C: np.ndarray, a: str) -> dict | None:
    """The per-stop test of axis ``a``: {T, m0, nu, nu_w, p, t, q, pairs, dropped, law_var, g}, or None when the
    pairs leave fewer than MIN_PAIR_DOF degrees of freedom."""
    rec = prep.rec
    g = prep.geometry.col(prep.machine.positioning_errors[a])          # (n, 3) mm per mm
    st_all = rec.stations()
    d, w = np.zeros(len(rec)), np.zeros(len(rec))
    for st in dict.fromkeys(st_all[rec.axis == a].tolist()):
        # one projection h per station: a translation shared by the readings (a knock, a drift) is the same d at
        # every position and cancels in the pairs (a per-reading C^-1 g would turn it with the beam)
        on = np.flatnonzero((rec.axis == a) & (st_all == st))
        gm, Cm = g[on].mean(axis=0), C[on].mean(axis=0)
        h = np.linalg.solve(Cm, gm)
        h /= h @ gm
        d[on] = prep.y[on] @ h                                          # mm: the positioning error seen
        w[on] = 1.0 / np.einsum("i,nij,j->n", h, C[on], h)              # 1/mm^2, law units
    rows_b, keys_b, dpos, dpos2, rnd, omega, dlt = [], [], [], [], [], [], []
    nu_w = {}
    for st in dict.fromkeys(st_all[rec.axis == a].tolist()):
        sel = np.flatnonzero((rec.axis == a) & (st_all == st) & (w > 0))
        k, nu = _within(prep, stop, sel, d, w)
        if nu < 1:
            continue
        nu_w[st] = nu
        D, Ws, info = _stop_means(prep, stop, sel, d, w)
        for r, seq in info.items():                                      # stops of one round in time order
            for s0, s1 in zip(seq[0::2], seq[1::2]):
                p0, p1 = s0[1][0], s1[1][0]
                keys_b.append((st, s0[1], s1[1]))
                dlt.append(D[s0[0]] - D[s1[0]])
                omega.append(1.0 / (k * (1.0 / Ws[s0[0]] + 1.0 / Ws[s1[0]])))
                dpos.append((p0 - p1) / 1000.0)
                dpos2.append((p0 ** 2 - p1 ** 2) / 1e6)
                rnd.append((st, r))
                rows_b.append(st)
    if not keys_b:
        return None
    keys = list(dict.fromkeys(keys_b))
    count = {kk: 0 for kk in keys}
    for kk in keys_b:
        count[kk] += 1
    keep = np.array([count[kk] >= 2 for kk in keys_b])
    if keep.sum() < 3:
        return None
    kb = [kk for kk, on in zip(keys_b, keep) if on]
    keys = list(dict.fromkeys(kb))
    key_of = np.array([keys.index(kk) for kk in kb])
    X = _pair_design(key_of, len(keys), np.array(dpos)[keep], np.array(dpos2)[keep],
                     [r for r, on in zip(rnd, keep) if on])
    sw = np.sqrt(np.array(omega)[keep])
    y = np.array(dlt)[keep] * sw
    Xw = X * sw[:, None]
    station = np.array([s for s, on in zip(rows_b, keep) if on], dtype=object)
    return _pair_test(Xw, y, key_of, len(keys), station, nu_w, np.array(omega)[keep], a, keys, g)


def _within(prep: Prepared, stop: np.ndarray, sel: np.ndarray, d: np.ndarray, w: np.ndarray) -> tuple[float, int]:
    """(k, dof): the law's scale at one station from the nests' scatter within the stops of ``sel`` -- d less a
    mean per stop, per nest and cell (position, direction) and per nest a quadratic in time (a creep, a warming);
    the stops' means are taken out by weighted centring within each stop (Frisch-Waugh)."""
    rec = prep.rec
    _, cell = np.unique(np.asarray([f"{p}|{q}|{r}" for p, q, r in zip(rec.point[sel], rec.position[sel],
                                                                       rec.direction[sel])]), return_inverse=True)
    X = np.zeros((len(sel), cell.max() + 1))
    X[np.arange(len(sel)), cell] = 1.0
    t = rec.time_s[sel] if np.all(np.isfinite(rec.time_s[sel])) else prep.order[sel].astype(float)
    tau = (t - t.mean()) / (np.ptp(t) or 1.0)
    _, nest = np.unique(rec.point[sel], return_inverse=True)
    N = np.zeros((len(sel), nest.max() + 1))
    N[np.arange(len(sel)), nest] = 1.0
    X = np.hstack([X, N * tau[:, None], N * tau[:, None] ** 2, d[sel][:, None]])
    _, s = np.unique(stop[sel], return_inverse=True)
    ws = w[sel]
    sums = np.zeros((s.max() + 1, X.shape[1]))
    np.add.at(sums, s, X * ws[:, None])
    X = (X - sums[s] / np.bincount(s, weights=ws)[s][:, None]) * np.sqrt(ws)[:, None]
    A, y = X[:, :-1], X[:, -1]
    coef, _, rank, _ = np.linalg.lstsq(A, y, rcond=None)
    nu = len(sel) - (s.max() + 1) - int(rank)
    if nu < 1:
        return float("nan"), 0
    e = y - A @ coef
    return float(e @ e / nu), nu


def _stop_means(prep: Prepared, stop: np.ndarray, sel: np.ndarray, d: np.ndarray, w: np.ndarray):
    """(D, W, rounds): the weighted mean d of every stop of ``sel`` (mm) and its weight (1/mm^2, law units), and
    per round the stops in time order as (stop, (position, direction)) -- the first stop of a cell in a round."""
    rec = prep.rec
    D, Ws, first = {}, {}, {}
    for s in np.unique(stop[sel]):
        i = sel[stop[sel] == s]
        Ws[s] = float(w[i].sum())
        D[s] = float(w[i] @ d[i] / Ws[s])
        first[s] = (int(np.min(prep.order[i])), int(rec.round[i[0]]), (float(rec.position[i[0]]),
                                                                        int(rec.direction[i[0]])))
    rounds: dict[int, list] = {}
    seen = set()
    for s, (_, r, cell) in sorted(first.items(), key=lambda kv: kv[1][0]):
        if (r, cell) not in seen:
            seen.add((r, cell))
            rounds.setdefault(r, []).append((s, cell))
    return D, Ws, rounds


def _pair_design(key_of: np.ndarray, n_keys: int, dpos: np.ndarray, dpos2: np.ndarray, rnd: list) -> np.ndarray:
    """The pairs' design: a mean per pair of cells (what repeats) and, per round but a station's first, a slope and
    a bow along the travel (position and position^2 differences of the pair, m and m^2)."""
    X = np.zeros((len(key_of), n_keys))
    X[np.arange(len(key_of)), key_of] = 1.0
    first = {}
    for r in rnd:
        first.setdefault(r[0], r)
    extra = []
    for r in dict.fromkeys(rnd):
        if first[r[0]] == r:
            continue
        on = np.array([q == r for q in rnd], float)
        extra += [on * dpos, on * dpos2]
    return np.column_stack([X] + extra) if extra else X


def _residual_maker(Xw: np.ndarray) -> tuple[np.ndarray, int]:
    """(I - H, dof) of the whitened design."""
    U, sv, _ = np.linalg.svd(Xw, full_matrices=False)
    rank = int(np.sum(sv > sv.max() * 1e-10)) if len(sv) else 0
    U = U[:, :rank]
    return np.eye(len(Xw)) - U @ U.T, len(Xw) - rank


def _pair_test(Xw, y, key_of, n_keys, station, nu_w, omega, a, keys, g) -> dict | None:
    """The trimmed statistic of the pairs and its simulated null (module docstring)."""
    M, _ = _residual_maker(Xw)
    e = M @ y
    contrib = np.bincount(key_of, weights=e ** 2, minlength=n_keys)
    drop = int(np.argmax(contrib))
    makers = {}

    def maker(k: int):
        if k not in makers:
            keep = key_of != k
            Mk, nu = _residual_maker(Xw[keep])
            makers[k] = (keep, Mk, nu)
        return makers[k]

    keep, Mk, nu = maker(drop)
    if nu < MIN_PAIR_DOF:
        return None
    T = float(np.sum((Mk @ y[keep]) ** 2))
    rng = np.random.default_rng(34)
    labels = list(nu_w)
    scale = np.ones((DRAWS, len(y)))
    for s in labels:
        kk = rng.chisquare(nu_w[s], DRAWS) / nu_w[s]
        scale[:, station == s] = 1.0 / np.sqrt(kk)[:, None]
    Z = rng.standard_normal((DRAWS, len(y))) * scale
    E = Z @ M.T
    onehot = np.zeros((len(y), n_keys))
    onehot[np.arange(len(y)), key_of] = 1.0
    worst = np.argmax((E ** 2) @ onehot, axis=1)
    Tn = np.empty(DRAWS)
    for k in np.unique(worst):
        kp, Mx, _ = maker(int(k))
        on = worst == k
        Tn[on] = np.sum((Z[on][:, kp] @ Mx.T) ** 2, axis=1)
    p = float((1 + np.sum(Tn >= T)) / (DRAWS + 1))
    m0 = float(Tn.mean())
    t = float(np.sum(Mk ** 2 @ omega[keep]))                         # d E[T] / d (2 s^2), 1/mm^2
    return {"T": T, "m0": m0, "nu": nu, "nu_w": int(sum(nu_w.values())), "p": p, "t": t,
            "q": [float(np.quantile(Tn, 0.025)), float(np.quantile(Tn, 0.975))], "pairs": int(n_keys),
            "dropped": [str(v) for v in keys[drop]], "law_var": float(np.mean(1.0 / omega[keep])) / 2.0, "g": g}


def _stop_found(prep: Prepared, fit: dict, t: dict) -> dict:
    """The extra scatter (sd, mm) of the axis' stops along its motion with its 95 % interval, in words."""
    a, T, m0, tt = t["axis"], fit["T"], fit["m0"], fit["t"]
    lo, hi = fit["q"][1], fit["q"][0]
    s2 = [max(v, 0.0) * m0 / (2.0 * tt) for v in (T / m0 - 1.0, T / lo - 1.0, T / hi - 1.0)]
    sd = [math.sqrt(v) for v in s2]
    law = math.sqrt(fit["law_var"])
    others = [b for b in fit["tested"] if b != a] or [b for b in prep.axes if b != a]
    names = " and ".join([", ".join(others[:-1]), others[-1]] if len(others) > 1 else others)
    return {"axis": a, "extra_sd_mm": sd[0], "interval_95_mm": [sd[1], sd[2]], "law_sd_mm": law,
            "F": T / m0, "p_adjusted": t["p_adjusted"], "per": "stop",
            "readings_reweighted": int(np.sum(prep.rec.axis == a)),
            "says": f"{a} repeats worse than {names}: {sd[0] * 1e3:.2g} um of extra scatter along {a} at every stop, "
                    f"shared by the nests read there (95 %: {sd[1] * 1e3:.2g} to {sd[2] * 1e3:.2g} um, beside the "
                    f"tracker's {law * 1e3:.2g} um on a stop's mean there); its readings re-weighted"}
