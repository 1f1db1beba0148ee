"""Identification of the error motions of each axis from laser-tracker recordings: ``identify``.

By default the joint weighted fit (mtcal.identify.joint) with the tracker's station given or estimated from the
scatter of the rounds; the three-point method below (Zhang & Hu) by name, or when the station cannot be estimated.

For every pass (axis, round, position, direction) the readings of the points P, Q, K (>= 3 non-collinear
reflectors; on the spindle for X, Y, Z, on the table for B, C) are compared with where the nominal machine
motion takes each point's reference reading (the round's reading at the position closest to zero, the first
time it is approached); the differences, expressed in the axis' own frame (derive/threepoint.py: B's stator
frame is tilted 45 deg), give the six error motions E_XJ, E_YJ, E_ZJ (mm) and E_AJ, E_BJ, E_CJ (rad) by least
squares over all 3 n equations (weighted by the AT960 covariance when the tracker position is known).  Passes of
one round at one position are averaged; rounds give the Type A statistics (thesis eqs. 2.45-2.49); reference
straight lines give squareness (mtcal.identify.fitting); continuous functions make the error model
(mtcal.model.errormodel).

Assumptions: readings are in the machine frame (mm); the axes not measured stand at zero (only matters for the
rotary axes: B is measured at C = 0, C at B = 0); errors are zero at the reference position.
"""
from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np

from mtcal.errors import InputError
from mtcal.identify import fitting
from mtcal.identify import joint as identify_joint
from mtcal.identify.build import build_model
from mtcal.identify.compare import split_half_worth
from mtcal.identify.frame import _in_iso_frame, _squareness_type_a, reference_lines, squareness_sigma
from mtcal.identify.results import IdentifyResult
from mtcal.identify.threepoint import _check_shape, _identify_axis, _passes
from mtcal.kinematics.machine import DEFAULT_MACHINE, Machine, load_machine
from mtcal.measurement import tracker as trk
from mtcal.measurement.recordings import Recording
from mtcal.measurement.screen import screen
from mtcal.measurement.slips import MAX_DEVIATION_MM, check_units_and_frame
from mtcal.measurement.tracker_position import (
    LR_LEVEL,
    PositionEstimate,
    estimate_position,
    estimate_shape,
    round_scatter,
    station_interval,
    station_scatter,
)
from mtcal.model.errormodel import ErrorModel

log = logging.getLogger(__name__)
METHODS = ("auto", "three-point", "joint")
METHOD_TEXT = {"three-point": "three-point (Zhang & Hu), least squares over all equations",
               "joint": "joint weighted fit of all readings and stations (error motions, reflectors, station "
                        "alignments; mtcal.identify.joint)"}


