"""``diagnose()``: the orchestration of prepare -> candidates -> selection -> report (see mtcal.diagnose)."""
from __future__ import annotations

import dataclasses
import logging

import numpy as np
from threadpoolctl import threadpool_limits

from mtcal.diagnose import effects as fx
from mtcal.diagnose.candidates import candidates, screen
from mtcal.diagnose.design import base_design, engine_for, family_degrees, raw_sigma, whiten
from mtcal.diagnose.predictive import predictive_checks
from mtcal.diagnose.prepare import TIE_POSITIONS, prepare, shared_axes
from mtcal.diagnose.prepared import LEVEL, STAGES
from mtcal.diagnose.report import Diagnosis, free_form_located, rejected_findings, selected_findings
from mtcal.diagnose.scans import beyond_the_family, collapsed, locate, one_at_a_time
from mtcal.diagnose.selection import (
    Columns,
    backward,
    beside_a_mismatch,
    cv_gain,
    folds,
    forward,
    growing_confounds,
    select_degrees,
    steps_per_place,
    untested_confounds,
    with_steps,
)
from mtcal.errors import InputError
from mtcal.kinematics.machine import DEFAULT_MACHINE, Machine, load_machine
from mtcal.measurement.recordings import Recording
from mtcal.measurement.screen import screen as screen_gross
from mtcal.measurement.slips import check_units_and_frame
from mtcal.measurement.tracker import as_tracker_model

log = logging.getLogger("mtcal.diagnose")
# BLAS_THREADS: the diagnosis is thousands of products and factorisations of a few hundred columns, where a second
# BLAS thread costs more than it gives: `mtcal diagnose demo_campaign.csv` took 45 CPU-s (70 s wall) with
# OpenBLAS's default threads on this 2-core machine at a load of 9, 4-5 CPU-s (6-8 s) on one thread
MAX_DEGREE = 7  # the quasi-static family: polynomials up to degree 7 on linear axes (two undulations over the
#                travel), harmonics up to design.ROTARY_HARMONICS on rotary axes


def diagnose(rec: Recording, model=None, *, machine: Machine | str = DEFAULT_MACHINE, tracker=None,
             level: float = LEVEL, max_degree: int = MAX_DEGREE, max_effects: int = 8,
             tie_positions: bool = TIE_POSITIONS, tracker_model=None) -> Diagnosis:
    """Diagnose a recording: what the quasi-static error model leaves out (mtcal.diagnose).

    The readings are fitted by the quasi-static model (error functions of each axis, or the given ``model``) and
    every candidate effect (backlash, drift, a knocked or creeping nest, outliers, periodic errors, tracker
    settling, ...) is tested against it, forward and backward at a family-wise level; mismatches no effect explains
    are located; what the data cannot separate is said in ``notes``.

    Parameters
    ----------
    rec : Recording
        The readings (mm, machine frame).
    model : ErrorModel, optional
        A reference model to test against (default: the quasi-static family fitted to the readings).
    machine : Machine or str, optional
        The machine spec (default ``dmu50``).
    tracker : array_like, shape (3,), optional
        Tracker position, mm, machine frame; None: the noise model is estimated from the data (a recording of
        several stations weighs each about its own tracker_x,y,z columns and fits every station's alignment).
    level : float, optional
        Family-wise significance level (default 0.005).
    max_degree : int, optional
        Largest polynomial degree of the quasi-static family on linear axes (default 7).
    max_effects : int, optional
        Most effects selected (default 8).
    tie_positions : bool, optional
        Reflector positions shared by the axes measured from the same reference pose (mtcal.diagnose.prepare),
        else one per (axis, reflector).
    tracker_model : str or TrackerSpec, optional
        The tracker's noise law, the prior of the noise model (an instrument's name, ``"a_r,b_r,a_t,b_t[,k]"`` MPE
        in um and um/m, or a TrackerSpec; default the AT960's); the repeated rounds still check its shape.

    Returns
    -------
    Diagnosis
        The noise before and after, the effects (significant or not), the located and unexplained mismatches.

    Raises
    ------
    mtcal.errors.InputError
        A bad level, an axis not of the machine, a model of another machine.

    Examples
    --------
    >>> import mtcal
    >>> rec, truth = mtcal.simulate(rounds=3, seed=1, plan={"axes": {"X": {}}},
    ...                             effects=["backlash:axis=X,amount=0.006"])  # 6 um planted
    >>> d = mtcal.diagnose(rec, tracker=(250, -1500, 150))
    >>> found = [f for f in d.effects if f.significant]
    >>> [(f.name, f.axis) for f in found]
    [('backlash', 'X')]
    >>> print(f"{found[0].estimate * 1e3:.1f} um")
    5.6 um
    """
    with threadpool_limits(limits=1, user_api="blas"):  # BLAS_THREADS
        return _diagnose(rec, model, machine, tracker, level, max_degree, max_effects, tie_positions, tracker_model)


