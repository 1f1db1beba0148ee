"""Signatures of left-out effects in laser-tracker readings: d(measured point) / d(effect parameters).

The diagnosis (mtcal.diagnose) tests each candidate effect against the fitted base model through the columns
it adds to the design.  Each effect is written here once as a physical model of how it moves a measured point
(machine frame, mm), and its signature is the exact derivative of that model with respect to the effect's
parameters at zero effect (all models below are linear in their amplitudes, so the signature is exact, not
just first order).  Where an effect acts through an error function of the machine, its model takes ``column``:
the generated point Jacobian column of that error (Machine.point_jacobian_errors: the machine's
``tool_point_jacobian_errors`` / ``table_point_jacobian_errors``, mm per mm or mm per rad), so the kinematics
stays in derive/kinematics.py.

The same model is emitted for simulation (mtcal.campaign.effects): ``<effect>_model`` gives the increment of the affected
error function (mm or rad), which the simulator adds to the machine's errors and carries to the reflectors
through the exact error-inclusive kinematics; ``thermal_drift_displacement`` and ``tracker_scale_reading`` move
the readings themselves.  So each effect is written once, and tests/test_effects_physics.py and tests/test_effects_new_physics.py show that
simulate(effect) - simulate(none) = signature x parameter to first order, with a second-order remainder.

Effects (names of docs/design.md; q = axis position, d = approach direction +-1, dt = time since the warm-up
started, s):
* backlash       positioning error + d * b / 2                                        -> column * d / 2
                 (b = error(+ approach) - error(- approach) of the positioning error in its own ISO 230-1 sense;
                 ISO 230-2's reversal value B (commanded sense) = b on a linear axis, s b on a rotary axis with
                 s = +1 when a positive command turns about +z of its stator, else -1 (DMU 50's C); mtcal.campaign.effects)
* reversal_angular  angular error (E_A/E_B/E_C of a linear axis) + d * r / 2             -> column * d / 2
                 (pitch / yaw / roll differs by r between + and - approach; the same reversal law as backlash)
* scale          positioning error + 1e-6 * ppm * q (q in mm, or rad for rotary)       -> column * q * 1e-6
* second_order   error function + c * q**2                                             -> column * q**2
* cross_axis     error function + c * q_own * q_on                                     -> column * q_own * q_on
* periodic       positioning error + a_s sin(2 pi q / pitch) + a_c cos(2 pi q / pitch)
                 (amplitude = hypot(a_s, a_c), phase = atan2(a_c, a_s))                -> column * [sin, cos]
* thermal_drift  point + A (1 - exp(-dt / tau)), A a 3-vector (mm)                     -> I3 (1 - exp(-dt / tau))
                 and d/d tau (for refining the time constant by Gauss-Newton)
* tracker_scale  tracker + (1 + 1e-6 ppm) (point - tracker): radial scaling about the tracker
                                                                                       -> 1e-6 (point - tracker)
* outlier        point + s (one reading, or the rest of a round for a bumped nest)    -> I3
* thermal_temperature  driven by the recorded temperature rise dT = T - T_ref (K):
                 positioning error of a linear axis + 1e-6 k dT q (expansion, k in ppm/K)  -> column * 1e-6 q dT
                 point + c dT (drift of one side, c a 3-vector in mm/K)                    -> I3 dT
                 and the warm-up curve of the simulated temperature channel T = T0 + rise (1 - exp(-dt / tau))
* nest_creep     one reflector's nest moves in its side's local frame: local + v dt (v in mm/s), carried by the
                 side's rigid motion x = b + R local                                        -> R dt (3 x 3)
* tracker_settling  every reading turns about a unit axis u through the tracker T by
                 theta = w dt + a (1 - exp(-dt / tau)) (w rad/s ramp, a rad settling):
                 T + Rot(u, theta) (point - T) (Rodrigues, exact)    -> u x (point - T) [dt, 1 - exp(-dt / tau)]
* squareness, rotary_location: constants of the machine model; their signature is the generated point
  Jacobian column of that constant itself (no extra derivation), so they are not emitted here.
"""
from __future__ import annotations

