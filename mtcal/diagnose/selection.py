"""Selection of the diagnosis: forward selection of candidate effects by F test, backward elimination that
never drops a large effect for a later overlapping smaller one, confounding, degrees by BIC, cross-validation.

Multiplicity: Bonferroni over families x members (scanned families: x the members scanned). Among the significant
candidates of a step, the strongest evidence (raw p) names the effect; a significant candidate that explains the
same misfit (the share of the chosen effect's fitted signal, whitened, after the base, that the other's columns also
explain: |cos| > CONFOUND_COS), or that was significant with evidence of the same order and is no longer once the
chosen effect is fitted, is reported with it as ``confounded_with``, with the measurement that separates them.
A candidate whose own model does not explain the pattern it fits (a reversal that differs between reflectors
beyond the named reversal effects; a one-off displacement that recurs in the other rounds) is not chosen
(``inadequate``); a free-form candidate (mtcal.diagnose.effects.reversal_free) that wins is reported as unexplained.
Validation: held-out rounds for effects that repeat over rounds; interleaved halves (alternate readings of every
sequence in time order) for those whose grammar says they depend on time (or a temperature) or are specific to one
round (fx.Grammar.varies_in_time); a single-reading outlier has nothing to predict (its test is its studentized
displacement).  Nesting, ties, rivals and the measurement that separates two candidates follow from the candidates'
grammar attributes (where x what x how) and their columns, not from their names."""
from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np
from scipy import optimize

from mtcal import _tails
from mtcal.diagnose import effects as fx
from mtcal.diagnose import strata as stratum
from mtcal.diagnose.candidates import reversal_named, scanned
from mtcal.diagnose.design import Base, base_design, engine_for, whiten
from mtcal.diagnose.engine import ALIAS_TOL, WEAK_TOL, Engine, Score
from mtcal.diagnose.places import (
    bump,
    frame_path,
    nest_path,
    place_motion,
    place_of,
    replicate_strata,
    step_pattern,
    step_rows,
    stop_motions,
    stops_of,
    stops_off,
    stops_rigid,
    tie,
    unsteady,
)
from mtcal.diagnose.prepare import Prepared
from mtcal.diagnose.scans import change_points, translations
from mtcal.diagnose.separate import separate_by

CONFOUND_COS = 0.9
RIVAL_LOGP_SHARE = 0.5  # a rival absorbed by the chosen effect, with at least this share of its log p: confounded
# two changes in time fitting one misfit: one is named over the other only when the likelihood ratio between them
# (equal columns; Akaike's penalty for a difference in columns) is at least 100, Jeffreys' "decisive" -- else the
# mismatch is reported once, located, with both as what it may be (_tied)
TIE_CHI2 = 2 * math.log(100)
# a candidate nests another (at the same place: _simplest; a tie: _may_tie) or holds it at another place
# (_contained_elsewhere) when every direction of the other's columns lies within its own beside the base to
# |cos| > CONFOUND_COS (_contains): the column spaces decide, not a table of names; to rounding (NESTED_COS), it is
# a member and the simpler one it contains (a backlash changing along the travel and the constant one), never tied
NESTED_COS = 1.0 - 1e-6


class Columns:
    """Whitened columns (3n, k) of candidates, computed once per candidate (kept on the candidate)."""

    def __init__(self, W: np.ndarray):
        self.W = W

    def __call__(self, c: fx.Candidate) -> np.ndarray:
        if "_w" not in c.extra:
            c.extra["_w"] = whiten(self.W, c.G)
        return c.extra["_w"]


@dataclass(eq=False)  # a step is itself: its candidate's arrays have no truth value to compare
class Step:
    """A selected effect: its candidate, F test at entry, Bonferroni-adjusted log p, family size, confounds."""

    candidate: fx.Candidate
    score: Score
    logp_adj: float
    confounded_with: list[dict] = field(default_factory=list)
    inadequate: str | None = None   # why the effect's model does not explain the misfit it fits (then not chosen)

    @property
    def log_multiplicity(self) -> float:
        """log of the Bonferroni factor (members x families) of this step's test."""
        return self.logp_adj - self.score.logp


def refine(c: fx.Candidate, s: Score, eng: Engine, w: Columns) -> tuple[fx.Candidate, Score]:
    """Refine a continuous parameter (pitch, tau) of the family winner by a bounded 1-D search (a periodic error's
    pitch no nearer the base family than WEAK_TOL: candidates.screen)."""
    if c.refine is None:
        return c, s
    lo, hi = c.refine_range
    v = c.refine_value
    a, b = max(lo, v / 1.5), min(hi, v * 1.5)
    if b <= a:
        return c, s
    res = optimize.minimize_scalar(lambda lv: -eng.score(w(c.refine(math.exp(lv)))).delta,
                                   bounds=(math.log(a), math.log(b)), method="bounded", options={"xatol": 1e-3})
    cc = c.refine(math.exp(res.x))
    sc = eng.score(w(cc))
    apart = sc.sep >= WEAK_TOL or c.name not in fx.NEEDS_SEPARATION
    return (cc, sc) if sc.separable and apart and sc.delta > s.delta else (c, s)


def score_all(prep: Prepared, eng: Engine, cands: list[fx.Candidate], w: Columns) -> dict[str, Step]:
    """Per family, its best member on the current fit (refined), with its Bonferroni-adjusted log p."""
    fams: dict[str, list[tuple[fx.Candidate, Score]]] = {}
    for c in cands:
        sc = eng.score(w(c))
        if sc.separable:
            fams.setdefault(c.family, []).append((c, sc))
    scans = [(f, c, n, eng.score(w(c))) for f, c, n in scanned(prep, eng)]
    scans = [s for s in scans if s[3].separable]
    n_fam = len(fams) + len(scans)
    out = {}
    for fam, members in fams.items():
        c, sc = refine(*min(members, key=lambda cs: cs[1].logp), eng, w)
        out[fam] = Step(c, sc, sc.logp + math.log(len(members) * n_fam))
    for fam, c, count, sc in scans:
        out[fam] = Step(c, sc, sc.logp + math.log(count * n_fam))
    return out


def forward(prep: Prepared, eng: Engine, cands: list[fx.Candidate], w: Columns, level: float, max_effects: int,
            say: Callable[[str], None]) -> tuple[list[Step], dict[str, Step], list[Step]]:
    """Forward selection (adds to ``eng``); returns the selected steps, the last scores of every family and the
    significant candidates skipped as inadequate."""
    selected: list[Step] = []
    last: dict[str, Step] = {}
    inadequate: dict[str, Step] = {}
    for step in range(max_effects):
        last = score_all(prep, eng, cands, w)
        sig = [v for v in last.values() if v.logp_adj < math.log(level)]
        if not sig:
            break
        best = _strongest_adequate(prep, eng, sig, w, level, inadequate, {x.candidate.family for x in selected},
                                   list(last.values()))
        if best is None:
            break
        c = best.candidate
        before = eng.sigma
        rivals = [v for v in sig if v is not best and v.candidate.family != c.family and _rival(c, v.candidate)]
        shared = {id(v): eng.shared_fit(w(c), w(v.candidate)) for v in rivals}
        eng.add(w(c))
        best.confounded_with += [_confound(c, v, shared[id(v)]) for v in rivals
                                 if shared[id(v)] > CONFOUND_COS or _absorbed(eng, best, v, w, level)]
        say(f"step {step + 1}: {c.name} {c.axis or ''} {c.label}: F = {best.score.F:.1f}, "
            f"sigma ratio {before:.3f} -> {eng.sigma:.3f}")
        selected.append(best)
        cands = [x for x in cands if x.family != c.family]  # one member per family (scanned ones: afresh, score_all)
    return selected, last, list(inadequate.values())


def _strongest_adequate(prep: Prepared, eng: Engine, sig: list[Step], w: Columns, level: float,
                        inadequate: dict[str, Step], taken: set[str], pool: list[Step]) -> Step | None:
    """The significant candidate with the strongest evidence (raw p) whose own model explains the pattern it
    fits (``inadequate_because``); the others are recorded in ``inadequate`` (by family, first reason kept).
    ``pool``: every family's best on the current fit, the rivals a name may tie with (_one_name).
    A candidate whose place's free form is still needed beside it gives way to that free form (place_needed),
    once: where it was selected already (``taken``: the families selected), the mismatch has its entry.
    A free-form candidate is taken only when the named effects it spans cannot explain what it fits.  Exact ties
    (a knock just after a reflector's first sequence is that nest's offset) go to the smaller family (the
    adjusted p breaks them)."""
    todo = sorted(sig, key=lambda v: v.score.logp)
    fallback: Step | None = None  # a place's free form, taken unless a name within that place is adequate
    while todo:
        top = todo[0].score.logp
        tol = 1e-9 * max(1.0, abs(top)) if math.isfinite(top) else 0.0
        near = [o for o in todo if o.score.logp <= top + tol]
        best = min(o.logp_adj for o in near)  # equal within round-off: the first in the candidates' order
        slack = 1e-9 * max(1.0, abs(best)) if math.isfinite(best) else 0.0
        v = next(o for o in sig if any(o is x for x in near) and o.logp_adj <= best + slack)
        todo.remove(v)
        if fallback is not None and not _within(eng, fallback.candidate, v, w):
            return fallback  # the stronger mismatch first; this one is scored again at the next step
        if v.candidate.free:
            if v.candidate.grammar is None or "direction" in v.candidate.grammar.how.on:
                if _reversal_misfit(prep, eng, v.candidate.axis, w, level) is not None:
                    return v  # the named reversal effects of the axis cannot explain it
                continue
            if _explained_by_a_name(eng, v, sig, w, level) or _one_place_instead(prep, eng, v, w, level):
                continue  # a member of the grammar (a side expanding, a scale about the tracker) moves them so
            return v  # no named effect changes an error motion's shape with time, or maps the tracker's readings
        why = (inadequate_because(prep, eng, v.candidate, w, level) or _contained_elsewhere(eng, v, sig, w)
               or _within_its_scatter(prep, eng, v, w, level))
        if why is None and (why := _stops_move_together(prep, eng, v, w, level)) and _frame_step(v.candidate):
            fallback = fallback or _strongest_in_place([_knock_stops(prep, eng, v, w), _path(prep, eng, v, w)], v,
                                                       level, taken)
        if why is None and (found := _change_points(prep, eng, v, w, level)):
            why, free = found
            fallback = fallback or _strongest_in_place(free, v, level, taken)
        if why is None:
            place = place_needed(prep, eng, v, w, level)
            if place is None:
                chosen = _simplest(prep, eng, v, sig, w, level)
                # the member named is tested against its place's error term too (one stratum for both)
                place = None if chosen is v else place_needed(prep, eng, chosen, w, level)
                if place is None:
                    return _stops_alike(prep, eng, v, w) or _one_name(eng, chosen, pool, w, level)
            free, sc, why = place
            if free is not None:
                fallback = fallback or _in_place(_stops_instead(prep, eng, v, free, w, level) or (free, sc), v,
                                                 level, taken)
        v.inadequate = why
        inadequate.setdefault(v.candidate.family, v)
    return fallback


