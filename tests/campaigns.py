"""Planted campaigns for the diagnosis proof (issue 13): an independent generator of small laser-tracker campaigns
of varied design, made by the physical simulator (mtcal.campaign.simulate: effects as physics through the exact
error-inclusive kinematics, AT960 noise), seeded, with the truth.  It never uses the diagnosis' signatures.

Design (``Design``): station in front of the machine, at the side or far (placed here from the machine's travel,
not from the spec's named stations, jittered by the seed), 3 to 6 rounds, five axes or three, 5 to 9 positions
per axis (small: a diagnosis takes about a second), and whether the diagnosis is told the tracker position
(``Campaign.tracker`` is then the position to pass as ``--tracker`` / ``tracker=``; None = not told; the
recording has no tracker columns in either case).

API:
* ``make(design, effects, seed, *, model=None, reference=None, positions=None, temperature=None, name="")``
  -> Campaign: one campaign with the planted effects (mtcal.campaign.effects names and parameters);
* ``random_design(rng, machine="dmu50", need=())`` -> Design: a varied design (``need``: axes that must be in);
* ``clean(seed, machine="dmu50")`` -> Campaign: a varied design, nothing planted (false-positive rate);
* ``planted(seed, machine="dmu50")`` -> Campaign: a varied design with one or two effects drawn from ``POOL``;
* ``CASES`` {name: builder(seed) -> Campaign}: the cases of the issue (C location with the reference model given,
  a knock overlapping it, C location of the axis measured last vs a knock at its start, a real warm-up with a
  temperature channel, direction-dependent pitch, an aliased pitch, a creeping nest, periodic X, tracker scale).

``Campaign.expect``: what a right answer contains, [{"name": effect name (docs/design.md / mtcal.campaign.effects),
"axis": ...,
"error": ..., "alternatives": [names that are an acceptable "confounded_with" partner or reading], ...}].
Units as everywhere: mm, rad, deg (rotary positions), s.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from mtcal import load_machine
from mtcal.campaign.plans import Plan
from mtcal.campaign.simulate import simulate
from mtcal.data.make_demo_data import build_for
from mtcal.kinematics.defaults import default_positions
from mtcal.kinematics.machine import Machine
from mtcal.measurement.recordings import Recording
from mtcal.model.errormodel import ErrorFunction, ErrorModel

STATIONS = ("front", "side", "far")


@dataclass(frozen=True)
class Design:
    machine: str = "dmu50"
    station: str = "front"        # front / side / far
    rounds: int = 4               # 3..6
    axes: tuple[str, ...] = ()    # measured axes in order (empty: all of the machine's)
    counts: tuple[int, ...] = ()  # positions per measured axis (empty: 6 linear, 8 rotary)
    tracker_given: bool = True    # the diagnosis is told the tracker position
    jitter: tuple[float, float, float] = (0.0, 0.0, 0.0)  # mm added to the station


@dataclass
class Campaign:
    name: str
    design: Design
    recording: Recording
    truth: dict                   # the simulator's truth (effects with their parameters, tracker, seed, ...)
    tracker: tuple[float, float, float] | None  # what the diagnosis is told (None: not told)
    tracker_true: tuple[float, float, float]
    model: ErrorModel | None      # reference model given to the diagnosis (None: no model)
    expect: list[dict] = field(default_factory=list)

    @property
    def duration_s(self) -> float:
        return float(np.nanmax(self.recording.time_s))


def station(m: Machine, where: str, jitter=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Tracker position (mm, machine frame) in front of (beam ~ Y), beside (beam ~ X) or far in front of the
    machine, from the middle of its linear travels."""
    pos = default_positions(m)
    mid = np.array([pos[a].mean() if a in pos else 0.0 for a in m.linear_axes[:3]])
    off = {"front": (0.0, -1700.0, 150.0), "side": (-1700.0, 0.0, 150.0), "far": (0.0, -4500.0, 500.0)}[where]
    return np.array([mid[0], mid[1], 0.0]) + off + np.asarray(jitter, dtype=float)


def _positions(m: Machine, axis: str, count: int) -> np.ndarray:
    p = default_positions(m)[axis]
    return np.linspace(p.min(), p.max(), count) if not (p.min() < 0 < p.max()) else \
        np.unique(np.append(np.linspace(p.min(), p.max(), count), 0.0))