import sympy as sp

from .codegen import Arg, Function, Module, symbols

PPM = sp.Rational(1, 10**6)


def _col() -> tuple[Arg, sp.Matrix]:
    c = symbols(["c_x", "c_y", "c_z"])
    return Arg("column", c, "point Jacobian column of the affected error, mm per error unit (mm or rad)"), sp.Matrix(c)


def _scalar(name: str, doc: str) -> tuple[Arg, sp.Symbol]:
    (s,) = symbols([name])
    return Arg(name, (s,), doc, vector=False), s


def _signature(displacement: sp.Matrix, params: list[sp.Symbol], simplify=sp.simplify) -> sp.Matrix:
    """d displacement / d params at params = 0 (3 x k); ``simplify``: the per-entry simplification (the
    identity keeps 1 - exp(-dt / tau) as written, where sp.simplify makes it (exp(dt / tau) - 1) exp(-dt / tau),
    which overflows for dt >> tau)."""
    jac = displacement.jacobian(sp.Matrix(params)).subs({p: 0 for p in params})
    return jac.applyfunc(simplify)


def build(progress=lambda m: None) -> Module:
    col_arg, col = _col()
    q_arg, q = _scalar("q", "axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise")
    d_arg, d = _scalar("d", "approach direction, +1 or -1")
    qo_arg, qo = _scalar("q_on", "position of the other axis, mm or deg")
    pitch_arg, pitch = _scalar("pitch", "period of the periodic error, same unit as q")
    dt_arg, dt = _scalar("dt", "time since the start of the warm-up, s (0 before it)")
    tau_arg, tau = _scalar("tau", "warm-up time constant, s")
    b, ppm, c2, cx, a_s, a_c = symbols(["b", "ppm", "c2", "cx", "a_s", "a_c"])
    amp = sp.Matrix(symbols(["A_x", "A_y", "A_z"]))
    amp_arg = Arg("amplitude", tuple(amp), "final displacement of the warm-up, mm")
    pt = sp.Matrix(symbols(["x", "y", "z"]))
    pt_arg = Arg("xyz", tuple(pt), "measured point, machine frame, mm")
    tr = sp.Matrix(symbols(["tx", "ty", "tz"]))
    tr_arg = Arg("tracker", tuple(tr), "tracker position, machine frame, mm")

    fns: list[Function] = []
    progress("error-function effects")
    r, k_t = symbols(["r", "k_ppm_per_K"])
    dT_arg, dT = _scalar("dT", "temperature rise T - T_ref of the reading, K")

    def reversal(v: sp.Symbol) -> sp.Expr:  # the reversal law, one formula for positioning and angular errors
        return d * v / 2

    models = {  # effect: (arguments besides the parameters, increment of the error function, parameters, doc)
        "backlash": ((d_arg,), reversal(b), [b],
                     "backlash: positioning error + d b / 2 (b = error(+ approach) - error(- approach), mm or rad)"),
        "reversal_angular": ((d_arg,), reversal(r), [r],
                             "reversal_angular: angular error of a linear axis + d r / 2 (r = angle(+ approach) - "
                             "angle(- approach), rad)"),
        "thermal_temperature": ((q_arg, dT_arg), PPM * k_t * dT * q, [k_t],
                                "thermal_temperature: positioning error of a linear axis + 1e-6 k dT q (expansion, "
                                "k in ppm/K, q in mm)"),
        "scale": ((q_arg,), PPM * ppm * q, [ppm],
                  "scale: positioning error + 1e-6 ppm q (q in mm, or rad for rotary)"),
        "second_order": ((q_arg,), c2 * q**2, [c2],
                         "second_order: error function + c q^2 (per mm^2 or deg^2)"),
        "cross_axis": ((q_arg, qo_arg), cx * q * qo, [cx],
                       "cross_axis: error function + c q_own q_on"),
        "periodic": ((q_arg, pitch_arg), a_s * sp.sin(2 * sp.pi * q / pitch) + a_c * sp.cos(2 * sp.pi * q / pitch),
                     [a_s, a_c], "periodic: positioning error + a_s sin(2 pi q / pitch) + a_c cos(2 pi q / pitch)"),
    }
    for name, (args, inc, params, doc) in models.items():
        par = Arg("params", tuple(params), f"effect parameters [{', '.join(map(str, params))}]")
        fns.append(Function(f"{name}_model", args + (par,), sp.Matrix([inc]),
                            f"{doc}: the increment of the error function (mm or rad), for simulation.",
                            vector_output=True))
        sig = _signature(col * inc, params)
        fns.append(Function(f"{name}_signature", (col_arg,) + args, sig,
                            f"{doc}: d point / d parameters at zero effect = column x d increment / d parameters, "
                            f"mm per parameter unit.", vector_output=sig.shape[1] == 1))

    progress("reading effects")
    warm = 1 - sp.exp(-dt / tau)
    drift = amp * warm
    fns.append(Function("thermal_drift_displacement", (amp_arg, dt_arg, tau_arg), drift,
                        "thermal_drift: displacement A (1 - exp(-dt / tau)) of a drifting point, mm", vector_output=True))
    fns.append(Function("thermal_drift_signature", (dt_arg, tau_arg), _signature(amp * warm, list(amp)),
                        "thermal_drift: d point / d A (3 x 3), 1 (mm per mm)"))
    fns.append(Function("thermal_drift_dtau", (amp_arg, dt_arg, tau_arg), drift.diff(tau).applyfunc(sp.simplify),
                        "thermal_drift: d point / d tau at amplitude A, mm per s", vector_output=True))
    scaled = tr + (1 + PPM * ppm) * (pt - tr)
    fns.append(Function("tracker_scale_reading", (pt_arg, tr_arg, Arg("ppm", (ppm,), "scale, 1e-6", vector=False)),
                        scaled, "tracker_scale: the reading (mm) of a point when the tracker's distances scale by "
                                "1 + 1e-6 ppm about the tracker (refractive index of air wrong)", vector_output=True))
    fns.append(Function("tracker_scale_signature", (pt_arg, tr_arg), _signature(scaled - pt, [ppm]),
                        "tracker_scale: d reading / d ppm (radial scaling about the tracker), mm per ppm",
                        vector_output=True))
    _temperature_effects(fns, dt_arg, dt, tau_arg, tau, dT_arg, dT, warm)
    _nest_creep(fns, dt_arg, dt)
    _tracker_settling(fns, pt_arg, pt, tr_arg, tr, dt_arg, dt, tau_arg, tau, warm)
    sv = sp.Matrix(symbols(["s_x", "s_y", "s_z"]))
    ind_arg, ind = _scalar("on", "1 for the displaced readings, 0 otherwise")
    fns.append(Function("outlier_signature", (ind_arg,), _signature((pt + ind * sv) - pt, list(sv)),
                        "outlier: d reading / d displacement s (3 x 3) for a displaced reading (on = 1)"))
    return Module("signatures", "signatures.py", __doc__.split("\n\n")[0], fns)


