"""Diagnosis of a Hocken-Borchardt plate fit (mtcal.plate.reversal) in the form of ``mtcal diagnose``."""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from mtcal.diagnose.engine import Engine
from mtcal.errors import InputError

PLATE_NAMES = {"gamma": "scale", "alpha": "squareness", "ex": "offset", "ey": "offset", "beta": "rotation"}


def diagnose_plate(fit, leave_out: Sequence[str] = (), level: float = 0.01) -> dict:
    """Diagnosis of a plate fit (mtcal.plate.reversal.PlateFit) in the form of ``mtcal diagnose``.

    Base model: the plate fit's design (``fit.design`` (N, m, p): the generated first-order design of
    derive/plate.py, or the Jacobian of the exact residual) without the columns named in ``leave_out``; the
    observations are rebuilt from the fit (residuals + design @ values).  Candidates: every parameter the fit
    held at zero (e.g. gamma with ``scale=False``, Reeve's model without the scale term) or left out here, with
    its generated column (alpha: squareness, gamma: scale, ex/ey: offset), and one outlier per plate point (its
    m observation rows).  Lengths in the plate's unit, angles in rad.
    """
    J = np.asarray(fit.design, dtype=float)
    if getattr(fit, "method", "first_order") == "exact":
        J = -J  # the exact fit's design is d residual / d params = -d prediction / d params
    N, m, p = J.shape
    y = (np.asarray(fit.residuals) + np.einsum("nmp,p->nm", J, np.asarray(fit.values))).reshape(-1)
    names = list(fit.names)
    unknown = [c for c in leave_out if c not in names]
    if unknown:
        raise InputError(f"plate diagnosis: unknown parameter(s) {unknown}; fitted: {names}")
    X = J.reshape(-1, p)
    eng = Engine([(np.arange(len(y)), X[:, [i for i, n in enumerate(names) if n not in leave_out]])], y)
    base_sigma = eng.sigma
    cands = [(PLATE_NAMES.get(n, n), n, X[:, [names.index(n)]]) for n in leave_out]
    cands += _held_at_zero(fit, names, N, m)
    for k in range(N):
        G = np.zeros((N * m, m))
        G[k * m:(k + 1) * m] = np.eye(m)
        cands.append(("outlier", str(fit.data.ids[k]), G))
    selected, stop = _select(eng, cands, level)
    located = [{"axis": None, "by": "point", "where": f.get("point"), "score": float(f.get("F", 0.0)),
                "p_adjusted": f.get("p_bonferroni")} for f in getattr(fit, "flagged", [])]
    held = [c[1] for c in cands if c[0] != "outlier" and c[1] not in leave_out]
    return {"base_sigma": base_sigma, "left_out": list(leave_out) + held, "effects": _effects(eng, selected) + stop,
            "located": located,
            "sigma_after": eng.sigma, "units": {"length": "plate input unit", "angle": "rad", "gamma": "1"}}


def _held_at_zero(fit, names: list[str], N: int, m: int) -> list[tuple[str, str, np.ndarray]]:
    """Candidates for the parameters the fit held at zero: their generated first-order columns (derive/plate.py;
    the offsets one column per turned position)."""
    from mtcal.generated import plate_numpy as PG
    from mtcal.plate.reversal import NOMINAL_TURN

    data = fit.data
    kk = len(data.positions)
    if m != 2 * (kk - 1):
        return []
    D = np.zeros((N, m, 5))
    per_pos = []
    for k in range(1, kk):
        d = PG.design_first_order(data.positions[k], NOMINAL_TURN[k])
        D[:, 2 * (k - 1):2 * k, :] += d
        per_pos.append(d)
    out = []
    for g, nme in enumerate(("alpha", "beta", "gamma", "ex", "ey")):
        if nme in names or nme == "beta" or any(n.startswith(nme) and n != nme for n in names if n != "beta"):
            continue
        if nme in ("ex", "ey"):
            if "ex" in names or "ex2" in names:
                continue
            G = np.zeros((N * m, kk - 1))
            for k in range(kk - 1):
                blk = np.zeros((N, m))
                blk[:, 2 * k:2 * k + 2] = per_pos[k][:, :, g]
                G[:, k] = blk.reshape(-1)
            out.append(("offset", nme, G))
        else:
            out.append((PLATE_NAMES[nme], nme, D[:, :, g].reshape(-1, 1)))
    return out