def make(design: Design, effects=(), seed: int = 0, *, model: ErrorModel | None = None,
         reference: ErrorModel | None = None, positions: dict | None = None, temperature=None, name: str = "",
         expect: list[dict] | None = None, tool_points: dict | None = None) -> Campaign:
    """One campaign: ``model`` is the simulated machine's error model (None: no errors), ``reference`` the model
    given to the diagnosis (default: ``model``); ``positions`` {axis: array} overrides the design's counts;
    ``tool_points`` {label: (x, y, z) mm} the spindle's reflectors (default: the spec's)."""
    m = load_machine(design.machine)
    axes = design.axes or m.axes
    counts = design.counts or tuple(6 if m.kind(a) == "linear" else 8 for a in axes)
    pos = {a: _positions(m, a, c) for a, c in zip(axes, counts)}
    pos.update(positions or {})
    tr = station(m, design.station, design.jitter)
    plan = Plan(m, tracker=tuple(float(c) for c in tr), rounds=design.rounds, positions=pos, tool_points=tool_points)
    rec, truth = simulate(model, plan=plan, seed=seed, effects=list(effects), temperature=temperature)
    return Campaign(name or "+".join(e[0] if not isinstance(e, str) else e.split(":")[0] for e in effects) or "clean",
                    design, rec, truth, tuple(plan.tracker) if design.tracker_given else None, tuple(plan.tracker),
                    reference if reference is not None else model, list(expect or []))


def random_design(rng: np.random.Generator, machine: str = "dmu50", need=()) -> Design:
    """Station front / side / far (jittered by up to 200 mm, 100 mm in z), 3-6 rounds, five axes or three (the
    linear axes, or two of them and a rotary axis; ``need`` forces axes in), 5-9 positions per axis, tracker
    told or not."""
    m = load_machine(machine)
    if rng.random() < 0.5:
        axes = m.axes
    else:
        lin, rot = list(m.linear_axes), list(m.rotary_axes)
        axes = tuple(lin) if rng.random() < 0.5 else tuple(sorted(rng.choice(lin, 2, replace=False),
                                                                   key=m.axes.index)) + (str(rng.choice(rot)),)
    axes = tuple(a for a in m.axes if a in set(axes) | set(need))
    counts = tuple(int(rng.integers(5, 10)) for _ in axes)
    jitter = tuple(float(v) for v in rng.uniform(-1, 1, 3) * (200.0, 200.0, 100.0))
    return Design(machine, str(rng.choice(STATIONS)), int(rng.integers(3, 7)), axes, counts,
                  bool(rng.random() < 0.5), jitter)


def clean(seed: int, machine: str = "dmu50") -> Campaign:
    """A varied design with nothing planted (and no machine errors): the diagnosis should report nothing."""
    return make(random_design(np.random.default_rng(seed), machine), (), seed, name="clean")


# effect pool of ``planted``: name -> (parameters given the machine and a generator, axes it needs, expectation);
# sizes clearly above the AT960 noise of a small campaign
def _pool(m: Machine, rng: np.random.Generator):
    lin, rot = m.linear_axes, m.rotary_axes
    a, r = str(rng.choice(lin)), str(rng.choice(rot))
    sgn = float(rng.choice([-1.0, 1.0]))
    return {
        "backlash": ({"axis": a, "amount": sgn * 0.012}, (a,), {"axis": a}),
        "scale": ({"axis": a, "ppm": sgn * 60.0}, (a,), {"axis": a}),
        "rotary_location": ({"error": f"E_X0{r}", "value": sgn * 0.030}, (r,), {"axis": r, "error": f"E_X0{r}"}),
        "thermal_drift": ({"amplitude": 0.030, "tau_s": 1200.0, "direction": str(rng.choice(["+X", "+Y", "+Z"]))},
                          (), {}),
        "reversal_angular": ({"error": f"E_B{a}", "amount": sgn * 150e-6}, (a,), {"axis": a, "error": f"E_B{a}"}),
        "tracker_settling": ({"angle_rad": 40e-6, "tau_s": 1800.0, "about": "+X"}, (), {}),
        "nest_creep": ({"point": m.campaign["reflectors"]["tool"][1][0], "side": "tool", "rate_mm_s": 20e-3 / 3600},
                       (a,), {"point": m.campaign["reflectors"]["tool"][1][0]}),
        "tracker_scale": ({"ppm": sgn * 15.0}, (), {}),
    }