def identify(rec: Recording, tracker=None, machine: str | Machine = DEFAULT_MACHINE, reference: str = "least-squares",
             outlier_k: float = 5.0, max_degree: int = 7, max_harmonics: int = 6,
             max_deviation_mm: float = MAX_DEVIATION_MM, method: str = "auto", worth: bool = True,
             noise_law: trk.TrackerSpec | None = None, tracker_model=None) -> IdentifyResult:
    """Identify the error motions of every axis in a recording, their squareness and the error model.

    By default (``method="auto"``) every reading is weighted by the tracker's anisotropic noise law and all axes
    are fitted at once (the joint fit, mtcal.identify.joint).  Without ``tracker`` (and without tracker_x,y,z
    columns) the tracker's position is estimated from the scatter of the repeated rounds
    (``estimate_station``, mtcal.measurement.tracker_position; ``model.meta["tracker_estimated"]``) and the
    joint fit is weighted about it.  Only when it cannot be estimated (one round; rounds that repeat exactly; a
    scatter with no tracker shape) does identify fall back to the three-point method per position (Zhang & Hu, the
    module docstring) with the readings weighted equally, and say so in ``warnings``.  Gross errors (swapped
    labels, far readings, duplicated rows) are screened out first and reported.

    Parameters
    ----------
    rec : Recording
        The readings (mm, machine frame; mtcal.read_recording).
    tracker : array_like, shape (3,), optional
        Tracker position, mm, machine frame.  None: the recording's tracker_x,y,z columns, else estimated from
        the rounds' scatter (above).
    machine : str or Machine, optional
        The machine spec (default ``dmu50``).
    reference : str, optional
        Reference straight-line method of straightness and squareness (mtcal.identify.fitting.REFERENCE_METHODS:
        ``"least-squares"`` (default), ``"end-point"``, ``"minimum-zone"``).
    outlier_k : float, optional
        A round whose value differs from the mean of the other rounds by more than k predicted sigma is reported
        in ``warnings`` (default 5).
    max_degree : int, optional
        Highest polynomial degree of a linear axis' fitted function (default 7; the degree is selected by the
        data).
    max_harmonics : int, optional
        Most harmonics of a rotary axis' fitted function (default 6).
    max_deviation_mm : float, optional
        A reading farther than this from the nominal motion is refused as a unit, frame or axis mix-up (mm,
        default 1).
    method : {"auto", "joint", "three-point"}, optional
        The estimator: ``"joint"`` (one weighted fit of all readings of all stations), ``"three-point"`` (per
        position, this module) or ``"auto"`` (joint when the tracker position is given or can be estimated, else
        three-point with a warning).
    worth : bool, optional
        Also run the estimator on two halves of the rounds to state the model's predicted error against what it
        corrects (``model.meta["worth"]``, mtcal.identify.compare.split_half_worth) and warn when compensating may
        make the machine worse (default True).
    noise_law : mtcal.measurement.tracker.TrackerSpec, optional
        The law the fit weights by, as it is.  Default: the prior's, or the one the repeated rounds show where they
        are shaped otherwise (``model.meta["noise_law"]``).
    tracker_model : str or TrackerSpec, optional
        The tracker's noise law, the prior: an instrument's name (``"AT960"``, ``"AT500"``), MPE numbers
        ``"a_r,b_r,a_t,b_t[,k]"`` in um and um/m, or a TrackerSpec (default: the AT960's).

    Returns
    -------
    IdentifyResult
        Per axis the error motions and their statistics, the squareness, the model (mm, rad), warnings.

    Raises
    ------
    mtcal.errors.InputError
        Bad options, an axis not of the machine, too few reflectors, readings far from the nominal motion, several
        stations without the joint fit.

    See Also
    --------
    mtcal.planning.plan.plan_uncertainty : the uncertainty this estimator will have, before measuring.
    mtcal.uncertainty.run.monte_carlo : the Monte Carlo of this function.

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.data import path
    >>> rec = mtcal.read_recording(path("demo_campaign.csv"))
    >>> res = mtcal.identify(rec, tracker=(250, -1500, 150))
    >>> res.method, sorted(res.squareness)
    ('joint', ['E_A0Z', 'E_B0Z', 'E_C0Y'])
    >>> print(f"{res.model.functions['E_XX'](100.0) * 1e3:.1f} um")  # E_XX at X = 100 mm
    1.9 um
    """
    m = machine if isinstance(machine, Machine) else load_machine(machine)
    prior = trk.as_tracker_model(tracker_model)
    if method not in METHODS:
        raise InputError(f"`method` must be one of {METHODS}, got {method!r}")
    if reference not in fitting.REFERENCE_METHODS:
        raise InputError(f"`reference` must be one of {fitting.REFERENCE_METHODS}, got {reference!r}")
    warnings: list[str] = []
    # gross errors of the data (swapped labels, far readings, duplicated rows): left out
    gross = screen(rec, m.sides, m)
    if gross.problems:
        rec = rec.select(gross.keep)
        warnings += [*(p.text for p in gross.problems), *gross.notes]
    # unit and frame slips (inch, radians, swapped columns, one point read throughout): refused before any estimator
    check_units_and_frame(rec, m, max_deviation_mm)
    estimated = None
    if method == "auto":
        method, tracker, estimated = _auto_method(rec, tracker, warnings, prior)
    t = None if tracker is None else np.asarray(tracker, dtype=float).reshape(3)
    for axis in rec.axes():
        if axis not in m.axes:
            raise InputError(f"{rec.source}: axis {axis} is not an axis of machine {m.name} ({', '.join(m.axes)})")
    results, slopes, joint, spec, law = _fit_axes(rec, m, t, method, reference, noise_law, warnings,
                                                  outlier_k, prior, known=estimated is None)
    sq = fitting.squareness(slopes)
    sq_stats = _squareness_type_a(results, m, reference, sq)
    if set(m.linear_axes) <= set(results) and len(sq) < 3:
        warnings.append("squareness: some straightness records are missing; only " + ", ".join(sorted(sq)) + " found")
    weighted = t is not None or joint is not None
    model, fits = build_model(results, sq, m, max_degree, max_harmonics, rec.source, reference, weighted, warnings)
    results = {a: replace(r, fits=fits[a]) for a, r in results.items()}
    meta = dict(model.meta, method=METHOD_TEXT[method])
    if estimated is not None:
        st = estimated.interval or {}
        meta["tracker_estimated"] = {"position_mm": estimated.position.tolist(),
                                     **({"sigma_mm": estimated.sigma_mm.tolist()} if st.get("determined", True)
                                        else {}),
                                     **{k: st[k] for k in ("determined", "interval_95_mm", "note") if k in st},
                                     "noise_scale_vs_at960": estimated.scale,  # vs the prior's (AT960 by default)
                                     "how": "estimated from the scatter of the repeated rounds, its distance "
                                            "checked against the reflectors' mutual distances "
                                            "(mtcal.measurement.tracker_position.station_interval)"}
    meta.update({"noise_law": law} if law else {})
    if worth:
        w = _worth(rec, m, model, warnings, dict(tracker=t, reference=reference, max_degree=max_degree,
                                                  max_harmonics=max_harmonics, method=method, noise_law=spec))
        meta.update({"worth": w} if w else {})
    meta["warnings"] = list(warnings)
    problems = [p.to_dict() for p in gross.problems]
    meta.update({"squareness_type_a": sq_stats} if sq_stats else {})
    meta.update({"data_problems": problems} if problems else {})
    summary = None
    if joint is not None:
        summary = {**joint.summary(), "squareness_sigma": squareness_sigma(results, reference)}
        meta["squareness_sigma"] = summary["squareness_sigma"]
    return IdentifyResult(results, sq, replace(model, meta=meta), warnings, reference, weighted, rec.source, sq_stats,
                          method, summary, problems)


