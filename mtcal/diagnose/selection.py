"""Forward selection, backward elimination and cross-validation of the candidate effects, and ``diagnose`` itself
(see mtcal.diagnose)."""
from __future__ import annotations

import logging
import math
from typing import Sequence

import numpy as np
from scipy import optimize

from mtcal.diagnose import candidates as fx
from mtcal.diagnose.candidates import NOT_SEPARABLE, all_candidates
from mtcal.diagnose.engine import WEAK_TOL, Base, Engine, base_design, engine_for
from mtcal.diagnose.prepare import Prepared, prepare, whiten
from mtcal.diagnose.report import Diagnosis
from mtcal.diagnose.scans import _knock_scan, _outlier_scan, _where, locate
from mtcal.errors import InputError
from mtcal.machine import DEFAULT_MACHINE, Machine
from mtcal.recordings import Recording

log = logging.getLogger("mtcal.diagnose")
MAX_DEGREE = 3


def _raw_sigma(prep: Prepared, r_w: np.ndarray, dof: int) -> float:
    n = len(prep.rec)
    raw = np.linalg.solve(prep.W, r_w.reshape(n, 3)[..., None])[..., 0]
    return math.sqrt(float(np.sum(raw**2)) / max(dof, 1))


def _select_degrees(prep: Prepared, wy: np.ndarray, max_degree: int, progress,
                    effects: Sequence[np.ndarray] = ()) -> dict[str, int]:
    """Per axis, the degree (1..max) with the least BIC of the axis' own whitened fit, with the whitened
    columns ``effects`` (N, k) of the selected effects in the fit (restricted to the axis' readings): an
    unmodelled effect (backlash) inflates the residual and would make BIC choose too low a degree."""
    out = {}
    for a in prep.axes:
        on = prep.rec.axis == a
        G = None
        if len(effects):
            G = np.hstack(effects)[np.repeat(on, 3)]
            G = G[:, np.any(G != 0, axis=0)]
        best = None
        for d in range(1, max_degree + 1):
            e = engine_for(prep, base_design(prep, {a: d}, [a]), wy, on)
            if G is not None and G.shape[1]:
                e.add(G)
            na = e.N
            bic = na * math.log(e.rss / na) + e.p * math.log(na)
            if best is None or bic < best[0]:
                best = (bic, d)
        out[a] = best[1]
        progress(f"axis {a}: degree {best[1]} by BIC" + (" (with the selected effects)" if G is not None else ""))
    return out


def _headline(c: fx.Candidate, theta: np.ndarray, cov: np.ndarray) -> dict:
    """The reported estimate (one number with its unit and standard uncertainty) and all parameters."""
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    params = {p: float(v) for p, v in zip(c.params, theta)}
    if c.name == "periodic":
        amp = float(np.hypot(*theta))
        g = theta / amp if amp > 0 else np.zeros(2)
        u = float(math.sqrt(max(g @ cov @ g, 0.0)))
        params["phase_deg"] = float(np.degrees(np.arctan2(theta[1], theta[0])))
        return {"estimate": amp, "uncertainty": u, "unit": c.extra["amplitude_unit"],
                "parameters": params, "direction": None}
    if c.extra.get("variant") == "tracker knock":  # the step: its size (mm) along its direction, from t0 on
        size = float(np.linalg.norm(theta))
        g = theta / size if size > 0 else np.zeros(3)
        k = int(np.argmax(np.abs(theta)))
        return {"estimate": size, "uncertainty": float(math.sqrt(max(g @ cov @ g, 0.0))), "unit": "mm",
                "parameters": params, "direction": ("+" if theta[k] >= 0 else "-") + "XYZ"[k],
                "unit_vector": [float(v) for v in g], "t0_s": c.extra["t0_s"],
                "vector": [float(v) for v in theta], "vector_uncertainty": [float(v) for v in sd]}
    if c.name in ("thermal_drift", "outlier", "offset"):
        k = int(np.argmax(np.abs(theta) / np.maximum(sd, 1e-300)))  # the best-determined component
        return {"estimate": float(abs(theta[k])), "uncertainty": float(sd[k]), "unit": "mm", "parameters": params,
                "direction": ("+" if theta[k] >= 0 else "-") + "XYZ"[k],
                "vector": [float(v) for v in theta], "vector_uncertainty": [float(v) for v in sd]}
    unit = c.params[0].split("(")[-1].rstrip(")") if "(" in c.params[0] else c.params[0]
    return {"estimate": float(theta[0]), "uncertainty": float(sd[0]), "unit": unit, "parameters": params,
            "direction": None}