def _temperature_effects(fns, dt_arg, dt, tau_arg, tau, dT_arg, dT, warm) -> None:
    """thermal_temperature: the drift of one side proportional to the temperature rise, and the warm-up curve of
    the simulated temperature channel (the same time law as thermal_drift)."""
    coef = sp.Matrix(symbols(["c_x", "c_y", "c_z"]))
    coef_arg = Arg("coefficient", tuple(coef), "drift per kelvin of the temperature rise, mm/K")
    fns.append(Function("thermal_temperature_displacement", (coef_arg, dT_arg), coef * dT,
                        "thermal_temperature: displacement c dT of a point of the drifting side, mm",
                        vector_output=True))
    fns.append(Function("thermal_temperature_drift_signature", (dT_arg,), _signature(coef * dT, list(coef)),
                        "thermal_temperature: d point / d c (3 x 3), mm per (mm/K)"))
    t0c, rise = symbols(["T0", "rise"])
    fns.append(Function("thermal_temperature_curve",
                        (Arg("start_c", (t0c,), "temperature at the start, degC", vector=False),
                         Arg("rise_c", (rise,), "final rise of the warm-up, K", vector=False), dt_arg, tau_arg),
                        sp.Matrix([t0c + rise * warm]),
                        "warm-up curve of the temperature channel: T0 + rise (1 - exp(-dt / tau)), degC",
                        vector_output=True))