POOL = ("backlash", "scale", "rotary_location", "thermal_drift", "reversal_angular", "tracker_settling",
        "nest_creep", "tracker_scale")


def planted(seed: int, machine: str = "dmu50") -> Campaign:
    """A varied design with one or two effects drawn from POOL (distinct names), through the physical simulator."""
    rng = np.random.default_rng(seed)
    m = load_machine(machine)
    pool = _pool(m, rng)
    names = [str(n) for n in rng.choice(POOL, int(rng.integers(1, 3)), replace=False)]
    need = tuple(a for n in names for a in pool[n][1])
    design = random_design(rng, machine, need)
    effects = [(n, pool[n][0]) for n in names]
    return make(design, effects, seed, expect=[{"name": n, **pool[n][2]} for n in names])


# ----------------------------------------------------------------------------- the cases
def _reference(machine: str = "dmu50") -> ErrorModel:
    """The reference model of the machine (a synthetic truth of thesis magnitudes, mtcal.data.make_demo_data)."""
    return build_for(load_machine(machine), seed=13)


def c_location_with_model(seed: int) -> Campaign:
    """C-axis location error, eccentricity 10 um (E_X0C 8 um, E_Y0C -6 um), on top of the reference model, which
    the diagnosis is given: only the planted location error is new."""
    ref = _reference()
    eff = [("rotary_location", {"error": "E_X0C", "value": 0.008}), ("rotary_location", {"error": "E_Y0C",
                                                                                          "value": -0.006})]
    return make(Design(rounds=4), eff, seed, model=ref, name="c_location_with_model",
                expect=[{"name": "rotary_location", "axis": "C", "error": ["E_X0C", "E_Y0C"]}])


def c_location_and_knock(seed: int) -> Campaign:
    """The C location error above and a tracker knock (20 um) in the middle of the B measurement, before C: both
    are there; the knock must not replace the location error."""
    c = c_location_with_model(seed)
    t_b = c.recording.time_s[c.recording.axis == "B"]
    knock = ("offset", {"size": 0.020, "direction": "+Y", "t_from_s": float(np.median(t_b))})
    eff = [("rotary_location", {"error": "E_X0C", "value": 0.008}),
           ("rotary_location", {"error": "E_Y0C", "value": -0.006}), knock]
    return make(c.design, eff, seed, model=c.model, name="c_location_and_knock",
                expect=[{"name": "rotary_location", "axis": "C", "error": ["E_X0C", "E_Y0C"]},
                        {"name": "offset", "t_from_s": knock[1]["t_from_s"]}])


def _c_last_design() -> Design:
    return Design(rounds=3, axes=("X", "Y", "C"), counts=(6, 6, 8))


def c_location_last(seed: int) -> Campaign:
    """A location error of C (15 um), the axis measured last, no reference model: it can look like a knock at
    the moment C starts; a right answer names the location error or reports the two as confounded (measure C
    again at the end, or from a second station)."""
    return make(_c_last_design(), [("rotary_location", {"error": "E_X0C", "value": 0.015})], seed,
                name="c_location_last",
                expect=[{"name": "rotary_location", "axis": "C", "error": "E_X0C", "alternatives": ["offset"]}])


def knock_at_c_start(seed: int) -> Campaign:
    """A tracker knock (15 um along X) just before C, the axis measured last, starts: the other face of the case
    above (the right answer is the knock, or the pair reported as confounded)."""
    base = make(_c_last_design(), (), seed)
    t0 = float(base.recording.time_s[base.recording.axis == "C"].min()) - 1.0
    return make(_c_last_design(), [("offset", {"size": 0.015, "direction": "+X", "t_from_s": t0})], seed,
                name="knock_at_c_start",
                expect=[{"name": "offset", "t_from_s": t0, "alternatives": ["rotary_location"]}])