def _explained_by_a_name(eng: Engine, v: Step, sig: list[Step], w: Columns, level: float) -> bool:
    """Whether a significant named candidate of ``sig`` leaves the free form of ``v`` insignificant beside it
    (its own test at ``level``, its multiplicity): the free form's misfit is that effect's.  A rigid shift at one
    moment (fx.Grammar.jump: one round's, or a step) does not count: a growth is no jump."""
    own = level * math.exp(-v.log_multiplicity)
    return any(_significant_beside(eng, w(o.candidate), w(v.candidate), own) is None for o in sig
               if not o.candidate.free and not o.candidate.grammar.jump)


def _one_place_instead(prep: Prepared, eng: Engine, v: Step, w: Columns, level: float) -> bool:
    """Whether the free form ``v``, spanning the readings of every axis (no axis of its own: the tracker's error
    map, effects.instrument_map), fits a misfit of one place: one axis' readings free at every pose (effects.by_cell:
    every nest, position and direction of it -- a shape of its error functions beyond the family's degree, its
    nests sagging) or one nest free at every pose (effects.by_pose: a reflector read off with its incidence).  Null:
    the one place's free form explains what ``v`` fits (``v`` adds nothing beside it); alternative: ``v`` adds a
    mean; F test at ``v``'s own level (its multiplicity), one rival enough.  The mismatch is then that place's,
    located by the scans, not the tracker's."""
    if v.candidate.axis is not None:
        return False
    g, own = prep.geometry, level * math.exp(-v.log_multiplicity)
    rivals = [fx.by_cell(g, np.flatnonzero(g.axis == a)) for a in prep.axes]
    rivals += [f[-1] for p, side in sorted(set(zip(g.point.tolist(), g.side.tolist())))
               if (f := fx.by_pose(g, p, side, 0))]
    return any(_significant_beside(eng, w(r), w(v.candidate), own) is None for r in rivals)


def _one_name(eng: Engine, v: Step, pool: list[Step], w: Columns, level: float) -> Step:
    """``v``, or -- where named changes in time at other places (of ``pool``) fit the same misfit alike (_tied) --
    one free form of them all (mtcal.diagnose.places.tie): the mismatch located, with every name it may be, none of
    them named.  Its evidence is ``v``'s test (the misfit is there; the free form's own test would spread it over
    every column)."""
    tied = _tied(eng, v, pool, w, level)
    if not tied:
        return v
    return Step(tie(v.candidate, [o.candidate for o, _ in tied], [lead for _, lead in tied]), v.score, v.logp_adj)


def _in_place(found: tuple[fx.Candidate, Score] | None, v: Step, level: float, taken: set[str]) -> Step | None:
    """A free form ``found`` (candidate, its score on the current fit) as the mismatch, once, where ``v``'s name
    was, at v's multiplicity: None where there is none, where its family has its entry already (``taken``), or
    where it is not significant at ``level``."""
    if found is None:
        return None
    free, sc = found
    if free.family in taken or sc.logp + v.log_multiplicity >= math.log(level):
        return None
    return Step(free, sc, sc.logp + v.log_multiplicity)


def _strongest_in_place(found: list[tuple[fx.Candidate, Score] | None], v: Step, level: float, taken: set[str]
                        ) -> Step | None:
    """Of the free forms ``found`` that may stand in the place of a rejected step of a frame (_in_place: its stops
    landing off, the frame moving smoothly), the one with the strongest evidence: gen2 3540/35, X repeating worse,
    had its knock's stops landing off (F = 40 on 7 columns) lose to a smooth path of the frame (F = 2.7 on 90)."""
    steps = [s for s in (_in_place(f, v, level, taken) for f in found) if s is not None]
    return min(steps, key=lambda s: s.logp_adj, default=None)


def _stops_alike(prep: Prepared, eng: Engine, v: Step, w: Columns) -> Step | None:
    """A tracker knock whose shorter side within its linear axis holds few stops gives way to those stops landing
    off (mtcal.diagnose.places.stops_off: a column per stop along the motion) where its lead over them (_lead) is
    below TIE_CHI2, the tie rule's measure: a step of a few stops along the motion is what a machine repeating
    worse there shows too (gen2 seed 3515 campaign 12: Y repeating worse, 1.7 um per stop, a per-stop test at
    p_adj 0.05, was a tracker knocked along +Y within Y's fourth round).  The free form takes the knock's
    evidence; None when the knock stands."""
    stops = _knock_stops(prep, eng, v, w)
    return Step(stops[0], v.score, v.logp_adj) if stops and _lead(eng, v, stops[1]) < TIE_CHI2 else None


def _knock_stops(prep: Prepared, eng: Engine, v: Step, w: Columns) -> tuple[fx.Candidate, Score] | None:
    """(stops, score on ``eng``): the stops of a tracker knock's linear axis landing off
    (mtcal.diagnose.places.stops_off) where they are separable on ``eng``; else None."""
    stops = stops_off(prep, v.candidate)
    if stops is None:
        return None
    sc = eng.score(w(stops))
    return (stops, sc) if sc.separable else None


def _stops_instead(prep: Prepared, eng: Engine, v: Step, free: fx.Candidate, w: Columns, level: float
                   ) -> tuple[fx.Candidate, Score] | None:
    """(stops, score): where a tracker knock's place (``free``: the station's rigid step, turning about the tracker)
    is needed beside it, its stops of the linear axis landing off (mtcal.diagnose.places.stops_off) in its place
    when the rigid step adds nothing significant beside them (F test at ``level``): the first stops of a round
    landing off the rest fit a knock, and its turn then carries their scatter to the other axes (gen2 seed 3540
    campaign 35: X repeating worse, reported as S1's frame stepping, largest on C).  None otherwise."""
    stops = _knock_stops(prep, eng, v, w)
    if stops is None or _significant_beside(eng, w(stops[0]), w(free), level) is not None:
        return None
    return stops


def _lead(eng: Engine, v: Step, other: Score) -> float:
    """``v``'s lead over a rival scored ``other`` on the same fit ``eng``: their chi^2 reductions' difference in the
    residual variance with ``v`` fitted, less twice the difference in columns (Akaike's penalty)."""
    s2 = max(eng.rss - v.score.delta, 1e-300) / max(v.score.dof, 1)
    return (v.score.delta - other.delta) / s2 - 2 * (v.score.k - other.k)


def _place(c: fx.Candidate) -> tuple | None:
    """Where a named change in time acts (fx.Grammar.place): the tracker (of a station), a side, one nest; None for
    what is constant in time, an axis' error motions or one reading, whose rivals the columns order."""
    return None if c.grammar is None else c.grammar.place


def _may_tie(base: Engine, w: Columns, v: Step, u: Step) -> bool:
    """Whether the candidates ``c`` of ``v`` and ``o`` of ``u`` are changes in time (_place) that may fit one misfit
    alike: of other families, not one motion by two clocks (_two_clocks), not one nesting the other (its columns within
    the other's to rounding, NESTED_COS, beside the base ``base``: a member and the simpler one it contains, which
    _simplest orders), nor, one dependence at two wheres (_across_places), one whose columns lie within the other's
    (_contains) where ``v``, the leader, fits at least as much (across places the columns and the fit decide, as in
    _contained_elsewhere: a drift along the beams that holds the air's one column and fits less; within one place two
    laws fitting alike tie: a knock within a re-levelling with its shift at another t0 to |cos| 0.95, gen2 3553/21), at
    other places (at the tracker also two time laws: a knock, a drift, the air), moving mostly the same readings (at
    least half of the fewer they move: effects that move different readings fit alike only through the base's freedoms,
    reflector positions and station alignments, where the base's rules and same_fit_as decide)."""
    c, o = v.candidate, u.candidate
    pc, po = _place(c), _place(o)
    if None in (pc, po) or o.family == c.family or _two_clocks(c, o):
        return False
    if pc == po and pc[0] != "tracker":
        return False
    a, b = (x.moved for x in (c, o))
    if not (a & b).sum() >= 0.5 * min(a.sum(), b.sum()) > 0:
        return False
    if _contains(base, w, c, o, NESTED_COS) or _contains(base, w, o, c, NESTED_COS):
        return False
    return not (_across_places(c, o) and v.score.delta >= u.score.delta
                and (_contains(base, w, c, o) or _contains(base, w, o, c)))


def _across_places(c: fx.Candidate, o: fx.Candidate) -> bool:
    """Whether ``c`` and ``o`` are one dependence at two wheres (the same how-variables): what the data then decide
    is the place, from the columns and the fit (_contained_elsewhere, _may_tie).  Where the dependence differs (a
    location error, constant, and a reflector re-seated for a round) the evidence and the parsimony decide."""
    return c.grammar.where != o.grammar.where and c.grammar.how.on == o.grammar.how.on