def _diagnose(rec, model, machine, tracker, level, max_degree, max_effects, tie_positions, tracker_model
              ) -> Diagnosis:
    say = log.info
    if not 0 < level < 1:
        raise InputError(f"level must be in (0, 1), got {level}")
    level /= STAGES  # each stage's share (STAGES)
    prep, gross = _prepared(rec, model, machine, tracker, level, max_degree, tie_positions, tracker_model)
    say(f"noise model: {prep.noise.kind} ({prep.noise.how})")
    wy, w = whiten(prep.W, prep.y), Columns(prep.W)
    # the null of every test: the quasi-static family at its largest degree (or the given model), not the
    # BIC-selected base: an effect is reported only if no smooth error function of the family explains it
    test_degrees = family_degrees(prep, max_degree)
    eng = null_eng = engine_for(prep, base_design(prep, test_degrees), wy)  # forward adds the effects to it
    cands, notes = candidates(prep, max_degree)
    if not prep.given_model:
        cands = screen(cands, notes, eng, w)
    say(f"{len(cands)} candidate effects; null model {eng.p} parameters, sigma ratio {eng.sigma:.3f}")
    steps, last, inadequate = forward(prep, eng, cands, w, level, max_effects, say)
    steps = steps_per_place(backward(eng, steps, w, level, say), say)
    growing_confounds(prep, eng, steps, w)
    untested_confounds(steps, notes)
    null = ("the given model" if prep.given_model else
            f"the quasi-static family at its largest degrees ({_degrees_text(test_degrees)})"
            ) + " + the effects selected before"

    # the reported base: degrees by BIC with the named effects (a free form is a mismatch, not the model's)
    degrees = dict(test_degrees) if prep.given_model else select_degrees(
        prep, wy, test_degrees, say, [w(s.candidate) for s in steps if not s.candidate.free])
    base = base_design(prep, degrees)
    eng = engine_for(prep, base, wy)
    base_sigma, base_ratio, r_before = raw_sigma(prep, eng.r, eng.dof), eng.sigma, eng.r.copy()
    located = collapsed(locate(prep, null_eng.copy_base(), level))  # against the tests' null, as "unexplained" below
    after = with_steps(eng, steps, w)

    def cv(step, others):
        held, how = folds(prep, step.candidate)
        why: list[str] = []
        gain = cv_gain(prep, base, wy, others, w(step.candidate), held, why) if held else None
        return gain, (f"{how}: {why[0]}" if why else how if held else f"no held-out gain: {how}")

    free = [s for s in steps if s.candidate.name == fx.UNEXPLAINED]
    effects = selected_findings(prep, eng, [s for s in steps if all(s is not f for f in free)], w, cv, null)
    predictive_checks(prep, eng.copy_base(), effects, after.r, after.sigma, level)
    effects.sort(key=lambda f: (not f.significant, -f.evidence["F"] * f.evidence["dof"][0]))
    effects += rejected_findings(last, {s.candidate.family for s in steps}, notes, inadequate)
    # located against the tests' null with the effects (a misfit a smooth error function of the family explains
    # is no effect, so not unexplained either), not the reported BIC base; what the error functions tabulated at
    # the measured positions explain is a shape beyond the family's degree (quasi-static), reported with the base
    with_effects = with_steps(null_eng, steps, w)
    left, shapes = beyond_the_family(prep, with_effects, locate(prep, with_effects, level), w, level)
    left = collapsed(left)
    beside_a_mismatch(prep, with_effects, steps, effects, left, w)  # every group a rival, then one at a time
    left = one_at_a_time(prep, with_effects, left, w, level)
    effects.sort(key=lambda f: not f.significant)  # stable: a withdrawn name after the named ones
    unexplained = [free_form_located(prep, with_steps(eng, [o for o in steps if o is not s], w), s, w, after.sigma)
                   for s in free] + left
    base_info = _base_info(prep, degrees, test_degrees, null, int(after.copy_base().p), shapes)
    return Diagnosis(base_sigma, base_ratio, raw_sigma(prep, after.r, after.dof), after.sigma, effects, located,
                     base_info, prep.noise, unexplained, _noise_notes(prep), residuals_before=r_before,
                     residuals_after=after.r.copy(), prep=prep, data_problems=[p.to_dict() for p in gross.problems])


def _prepared(rec, model, machine, tracker, level, max_degree, tie_positions, tracker_model):
    """(the prepared data, the gross-error screen) of a recording: screened, its station placed, weighted."""
    prior = as_tracker_model(tracker_model)
    machine = machine if isinstance(machine, Machine) else load_machine(machine)
    rec, gross = _screened(rec, machine)
    tracker = _station_tracker(rec, tracker)
    return prepare(rec, machine, model, tracker, max_degree, tie_positions, prior, level), gross


