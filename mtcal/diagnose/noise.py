"""The noise model of the diagnosis: the covariance of every reading, given or estimated from the data.

A laser tracker's reading covariance is a small radial part along the beam and a much larger transverse part across
it (angle encoders; mtcal.measurement.tracker). The prior law is the AT960's unless another instrument or numbers
are named (``tracker_model``); with the tracker position given (``--tracker``), its covariance about the tracker
weights the readings, unless the repeated rounds' scatter is shaped otherwise (estimate_shape, a ratio test against
the prior law): then the data's law, said. Without it, the position is estimated from the scatter of the repeated
rounds: the residuals of the quasi-static base family (unweighted) at every reflector have their smallest spread
along the beam; each reading's residual is taken about the mean of its cell over the rounds, less each round's mean
(tracker_position.station_scatter), so a misfit that repeats every round and a motion of a whole round stay out
of the noise model; (1) each
reflector's residual scatter (3x3, pooled over its readings) gives a beam line through the reflector along its
least-spread direction, (2) the point closest to all beam lines starts (3) a maximum-likelihood fit of the tracker
position together with the prior law's radial and transverse scales (the data's shape; the transverse scale near 1,
prior log c_t ~ N(0, 0.3^2): the distance comes from the size of the transverse scatter as well as from the
convergence of the beams; Student-t; Nelder-Mead from that start and from 1.5 m along the mean beam on either side),
(4) twice: the base refitted with the weights of the estimate, and the fit of (3) repeated on its residuals (the
unweighted fit leaks the large transverse noise into the radial residuals of other readings). The estimate is used
when it beats the isotropic model by a likelihood-ratio test (chi^2 with 4 dof, p < 1e-3); else (or with one round)
the readings are weighted equally, sigma from the residuals. The estimation itself (starts, likelihood, test) is
mtcal.measurement.tracker_position, shared with identify. Units: mm."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from mtcal import _tails
from mtcal.diagnose.design import base_design, engine_for, family_degrees, whiten
from mtcal.diagnose.prepared import NoiseModel, Prepared
from mtcal.measurement.tracker import AT960, TrackerSpec, law_report
from mtcal.measurement.tracker_position import (
    LR_LEVEL,
    SHAPE_NEAR_FIT,
    ShapeEstimate,
    against_isotropic,
    best_start,
    estimate_shape,
    refine,
    round_scatter,
    shape_ratio,
    station_interval,
    station_scatter,
)

ITERATIONS = 2          # refits of the base with the estimated weights
MIN_STATION_READINGS = 30  # readings with scatter a station needs for its own sigmas (else the common law)


def noise_model(prep: Prepared, tracker: np.ndarray | None, max_degree: int, prior: TrackerSpec = AT960
                ) -> NoiseModel:
    """The noise model of ``prep``'s readings (see module docstring) under the ``prior`` law (the AT960's unless
    another instrument or numbers are named, mtcal.measurement.tracker.tracker_model): its shape is checked against
    the repeated rounds (estimate_shape, a ratio test against the prior, not the AT960) and gives way to the data's
    where they differ."""
    xyz = prep.rec.xyz
    n = len(xyz)
    name = prior.name or "given law"
    several = len(set(prep.rec.round.tolist())) >= 2
    if tracker is not None:
        t = np.asarray(tracker, float)
        sh = estimate_shape(prep.rec, t, prior) if several else None
        if sh is not None and sh.replaces_base:
            return NoiseModel.at960(xyz, t, "tracker law estimated (given tracker)",
                                    f"tracker position given; {sh.source} are not shaped like {prior.whose}: "
                                    f"{sh.law_text()}", sh.spec, _law(sh, prior), shape=sh.to_dict())
        return NoiseModel.at960(xyz, t, f"{name} (given tracker)",
                                "tracker position given (`tracker` or the recording's tracker_x,y,z columns)",
                                prior, _law(sh, prior), **({"shape": sh.to_dict()} if sh is not None else {}))
    if not several:
        return NoiseModel.isotropic(n, "one round: no repeated readings to estimate the beam directions from")
    r = _base_residuals(prep, max_degree, prior)
    groups = list(_groups(prep))
    t, logs, nll = best_start(xyz, r, groups, prior)
    for _ in range(ITERATIONS):  # refit the base with the weights of the estimate: the unweighted fit leaks the
        # large transverse noise into the radial residuals of other readings
        r = _base_residuals(prep, max_degree, prior, NoiseModel.at960(xyz, t, "", "", _scaled(prior, logs)).W)
        t, logs, nll = refine(xyz, r, t, prior, logs=logs)
    sh = _estimated_shape(prep, r, t, nll, prior)
    spec = sh.spec if sh.replaces_base else prior
    c = xyz.mean(axis=0)
    lr, p = against_isotropic(r, nll)
    details = {"likelihood_ratio": lr, "p_isotropic": p,
               "distance_mm": float(np.linalg.norm(t - c)), "shape": sh.to_dict()}
    if p < LR_LEVEL:
        details["station_interval"] = _trusted(station_interval(xyz, r, t, logs, nll, prior, rec=prep.rec), sh)
    if p >= LR_LEVEL:
        return NoiseModel.isotropic(n, f"the scatter of the repeated rounds shows no tracker shape (likelihood "
                                       f"ratio {lr:.1f}, p = {p:.2g}): equal weights, sigma from the residuals")
    if sh.replaces_base:
        return NoiseModel.at960(xyz, t, "tracker law estimated (estimated tracker)",
                                "tracker position estimated from the scatter of the repeated rounds, the noise "
                                f"law from {sh.source}: "
                                f"{sh.law_text()}", spec, _law(sh, prior), **details)
    return NoiseModel.at960(xyz, t, f"{name} (estimated tracker)",
                            "tracker position estimated from the shape of the scatter of the repeated rounds "
                            f"(beam lines of the least spread, then maximum likelihood under the {name} shape)",
                            prior, _law(sh, prior), **details)


def _estimated_shape(prep: Prepared, r: np.ndarray, t: np.ndarray, nll: float, prior: TrackerSpec
                     ) -> ShapeEstimate:
    """The shape about an estimated position ``t`` (mm; ``nll`` its negative log-likelihood with the shape free, on
    the scatter ``r``): the wide band, and the near band only where the free shape fits the scatter better than the
    prior's, its own position refitted, by a likelihood-ratio test (chi^2, 1 dof, p < LR_LEVEL), with ``t`` no
    farther from the readings than that position.  A position's error raises the radial : transverse ratio with and
    without the round means alike; a law that is right raises the likelihood and brings the position in (the size
    of the transverse scatter tells the distance), while a scatter that an effect of the campaign distorts (a
    knocked nest) runs it away."""
    sh = estimate_shape(prep.rec, t, prior, known=False)
    near = replace(sh, known=True, near_band=SHAPE_NEAR_FIT)  # the same ratios under the near band
    if sh.replaces_base or not near.replaces_base:
        return sh
    t_prior, _, nll_prior = refine(prep.rec.xyz, r, t, prior, shape=False)
    c = prep.rec.xyz.mean(axis=0)
    closer = np.linalg.norm(t - c) <= np.linalg.norm(t_prior - c)
    return near if closer and _tails.chi2_sf(max(2.0 * (nll_prior - nll), 0.0), 1) < LR_LEVEL else sh


def _trusted(interval: dict, sh: ShapeEstimate) -> dict:
    """The station's profile interval (station_interval) holds only when the scatter it is read from is the
    tracker's noise: where the round scatter and the reflectors' mutual distances disagree about the law
    (ShapeEstimate.note), the rounds hold a motion shared by a side, whose shape places a station that is not the
    tracker's (icelinker: 1.08 m from the readings, determined to 0.95-1.27 m by the rounds alone, where the mutual
    distances put it 2.8 m away): not determined, and said.  So too where the distances, read about that station,
    do not determine the scatter across the beams (icelinker: a transverse factor of 3e-8 about the rounds' station
    1.08 m away, 0.18 (0.17-0.18) about the tracker's own origin 2.8 m away): what is rigid shows no tracker's
    noise about it."""
    if not interval["determined"]:
        return interval
    across = (sh.rigid or {}).get("transverse") or {}
    if sh.rigid and not across.get("determined"):
        return {**interval, "determined": False,
                "note": "the station is not determined by the data: about the station the scatter of the rounds "
                        f"places (at {interval['distance_mm'] / 1e3:.3g} m from the readings) the reflectors' mutual "
                        "distances show no tracker's noise (their scatter across the beams is not determined there, "
                        f"factor {across.get('factor', float('nan')):.2g} of the law's), so the rounds' scatter "
                        "holds a motion shared by a side (a drift, the machine's motion), not only the tracker's "
                        "noise; the weights, and the findings that depend on them, are conditional on it: give the "
                        "tracker's position (--tracker or the tracker_x,y,z columns)"}
    if not sh.note:
        return interval
    return {**interval, "determined": False,
            "note": "the station is not determined by the data: the scatter of the rounds that places it (at "
                    f"{interval['distance_mm'] / 1e3:.3g} m from the readings) disagrees with the reflectors' "
                    "mutual distances about the tracker's law, so it holds a motion shared by a side (a drift, "
                    "the machine's motion), not only the tracker's noise; the weights, and the findings that "
                    "depend on them, are conditional on it: give the tracker's position (--tracker or the "
                    "tracker_x,y,z columns)"}


def _scaled(prior: TrackerSpec, logs: np.ndarray) -> TrackerSpec:
    """``prior``'s law with its radial and transverse variances scaled by exp(logs) (refine's log c_r, log c_t)."""
    return prior.scaled(math.exp(0.5 * logs[0]), math.exp(0.5 * logs[1]))


def stations_model(prep: Prepared, max_degree: int, prior: TrackerSpec = AT960) -> NoiseModel:
    """The noise model of a recording of several stations (each reading about its own station's tracker, given):
    one instrument's law, its shape checked against the scatter of the repeated rounds of every station together
    (estimate_shape about each reading's own tracker) and replaced by the data's where they differ.  Where no
    station repeats a reading (one round each), the base's residuals show the shape instead: fitted under the
    prior, then ITERATIONS times under the law they gave (a fit under the wrong shape absorbs the noise of the
    direction it overweights, which hides that direction's share).  Each station's sigmas are then scaled to its
    own scatter (_station_laws)."""
    g, rec = prep.geometry, prep.rec
    t = np.stack([g.trackers[s] for s in g.station.tolist()])
    model = NoiseModel.stations(rec.xyz, g.station, g.trackers, prior)
    r = round_scatter(rec)
    if np.any(r):
        sh, how = estimate_shape(rec, t, prior, r), "the repeated rounds of every station"
    else:
        how = "the residuals of the base (no station repeats a reading)"
        for _ in range(ITERATIONS + 1):
            r = _base_residuals(prep, max_degree, prior, model.W, scatter=False)
            if not np.any(r):
                return model
            sh = estimate_shape(rec, t, prior, r)
            model = NoiseModel.stations(rec.xyz, g.station, g.trackers, sh.spec)
    spec = sh.spec if sh.replaces_base else prior
    specs, factors = _station_laws(prep, r, t, spec)
    for _ in range(ITERATIONS if len(specs) < len(g.trackers) else 0):  # a station that repeats no reading: its
        # sigmas from the base's residuals, refitted under the laws so far
        W = NoiseModel.stations(rec.xyz, g.station, g.trackers, spec, specs=specs).W
        res = _base_residuals(prep, max_degree, prior, W, scatter=False)
        specs, factors = _station_laws(prep, r, t, spec, res)
    return NoiseModel.stations(rec.xyz, g.station, g.trackers, spec, _law(sh, prior), specs,
                               shape={**sh.to_dict(), "from": how}, per_station=factors)


def _station_laws(prep: Prepared, r: np.ndarray, t: np.ndarray, spec: TrackerSpec, res: np.ndarray | None = None
                  ) -> tuple[dict[str, TrackerSpec], dict[str, dict]]:
    """Each station's law: ``spec`` with its radial and transverse sigmas scaled to that station's own scatter
    ``r`` (shape_ratio: robust medians along and across its beams), or where it repeats too few readings to its
    base residuals ``res`` (when given).  The distance law (a : b) is the prior's, and stations at other distances
    show where the instrument's is not (a law constant in distance reads low near the tracker and high far from
    it); a station with neither keeps ``spec``.  Returns the laws and the factors."""
    specs, factors = {}, {}
    for label in prep.geometry.trackers:
        mine = prep.geometry.station == label
        v = r if (mine & np.any(r != 0, axis=1)).sum() >= MIN_STATION_READINGS or res is None else res
        on = mine & np.any(v != 0, axis=1)
        if on.sum() < MIN_STATION_READINGS:
            continue
        rho, st2 = shape_ratio(prep.rec.xyz[on], v[on], t[on], spec)
        fr, ft = rho * math.sqrt(st2), math.sqrt(st2)
        specs[label] = spec.scaled(fr, ft)
        factors[label] = {"radial": round(fr, 3), "transverse": round(ft, 3)}
    return specs, {"factors": factors, "rule": "each station's sigmas scaled to its own scatter (robust medians "
                                               "along and across the beam) against the law above"}


def _law(sh: ShapeEstimate | None, prior: TrackerSpec) -> dict:
    """``noise_model.law``: the prior's law, or the data's where the repeated rounds reject the prior's shape."""
    if sh is None:
        return law_report(prior, prior, "prior", "one round (or noise-free rounds): the shape is not checked")
    return sh.report()


def _base_residuals(prep: Prepared, max_degree: int, prior: TrackerSpec, W: np.ndarray | None = None,
                    scatter: bool = True) -> np.ndarray:
    """(n, 3) residuals (mm) of the quasi-static base family (or the given model), fitted with the whitening W
    (None: unweighted); ``scatter``: about the mean of each reading's cell over the rounds, less each round's
    mean (station_scatter: what places the station)."""
    n = len(prep.rec)
    if W is not None:
        prep = replace(prep, noise=NoiseModel(W, prior.label, ""))
    degrees = family_degrees(prep, max_degree)
    eng = engine_for(prep, base_design(prep, degrees), whiten(prep.W, prep.y))
    raw = np.linalg.solve(prep.W, eng.r.reshape(n, 3)[..., None])[..., 0]
    # about the cell means: a misfit that repeats every round stays out of the noise model
    return station_scatter(prep.rec, raw) if scatter else raw


def _groups(prep: Prepared):
    rec = prep.rec
    for a in prep.axes:
        for lab in np.unique(rec.point[rec.axis == a]):
            sel = (rec.axis == a) & (rec.point == lab)
            if sel.sum() >= 6:
                yield sel