def _two_clocks(c: fx.Candidate, o: fx.Candidate) -> bool:
    """Whether ``c`` and ``o`` are one gradual motion (the same where and what, neither a step) by two clocks (they
    depend on different variables: the time, a temperature that follows it): the name and its place are the
    data's, the clock is said in confounded_with, never a tie."""
    gc, go = c.grammar, o.grammar
    return ((gc.where.at, gc.where.key, gc.what) == (go.where.at, go.where.key, go.what)
            and gc.how.on != go.how.on and not (gc.step or go.step))


def _gives_way(base: Engine, w: Columns, small: Step, big: Step) -> bool:
    """Whether ``small`` gives way to ``big``: big's columns contain small's (_contains, beside the base ``base``)
    and big explains at least as much of the misfit (its sum of squares, on the same fit), so that small's lead in
    the evidence is its fewer columns, not the data (the air's one column within a drift along the beams)."""
    return big.score.delta >= small.score.delta and _contains(base, w, big.candidate, small.candidate)


def _contains(base: Engine, w: Columns, c: fx.Candidate, o: fx.Candidate, cos: float = CONFOUND_COS) -> bool:
    """Whether the columns of ``c`` contain those of ``o`` beside the base ``base``: every principal direction of
    o's columns (residualized on the base) lies within c's to |cos| > ``cos`` (CONFOUND_COS: the campaign cannot tell
    them apart; NESTED_COS: to rounding), i.e. the projection of o on c leaves less than 1 - cos^2 of any of o's
    directions (a backlash within a backlash changing along the
    travel, exactly; a knock within a re-levelling with its shift; a side's drift within its expansion about a
    fitted centre with the same law; the air's scale about a station within a drift along the beams, to 1 part in
    300).  o with more directions than c, or none beside the base, is not contained."""
    a, b = _beside(base, w(o)), _beside(base, w(c))
    if a.shape[1] == 0 or a.shape[1] > b.shape[1]:
        return False
    return float(np.linalg.svd(a.T @ b, compute_uv=False).min()) > cos


def _beside(base: Engine, G: np.ndarray) -> np.ndarray:
    """An orthonormal basis of the whitened columns ``G`` with the base projected out, each column scaled to unit
    size first (a turn's columns in mm/rad dwarf a shift's in mm: Engine.residualized's tolerance, relative to all
    of G, would drop the shift); a column the base takes (less than ALIAS_TOL of it left) is dropped."""
    Gp = G - base.project(G)
    Gp = Gp - base.project(Gp)
    size = np.linalg.norm(Gp, axis=0)
    keep = size > ALIAS_TOL * np.maximum(np.linalg.norm(G, axis=0), 1e-300)
    if not keep.any():
        return np.zeros((G.shape[0], 0))
    u, sv, _ = np.linalg.svd(Gp[:, keep] / size[keep], full_matrices=False)
    return u[:, sv > ALIAS_TOL * sv[0]]


def _tied(eng: Engine, v: Step, pool: list[Step], w: Columns, level: float) -> list[tuple[Step, float]]:
    """The candidates of ``pool`` (every family's best on the current fit, significant or not: a rival's
    multiplicity says how hard it is to find among its members, not how well it explains the misfit ``v`` found)
    that may tie with ``v`` (_may_tie) and fit its misfit about as well, each with ``v``'s lead over it (_lead)
    below TIE_CHI2; the other not significant beside ``v``, or fitting less than WITHIN of what it fits
    alone (the same misfit: planted seed 7, a tracker settling 369.1 alone, 34.6 beside a spindle side's expansion
    that fits 367.1, was left significant and the expansion named).  gen2 seed 3520 campaign 19: X's straightness
    bowing with time was a tracker re-levelled before X's third round (24.4), beside a knock of the tracker that
    fitted 23.8 but, its t0 scanned, was not itself significant."""
    c = v.candidate
    out, beside, base = [], None, eng.copy_base()
    for o in (o for o in pool if _may_tie(base, w, v, o)):
        lead = _lead(eng, v, o.score)
        if lead >= TIE_CHI2:
            continue
        if beside is None:
            beside = eng.copy()
            beside.add(w(c))
        sc = beside.score(w(o.candidate))
        if not (sc.separable and sc.logp + o.log_multiplicity < math.log(level)) or sc.delta < WITHIN * o.score.delta:
            out.append((o, lead))
    return out


def _contained_elsewhere(eng: Engine, v: Step, sig: list[Step], w: Columns) -> str | None:
    """Why the named candidate of ``v`` gives way (_gives_way) to a significant named candidate of ``sig`` with the same
    dependence at another place (_across_places), with more columns that contain its own (beside the base) and that
    explains at least as much of the misfit (its sum of squares): v's lead in the evidence is then its fewer columns,
    not the data. From one station in front of an XY campaign a spindle drifting along the beams is a scale about the
    tracker to 1 part in 300 (the columns' |cos| after the base 0.992-0.9997), and the air (one column) was named in its
    place; the drift, named, lists the air beside it."""
    c = v.candidate
    if c.free:
        return None
    base = eng.copy_base()
    o = max((o for o in sig if not o.candidate.free and _across_places(c, o.candidate)
             and o.candidate.G.shape[2] > c.G.shape[2] and _gives_way(base, w, v, o)),
            key=lambda o: o.score.delta, default=None)
    if o is None:
        return None
    return (f"{o.candidate.title} ({o.candidate.label}) explains as much of the misfit ({o.score.delta:.4g} against "
            f"{v.score.delta:.4g}, whitened sums of squares) with columns that contain its own")


def _simplest(prep: Prepared, eng: Engine, v: Step, sig: list[Step], w: Columns, level: float) -> Step:
    """``v``, or the simpler member it contains where what ``v`` adds beside it is not significant (lack_of_fit:
    against the replicates' scatter where what it adds is a function of the stop -- a reversal's change along the
    travel beside a constant one -- else against the fit's residual; at v's own multiplicity): its own
    ``nested`` member (a re-levelling with its shift: the knock at its t0), or a named one of ``sig`` at the same
    where with fewer columns that v's columns contain (_contains, beside the base); beyond the float range of p,
    the chi^2 tail that orders the evidence favours the member with more columns (xyzac: a constant 50 urad
    backlash of A was named backlash_travel, F = 2082 on 2 columns; icelinker's base reflectors drifting 56 um
    together were a tool side expanding about a fitted centre)."""
    c = v.candidate
    if c.nested is not None:
        sc = eng.score(w(c.nested))
        o = Step(c.nested, sc, v.logp_adj) if sc.separable else None
    else:
        base = eng.copy_base()
        o = next((o for o in sig if not (o.candidate.free or c.free) and o.candidate.grammar.where == c.grammar.where
                  and o.candidate.G.shape[2] < c.G.shape[2] and _contains(base, w, c, o.candidate)), None)
    if o is None:
        return v
    e = eng.copy()
    e.add(w(o.candidate))
    sc = lack_of_fit(prep, e, v.candidate, w)
    return v if sc.separable and sc.logp < math.log(level) - v.log_multiplicity else o


WITHIN = 0.1  # a candidate whose fit the free form of a place leaves less than this share of is within that place


def _within(eng: Engine, free: fx.Candidate, v: Step, w: Columns) -> bool:
    """Whether the candidate of ``v`` describes the mismatch at ``free``'s place: beside the free form it fits
    less than WITHIN of what it fits alone (a tracker re-levelled, named beside the rigid step a knock left)."""
    e = eng.copy()
    e.add(w(free))
    sc = e.score(w(v.candidate))
    return not sc.separable or sc.delta < WITHIN * v.score.delta


def place_needed(prep: Prepared, eng: Engine, v: Step, w: Columns, level: float
                 ) -> tuple[fx.Candidate | None, Score | None, str] | None:
    """One finding per mismatch (mtcal.diagnose.places), the member ``v`` and its place tested against one error
    term: why ``v``'s candidate is not named, or None.

    Error term (_place_error): where the place's free form F_P is a function of the stop (places.replicate_strata),
    the scatter of the stops repeated over the rounds, estimated once on the fullest model of the place (the fit,
    the place's named members and F_P: strata.pure_error), so that it holds neither the member nor the free
    form's shape, nor the effects in time already selected; else the fit's residual.  Two tests against it:
    1. the member's own: null, M adds no mean beyond the fit; alternative, it adds one; at v's multiplicity (the
       Bonferroni factor of its entry test).  Not significant: (None, None, why) -- the stops' scatter from round
       to round makes the member as well (a stop-level contrast whose test against the readings' scatter alone
       counts every nest of a stop as if it landed on its own);
    2. the place's: null, the named members of the place (M and every named effect of the same kind there) are
       adequate, F_P (and its sharper members) adds nothing beside them; alternative, it adds a mean; Bonferroni
       over F_P and its sharper members at ``level``.  Significant: (F_P, its score on the current fit, why)."""
    c = v.candidate
    place = place_of(prep, c, lambda axis: reversal_named(prep, axis))
    if place is None:
        return None
    e, err = _place_error(prep, eng, place, w)
    if err is not None:
        own = stratum.against(eng, w(c), err)
        if own is not None and own.logp + v.log_multiplicity >= math.log(level):
            return None, None, (f"against the scatter of its place's stops repeated over the rounds (the error term "
                                f"of the place's free form beside it) it is not significant (F = {own.F:.2g} on "
                                f"{own.k} and {own.dof} degrees of freedom, p = {math.exp(own.logp):.2g} before its "
                                "multiplicity): the stops landing off from round to round make it as well")
    tests = (*place.sharper, place.candidate)
    scores = [sc for sc in (_tested(e, w(x), err) for x in tests) if sc is not None and sc.separable]
    beside = min(scores, key=lambda sc: sc.logp, default=None)
    if beside is None or beside.logp >= math.log(level / len(tests)):
        return None
    sc = eng.score(w(place.candidate))
    if not sc.separable:
        return None
    return place.candidate, sc, place.why.format(F=f"{beside.F:.1f}", p=f"{math.exp(beside.logp):.2g}")