def warm_up(seed: int) -> Campaign:
    """A real warm-up: the spindle grows 25 um along Z with tau 1500 s while the temperature channel rises 2 K
    with the same law (thermal_drift writes it); a knock must not win over it."""
    return make(Design(rounds=4, axes=("X", "Y", "Z")), [("thermal_drift", {"amplitude": 0.025, "tau_s": 1500.0,
                                                                            "direction": "+Z"})], seed,
                name="warm_up", expect=[{"name": "thermal_drift", "alternatives": ["thermal_temperature"]}])


def thermal_temperature(seed: int, size: float = 1.0) -> Campaign:
    """Thermal drift driven by the recorded temperature: X expands 8 ppm/K and the spindle drifts 6 um/K along Z
    (both times ``size``) under a 2.5 K warm-up (tau 1200 s) written to temperature_c."""
    eff = [("thermal_temperature", {"axis": "X", "ppm_per_k": 8.0 * size, "drift_mm_per_k": 0.006 * size,
                                    "direction": "+Z"})]
    return make(Design(rounds=4, axes=("X", "Y", "Z")), eff, seed, temperature={"rise_c": 2.5, "tau_s": 1200.0},
                name="thermal_temperature",
                expect=[{"name": "thermal_temperature", "axis": "X", "alternatives": ["thermal_drift"]}])


def reversal_pitch(seed: int) -> Campaign:
    """Direction-dependent pitch of X: E_BX differs by 80 urad between + and - approach."""
    return make(Design(rounds=5, axes=("X", "Y", "Z"), counts=(9, 6, 6)),
                [("reversal_angular", {"error": "E_BX", "amount": 80e-6})],
                seed, name="reversal_pitch", expect=[{"name": "reversal_angular", "axis": "X", "error": "E_BX"}])


def aliased_pitch(seed: int) -> Campaign:
    """A 30 mm pitch (5 um) of X sampled every 25 mm: it aliases to a 150 mm pitch (1/25 - 1/30 = 1/150 per mm);
    a right answer names the periodic error with an alias warning, not a confident 150 mm pitch."""
    return make(Design(rounds=3, axes=("X", "Y", "Z")), [("periodic", {"axis": "X", "amplitude": 0.005,
                                                                       "pitch": 30.0})], seed,
                positions={"X": np.arange(0.0, 501.0, 25.0)}, name="aliased_pitch",
                expect=[{"name": "periodic", "axis": "X", "pitch": 30.0, "alias_pitch": 150.0, "step": 25.0}])


def periodic_x(seed: int) -> Campaign:
    """A resolved periodic error of X: 6 um, pitch 100 mm, sampled every 25 mm."""
    return make(Design(rounds=3, axes=("X", "Y", "Z")), [("periodic", {"axis": "X", "amplitude": 0.006,
                                                                       "pitch": 100.0, "phase_deg": 30.0})], seed,
                positions={"X": np.arange(0.0, 501.0, 25.0)}, name="periodic_x",
                expect=[{"name": "periodic", "axis": "X", "pitch": 100.0}])


def nest_creep(seed: int, rate_um_h: float = 10.0) -> Campaign:
    """One reflector's nest (the second spindle reflector) creeping ``rate_um_h`` along +Z over a record of about
    1.5 h: a right answer names that reflector and reports the creep over the record, not a warm-up of the whole
    spindle extrapolated beyond it."""
    m = load_machine("dmu50")
    pt = m.campaign["reflectors"]["tool"][1][0]
    d = Design(rounds=4, axes=("X", "Y", "Z"), counts=(8, 8, 8))  # 1.50 h
    rate = rate_um_h * 1e-3 / 3600
    return make(d, [("nest_creep", {"point": pt, "side": "tool", "rate_mm_s": rate, "direction": "+Z"})],
                seed, name="nest_creep", expect=[{"name": "nest_creep", "point": pt, "rate_mm_s": rate}])


def tracker_scale(seed: int) -> Campaign:
    """The tracker's distances 12 ppm short (air 12 K warmer than the tracker assumes), tracker told."""
    return make(Design(rounds=4), [("tracker_scale", {"ppm": -12.0})], seed, name="tracker_scale",
                expect=[{"name": "tracker_scale", "ppm": -12.0, "alternatives": ["scale", "rotary_location"]}])


