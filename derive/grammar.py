"""The grammar of effects: every left-out effect of the diagnosis is WHERE x WHAT MOVES x HOW IT DEPENDS.

* WHERE: the tool side, the table side, the tracker, one reflector (a nest), one axis (an error function of it).
* WHAT MOVES (``WHAT``, each written once here as the displacement of a reading, mm, machine frame):
  - ``translation``  v h                                         (v a 3-vector, mm)
  - ``rotation``     Rot(u, theta h) (p - pivot) - (p - pivot)       (Rodrigues, exact; pivot: the tracker)
  - ``expansion``    1e-6 e h R (local - centroid)                (the side's reflector layout growing about its
                                                                  centroid: e in ppm, R the side's rotation), or
                     1e-6 e h (point - tracker)                   (the tracker's distances scaling: the air)
  - ``error``        column x (increment of an error function)   (column: the machine's generated point Jacobian
                                                                  column of that error, mm per mm or per rad)
  - ``scatter``      no displacement: a variance component of the readings (a weight, not a column)
* HOW IT DEPENDS (``LAWS``, the factor h of the amplitude): on time (``step`` [t >= t0], ``ramp`` t - t0,
  ``ramp_h`` (t - t0) / 3600 s, ``lag`` 1 - exp(-(t - t0) / tau), ``temperature`` T - T_ref), on position
  (``position`` q, ``position2`` q^2), on direction (``direction`` d / 2, d = +-1), on round (a ``step`` at a
  round's first reading), and products (``position_direction`` d / 2 q, ``position_position`` q q_on,
  ``position_temperature`` 1e-6 q dT).

A member's signature (d reading / d its parameters at zero effect) is the Jacobian of WHAT(LAW) with respect to
the parameters, generated (derive/signatures.py) like the kinematics; its simulation uses the same expression.
``MEMBERS`` names every effect of the simulator and the diagnosis (docs/design.md's table): a new physics is one
entry here plus its composite in ``composites`` (a few lines), a simulator model in mtcal.campaign.effects and a
candidate in mtcal.diagnose.effects.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

PPM = sp.Rational(1, 10**6)
HOUR_S = 3600


# ----------------------------------------------------------------------------- HOW IT DEPENDS
def law(kind: str, **s: sp.Expr) -> sp.Expr:
    """The factor h of a member's amplitude (keyword symbols: dt (s, time since the onset), tau (s), on (0 / 1),
    dT (K), q, q_on (axis positions), d (+-1))."""
    laws = {
        "constant": lambda: sp.Integer(1),
        "step": lambda: s["on"],
        "ramp": lambda: s["dt"],
        "ramp_h": lambda: s["dt"] / HOUR_S,
        "lag": lambda: 1 - sp.exp(-s["dt"] / s["tau"]),
        "temperature": lambda: s["dT"],
        "position": lambda: s["q"],
        "position2": lambda: s["q"] ** 2,
        "direction": lambda: s["d"] / 2,
        "position_direction": lambda: s["d"] / 2 * s["q"],
        "position_position": lambda: s["q"] * s["q_on"],
        "position_temperature": lambda: PPM * s["q"] * s["dT"],
    }
    return laws[kind]()


LAWS = ("constant", "step", "ramp", "ramp_h", "lag", "temperature", "position", "position2", "direction",
        "position_direction", "position_position", "position_temperature")


# ----------------------------------------------------------------------------- WHAT MOVES
def rodrigues(u: sp.Matrix, theta: sp.Expr) -> sp.Matrix:
    """Rotation by ``theta`` (rad) about the unit vector ``u``."""
    ux = sp.Matrix([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    return sp.eye(3) * sp.cos(theta) + ux * sp.sin(theta) + (1 - sp.cos(theta)) * (u * u.T)


def translation(v: sp.Matrix, h: sp.Expr) -> sp.Matrix:
    """A translation v h (mm)."""
    return v * h


def rotation(u: sp.Matrix, theta: sp.Expr, point: sp.Matrix, pivot: sp.Matrix) -> sp.Matrix:
    """Displacement (mm) of ``point`` turned by ``theta`` about the axis ``u`` through ``pivot`` (exact)."""
    return rodrigues(u, theta) * (point - pivot) - (point - pivot)


def expansion(e: sp.Expr, h: sp.Expr, offset: sp.Matrix) -> sp.Matrix:
    """Displacement (mm) of a point at ``offset`` from the centre of an expansion by 1e-6 e h (e in ppm): a
    reflector at local - centroid of its side's layout (the side's local frame), or a reading at point - tracker
    (the machine frame: the tracker's distances scaling)."""
    return PPM * e * h * offset


def error(column: sp.Matrix, increment: sp.Expr) -> sp.Matrix:
    """Displacement (mm) of a reading by an increment of one error function (first order: the point Jacobian
    column times the increment; the simulator carries the increment through the exact kinematics)."""
    return column * increment


WHAT = ("translation", "rotation", "expansion", "error", "scatter")
WHERE = ("tool side", "table side", "tracker", "one reflector", "one axis")


# ----------------------------------------------------------------------------- the members
@dataclass(frozen=True)
class Member:
    """One named member of the grammar: where, what moves, how it depends, its parameters with units."""

    where: str
    what: str
    how: str
    params: str


MEMBERS: dict[str, Member] = {
    # the effects of issue 13 and before, named members (their generated functions are unchanged)
    "backlash": Member("one axis", "error (positioning)", "direction", "b: error(+) - error(-), mm (rad rotary)"),
    "reversal_angular": Member("one axis", "error (pitch, yaw, roll)", "direction", "r: angle(+) - angle(-), rad"),
    "reversal_straightness": Member("one axis", "error (straightness)", "direction",
                                    "r: straightness(+) - straightness(-), mm"),
    "scale": Member("one axis", "error (positioning)", "position", "ppm (1e-6 per mm, or per rad rotary)"),
    "second_order": Member("one axis", "error (any)", "position2", "c, mm or rad per mm^2 or deg^2"),
    "cross_axis": Member("one axis", "error (any)", "position_position", "c, per mm (deg) of both axes"),
    "periodic": Member("one axis", "error (positioning)", "sin, cos of position / pitch",
                       "a_s, a_c mm (rad); pitch mm (deg)"),
    "squareness": Member("one axis", "error (constant)", "constant", "rad"),
    "rotary_location": Member("one axis", "error (constant)", "constant", "mm or rad"),
    "thermal_temperature": Member("one axis; tool or table side", "error (positioning); translation",
                                  "position_temperature; temperature", "k ppm/K; c mm/K (3-vector)"),
    "thermal_drift": Member("tool side, table side, tracker", "translation", "lag", "A mm (3-vector), tau s"),
    "tracker_scale": Member("tracker", "expansion about the tracker", "constant", "ppm"),
    "tracker_settling": Member("tracker", "rotation about the tracker", "ramp + lag",
                               "w rad/s, a rad (3-vectors), tau s"),
    "offset": Member("tracker; one reflector", "translation", "step (in time; a sequence)", "s mm (3-vector)"),
    "outlier": Member("one reflector", "translation", "step (one reading or the rest of a round)",
                      "s mm (3-vector)"),
    "nest_creep": Member("one reflector", "translation (side's frame)", "ramp", "v mm/s (3-vector)"),
    "nest_knock": Member("one reflector", "translation (side's frame)", "step", "s mm (3-vector), t0 s"),
    # issue 34
    "side_expansion": Member("tool side, table side", "expansion about the side's reflector centroid",
                             "ramp_h; lag", "ramp: ppm per hour; lag: ppm (final), tau s"),
    "backlash_travel": Member("one axis", "error (positioning)", "direction; position_direction",
                              "b mm (rad) at position 0, g mm per mm (rad per deg)"),
    "axis_scatter": Member("one axis", "scatter (along its motion)",
                           "each stop (random, shared by the nests read there: a variance component)",
                           "sd mm (rad rotary)"),
    "tracker_relevel": Member("tracker", "rotation about the tracker (horizontal axes x, y)",
                              "step (at a round's first reading)", "w_x, w_y rad"),
    # the air's refractive index drifting while the tracker's weather compensation stays at its first value: every
    # distance of every station scales by the same 1e-6 e h(t) (one air, one law; about 1 ppm per K, 0.27 ppm per
    # hPa).  A scale constant over the campaign is tracker_scale (the machine frame's, or a station's relative one)
    "air_index_drift": Member("tracker (every station, one law shared by all)", "expansion about the tracker",
                              "ramp_h; lag", "ramp: ppm per hour; lag: ppm (final), tau s"),
}


# ----------------------------------------------------------------------------- issue 34's composites
def composites(sym: dict) -> list[tuple[str, tuple, sp.Matrix, list, str]]:
    """The new members' generated functions: (name, argument keys, expression, parameters, doc).  A
    ``_signature`` is the Jacobian of its expression with respect to the parameters at zero (derive/signatures.py);
    a ``_model`` is the expression itself (the parameters its last argument, ``params``), which the simulator
    applies.  ``sym``: the shared symbols (signatures.build)."""
    s = sym
    e, b, g, wx, wy = s["e"], s["b"], s["g"], s["w_x"], s["w_y"]
    ramp, lag = law("ramp_h", dt=s["dt"]), law("lag", dt=s["dt"], tau=s["tau"])
    inc = law("direction", d=s["d"]) * b + law("position_direction", d=s["d"], q=s["q"]) * g
    relevel = (rotation(sp.Matrix([1, 0, 0]), wx * law("step", on=s["on"]), s["xyz"], s["tracker"])
               + rotation(sp.Matrix([0, 1, 0]), wy * law("step", on=s["on"]), s["xyz"], s["tracker"]))
    beam = s["xyz"] - s["tracker"]  # a reading's distance vector from its station: what the air scales
    return [
        ("air_index_drift_ramp_model", ("xyz", "tracker", "dt"), expansion(e, ramp, beam), [e],
         "air_index_drift (ramp): displacement 1e-6 e (dt / 3600 s) (point - tracker) of a reading, mm (e in ppm "
         "per hour: the tracker's distances scale as the air's refractive index drifts uncompensated)"),
        ("air_index_drift_ramp_signature", ("xyz", "tracker", "dt"), expansion(e, ramp, beam), [e],
         "air_index_drift (ramp): d reading / d e = 1e-6 (dt / 3600 s) (point - tracker), mm per (ppm/h)"),
        ("air_index_drift_lag_model", ("xyz", "tracker", "dt", "tau"), expansion(e, lag, beam), [e],
         "air_index_drift (lag): displacement 1e-6 e (1 - exp(-dt / tau)) (point - tracker), mm (e in ppm)"),
        ("air_index_drift_lag_signature", ("xyz", "tracker", "dt", "tau"), expansion(e, lag, beam), [e],
         "air_index_drift (lag): d reading / d e = 1e-6 (1 - exp(-dt / tau)) (point - tracker), mm per ppm"),
        ("side_expansion_ramp_model", ("offset", "dt"), expansion(e, ramp, s["offset"]), [e],
         "side_expansion (ramp): displacement 1e-6 e (dt / 3600 s) (local - centroid) of a reflector in its side's "
         "local frame, mm (e in ppm per hour)"),
        ("side_expansion_ramp_signature", ("rotation", "offset", "dt"),
         s["R"] * expansion(e, ramp, s["offset"]), [e],
         "side_expansion (ramp): d reading / d e = 1e-6 (dt / 3600 s) R (local - centroid), mm per (ppm/h)"),
        ("side_expansion_lag_model", ("offset", "dt", "tau"), expansion(e, lag, s["offset"]), [e],
         "side_expansion (lag): displacement 1e-6 e (1 - exp(-dt / tau)) (local - centroid), mm (e in ppm)"),
        ("side_expansion_lag_signature", ("rotation", "offset", "dt", "tau"),
         s["R"] * expansion(e, lag, s["offset"]), [e],
         "side_expansion (lag): d reading / d e = 1e-6 (1 - exp(-dt / tau)) R (local - centroid), mm per ppm"),
        ("backlash_travel_model", ("d", "q"), sp.Matrix([inc]), [b, g],
         "backlash_travel: positioning error + d / 2 (b + g q): a reversal b + g q growing along the travel, "
         "mm (rad)"),
        ("backlash_travel_signature", ("column", "d", "q"), error(s["column"], inc), [b, g],
         "backlash_travel: d reading / d [b, g] = column d / 2 [1, q], mm per mm and mm per (mm/mm)"),
        ("tracker_relevel_signature", ("xyz", "tracker", "on"), relevel, [wx, wy],
         "tracker_relevel: d reading / d [w_x, w_y] = on [e_x, e_y] x (point - tracker), mm per rad (a rotation "
         "step about horizontal axes through the tracker, from a round's first reading on)"),
    ]