def _place_error(prep: Prepared, eng: Engine, place, w: Columns) -> tuple[Engine, stratum.PureError | None]:
    """The fit with the named members of ``place`` (places.Place), and the error term of every test at the place:
    the pure error of the stops its free form moves, repeated over the rounds (places.replicate_strata), pure of
    the fit, the named members and the free form (strata.pure_error); None where the free form is not a function
    of the stop or no stop is repeated (the fit's residual is the error term)."""
    e = eng.copy()
    e.add(np.hstack([w(x) for x in place.named]))
    strata = replicate_strata(prep, w.W, place.candidate.G)
    if not strata:
        return e, None
    full = e.copy()
    full.add(w(place.candidate))
    return e, stratum.pure_error(full, *strata)


def _tested(e: Engine, G: np.ndarray, err: stratum.PureError | None) -> Score | None:
    """The F test of the columns ``G`` beside the fit ``e`` against the error term ``err`` (strata.against), or
    against the fit's residual where there is none (Engine.score)."""
    return e.score(G) if err is None else stratum.against(e, G, err)


def _reversal_misfit(prep: Prepared, eng: Engine, axis: str, w: Columns, level: float) -> Score | None:
    """The free-form reversal of ``axis`` beyond every named reversal effect of the axis together (backlash and
    the angular reversals), when significant at ``level``; else None."""
    g = prep.geometry
    named = reversal_named(prep, axis)
    e = eng.copy()
    e.add(np.hstack([w(c) for c in named]))
    sc = lack_of_fit(prep, e, fx.reversal_free(g, axis), w)
    return sc if sc.separable and sc.logp < math.log(level) else None


def lack_of_fit(prep: Prepared, e: Engine, x: fx.Candidate, w: Columns) -> Score:
    """The score of the free form ``x`` beside the fit ``e`` (the named members of its place fitted): where ``x``
    is the same at each nest of a stop over the rounds (places.replicate_strata), the lack-of-fit F test against
    the replicates' variance components (strata.lack_of_fit; null: the named members are adequate, x adds no
    mean; error term: what a stop shares from round to round for a contrast between stops, the readings' own
    round x nest scatter for one between the nests of a stop; multiplicity: the caller's); else, or where no stop
    is read twice, the F test against the fit's residual (Engine.score)."""
    strata = replicate_strata(prep, w.W, x.G)
    sc = stratum.lack_of_fit(e, w(x), *strata) if strata else None
    return sc if sc is not None else e.score(w(x))


def inadequate_because(prep: Prepared, eng: Engine, c: fx.Candidate, w: Columns, level: float) -> str | None:
    """Why the effect ``c`` does not explain the misfit it fits, or None: the first of its place's free forms
    (_adequacy_checks, chosen by its grammar attributes) that is still needed beside it, in words.  Null of each
    check: ``c`` is adequate, the free form adds nothing beside it; alternative: it adds a mean; F test at
    ``level`` against the fit's residual (the stops' scatter for whole stops, _against_the_stops); the multiplicity
    is the candidate's (one check failing is enough to refuse the name, so no adjustment widens the refusal)."""
    for check in _adequacy_checks(c):
        why = check(prep, eng, c, w, level)
        if why:
            return why
    return None


def _adequacy_checks(c: fx.Candidate) -> list[Callable]:
    """The free forms of ``c``'s place that must not be needed beside it (inadequate_because), chosen by its grammar
    attributes (effects.Grammar), never its name: a member that moves whole stops is checked against them; a rigid
    shift at one moment against moving one sequence to its nest's last reading (_to_its_end); one depending on the
    direction of approach at an axis against the reversal free per reflector; a nest's step against its persisting;
    a step in time (t0) against going on growing; a gradual change alike at every pose (a side's or the tracker's
    translation, a side's expansion: Grammar.alike_at_every_pose) against a misfit growing with an axis' position;
    a periodic law against the free shape over the positions; a translation of one round against recurring in the
    other rounds (one reading) and against the other nests of its stops."""
    g = c.grammar
    checks: list[Callable] = [_against_the_stops]
    if g is None or g.free:
        return checks
    if g.jump:
        checks.append(_to_its_end)
    if g.where.at == "axis" and "direction" in g.how.on:
        checks.append(_reversal_differs)
    if g.where.at == "nest" and g.step:
        checks.append(_knock_does_not_persist)
    if g.where.at == "nest" and "time" in g.how.on:
        checks.append(_moves_with_the_pose)
    if "t0_s" in c.extra:
        checks.append(_knock_keeps_growing)
    if g.alike_at_every_pose and g.how.gradual:
        checks.append(_drift_grows_with_position)
    if g.how.law == "periodic":
        checks.append(_shape_beyond_period)
    if _one_round(g):
        checks += [_recurs_in_other_rounds] * (g.where.at == "reading") + [_shared_by_its_stops]
    return checks


def _one_round(g: fx.Grammar) -> bool:
    """A translation keyed by the round (an outlier, a bump, a re-seated reflector: some readings of one round)."""
    return g.what == "translation" and "round" in g.how.on


def _reversal_differs(prep: Prepared, eng: Engine, c: fx.Candidate, w: Columns, level: float) -> str | None:
    sc = _reversal_misfit(prep, eng, c.axis, w, level)
    return None if sc is None else (
        f"no reversal effect explains the direction-dependent misfit on {c.axis}: it differs between reflectors "
        f"beyond their signatures (free-form reversal per reflector: F = {sc.F:.1f}, p = {math.exp(sc.logp):.2g})")


def _shape_beyond_period(prep: Prepared, eng: Engine, c: fx.Candidate, w: Columns, level: float) -> str | None:
    sc = _significant_beside(eng, w(c), w(fx.by_position(prep.geometry, c)), level)
    return None if sc is None else (
        f"the error motion's misfit over the positions goes beyond the periodic error (the shapes beside it: "
        f"F = {sc.F:.1f}, p = {math.exp(sc.logp):.2g}): a shape of the error function, not a period")


def _to_its_end(prep: Prepared, eng: Engine, c: fx.Candidate, w: Columns, level: float) -> str | None:
    """Why a rigid shift at one moment (fx.Grammar.jump: a translation of one round, a step in time of a nest or of
    the tracker's frame) is not told from the others, or None: where the readings it moves are one sequence's (one
    nest in one axis' round) and run to that nest's last reading, no later reading shows whether the nest came back
    (displaced for a while) or stayed (knocked), nor whether the tracker or the nest moved -- the recording is
    censored there and they are the same columns.  None is named; the mismatch stays located (the nest in that
    round, from that time)."""
    on = c.moved
    g = prep.geometry
    if len(set(prep.seq[on].tolist())) != 1:
        return None
    point, side = str(g.point[on][0]), str(g.side[on][0])
    nest = (g.point == point) & (g.side == side)
    if prep.order[nest].max() > prep.order[on].max():
        return None
    return (f"the readings it moves are {point}'s ({side} side) to its last: no later reading shows whether the nest "
            "came back (displaced for a while) or stayed (knocked), or whether the tracker moved -- measure the nests "
            "again at the end of the campaign")


def _recurs_in_other_rounds(prep: Prepared, eng: Engine, c: fx.Candidate, w: Columns, level: float) -> str | None:
    # given the one-off displacement: else the base's share of it shows at those places
    sc = _same_way_beside(eng, w(c), w(fx.repeated(prep.geometry, c)), level)
    return None if sc is None else (
        f"the same displacement recurs at the same places in the other rounds (F = {sc.F:.1f}, "
        f"p = {math.exp(sc.logp):.2g}): a systematic pattern, not a one-off event")


def _shared_by_its_stops(prep: Prepared, eng: Engine, c: fx.Candidate, w: Columns, level: float) -> str | None:
    sc = _same_way_beside(eng, w(c), w(fx.same_stops(prep.geometry, c, prep.stop)), level)
    return None if sc is None else (
        f"the other nests read at the same stop(s) are displaced the same way (F = {sc.F:.1f}, "
        f"p = {math.exp(sc.logp):.2g}): the stop landed off or the tracker moved, not "
        + ("one reading" if c.grammar.where.at == "reading" else "the nest"))


NEIGHBOURS = 24  # readings of the station nearest in time either side of a displacement: its neighbours' stratum