def _refine(prep: Prepared, c: fx.Candidate, eng: Engine, s: dict) -> tuple[fx.Candidate, dict]:
    """Refine a continuous parameter (pitch, tau) of the family winner by a bounded 1-D search."""
    if c.refine is None:
        return c, s
    lo, hi = c.refine_range
    v = c.refine_value
    a, b = max(lo, v / 1.5), min(hi, v * 1.5)
    if b <= a:
        return c, s

    def f(logv: float) -> float:
        cc = c.refine(math.exp(logv))
        sc = eng.score(prep.white(cc))
        return -sc.get("delta", 0.0)
    res = optimize.minimize_scalar(f, bounds=(math.log(a), math.log(b)), method="bounded",
                                   options={"xatol": 1e-3})
    cc = c.refine(math.exp(res.x))
    sc = eng.score(prep.white(cc))
    if sc.get("separable") and sc["delta"] > s["delta"]:
        return cc, sc
    return c, s


def _cv(prep: Prepared, base: Base, wy: np.ndarray, Gs: list[np.ndarray]) -> tuple[float, float]:
    """Held-out-round gain of the effects Gs: estimated on the other rounds, applied to the held-out round
    after the base model (all its parameters) is fitted to that round alone.  Returns 1 - RSS_with / RSS_without
    summed over rounds: returns (RSS with, RSS without), both whitened."""
    rounds = sorted(set(prep.rec.round.tolist()))
    if len(rounds) < 2 or not Gs:
        return float("nan"), float("nan")
    G = np.hstack(Gs)
    r3 = np.repeat(prep.rec.round, 3)
    with_, without = 0.0, 0.0
    for k in rounds:
        tr = prep.rec.round != k
        e_tr = engine_for(prep, base, wy, tr)
        Gtr = G[np.repeat(tr, 3)]
        if not np.any(Gtr):
            continue
        theta, _ = e_tr.estimate([Gtr])
        te = ~tr
        e_te = engine_for(prep, base, wy, te)
        pred = G[r3 == k] @ theta
        res = e_te.r - (pred - e_te.project(pred[:, None])[:, 0])
        with_ += float(res @ res)
        without += e_te.rss
    return with_, without


def _screen(prep: Prepared, eng: Engine, cands: list, notes: list[dict]) -> list:
    """Without a given model, the quasi-static candidates (and the tracker scale) that the base family at its
    largest degree already contains are not separable: reported as notes, not tested."""
    if prep.given_model:
        return cands
    keep, seen = [], set()
    for c in cands:
        if c.name in fx.QUASI_STATIC or c.name == "tracker_scale":
            sc = eng.score(prep.white(c))
            if not sc["separable"] or (c.name == "tracker_scale" and sc["sep"] < WEAK_TOL):
                if (c.name, c.axis) not in seen:
                    seen.add((c.name, c.axis))
                    notes.append({"name": c.name, "axis": c.axis, "not_separable": NOT_SEPARABLE[c.name],
                                  "separability": sc["sep"]})
                continue
        keep.append(c)
    return keep


def _forward(prep: Prepared, eng: Engine, cands: list, level: float, max_effects: int):
    """Forward selection: per step the best member of every family (refined; outlier and knock scans), penalised
    for families x members (Bonferroni); the strongest significant one is added.  Returns (selected
    [(candidate, score, adjusted log p)], the last step's best per family, the engine with the selected)."""
    say = log.info
    selected: list[tuple[fx.Candidate, dict, float]] = []
    last_scores: dict[str, tuple[fx.Candidate, dict, float]] = {}
    for step in range(max_effects):
        fams: dict[str, list[tuple[fx.Candidate, dict]]] = {}
        for c in cands:
            sc = eng.score(prep.white(c))
            if sc["separable"]:
                fams.setdefault(c.family, []).append((c, sc))
        oscan, ocount = _outlier_scan(prep, eng)
        kscan, kcount = _knock_scan(prep, eng)
        n_fam = len(fams) + (1 if ocount else 0) + (1 if kcount else 0)
        last_scores = {}
        for fam_name, members in fams.items():
            c, sc = min(members, key=lambda cs: cs[1]["logp"])
            c, sc = _refine(prep, c, eng, sc)
            last_scores[fam_name] = (c, sc, sc["logp"] + math.log(len(members) * n_fam))
        scanned = []  # (family, best member, members scanned): penalised for the whole scan
        if ocount:
            scanned.append(("outlier", fx.outlier(prep.geometry, oscan["rows"], oscan["mode"],
                                                  _where(prep, oscan["rows"])), ocount))
        if kcount:  # tracker knock: the change point t0 scanned over the reading times (kcount members)
            first = kscan["rows"][np.argmin(prep.order[kscan["rows"]])]
            where = {"from_axis": str(prep.rec.axis[first]), **_where(prep, kscan["rows"]),
                     "last_reading_before_s": kscan["before_s"], "first_reading_after_s": kscan["after_s"]}
            scanned.append(("offset", fx.tracker_knock(prep.geometry, kscan["t0"], where), kcount))
        for fam_name, cand, count in scanned:
            sc = eng.score(prep.white(cand))
            if sc["separable"]:
                last_scores[fam_name] = (cand, sc, sc["logp"] + math.log(count * n_fam))
        if not last_scores or min(v[2] for v in last_scores.values()) >= math.log(level):
            break
        # among the significant candidates, the strongest evidence (raw p) names the effect: the multiplicity
        # penalty decides significance, not which of two correlated explanations wins
        # exact ties (a knock just after a reflector's first sequence is the same column space as that nest's
        # offset) go to the smaller family: the adjusted p breaks them
        sig_c = [v for v in last_scores.values() if v[2] < math.log(level)]
        top_lp = min(v[1]["logp"] for v in sig_c)
        tol = 1e-9 * max(1.0, abs(top_lp)) if math.isfinite(top_lp) else 0.0
        tied = [v for v in sig_c if v[1]["logp"] <= top_lp + tol]
        c, sc, lp = min(tied, key=lambda v: v[2])
        sig_before = eng.sigma
        eng.add(prep.white(c))
        say(f"step {step + 1}: {c.name} {c.axis or ''} {c.label}: F = {sc['F']:.1f}, "
            f"sigma ratio {sig_before:.3f} -> {eng.sigma:.3f}")
        selected.append((c, sc, lp))
        if c.family not in ("outlier", "offset"):  # one member per family (a second periodic pitch: a new step;
            # outliers and tracker knocks are scanned afresh every step)
            cands = [x for x in cands if x.family != c.family]

    return selected, last_scores, eng