def _fit_axes(rec: Recording, m: Machine, t: np.ndarray | None, method: str, reference: str,
              noise_law: trk.TrackerSpec | None, warnings: list[str], outlier_k: float,
              prior: trk.TrackerSpec = trk.AT960, known: bool = True):
    """(results {axis: AxisResult with its reference lines}, straightness slopes {E_IJ: mm/mm}, the joint fit or
    None, the noise law the fit weighted by, its report (trk.law_report) or None): the joint fit of all axes, or
    three-point axis by axis (the rotary axes on readings turned into the ISO frame the linear axes' reference lines
    define); ``known``: the tracker position was given, not estimated (the shape check's band, estimate_shape)."""
    joint, spec, law = None, noise_law, None
    if noise_law is None and (t is not None or method == "joint"):  # the fits that weight by a law
        spec, law = _noise_law(rec, t, warnings, prior, known=known)
    if method == "joint" or len(set(rec.stations().tolist())) > 1:
        if method != "joint":
            raise InputError(f"{rec.source}: several tracker stations need the joint fit (`method` joint)")
        log.info("joint weighted fit of %d readings from %d station(s)", len(rec), len(set(rec.stations().tolist())))
        for axis in rec.axes():  # the same input checks as the per-position method (gross errors, collinearity)
            sub = rec.select(rec.axis == axis)
            _check_shape(sub, axis, _passes(sub, axis))
        joint = identify_joint.joint_fit(rec, m, t, spec)
        warnings += joint.warnings
        results = {axis: identify_joint.axis_result(joint, rec, m, axis) for axis in rec.axes()}
    else:
        results = {}
        for axis in (a for a in rec.axes() if m.kind(a) == "linear"):
            log.info("identifying axis %s", axis)
            results[axis] = _identify_axis(rec, axis, m, t, warnings, outlier_k, spec=spec or prior)
    lines = reference_lines(results, m, reference)
    results = {a: replace(r, lines=lines.get(a, {})) for a, r in results.items()}
    slopes = {nm: line["slope"] for ls in lines.values() for nm, line in ls.items()}
    if joint is None and len(results) < len(rec.axes()):
        iso, t_iso = _in_iso_frame(rec, t, m, slopes)
        for axis in rec.axes():
            if axis not in results:
                log.info("identifying axis %s (readings turned into the ISO frame of the linear axes)", axis)
                results[axis] = _identify_axis(iso, axis, m, t_iso, warnings, outlier_k, spec=spec or prior)
        results = {a: results[a] for a in rec.axes()}
    return results, slopes, joint, spec, law