def tracker_settling(seed: int) -> Campaign:
    """The tracker stand settling: the readings turn 40 urad about a horizontal axis through the tracker
    (tau 1800 s), i.e. up to ~70 um across the beam at 1.7 m, over a five-axis campaign."""
    return make(Design(rounds=3), [("tracker_settling", {"angle_rad": 40e-6, "tau_s": 1800.0, "about": "+X"})],
                seed, name="tracker_settling", expect=[{"name": "tracker_settling"}])


def _constant(m: Machine, error: str, value: float) -> ErrorModel:
    """An error model with one error function held at ``value`` (mm or rad) over its axis' whole travel."""
    axis = error[-1]  # ISO 230-1: E_<direction><axis> is an error motion of <axis>
    lim = np.array([-1e4, 1e4])  # every position of a campaign (the spec may leave a linear axis unlimited)
    return ErrorModel(m.name, functions={error: ErrorFunction(axis, lim, np.full(2, value))})


def lateral_play(seed: int, play_mm: float = 0.015) -> Campaign:
    """The X carriage sits ``play_mm`` further along +Y when a target is approached in the - direction than in
    the + direction (a guideway gib with play: a direction-dependent straightness E_YX).  Simulated as two
    machines through the exact kinematics (E_YX = +-play/2, same seed and noise), each reading taken from the
    one its direction of approach selects.  A right answer names reversal_straightness X E_YX (or reports the
    roll reversal it cannot be told from as confounded with it)."""
    m = load_machine("dmu50")
    d = Design(rounds=4, axes=("X", "Y", "Z"))
    plus, minus = (make(d, (), seed, model=_constant(m, "E_YX", s * play_mm / 2)) for s in (-1.0, 1.0))
    rec = plus.recording
    back = (rec.direction == -1) & (rec.axis == "X")  # the other axes are measured with X parked
    rec.xyz[back] = minus.recording.xyz[back]
    rec.truth = {**plus.truth, "effects": [{"name": "lateral_play", "error": "E_YX", "axis": "X",
                                            "play_mm": play_mm, "outside_candidates": True}]}
    return replace(plus, name="lateral_play", truth=rec.truth, model=None,
                   expect=[{"name": "reversal_straightness", "axis": "X", "error": "E_YX"}])


def loose_nest(seed: int, shift_mm: float = 0.006) -> Campaign:
    """Physics outside the candidate list: the reflector in the spindle's second nest is loose and is thrown
    ``shift_mm`` along the direction of travel at every reversal (it sits +shift/2 along the measured linear
    axis after a + approach, -shift/2 after a - approach); the other reflectors sit firm.  Simulated through the
    exact kinematics with that reflector's position moved in the plan (same seed and noise), each reading taken
    from the campaign its direction of approach selects.  No rigid motion of the carriage does this: a right
    answer reports it unexplained (direction x point) on the axes where the shift is above the noise (along the
    beam; across it, 6 um is below the transverse noise), never a confident name."""
    m = load_machine("dmu50")
    d = Design(rounds=4, axes=("X", "Y", "Z"))
    label, p0 = m.campaign["reflectors"]["tool"][1]
    base = make(d, (), seed)
    rec = base.recording
    for k, a in enumerate(d.axes):
        for sign in (1, -1):
            moved = np.array(p0, float) + sign * shift_mm / 2 * np.eye(3)[k]
            pts = {lb: tuple(moved) if lb == label else tuple(p) for lb, p in m.campaign["reflectors"]["tool"]}
            other = make(d, (), seed, tool_points=pts).recording
            sel = (rec.axis == a) & (rec.point == label) & (rec.direction == sign)
            rec.xyz[sel] = other.xyz[sel]
    rec.truth = {**base.truth, "effects": [{"name": "loose_nest", "point": label, "shift_mm": shift_mm,
                                            "outside_candidates": True}]}
    return replace(base, name="loose_nest", truth=rec.truth, expect=[{"name": "loose_nest"}])


CASES = {f.__name__: f for f in (c_location_with_model, c_location_and_knock, c_location_last, knock_at_c_start,
                                 warm_up, thermal_temperature, reversal_pitch, aliased_pitch, periodic_x, nest_creep,
                                 tracker_scale, tracker_settling, lateral_play, loose_nest)}


def without_tracker(c: Campaign) -> Campaign:
    """The same campaign with the diagnosis not told the tracker position."""
    return replace(c, design=replace(c.design, tracker_given=False), tracker=None)