def _nest_creep(fns, dt_arg, dt) -> None:
    """nest_creep: one reflector's nest creeping at velocity v (mm/s, in its side's local frame: spindle or
    workpiece coordinates); the reading is b + R (local + v dt), so d reading / d v = R dt (R the side's nominal
    rotation, Machine.rigid_motion)."""
    v = sp.Matrix(symbols(["v_x", "v_y", "v_z"]))
    v_arg = Arg("velocity", tuple(v), "creep velocity of the nest in its side's local frame, mm/s")
    rot = sp.Matrix(3, 3, symbols([f"R_{i}{j}" for i in range(3) for j in range(3)]))
    rot_arg = Arg("rotation", tuple(rot), "the side's rotation local -> machine frame, row-major (9,)")
    fns.append(Function("nest_creep_model", (v_arg, dt_arg), v * dt,
                        "nest_creep: displacement v dt of the nest in its side's local frame, mm (for simulation: "
                        "added to the reflector's local coordinates before the exact kinematics)", vector_output=True))
    fns.append(Function("nest_creep_signature", (rot_arg, dt_arg), _signature(rot * (v * dt), list(v)),
                        "nest_creep: d reading / d v (3 x 3) = R dt, mm per (mm/s)"))


def _tracker_settling(fns, pt_arg, pt, tr_arg, tr, dt_arg, dt, tau_arg, tau, warm) -> None:
    """tracker_settling: the stand tilts by theta = w dt + a (1 - exp(-dt / tau)) about a unit axis u through the
    tracker; the readings turn with it (Rodrigues' rotation, exact)."""
    w, a, th = symbols(["w", "a", "theta"])
    u = sp.Matrix(symbols(["u_x", "u_y", "u_z"]))
    u_arg = Arg("about", tuple(u), "unit vector of the rotation axis through the tracker, machine frame")
    ux = sp.Matrix([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    rot = sp.eye(3) * sp.cos(th) + ux * sp.sin(th) + (1 - sp.cos(th)) * (u * u.T)
    reading = tr + rot * (pt - tr)
    angle = w * dt + a * warm
    fns.append(Function("tracker_settling_angle", (Arg("params", (w, a), "[w (rad/s), a (rad)]"), dt_arg, tau_arg),
                        sp.Matrix([angle]), "tracker_settling: tilt angle w dt + a (1 - exp(-dt / tau)), rad",
                        vector_output=True))
    fns.append(Function("tracker_settling_reading", (pt_arg, tr_arg, u_arg, Arg("theta", (th,), "tilt, rad",
                                                                                  vector=False)),
                        reading, "tracker_settling: the reading (mm) of a point when the tracker has turned by theta "
                                 "about the axis u through it (exact rotation)", vector_output=True))
    fns.append(Function("tracker_settling_signature", (pt_arg, tr_arg, u_arg, dt_arg, tau_arg),
                        _signature(reading.subs(th, angle) - pt, [w, a], lambda e: e),
                        "tracker_settling: d reading / d [w, a] (3 x 2) = u x (point - T) [dt, 1 - exp(-dt / tau)], "
                        "mm per (rad/s) and mm per rad"))