def _select(eng: Engine, cands: list, level: float) -> tuple[list, list[dict]]:
    """Forward selection: the best candidate of the best family (Bonferroni over families x members) added while
    significant at ``level``; (selected (candidate, score, log p_adj, sigma after), the first one not added)."""
    selected, remaining = [], list(cands)
    while remaining:
        scored = [(c, s) for c in remaining if (s := eng.score(c[2])).separable]
        if not scored:
            break
        fams: dict = {}
        for c, s in scored:
            fams.setdefault(c[0] if c[0] == "outlier" else c[1], []).append((c, s))
        best = None
        for mem in fams.values():
            c, s = min(mem, key=lambda cs: cs[1].logp)
            lp = s.logp + math.log(len(mem) * len(fams))
            if best is None or lp < best[2]:
                best = (c, s, lp)
        c, s, lp = best
        if lp >= math.log(level) or s.k >= eng.dof:
            return selected, [{"name": c[0], "axis": None, "direction": None, "significant": False, "estimate": None,
                               "sigma_after": None, "where": c[1],
                               "evidence": {"test": "F", "F": s.F, "p_value": math.exp(s.logp),
                                            "p_adjusted": min(1.0, math.exp(lp)), "cv_gain": None}}]
        eng.add(c[2])
        selected.append((c, s, lp, eng.sigma))
        remaining = [x for x in remaining if x is not c]
    return selected, []


def _effects(eng: Engine, selected: list) -> list[dict]:
    """The selected effects with their joint estimates and standard uncertainties (a vector's norm for several
    columns)."""
    if not selected:
        return []
    th, cov = eng.estimate([c[2] for c, _, _, _ in selected])
    out, off = [], 0
    for c, s, lp, sig in selected:
        k = c[2].shape[1]
        est = th[off:off + k]
        u = np.sqrt(np.maximum(np.diag(cov[off:off + k, off:off + k]), 0.0))
        off += k
        out.append({"name": c[0], "axis": None, "direction": None, "significant": True,
                    "estimate": float(est[0]) if k == 1 else float(np.linalg.norm(est)),
                    "uncertainty": float(u[0]) if k == 1 else float(np.linalg.norm(u)),
                    "parameter": c[1], "sigma_after": sig,
                    "evidence": {"test": "F", "F": s.F, "dof": [s.k, eng.dof],
                                 "p_value": math.exp(s.logp), "p_adjusted": min(1.0, math.exp(lp)),
                                 "cv_gain": None, "multiplicity": "Bonferroni over families x members"},
                    **({"vector": [float(v) for v in est]} if k > 1 else {})})
    return out


def format_plate_diagnosis(d: dict) -> str:
    """Text lines of a plate diagnosis (lengths in the plate's unit)."""
    lines = [f"diagnosis: sigma {d['base_sigma']:.4g} -> {d['sigma_after']:.4g} (input unit); held at zero / "
             f"left out: {', '.join(d['left_out']) or 'none'}"]
    sig = [e for e in d["effects"] if e["significant"]]
    for e in sig:
        lines.append(f"  {e['name']} ({e.get('parameter')}): {e['estimate']:.4g} +- {e['uncertainty']:.2g}, "
                     f"F = {e['evidence']['F']:.1f}, p_adj = {e['evidence']['p_adjusted']:.2g}, "
                     f"sigma after {e['sigma_after']:.4g}")
    if not sig:
        lines.append("  nothing left out at this level")
    return "\n".join(lines)