def _backward(prep: Prepared, eng: Engine, selected: list, level: float):
    """Backward elimination: drop a selected effect that the others have made insignificant."""
    say = log.info
    while len(selected) > 1:
        worst = None
        for j, (c, sc, lp) in enumerate(selected):
            e = eng.copy_base()
            for i, (o, _, _) in enumerate(selected):
                if i != j:
                    e.add(prep.white(o))
            s2 = e.score(prep.white(c))
            lp2 = (s2["logp"] + lp - sc["logp"]) if s2["separable"] else 0.0
            if worst is None or lp2 > worst[1]:
                worst = (j, lp2)
        if worst[1] < math.log(level):
            break
        c = selected.pop(worst[0])[0]
        say(f"backward: {c.name} {c.axis or ''} {c.label} dropped (explained by the other effects)")
        eng = eng.copy_base()
        for o, _, _ in selected:
            eng.add(prep.white(o))

    return selected, eng


def _report_effects(prep: Prepared, base: Base, wy: np.ndarray, eng: Engine, selected: list, last_scores: dict,
                    notes: list[dict], null_model: str) -> tuple[list[dict], Engine]:
    """The reported effects: joint estimates on the reported base, cumulative sigma, held-out-round
    cross-validation; then the best not-selected member of every family and the not-separable notes.  Returns
    (effects, the engine with the selected effects ``cum``)."""
    effects_out: list[dict] = []
    # final joint estimates, cumulative sigma and held-out-round cross-validation
    theta_all, cov_all = (eng.estimate([prep.white(c) for c, _, _ in selected]) if selected
                          else (np.zeros(0), np.zeros((0, 0))))
    cum = eng.copy_base()
    Gs: list[np.ndarray] = []
    off = 0
    prev_cv = None
    for c, sc, lp in selected:
        k = c.G.shape[-1]
        th, cv = theta_all[off:off + k], cov_all[off:off + k, off:off + k]
        off += k
        cum.add(prep.white(c))
        Gs.append(prep.white(c))
        with_, without = _cv(prep, base, wy, Gs)
        if prev_cv is None:
            prev_cv = without
        gain = 1.0 - with_ / prev_cv if prev_cv and prev_cv > 0 else float("nan")
        prev_cv = with_
        h = _headline(c, th, cv)
        ev = {"test": "F", "F": sc["F"], "dof": [sc["k"], sc["dof"]], "p_value": math.exp(sc["logp"]),
              "p_adjusted": min(1.0, math.exp(lp)), "log10_p_adjusted": lp / math.log(10),
              "cv_gain": gain, "cv": "held-out rounds", "separability": sc["sep"],
              "multiplicity": "Bonferroni over families x members", "null": null_model}
        item_dir = h.pop("direction")
        item = {"name": c.name, "axis": c.axis, "direction": item_dir, "significant": True,
                "estimate": h.pop("estimate"), "uncertainty": h.pop("uncertainty"), "unit": h.pop("unit"),
                "sigma_after": _raw_sigma(prep, cum.r, cum.dof), "sigma_ratio_after": cum.sigma,
                "evidence": ev, "where": (f"step along {item_dir}, {c.label}" if "t0_s" in h else c.label),
                **{k2: v for k2, v in c.extra.items() if not k2.startswith("_") and k2 != "rows"}, **h}
        if sc["sep"] < WEAK_TOL:
            item["note"] = "weakly separable from the base model: the estimate is correlated with the fitted errors"
        if c.name not in ("outlier", "offset") and not (gain > 0):  # round-specific: nothing to predict
            item["significant"] = False
            item["note"] = "significant in the F test but no gain on held-out rounds"
        effects_out.append(item)
    effects_out.sort(key=lambda d: (not d["significant"], -d["evidence"]["F"] * d["evidence"]["dof"][0]))
    chosen = {c.family for c, _, _ in selected}
    for fam_name, (c, sc, lp) in sorted(last_scores.items(), key=lambda kv: kv[1][2]):
        if fam_name in chosen:
            continue
        effects_out.append({"name": c.name, "axis": c.axis, "direction": None, "significant": False,
                            "estimate": None, "sigma_after": None, "where": c.label,
                            "evidence": {"test": "F", "F": sc["F"], "p_value": math.exp(sc["logp"]),
                                         "p_adjusted": min(1.0, math.exp(lp)), "cv_gain": None,
                                         "separability": sc["sep"]}})
    for nt in notes:
        effects_out.append({"name": nt["name"], "axis": nt["axis"], "direction": None, "significant": False,
                            "estimate": None, "sigma_after": None, "evidence": None,
                            "not_separable": nt["not_separable"],
                            **({"separability": nt["separability"]} if "separability" in nt else {})})
    return effects_out, cum