def _within_its_scatter(prep: Prepared, eng: Engine, v: Step, w: Columns, level: float) -> str | None:
    """Why ``v``, a displacement of some readings of one nest in one round (a translation keyed by the round: an
    outlier, a bump, a re-seated reflector), is not told from the scatter it lies in, or None.  The split-plot F
    test: ``v`` is a contrast between its readings and those of its strata -- the nest's other readings on the
    axis (same reflector, station and axis), and the station's readings nearest in time (NEIGHBOURS, half before
    and half after) -- so each stratum's scatter is an error term: its 3 x 3 covariance (whitened residuals beside
    ``v``, scaled to what each reading displaced on its own explains, so the fit's share is not counted as
    scatter) as every one of the stratum's readings' own and ``v``'s (strata.against: F on Satterthwaite's degrees
    of freedom, the covariance's shape kept: a reflector scattering along the beam and not across it).  Null: the
    displaced readings scatter as the stratum's others; alternative: they are displaced beyond it.  ``v`` is
    named only where it is significant against each, at ``level`` over its own multiplicity (the same test,
    against these error terms); where the strata scatter as the law says this is the usual test.  A dirty or
    chipped reflector scatters beyond the law at every reading, a floor shaking makes every reading of a while
    scatter: against the law alone their largest readings were "outliers" and a round of the reflector
    "re-seated" (gen3's damaged_reflector: five outliers and an offset; floor_vibration: an outlier)."""
    c = v.candidate
    g = c.grammar
    rows = np.asarray(c.extra.get("rows", ()), int)
    if g is None or not _one_round(g) or not len(rows):
        return None
    geo, st = prep.geometry, np.asarray(prep.rec.stations())
    here = st == st[rows[0]]
    nest = (geo.point == geo.point[rows[0]]) & (geo.axis == geo.axis[rows[0]]) & here
    rank = np.argsort(np.argsort(np.where(here, prep.order, np.inf), kind="stable"), kind="stable")
    near = here & (rank >= rank[rows].min() - NEIGHBOURS // 2) & (rank <= rank[rows].max() + NEIGHBOURS // 2)
    for of, what in ((nest, "the other readings of its reflector"), (near, "the readings nearest it in time")):
        found = _against_scatter(eng, w(c), rows, np.setdiff1d(np.flatnonzero(of), rows))
        if found is None or found[0].logp + v.log_multiplicity < math.log(level):
            continue
        sc, between = found
        return (f"against the scatter of {what} (each displaced on its own, beside it: F = {between.F:.1f}, "
                f"p = {math.exp(between.logp):.2g}) it is not significant (F = {sc.F:.2g} on {sc.k} and {sc.dof} "
                f"degrees of freedom, p_adj = {min(1.0, math.exp(sc.logp + v.log_multiplicity)):.2g}): they scatter "
                "more than the law (a reflector dirty, chipped or weak; the stand shaking for a while), and such a "
                "scatter makes it as well")
    return None


def _against_scatter(eng: Engine, G: np.ndarray, rows: np.ndarray, others: np.ndarray
                     ) -> tuple[Score, Score] | None:
    """The F test of the whitened columns ``G`` (displacing the readings ``rows``) against the scatter of the
    readings ``others`` (_within_its_scatter's error term): (its score, the others' each displaced on its own
    beside G), or None where fewer than two others are left or either is not separable."""
    if len(others) < 2:
        return None
    e = eng.copy()
    e.add(G)
    between = e.score_blocks([(np.arange(3 * i, 3 * i + 3), np.eye(3)) for i in others])
    if not between.separable:
        return None
    R = e.r.reshape(-1, 3)[others]
    C = R.T @ R
    C *= 3.0 * (between.delta / between.k) / max(float(np.trace(C)), 1e-300)  # the fit's share left out
    units = [np.arange(3 * i, 3 * i + 3) for i in (*others, *rows)]
    sc = stratum.against(eng, G, stratum.PureError(C, np.zeros((3, 3)), C, between.k, len(others), 0, units,
                                                   e.rss / max(e.dof, 1)))
    return None if sc is None else (sc, between)


def _against_the_stops(prep: Prepared, eng: Engine, c: fx.Candidate, w: Columns, level: float) -> str | None:
    """Why ``c``, an effect that moves whole stops of a linear axis (places.stops_of), is not told from those stops
    landing off at random, or None.  The split-plot F test: ``c`` is a contrast between the stops, so its error
    term is their scatter -- its mean square over that of every stop landing off on its own beside it,
    F(k_c, k_stops); where the stops scatter no more than the tracker's noise, this is the usual test with fewer
    degrees of freedom in the denominator.  Where no stop is left to estimate their scatter (stops of the axis
    already located as landing off), ``c`` is not told from them.  Against the tracker's noise alone a backlash of
    stops that scatter 4.4 um each is "found" (gen2 seed 3542 campaign 30: X repeating worse in two rounds,
    backlash F = 17.5)."""
    free = stops_of(prep, c)
    if free is None:
        return None
    own = eng.score(w(c))
    if not own.separable:
        return None
    e = eng.copy()
    e.add(w(c))
    between = e.score(w(free))
    if not between.separable:  # the stops' free form is already fitted (stops located as landing off) but c's
        return (f"the stops of {c.axis} left beside it do not estimate their scatter (stops of the axis are "
                "located as landing off, and every other stop is taken by the base and by it): it is not told "
                "from the stops landing off at random (the axis repeating worse)")
    F = (own.delta / own.k) / (between.delta / between.k)
    p = float(_tails.f_sf(F, own.k, between.k))
    if p < level:
        return None
    return (f"against the scatter of the stops of {c.axis} (each stop landing off on its own, beside it: "
            f"F = {between.F:.1f}, p = {math.exp(between.logp):.2g}) it is not "
            f"significant (F = {F:.2g} on {own.k} and {between.k} degrees of freedom, p = {p:.2g}): the stops "
            "landing off at random (the axis repeating worse) make it as well")


def _stops_move_together(prep: Prepared, eng: Engine, v: Step, w: Columns, level: float) -> str | None:
    """Why a step of the tracker's frame (a knock, a re-levelling) or of a nest (a nest knock) is not told from its
    stops moving at random, or None: set against their own motion (_against_stops), it is not significant at
    ``level`` over the step's own multiplicity."""
    c = v.candidate
    if not _place_step(c):
        return None
    found = _against_stops(prep, eng, c, w(c), c.moved, v.score, _fitted_motion(prep, eng, c, w), w, level)
    if found is None or found[0] + v.log_multiplicity < math.log(level):
        return None
    return found[1]


def _against_stops(prep: Prepared, eng: Engine, c: fx.Candidate, G: np.ndarray, moved: np.ndarray, own: Score,
                   pattern: np.ndarray, w: Columns, level: float) -> tuple[float, str] | None:
    """A step of the place of ``c`` (its station's frame or its nest) -- whitened columns ``G`` on ``eng``
    (``own``: their score there) that move the readings ``moved`` (bool (n,)) -- set against its stops' own motion:
    (its log p there, the words for a step not significant so), or None where its usual test holds.

    A frame's step between whole stops is a contrast between them, so its error term is their scatter: the
    split-plot F test of its mean square over that of every stop moving on its own the way the step moves it
    (``pattern``, (n, 3) mm: the step's fitted motion at every reading; _split_plot), F(k, k_stops).  icelinker's
    replica (tests/test_real_icelinker.py: the three reflectors moving together 8 um / 4 urad from pose to pose,
    no knock) had tracker knocks named at F = 11.6 (seed 7, p_adj 2e-3), 3.6e-5 against the poses' motion, 0.4
    with the scan's multiplicity.  A step that splits a stop is not such a contrast (None).

    A nest's step, where the stops that read the nest move rigidly beyond the noise (each stop's translation and
    turn, places.stops_rigid, significant beside it at ``level``), is the nest's own only by its share that
    changes the stops' layout: its F test beside every stop's rigid motion (Engine.score_beside_blocks; its error
    the stops' residual layout, which their motion does not touch).  A nest moved at right angles to the line
    through two others is, to first order, the three turning about that line: icelinker's base_2 "knocked" at
    pose 595 (the base moving from pose to pose 9 times the noise), its mutual distances moving -0.7 +- 0.4,
    -0.3 +- 0.8 and +1.2 +- 0.8 um over poses 573-594 against the 40 either side."""
    if _frame_step(c):
        found = _split_plot(prep, eng, G, own, pattern, w) if _whole_stops(prep, moved) else None
        if found is None:
            return None
        F, logp, between = found
        return logp, (f"against the stops moving together at random (each stop moving on its own as the step moves "
                      f"it, beside it: F = {between.F:.1f}, p = {math.exp(between.logp):.2g}) it is not significant "
                      f"(F = {F:.2g} on {own.k} and {between.k} degrees of freedom, p = {math.exp(logp):.2g} before "
                      "its multiplicity): the readings of each stop move together from one stop to the next (a robot "
                      "or the machine moving the side, the tracker disturbed), and such a motion makes the step as "
                      "well")
    blocks = stops_rigid(prep, w.W, step_rows(prep, c))
    e = eng.copy()
    e.add(G)
    moving = e.score_blocks(blocks)
    if not moving.separable or moving.logp >= math.log(level):
        return None
    sc = eng.score_beside_blocks(G, blocks)
    return (sc.logp if sc.separable else 0.0), (
        f"beside its stops moving rigidly at random (each stop's translation and turn: F = {moving.F:.1f}, "
        f"p = {math.exp(moving.logp):.2g}) it is not significant"
        + (f" (F = {sc.F:.2g}, p = {math.exp(sc.logp):.2g} before its multiplicity)" if sc.separable else "")
        + ": it does not change the layout of the nests read with it, and the stops tilting or shifting from one to "
        "the next make it as well")


def _frame_step(c: fx.Candidate) -> bool:
    """Whether ``c`` is a step of a station's frame (its grammar: where the frame, how a step in time): a tracker
    knock or a re-levelling."""
    return c.grammar is not None and c.grammar.where.at == "frame" and c.grammar.step


def _place_step(c: fx.Candidate) -> bool:
    """Whether ``c`` is a step of a place: of a station's frame (_frame_step) or of a nest (a nest knock)."""
    return c.grammar is not None and c.grammar.where.at in ("frame", "nest") and c.grammar.step


def _whole_stops(prep: Prepared, moved: np.ndarray) -> bool:
    """Whether the readings ``moved`` (bool (n,)) are whole stops (Prepared.stop), none in part."""
    return not np.any(np.bincount(prep.stop, moved) % np.bincount(prep.stop))


def _split_plot(prep: Prepared, eng: Engine, G: np.ndarray, own: Score, pattern: np.ndarray, w: Columns
                ) -> tuple[float, float, Score] | None:
    """The split-plot F test of a step of a station's frame (whitened columns ``G``), a contrast between whole
    stops: its mean square on ``eng`` (``own``: its score there) over that of every stop moving on its own the way
    the step moves it (``pattern``: places.stop_motions, Engine.score_blocks): (F, its log p, the stops' motion's
    score); None where either is not separable.  The step's direction is read from the data, so it keeps its own
    degrees of freedom; against the stops' scatter along that direction the test is conservative (Hotelling's T^2
    takes the scatter in every direction)."""
    e = eng.copy()
    e.add(G)
    between = e.score_blocks(stop_motions(prep, w.W, pattern))
    if not (own.separable and between.separable) or between.delta <= 0:
        return None
    F = (own.delta / own.k) / (between.delta / between.k)
    return F, float(_tails.f_logsf(F, own.k, between.k)), between


BACK = 0.5  # two steps come back when what is left after both is less than this share of the motion between them


def _change_points(prep: Prepared, eng: Engine, v: Step, w: Columns, level: float
                   ) -> tuple[str, list[tuple[fx.Candidate, Score] | None]] | None:
    """What a step of a place -- a station's frame (a knock, a re-levelling) or a nest (a nest knock) -- is, read
    from its place's one change-point search (scans.change_points over k = 1, 2, ... steps of the place's own
    motion, places.place_motion, each amplitude free, from ``v``'s step on; each further change point at ``level``
    over the change points scanned for it, against the stops' own motion where it moves whole stops,
    _against_stops; then the place's smooth path, places.frame_path / nest_path, beside the steps found): the
    words for why it is not one step and the free forms of its place that may stand instead (with their scores on
    ``eng``), or None where the search reads one step (k-hat = 1, no drift).

    * a drift instead of steps (the smooth path still needed beside the k-hat steps): the place moving smoothly,
      the steps sampling it where it moved most (and, for a frame, its stops landing off, _knock_stops);
    * k-hat = 2 and less than BACK of the motion between the two change points left after them: the place
      displaced for a while and back (places.bump: a nest bumped and re-seated, a side tilted for a while);
    * k-hat >= 3: the place stepping again and again (places.unsteady; for a frame, or its stops landing off);
    * k-hat = 2 not coming back: the first step stands; the second is tested afresh by the forward selection, and
      the steps selected at one place are read together at the end (steps_per_place).

    icelinker's replica (tests/test_real_icelinker.py): a frame or a nest wandering smoothly had one to four
    knocks named; base_2 64 um off for poses 101-125, knocked at 101 and again, back, at 126."""
    c = v.candidate
    if not _place_step(c):
        return None
    pattern = _fitted_motion(prep, eng, c, w)
    path = frame_path(prep, c) if _frame_step(c) else nest_path(prep, c)

    def against(e: Engine, X: np.ndarray, later: np.ndarray, sc: Score) -> float | None:
        on = np.zeros(len(pattern), bool)
        on[later] = True
        found = _against_stops(prep, e, c, X, on, sc, pattern, w, level)
        return found[0] if found else None

    G = place_motion(prep, c)
    cp = change_points(prep, eng, step_rows(prep, c), G, level, given=[c.moved], against=against, smooth=path.G)
    if cp.drift is not None:
        what = "the tracker's frame" if _frame_step(c) else f"the nest of {c.extra['point']}"
        return (f"{what} moves smoothly beyond {cp.k} step(s) of it (a smooth path in the order of the readings "
                f"beside them: F = {cp.drift.F:.2g}, p = {math.exp(cp.drift.logp):.2g}): a drift or wander, not "
                "steps", [_knock_stops(prep, eng, v, w), _path(prep, eng, v, w, path)])
    if cp.k == 2:
        return _back(prep, eng, c, G, cp, w)
    if cp.k < 3:
        return None
    steps = _steps_of(prep, c, G, cp)
    free = unsteady(steps)
    return (f"its place steps {cp.k} times (each change point at p_adj < {level:g} over those scanned for it): "
            "not one step", [_knock_stops(prep, eng, v, w), (free, eng.score(w(free)))])


def _back(prep: Prepared, eng: Engine, c: fx.Candidate, G: np.ndarray, cp, w: Columns
          ) -> tuple[str, list[tuple[fx.Candidate, Score]]] | None:
    """_change_points' reading of k-hat = 2 steps of the place of ``c`` (its motion per parameter ``G``): where less
    than BACK of the motion between the two change points is left after both, the words and the place displaced
    for a while and back (places.bump, with its score on ``eng``); else None (the step stands)."""
    motion = [np.linalg.norm(np.einsum("nij,j->ni", G, t)) for t in (cp.theta.sum(axis=0), *cp.theta)]
    moved = [np.isin(np.arange(len(G)), r) for r in cp.rows]
    between = motion[1] if moved[0].sum() >= moved[1].sum() else motion[2]  # the earlier step's motion
    if motion[0] >= BACK * between:
        return None
    back = bump(prep, c, moved[0] ^ moved[1])
    return (f"a second step of its place takes it back ({motion[0] / between:.0%} of it left after; p = "
            f"{math.exp(cp.logp_adj[1]):.2g} over {cp.scanned[1]} change points): displaced for a while and back, "
            "not a step that stays", [(back, eng.score(w(back)))])


def _steps_of(prep: Prepared, c: fx.Candidate, G: np.ndarray, cp) -> list[fx.Candidate]:
    """The change points ``cp`` of the place of the step ``c`` (its motion per parameter ``G``) as steps, in time
    order: each ``c``'s columns switched on from its t0 (its ``extra`` with that t0)."""
    out = []
    for rows, t0 in sorted(zip(cp.rows, cp.t0), key=lambda x: x[1]):
        X = np.zeros_like(G)
        X[rows] = G[rows]
        first = rows[np.argmin(prep.order[rows])]
        out.append(fx.Candidate(c.name, c.axis, c.label, X, c.params, family=c.family, extra={
            **c.extra, "t0_s": float(t0), "from_axis": str(prep.rec.axis[first]), "round": int(prep.rec.round[first])}))
    return out


def _fitted_motion(prep: Prepared, eng: Engine, c: fx.Candidate, w: Columns) -> np.ndarray:
    """(n, 3) mm: the motion the step ``c``, fitted on ``eng``, gives every reading of its place
    (places.step_pattern)."""
    Gc = w(c)
    theta, *_ = np.linalg.lstsq(Gc - eng.project(Gc), eng.r, rcond=None)
    return step_pattern(prep, c, theta)


def _path(prep: Prepared, eng: Engine, v: Step, w: Columns, path: fx.Candidate | None = None
          ) -> tuple[fx.Candidate, Score]:
    """The free form ``path`` (by default the frame of the station of ``v``'s step moving smoothly,
    places.frame_path) and its score on ``eng``."""
    path = path or frame_path(prep, v.candidate)
    return path, eng.score(w(path))


def _significant_beside(eng: Engine, Gc: np.ndarray, G: np.ndarray, level: float) -> Score | None:
    """The score of the whitened columns ``G`` beside ``Gc`` (both fitted on ``eng``) when significant at
    ``level``; else None."""
    with_it = eng.copy()
    with_it.add(Gc)
    sc = with_it.score(G)
    return sc if sc.separable and sc.logp < math.log(level) else None


def _same_way_beside(eng: Engine, Gc: np.ndarray, G: np.ndarray, level: float) -> Score | None:
    """_significant_beside, when ``G`` also moves the readings the same way as ``Gc`` (their joint estimates' dot
    product > 0); else None."""
    sc = _significant_beside(eng, Gc, G, level)
    if sc is None:
        return None
    A = np.hstack([Gc, G])
    theta, *_ = np.linalg.lstsq(A - eng.project(A), eng.r, rcond=None)
    k = Gc.shape[1]
    return sc if theta[:k] @ theta[k:] > 0 else None


def _knock_does_not_persist(prep: Prepared, eng: Engine, c: fx.Candidate, w: Columns, level: float) -> str | None:
    """Why a knocked nest is not one, or None: its displacement must persist beyond the sequence (axis, round,
    reflector) it starts in, in the same direction (else a one-off reading or a bump fits it, and a second "knock"
    would step the nest back)."""
    on = c.moved
    first = prep.seq[np.flatnonzero(on)[np.argmin(prep.order[on])]]
    late = on & (prep.seq != first)
    if not late.any():
        return "displaced within one sequence only: a one-off reading or a bump, not a knock"
    Gc, Gl = w(c), w(fx.Candidate(c.name, c.axis, "", c.G * late[:, None, None], c.params))
    sc = eng.score(Gl)
    if not (sc.separable and sc.logp < math.log(level)):
        return (f"the displacement does not persist after the readings where it starts (the later readings alone: "
                f"F = {sc.F:.1f}, p = {math.exp(sc.logp):.2g}): a one-off reading or a bump, not a knock")
    t_all, t_late = (np.linalg.lstsq(G - eng.project(G), eng.r, rcond=None)[0] for G in (Gc, Gl))
    if t_all @ t_late <= 0:
        return "the later readings are displaced the other way: a one-off reading or a bump, not a knock"
    return None


POSE_DEGREE = 2  # the smooth member of a nest's displacement with the pose: a quadratic in each axis' position


def _moves_with_the_pose(prep: Prepared, eng: Engine, c: fx.Candidate, w: Columns, level: float) -> str | None:
    """Why a nest's motion in time (a step, a creep) is not one, or None: with it fitted, the nest's own
    displacement with the pose of the machine (the same in every round and either direction: fx.by_pose, free at
    each pose, and its sharper member smooth in each axis' position, POSE_DEGREE; Bonferroni over the two) must
    not be needed beside it.  A motion in time moves the nest whatever the pose; a reflector whose apparent
    centre depends on how it faces the beam, or a side sagging with the pose, moves with the pose in every round,
    before the "step" too.  Nor, read from several stations, may the nest's translation per station
    (fx.by_station) explain the motion as well: the motion must still be needed beside it (F test at ``level``) --
    the stations are read one after another, so a nest seen differently from each station moves in time too, and
    the data do not tell which (gen3 1013/20: a reflector reading long with its incidence, from three stations,
    was named creeping)."""
    g, x = prep.geometry, c.extra
    forms = fx.by_pose(g, x["point"], x["side"], POSE_DEGREE)
    found = [sc for sc in (_significant_beside(eng, w(c), w(f), level / len(forms)) for f in forms)
             if sc is not None]
    sc = min(found, key=lambda s: s.logp, default=None)
    if sc is not None:
        return (f"the nest's displacement changes with the machine's pose, the same in every round (a translation "
                f"with the pose beside it: F = {sc.F:.1f}, p = {math.exp(sc.logp):.2g}): the reflector seen "
                "differently at each pose, or its side bending with the pose, not moving with time")
    per_station = fx.by_station(g, x["point"], x["side"])
    if per_station is None:
        return None
    with_it = eng.copy()
    with_it.add(w(per_station))
    own = with_it.score(w(c))
    return None if own.separable and own.logp < math.log(level) else (
        f"its motion is as well the nest read differently from each station (beside a translation of the nest per "
        f"station it adds F = {own.F:.1f}, p = {math.exp(own.logp):.2g}): the reflector facing each station's beam "
        "at its own angle, or moving with time -- measure the nest from the first station again at the end")


def _drift_grows_with_position(prep: Prepared, eng: Engine, c: fx.Candidate, w: Columns, level: float
                               ) -> str | None:
    """Why a gradual change alike at every pose (a drift of a side or of the tracker, a side's expansion:
    fx.Grammar.alike_at_every_pose) is not one, or None: with it fitted, no misfit may grow with the position of an
    axis it moves while that axis is measured (the linear member of the axis' error motions changing with time,
    fx.growing_free; F test at ``level`` over the axes tested).  A drift moves every reading of its side alike at
    one time, and an expansion each nest alike, whatever the position; a scale or straightness growing while the
    axis is measured (a ball screw warming, no temperature channel) it absorbs only in part (gen2 seed 17: growing
    scales of X named drifts of the spindle), and so does a side turning with time (a column tilting: gen3 1015/41,
    an expansion about a centre fitted 11 m away)."""
    g, rec = prep.geometry, prep.rec
    moved = c.moved
    axes = [a for a in prep.axes if (moved & (g.axis == a)).any() and np.isfinite(g.time_s[g.axis == a]).all()
            and len(set(rec.round[g.axis == a].tolist())) >= 2]
    for a in axes:
        sc = _significant_beside(eng, w(c), w(fx.growing_free(g, a, full=False)), level / len(axes))
        if sc is not None:
            return (f"a misfit growing with the position of {a} while it is measured is left beside it (F = "
                    f"{sc.F:.1f}, p = {math.exp(sc.logp):.2g}): an error motion of {a} changing with time, not a "
                    "change of the whole side alike")
    return None


def _knock_keeps_growing(prep: Prepared, eng: Engine, c: fx.Candidate, w: Columns, level: float) -> str | None:
    """Why a knock is no step, or None: with the step fitted, its displacement must not go on growing after t0
    through the axis block it falls in (the same columns times the time since t0, over that block's later
    readings; F test at ``level``, the same direction as the step).  A drift, or an error motion growing while
    the axis is measured, seen from a reference position that is not its zero, is such a ramp."""
    rec, t0 = prep.rec, c.extra["t0_s"]
    on = c.moved
    first = np.flatnonzero(on)[np.argmin(rec.time_s[on])]
    block = on & (rec.axis == rec.axis[first])
    t = rec.time_s[block]
    if block.sum() < 3 or np.ptp(t) <= 0:
        return None
    ramp = np.zeros(len(rec))
    ramp[block] = (rec.time_s[block] - t0) / np.ptp(t)
    sc = _same_way_beside(eng, w(c), w(fx.Candidate(c.name, c.axis, "", c.G * ramp[:, None, None], c.params)),
                          level)
    if sc is None:
        return None
    return (f"the displacement goes on growing after t0 through axis {rec.axis[first]} (a ramp beside the step: "
            f"F = {sc.F:.1f}, p = {math.exp(sc.logp):.2g}): a gradual change (a drift, or an error motion growing "
            "while the axis is measured), not a knock")


def _absorbed(eng: Engine, best: Step, v: Step, w: Columns, level: float) -> bool:
    """A rival ``v`` significant before ``best`` was added (to ``eng``), no longer significant after it, with
    evidence of the same order (log p at least half of best's): the campaign cannot tell the two apart."""
    if not v.score.logp <= RIVAL_LOGP_SHARE * best.score.logp:
        return False
    sc = eng.score(w(v.candidate))
    return not (sc.separable and sc.logp + v.log_multiplicity < math.log(level))


def _rival(c: fx.Candidate, o: fx.Candidate) -> bool:
    """Whether ``o`` may be reported as confounded with the selected ``c``: members of the grammar with each other,
    and a member with a free form that changes with time (an axis' error motions changing while measured: a named
    effect that absorbs it may be that instead); never a free form selected itself, nor one constant in time (the
    reversal's free form holds its axis' reversal members: place_needed weighs it)."""
    return not c.free and (not o.free or o.grammar is not None and o.grammar.varies_in_time)


def _confound(c: fx.Candidate, v: Step, cos: float) -> dict:
    o = v.candidate
    return {"name": o.name, "axis": o.axis, "where": o.label, "overlap_cos": cos,
            "p_adjusted": min(1.0, math.exp(v.logp_adj)), "separate_by": separate_by(c, o)}


GROWING_SHARE = 0.8  # a change in time changing this much (whitened, beside the base) within one axis' block


def growing_confounds(prep: Prepared, eng: Engine, steps: list[Step], w: Columns) -> None:
    """A translation of a side or of the tracker changing with time (its grammar) whose change falls within the
    block of one axis (GROWING_SHARE of its columns beside the base: the base's per-axis positions take what stays
    constant after it) cannot be told from that axis' error motions changing with time as seen from its reference
    position (the base's error functions vanish there, so their growth there moves every reading of the axis
    alike).  Where such a free form of that axis (depending on the position and the time) is also selected, the
    change lists it in ``confounded_with`` (gen2 seed 17: a scale of X growing while X is measured, from a
    reference position away from its zero, came out as the growth and a drift)."""
    grow = {s.candidate.axis: s for s in steps if s.candidate.grammar is not None and s.candidate.grammar.free
            and s.candidate.grammar.how.on >= {"position", "time"}}
    n, base = len(prep.rec), eng.copy_base()
    for s in (s for s in steps if grow and _moves_in_time(s.candidate)):
        G = w(s.candidate)
        e = np.sum((G - base.project(G)).reshape(n, 3, -1) ** 2, axis=(1, 2))
        for a, g in grow.items():
            share = float(e[prep.rec.axis == a].sum() / e.sum())
            if share > GROWING_SHARE and all((c["name"], c.get("axis")) != (g.candidate.name, a)
                                             for c in s.confounded_with):
                s.confounded_with.append({**_confound(s.candidate, g, 0.0), "overlap_cos": None,
                                          "share_in_block": share})


def _moves_in_time(c: fx.Candidate) -> bool:
    """A member translating a side or the tracker's frame with time."""
    g = c.grammar
    return not c.free and g.what == "translation" and g.where.at in ("side", "frame") and "time" in g.how.on


def untested_confounds(steps: list[Step], notes: list[dict]) -> None:
    """Where a member could not be tested because the data do not locate its place (a note carrying the member's
    grammar, ``untested``: the air's drift about a station that is not determined or not placed at all,
    mtcal.diagnose.candidates.air_index_drift), a selected gradual translation of a side or of the tracker with
    the same dependence (its grammar) lists it in ``confounded_with``: an expansion about a place the data do not
    locate is, to first order, a translation along the unknown direction with a remainder too small to tell apart
    (gen2 seed 9000 campaign 2, B and C from one station, the tracker columns removed: a 4.6 ppm ramp of the air
    came out as a drift of the table alone; seed 3537 campaign 12, an isotropic tracker whose rounds show no shape
    to place it: a 5 ppm ramp a drift of the tracker)."""
    for nt in (nt for nt in notes if "untested" in nt):
        g = nt["untested"]
        other = fx.Candidate(nt["name"], nt["axis"], nt["where"], np.zeros((0, 3, 0)), [], grammar=g)
        for s in steps:
            c = s.candidate
            if (_moves_in_time(c) and c.grammar.how.gradual and c.grammar.how.on == g.how.on
                    and all(o["name"] != nt["name"] for o in s.confounded_with)):
                s.confounded_with.append({"name": nt["name"], "axis": nt["axis"], "where": nt["where"],
                                          "overlap_cos": None, "p_adjusted": None, "why": nt["not_separable"],
                                          "separate_by": separate_by(c, other)})


def backward(eng: Engine, selected: list[Step], w: Columns, level: float,
             say: Callable[[str], None]) -> list[Step]:
    """Drop a selected effect that the others have made insignificant -- unless a LATER, smaller effect that
    overlaps it took its signal and dropping that one leaves less misfit: then the later effect goes and is
    reported as confounded with the kept one (a large effect is never lost to a smaller overlapping one)."""
    selected = list(selected)
    while len(selected) > 1:
        worst = None
        for j, s in enumerate(selected):
            e = with_steps(eng, [o for i, o in enumerate(selected) if i != j], w)
            s2 = e.score(w(s.candidate))
            lp2 = (s2.logp + s.log_multiplicity) if s2.separable else 0.0
            if worst is None or lp2 > worst[1]:
                worst = (j, lp2)
        if worst[1] < math.log(level):
            break
        j = worst[0]
        kept = selected[j]
        # a later, overlapping, smaller effect may have taken j's signal: drop whichever leaves the least misfit
        rss_j = with_steps(eng, selected[:j] + selected[j + 1:], w).rss
        later = [(with_steps(eng, selected[:i] + selected[i + 1:], w).rss, i) for i, o in enumerate(selected)
                 if i > j and o.score.delta < kept.score.delta
                 and eng.copy_base().overlap(w(kept.candidate), w(o.candidate)) > 0.5]
        rss_o, i = min(later, default=(float("inf"), -1))
        if rss_o < rss_j:
            gone = selected.pop(i)
            cos = eng.copy_base().overlap(w(kept.candidate), w(gone.candidate))
            kept.confounded_with.append(_confound(kept.candidate, gone, cos))
            say(f"backward: {gone.candidate.name} {gone.candidate.label} dropped: it overlaps "
                f"{kept.candidate.name} (cos {cos:.2f}), which explains more")
        else:
            gone = selected.pop(j)
            say(f"backward: {gone.candidate.name} {gone.candidate.axis or ''} {gone.candidate.label} dropped "
                f"(explained by the other effects)")
    return selected


def steps_per_place(steps: list[Step], say: Callable[[str], None]) -> list[Step]:
    """``steps`` with the steps selected at one place (a station's frame: knocks, re-levellings; one nest), where
    there are several, replaced by one free form of them together (mtcal.diagnose.places.unsteady), with the
    strongest one's evidence.  The forward selection is the place's change-point search continued (each step
    entered at the level over the change points scanned for it: scans.change_points' penalty); k-hat >= 2 steps
    of one place that did not come back when the second was tested (_change_points) read as the place stepping
    again and again, not as one knock after another (gen2 seed 3505 campaign 7: Y repeating worse, 3 um per
    stop, was two knocks 210 s apart in Y's second round, +3.3 um then -7.0 um along Y)."""
    places: dict[tuple, list[Step]] = {}
    for s in steps:
        c = s.candidate
        if _place_step(c):
            key = ("frame", c.extra.get("station")) if _frame_step(c) else (c.extra["point"], c.extra["side"])
            places.setdefault(key, []).append(s)
    out = list(steps)
    for group in (g for g in places.values() if len(g) > 1):
        free = unsteady(sorted((s.candidate for s in group), key=lambda c: c.extra["t0_s"]))
        strong = min(group, key=lambda s: s.logp_adj)
        say(f"{len(group)} steps at one place: {free.label}")
        out = [s for s in out if all(s is not k for k in group)] + [Step(free, strong.score, strong.logp_adj)]
    return out


def with_steps(eng: Engine, steps: Sequence[Step], w: Columns) -> Engine:
    """``eng``'s base with the columns of ``steps`` added (a new engine)."""
    e = eng.copy_base()
    for s in steps:
        e.add(w(s.candidate))
    return e


def select_degrees(prep: Prepared, wy: np.ndarray, largest: dict[str, int], say: Callable[[str], None],
                   effects: Sequence[np.ndarray] = ()) -> dict[str, int]:
    """Per axis, the degree (1..``largest[axis]``, design.family_degrees) with the least BIC of the axis' own
    whitened fit, with the whitened columns ``effects`` (N, k) of the selected effects in the fit (restricted to
    the axis' readings): an unmodelled effect (backlash) inflates the residual and would make BIC choose too low
    a degree."""
    out = {}
    for a in prep.axes:
        on = prep.rec.axis == a
        G = None
        if len(effects):
            G = np.hstack(effects)[np.repeat(on, 3)]
            G = G[:, np.any(G != 0, axis=0)]
        best = None
        for d in range(1, largest[a] + 1):
            e = engine_for(prep, base_design(prep, {a: d}, [a]), wy, on)
            if G is not None and G.shape[1]:
                e.add(G)
            bic = e.N * math.log(e.rss / e.N) + e.p * math.log(e.N)
            if best is None or bic < best[0]:
                best = (bic, d)
        out[a] = best[1]
        say(f"axis {a}: degree {best[1]} by BIC" + (" (with the selected effects)" if G is not None else ""))
    return out


def folds(prep: Prepared, c: fx.Candidate) -> tuple[list[np.ndarray], str]:
    """Held-out reading sets (bool (n,)) of the validation of ``c`` and their description."""
    rec = prep.rec
    touched = c.moved
    rounds = sorted(set(rec.round[touched].tolist()))
    if not (c.grammar is not None and c.grammar.varies_in_time) and len(rounds) >= 2:
        return [rec.round == k for k in sorted(set(rec.round.tolist()))], "held-out rounds"
    if touched.sum() < 2:
        return [], "one reading: tested by its studentized displacement only"
    # every sequence one reading (a pose a round, each nest read once in it: icelinker): alternate readings of each
    # nest over the rounds instead, else one fold would hold every reading and the other none
    single = np.bincount(prep.seq).max() < 2
    of = prep.seq
    if single:
        _, of = np.unique([f"{s}|{a}|{p}" for s, a, p in zip(rec.stations(), rec.axis, rec.point)],
                          return_inverse=True)
    rank = np.empty(len(rec), int)
    for s in range(of.max() + 1):
        idx = np.flatnonzero(of == s)
        rank[idx[np.argsort(prep.order[idx], kind="stable")]] = np.arange(len(idx))
    return [rank % 2 == 0, rank % 2 == 1], ("held-out alternate rounds of each nest (one reading a sequence)"
                                            if single else "held-out alternate readings")


def cv_gain(prep: Prepared, base: Base, wy: np.ndarray, others: list[np.ndarray], G: np.ndarray,
            held: list[np.ndarray], why: list[str] | None = None) -> float | None:
    """1 - RSS_with / RSS_without on held-out readings: the effects (others + G) estimated on the rest, applied to
    the held-out readings after the base model (all its parameters) is fitted to them alone; "without" uses the
    others only.  A fold where G cannot be estimated (not separable on the training readings) or where the base
    leaves no residual is skipped; None when no fold is usable (and why, appended to ``why``)."""
    skipped = Counter()
    with_, without = 0.0, 0.0
    used = False
    for te in held:
        tr = ~te
        if not te.any() or not tr.any():
            skipped["the fold holds every reading or none"] += 1
            continue
        r3tr, r3te = np.repeat(tr, 3), np.repeat(te, 3)
        e_tr, e_te = engine_for(prep, base, wy, tr), engine_for(prep, base, wy, te)
        if e_te.rss <= 0 or e_tr.dof <= 0:
            skipped["the base leaves no residual on the held-out readings (each fold's base fitted alone)"
                    if e_te.rss <= 0 else "the base has no degrees of freedom left on the training readings"] += 1
            continue
        res = {}
        for tag, cols in (("with", others + [G]), ("without", others)):
            if not cols:
                res[tag] = e_te.rss
                continue
            Gall = np.hstack(cols)
            Gtr = Gall[r3tr]
            if not e_tr.score(Gtr[:, -G.shape[1]:] if tag == "with" else Gtr).separable:
                skipped["the effect is not separable from the base on the training readings"] += 1
                break
            theta, _ = e_tr.estimate([Gtr])
            pred = Gall[r3te] @ theta
            if tag == "with" and _absorbed_on(e_te, Gall[r3te][:, -G.shape[1]:] @ theta[-G.shape[1]:]):
                skipped["the base fitted to the held-out readings alone takes the whole effect"] += 1
                break
            rr = e_te.r - (pred - e_te.project(pred[:, None])[:, 0])
            res[tag] = float(rr @ rr)
        if len(res) < 2:
            continue
        used = True
        with_ += res["with"]
        without += res["without"]
    if not used or without <= 0:
        if why is not None:
            why.append(f"no held-out gain: in {sum(skipped.values())} of {len(held)} folds "
                       + "; ".join(f"{k} ({v})" for k, v in skipped.items()) if skipped else
                       "no held-out gain: the held-out folds leave no residual")
        return None
    return 1.0 - with_ / without


ABSORBED = 1e-6  # what the held-out base leaves of an effect's prediction, relative to it: rounding, not a gain


def _absorbed_on(e: Engine, pred: np.ndarray) -> bool:
    """Whether the base fitted on held-out readings (``e``) takes the whole of an effect's prediction ``pred``
    (whitened, their rows) to rounding: the fold cannot show a gain either way.  A station's tracker scale on a
    held-out round of one linear axis is a translation and that axis' linear positioning error there (exactly, with
    the nominal lever arms), and its "gain" of 1e-5 came from the readings' noise in the lever arms."""
    size = float(np.linalg.norm(pred))
    return size == 0 or float(np.linalg.norm(pred - e.project(pred[:, None])[:, 0])) <= ABSORBED * size


def beside_a_mismatch(prep: Prepared, eng: Engine, steps: Sequence[Step], effects: list, left: list,
                      w: Columns) -> None:
    """Withdraw a name that does not lead, as the explanation of its readings, the mismatch still located among them.
    ``left``: the located scan after the effects (scans.locate on ``eng``, the tests' null with every step; beyond
    the family's shapes), every group it locates (before scans.one_at_a_time keeps those still located beside the
    ones before them: a group the misfit leaks into is a rival too). For a significant finding whose readings
    (``touched``) hold located mean shifts, the rival is their free form -- a translation of each such group's
    readings -- fitted instead of the finding beside the base and the other steps; the finding keeps its name only
    where its lead over that rival (_lead: the chi^2 reductions' difference in the residual variance, less Akaike's
    penalty for the difference in columns) is at least TIE_CHI2, the likelihood ratio of 100 the ties are named by.
    Null: the name explains its readings at least as well as the located free form beside it; the decision is a
    stated evidence ratio, not a test, so no multiplicity enters. A constant backlash with one stop not approached
    in its direction keeps its name (it leads the stop's translation by thousands); a quadratic of a rotary axis
    beside that axis' nests displaced position by position (a tracker's cyclic distance error) gives way. A spread
    left among the readings (a reflector or an axis scattering more than the law) is a variance, which no mean
    effect is asked to explain. The withdrawn name stays in ``effects``, not significant, ``inadequate`` saying why;
    the located entries stand."""
    for f in effects:
        if not f.significant or f.touched is None or f.candidate is None:
            continue
        here = [u for u in left if u.kind == "mean" and u.rows is not None and len(u.rows)
                and f.touched[u.rows].any()]
        step = next((x for x in steps if x.candidate is f.candidate), None)
        if not here or step is None:
            continue
        others = with_steps(eng, [x for x in steps if x is not step], w)
        own, rival = others.score(w(f.candidate)), others.score(translations(prep.W, [u.rows for u in here]))
        lead = _lead(others, Step(f.candidate, own, step.logp_adj), rival) if rival.separable else math.inf
        if lead < TIE_CHI2:
            f.significant = False
            f.details["inadequate"] = (
                f"the mismatch located among the readings it moves (axis {here[0].axis} by {here[0].by}"
                + (f", and {len(here) - 1} more" if len(here) > 1 else "") + ") explains them as well as it does "
                f"(its lead over them {lead:.1f}, below {TIE_CHI2:.1f}: a likelihood ratio of 100): reported "
                "where it is located, not named")