def _worth(rec: Recording, m: Machine, model: ErrorModel, warnings: list[str], kw: dict) -> dict | None:
    """The model's worth (``model.meta["worth"]``) from the same estimator on the even and the odd rounds
    (``split_half_worth``), and a warning when compensating with the model may leave the machine worse than
    without it; None (and the reason in ``warnings``) when the halves cannot say."""
    rounds = np.unique(rec.round)
    if len(rounds) < 2:
        warnings.append("one round: the model's error cannot be predicted from the data (measure two or more rounds)")
        return None
    halves = (rounds[::2], rounds[1::2])
    short = [a for a in rec.axes() for h in halves if not np.isin(rec.round[rec.axis == a], h).any()]
    if short:
        warnings.append(f"the model's error was not predicted: axis {short[0]} is not measured in both halves of the "
                        f"rounds (even and odd)")
        return None
    quiet = logging.getLogger("mtcal")
    level = quiet.level
    quiet.setLevel(max(level, logging.WARNING))  # the halves' progress is not the user's
    try:
        a, b = [identify(rec.select(np.isin(rec.round, h)), machine=m, worth=False, **kw).model for h in halves]
    except InputError as e:  # a half lacks what the whole has (a position measured in one round only)
        warnings.append(f"the model's error was not predicted: a half of the rounds cannot be identified ({e})")
        return None
    finally:
        quiet.setLevel(level)
    w = split_half_worth(m, model, a, b, len(halves[0]), len(halves[1]))
    log.info("model: corrects %.1f um RMS over the measured volume; predicted error %.1f um RMS (%s)",
             w.corrects_rms_um, w.predicted_error_rms_um, w.how)
    if w.may_worsen:
        warnings.append(f"compensating with this model may make the machine worse: it corrects {w.corrects_rms_um:.1f} "
                        f"um RMS and is itself uncertain by {w.predicted_error_rms_um:.1f} um RMS over the measured "
                        f"volume; measure more rounds or from more tracker stations (mtcal plan shows the gain)")
    return w.to_dict()


def _noise_law(rec: Recording, t: np.ndarray | None, warnings: list[str], prior: trk.TrackerSpec = trk.AT960,
               known: bool = True) -> tuple[trk.TrackerSpec, dict]:
    """The law the fit weights by, and its report (trk.law_report): the prior's (the AT960's unless
    ``tracker_model`` names another), or where the repeated rounds (every station's about its own tracker) are
    shaped otherwise (mtcal.measurement.tracker_position.estimate_shape, a ratio test against the prior) the
    data's, said in ``warnings``."""
    if t is None and rec.tracker_xyz is not None:
        t = rec.tracker_xyz  # each reading's own station's tracker
    if t is None or len(set(rec.round.tolist())) < 2:
        return prior, trk.law_report(prior, prior, "prior", "the shape is not checked (one round or no tracker)")
    if not np.any(round_scatter(rec)):
        return prior, trk.law_report(prior, prior, "prior", "no reading is repeated at one station (noise-free "
                                                            "readings, or one round per station): the shape is "
                                                            "not checked")
    sh = estimate_shape(rec, t, prior, known=known)
    if not sh.replaces_base:
        return prior, sh.report()
    warnings.append(f"noise law: {sh.source} are not shaped like {prior.whose}; the fit weights by the "
                    f"data's: {sh.law_text()}")
    return sh.spec, sh.report()