def diagnose(rec: Recording, model=None, *, machine: Machine | str = DEFAULT_MACHINE, tracker=None, level: float = 0.01,
             max_degree: int = MAX_DEGREE, max_effects: int = 8) -> Diagnosis:
    """Diagnose a recording (see the package docstring).  ``level``: family-wise significance level."""
    say = log.info
    if not 0 < level < 1:
        raise InputError(f"level must be in (0, 1), got {level}")
    prep = prepare(rec, machine, model, tracker)
    wy = whiten(prep.W, prep.y)
    # the null hypothesis of every test: the quasi-static family itself (every axis at the largest degree), not
    # the BIC-selected base: an effect is reported only if no smooth error function of the family explains it
    # (a cubic misfit of a degree-2 base is not a long-pitch periodic error); BIC picks the reported base after
    test_degrees = {a: 0 if prep.given_model else max_degree for a in prep.axes}
    eng = engine_for(prep, base_design(prep, test_degrees), wy)
    say(f"null model of the tests: {eng.p} parameters (quasi-static family"
        f"{', given model' if prep.given_model else f' at degree {max_degree}'}), sigma ratio {eng.sigma:.3f}")
    cands, notes = all_candidates(prep, max_degree)
    cands = _screen(prep, eng, cands, notes)
    say(f"{len(cands)} candidate effects")
    selected, last_scores, eng = _forward(prep, eng, cands, level, max_effects)
    selected, eng = _backward(prep, eng, selected, level)

    null_model = ("the given model" if prep.given_model else
                  f"the quasi-static family at degree {max_degree} on every axis") + " + the effects selected before"
    # the reported base model: degrees by BIC with the selected effects in the fit (an unmodelled effect would
    # bias BIC low), then the base alone (sigma before, located) and with the effects (estimates, sigma after)
    degrees = (dict(test_degrees) if prep.given_model
               else _select_degrees(prep, wy, max_degree, say, [prep.white(c) for c, _, _ in selected]))
    base = base_design(prep, degrees)
    eng = engine_for(prep, base, wy)
    base_sigma = _raw_sigma(prep, eng.r, eng.dof)
    base_ratio = eng.sigma
    say(f"base model: {eng.p} parameters, sigma {base_sigma * 1e3:.3f} um (ratio {base_ratio:.3f})")
    located, _ = locate(prep, eng, level)
    r_before = eng.r.copy()
    for c, _, _ in selected:
        eng.add(prep.white(c))
    effects_out, cum = _report_effects(prep, base, wy, eng, selected, last_scores, notes, null_model)
    base_info = {"kind": "given model" if prep.given_model else "fitted quasi-static",
                 "degrees": degrees, "parameters": int(cum.copy_base().p), "readings": len(rec),
                 "tests_against": null_model if prep.given_model else
                 f"the quasi-static family at degree {max_degree} on every axis (degrees above: BIC with the "
                 f"selected effects in the fit)",
                 "weighted": prep.weighted,
                 "basis": "polynomials in (q - q_ref) for the linear axes; harmonics for the rotary axes; "
                          "per-(round, point) offsets"}
    return Diagnosis(base_sigma, base_ratio, _raw_sigma(prep, eng.r, eng.dof), eng.sigma, effects_out, located,
                     base_info, residuals_before=r_before, residuals_after=eng.r.copy(), prep=prep)