def _noise_notes(prep) -> list[str]:
    """What the noise model's findings depend on, said in ``notes``: where the round scatter and the reflectors'
    mutual distances disagree about the tracker's law (mtcal.measurement.tracker_position.rigid_law), which was
    used; where the station is not determined by the data, what that leaves; an axis repeating worse than the
    others (mtcal.diagnose.scatter), found and its readings re-weighted."""
    shape = prep.noise.details.get("shape") or {}
    out = [(shape.get("mutual_distances") or {}).get("disagreement")]
    out.append((prep.noise.details.get("station_interval") or {}).get("note"))
    out.append(((prep.noise.details.get("axis_scatter") or {}).get("found") or {}).get("says"))
    return [n for n in out if n]


def _screened(rec: Recording, machine: Machine):
    """The recording less its gross errors (swapped labels, far readings, duplicated rows:
    mtcal.measurement.screen, each said as a warning), and the screen's result; unit and frame slips refused
    (mtcal.measurement.slips)."""
    gross = screen_gross(rec, machine.sides, machine)
    for p in gross.problems:
        log.warning("warning: data problem: %s", p.text)
    for note in gross.notes:
        log.warning("warning: %s", note)
    kept = rec.select(gross.keep) if gross.problems else rec
    if gross.untimed:  # the clock is not what it claims (a "clock" data problem): nothing reads it
        kept = dataclasses.replace(kept, time_s=np.full(len(kept), np.nan))
    check_units_and_frame(kept, machine)  # inch, radians, swapped columns: refused before any fit (as identify)
    return kept, gross


def _base_info(prep, degrees: dict[str, int], test_degrees: dict[str, int], null: str, parameters: int,
               shapes: list) -> dict:
    """The reported base (``base_model`` in the JSON answer): kind, BIC degrees, what the tests are against, the
    basis in words, shapes beyond the family (``shapes``: located entries), the station alignments."""
    info = {"kind": "given model" if prep.given_model else "fitted quasi-static", "degrees": degrees,
            "parameters": parameters, "readings": len(prep.rec),
            "tests_against": null if prep.given_model else
            f"the quasi-static family at its largest degrees ({_degrees_text(test_degrees)}; degrees above: "
            "BIC with the selected effects in the fit)", "weighted": prep.weighted,
            "basis": "polynomials in (q - q_ref) for linear axes; harmonics for rotary axes; "
                     + _positions(prep) + _alignments(prep)}
    if shapes:
        info["shape_beyond_family"] = [u.to_dict() for u in shapes]
    if prep.stations:
        info["alignment"] = {"stations": prep.stations, "fixed": prep.stations[0],
                             "per_station": "tx, ty, tz (mm), wx, wy, wz (rad) about the station's readings' centroid"}
    return info


def _degrees_text(degrees: dict[str, int]) -> str:
    return ", ".join(f"{a} {d}" for a, d in degrees.items())


def _positions(prep) -> str:
    """How the base's reflector positions are shared between the axes (mtcal.diagnose.prepare), in words."""
    ties = [", ".join(c) for c in shared_axes(prep)]
    if not ties:
        return "per-(axis, point) positions"
    return (f"reflector positions shared by {' and by '.join(ties)} (the same reference pose and side; each of "
            "these axes with a free rigid motion of its side), else per (axis, point)")


def _alignments(prep) -> str:
    """The station alignment unknowns of the base (mtcal.diagnose.design), in words ("" for one station)."""
    if not prep.stations:
        return ""
    return (f"; {len(prep.stations)} tracker stations ({', '.join(prep.stations)}): a rigid alignment (3 "
            f"translations mm, 3 rotations rad about the station's readings' centroid) per station but the first "
            f"{prep.stations[0]} (gauge: the first station's alignment is the frame)")


def _station_tracker(rec: Recording, tracker):
    """The tracker position(s) of the noise model: ``tracker`` if given, else the recording's own tracker_x,y,z
    columns (docs/design.md); several stations: a dict station label -> tracker position (3,) mm (each station's
    readings are then weighted about its own tracker and the base carries every station's alignment)."""
    labels = list(dict.fromkeys(rec.stations().tolist()))
    if len(labels) > 1:
        if tracker is not None:
            raise InputError(f"{rec.source}: {len(labels)} tracker stations ({', '.join(labels)}): one `tracker` "
                             "position cannot weigh them; give the tracker_x,y,z columns or `station` LABEL")
        if rec.tracker_xyz is None:
            raise InputError(f"{rec.source}: {len(labels)} tracker stations ({', '.join(labels)}) but no "
                             "tracker_x,tracker_y,tracker_z columns: add each station's tracker position, or "
                             "give `station` LABEL")
        return {k: rec.tracker_xyz[np.flatnonzero(rec.stations() == k)[0]] for k in labels}
    if tracker is None and rec.tracker_xyz is not None:
        return rec.tracker_xyz[0]
    return tracker