def _auto_method(rec: Recording, tracker, warnings: list[str], prior: trk.TrackerSpec = trk.AT960):
    """identify's default estimator: (method, tracker position or None, the estimate or None).  The joint fit
    when the tracker position is given or estimated from the rounds' scatter; else three-point, with a warning
    naming what is lost."""
    estimated = None
    if tracker is None and rec.tracker_xyz is None:
        estimated, why = estimate_station(rec, prior)
        if estimated is None and len(np.unique(rec.round)) > 1 and not np.any(round_scatter(rec)):  # noise-free
            log.info("tracker position not estimated (%s): three-point method", why)
        elif estimated is None:
            warnings.append(f"{rec.source}: tracker position not given and not estimated ({why}): three-point "
                            f"method, readings weighted equally; lost: the weighting by the tracker's anisotropic "
                            f"noise and the joint fit (about twice the model error, benchmarks/identify_truth.py); "
                            f"give `tracker` x,y,z")
        else:
            tracker = estimated.position
            log.info("tracker position estimated from the scatter: %s mm", station_text(estimated))
    method = "joint" if tracker is not None or rec.tracker_xyz is not None else "three-point"
    return method, tracker, estimated


def estimate_station(rec: Recording, spec: trk.TrackerSpec = trk.AT960) -> tuple[PositionEstimate | None, str]:
    """Where the tracker stood, from the scatter of the repeated rounds (mtcal.measurement.tracker_position):
    (estimate, "")
    or (None, why not).  One station only (a multi-station recording carries its trackers' positions)."""
    if len(set(rec.stations().tolist())) > 1:
        return None, "several stations without tracker_x,y,z columns"
    if len(set(rec.round.tolist())) < 2:
        return None, "one round: no repeated readings to show the beam directions"
    r = station_scatter(rec)
    if not np.any(r):
        return None, "the rounds repeat exactly: no scatter (noise-free readings?)"
    groups = [sel for a in rec.axes() for p in np.unique(rec.point[rec.axis == a])
              if (sel := (rec.axis == a) & (rec.point == p)).sum() >= 6]
    est = estimate_position(rec.xyz, r, groups, spec)
    if not est.accepted:
        return None, (f"the scatter shows no tracker shape (likelihood ratio {est.likelihood_ratio:.1f}, "
                      f"p = {est.p_isotropic:.2g})" if est.p_isotropic >= LR_LEVEL else
                      "the scatter does not pin the position down")
    return replace(est, interval=station_interval(rec.xyz, r, est.position, est.logs, est.nll, spec, rec=rec)), ""


def station_text(est: PositionEstimate) -> str:
    """'x, y, z +- sx, sy, sz' (mm) where the station is determined (station_interval: the profile of its
    distance, and the mutual distances where they tell), else 'x, y, z mm, not determined: ...' with the profile
    interval of its distance from the readings -- a curvature sigma says nothing where the profile is flat, and a
    +- that excludes where the data put the station is never printed."""
    xyz = ", ".join(f"{v:.0f}" for v in est.position)
    st = est.interval
    if st is None or st["determined"]:
        return xyz + " +- " + ", ".join(f"{v:.0f}" for v in est.sigma_mm)
    where = (f"the data put it {st['interval_95_mm'][0] / 1e3:.3g}-{st['interval_95_mm'][1] / 1e3:.3g} m from the "
             "readings' centre" if st["interval_95_mm"] else "its distance's profile likelihood is many-moded")
    by = " (the reflectors' mutual distances)" if "scatter" in st else ""
    return (f"{xyz} mm, not determined: {where}{by}, this estimate {st['distance_mm'] / 1e3:.3g} m; give "
            "`tracker` x,y,z")


# ----------------------------------------------------------------------------- Inspire export layout
