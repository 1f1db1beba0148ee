# -----------------------------------------------------------------------------
# GENERATED FILE - DO NOT EDIT.
# Generator: python -m derive (signatures); source: derive/signatures.py
# Target: CasADi SX.  Regenerate with `python -m derive`; CI runs `python -m derive --check`.
# Inputs (machine spec, SymPy/CasADi versions, hash of derive/) are in manifest.json.
# -----------------------------------------------------------------------------
"""Signatures of left-out effects in laser-tracker readings: d(measured point) / d(effect parameters).

CasADi implementation: each function returns a cached casadi.Function."""
import functools

import casadi as ca

FUNCTIONS = ('backlash_model', 'backlash_signature', 'reversal_angular_model', 'reversal_angular_signature', 'thermal_temperature_model', 'thermal_temperature_signature', 'scale_model', 'scale_signature', 'second_order_model', 'second_order_signature', 'cross_axis_model', 'cross_axis_signature', 'periodic_model', 'periodic_signature', 'thermal_drift_displacement', 'thermal_drift_signature', 'thermal_drift_dtau', 'tracker_scale_reading', 'tracker_scale_signature', 'thermal_temperature_displacement', 'thermal_temperature_drift_signature', 'thermal_temperature_curve', 'nest_creep_model', 'nest_creep_signature', 'tracker_settling_angle', 'tracker_settling_reading', 'tracker_settling_signature', 'tracker_spherical_coordinates', 'tracker_spherical_reading', 'tracker_spherical_signature', 'outlier_signature', 'air_index_drift_ramp_model', 'air_index_drift_ramp_signature', 'air_index_drift_lag_model', 'air_index_drift_lag_signature', 'side_expansion_ramp_model', 'side_expansion_ramp_signature', 'side_expansion_lag_model', 'side_expansion_lag_signature', 'backlash_travel_model', 'backlash_travel_signature', 'tracker_relevel_signature')


@functools.cache
def backlash_model():
    """backlash: positioning error + d b / 2 (b = error(+ approach) - error(- approach), mm or rad): the increment of the error function (mm or rad), for simulation.

    d (...): approach direction, +1 or -1
    params (..., 1): effect parameters [b]
        [b]
    returns (..., 1)
    """
    d = ca.SX.sym('d', 1)
    d = d[0]
    params = ca.SX.sym('params', 1)
    b = params[0]
    _out = ca.SX.zeros(1, 1)
    _out[0, 0] = (1/2)*b*d
    return ca.Function('signatures_backlash_model', [d, params], [_out], ['d', 'params'], ['out'])


@functools.cache
def backlash_signature():
    """backlash: positioning error + d b / 2 (b = error(+ approach) - error(- approach), mm or rad): d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    d (...): approach direction, +1 or -1
    returns (..., 3)
    """
    column = ca.SX.sym('column', 3)
    c_x = column[0]
    c_y = column[1]
    c_z = column[2]
    d = ca.SX.sym('d', 1)
    d = d[0]
    _x0 = (1/2)*d
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*c_x
    _out[1, 0] = _x0*c_y
    _out[2, 0] = _x0*c_z
    return ca.Function('signatures_backlash_signature', [column, d], [_out], ['column', 'd'], ['out'])


@functools.cache
def reversal_angular_model():
    """reversal_angular: angular error of a linear axis + d r / 2 (r = angle(+ approach) - angle(- approach), rad): the increment of the error function (mm or rad), for simulation.

    d (...): approach direction, +1 or -1
    params (..., 1): effect parameters [r]
        [r]
    returns (..., 1)
    """
    d = ca.SX.sym('d', 1)
    d = d[0]
    params = ca.SX.sym('params', 1)
    r = params[0]
    _out = ca.SX.zeros(1, 1)
    _out[0, 0] = (1/2)*d*r
    return ca.Function('signatures_reversal_angular_model', [d, params], [_out], ['d', 'params'], ['out'])


@functools.cache
def reversal_angular_signature():
    """reversal_angular: angular error of a linear axis + d r / 2 (r = angle(+ approach) - angle(- approach), rad): d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    d (...): approach direction, +1 or -1
    returns (..., 3)
    """
    column = ca.SX.sym('column', 3)
    c_x = column[0]
    c_y = column[1]
    c_z = column[2]
    d = ca.SX.sym('d', 1)
    d = d[0]
    _x0 = (1/2)*d
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*c_x
    _out[1, 0] = _x0*c_y
    _out[2, 0] = _x0*c_z
    return ca.Function('signatures_reversal_angular_signature', [column, d], [_out], ['column', 'd'], ['out'])


@functools.cache
def thermal_temperature_model():
    """thermal_temperature: positioning error of a linear axis + 1e-6 k dT q (expansion, k in ppm/K, q in mm): the increment of the error function (mm or rad), for simulation.

    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    dT (...): temperature rise T - T_ref of the reading, K
    params (..., 1): effect parameters [k_ppm_per_K]
        [k_ppm_per_K]
    returns (..., 1)
    """
    q = ca.SX.sym('q', 1)
    q = q[0]
    dT = ca.SX.sym('dT', 1)
    dT = dT[0]
    params = ca.SX.sym('params', 1)
    k_ppm_per_K = params[0]
    _out = ca.SX.zeros(1, 1)
    _out[0, 0] = (1/1000000)*dT*k_ppm_per_K*q
    return ca.Function('signatures_thermal_temperature_model', [q, dT, params], [_out], ['q', 'dT', 'params'], ['out'])


@functools.cache
def thermal_temperature_signature():
    """thermal_temperature: positioning error of a linear axis + 1e-6 k dT q (expansion, k in ppm/K, q in mm): d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    dT (...): temperature rise T - T_ref of the reading, K
    returns (..., 3)
    """
    column = ca.SX.sym('column', 3)
    c_x = column[0]
    c_y = column[1]
    c_z = column[2]
    q = ca.SX.sym('q', 1)
    q = q[0]
    dT = ca.SX.sym('dT', 1)
    dT = dT[0]
    _x0 = (1/1000000)*dT*q
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*c_x
    _out[1, 0] = _x0*c_y
    _out[2, 0] = _x0*c_z
    return ca.Function('signatures_thermal_temperature_signature', [column, q, dT], [_out], ['column', 'q', 'dT'], ['out'])


@functools.cache
def scale_model():
    """scale: positioning error + 1e-6 ppm q (q in mm, or rad for rotary): the increment of the error function (mm or rad), for simulation.

    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    params (..., 1): effect parameters [ppm]
        [ppm]
    returns (..., 1)
    """
    q = ca.SX.sym('q', 1)
    q = q[0]
    params = ca.SX.sym('params', 1)
    ppm = params[0]
    _out = ca.SX.zeros(1, 1)
    _out[0, 0] = (1/1000000)*ppm*q
    return ca.Function('signatures_scale_model', [q, params], [_out], ['q', 'params'], ['out'])


@functools.cache
def scale_signature():
    """scale: positioning error + 1e-6 ppm q (q in mm, or rad for rotary): d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    returns (..., 3)
    """
    column = ca.SX.sym('column', 3)
    c_x = column[0]
    c_y = column[1]
    c_z = column[2]
    q = ca.SX.sym('q', 1)
    q = q[0]
    _x0 = (1/1000000)*q
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*c_x
    _out[1, 0] = _x0*c_y
    _out[2, 0] = _x0*c_z
    return ca.Function('signatures_scale_signature', [column, q], [_out], ['column', 'q'], ['out'])


@functools.cache
def second_order_model():
    """second_order: error function + c q^2 (per mm^2 or deg^2): the increment of the error function (mm or rad), for simulation.

    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    params (..., 1): effect parameters [c2]
        [c2]
    returns (..., 1)
    """
    q = ca.SX.sym('q', 1)
    q = q[0]
    params = ca.SX.sym('params', 1)
    c2 = params[0]
    _out = ca.SX.zeros(1, 1)
    _out[0, 0] = c2*q**2
    return ca.Function('signatures_second_order_model', [q, params], [_out], ['q', 'params'], ['out'])


@functools.cache
def second_order_signature():
    """second_order: error function + c q^2 (per mm^2 or deg^2): d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    returns (..., 3)
    """
    column = ca.SX.sym('column', 3)
    c_x = column[0]
    c_y = column[1]
    c_z = column[2]
    q = ca.SX.sym('q', 1)
    q = q[0]
    _x0 = q**2
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*c_x
    _out[1, 0] = _x0*c_y
    _out[2, 0] = _x0*c_z
    return ca.Function('signatures_second_order_signature', [column, q], [_out], ['column', 'q'], ['out'])


@functools.cache
def cross_axis_model():
    """cross_axis: error function + c q_own q_on: the increment of the error function (mm or rad), for simulation.

    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    q_on (...): position of the other axis, mm or deg
    params (..., 1): effect parameters [cx]
        [cx]
    returns (..., 1)
    """
    q = ca.SX.sym('q', 1)
    q = q[0]
    q_on = ca.SX.sym('q_on', 1)
    q_on = q_on[0]
    params = ca.SX.sym('params', 1)
    cx = params[0]
    _out = ca.SX.zeros(1, 1)
    _out[0, 0] = cx*q*q_on
    return ca.Function('signatures_cross_axis_model', [q, q_on, params], [_out], ['q', 'q_on', 'params'], ['out'])


@functools.cache
def cross_axis_signature():
    """cross_axis: error function + c q_own q_on: d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    q_on (...): position of the other axis, mm or deg
    returns (..., 3)
    """
    column = ca.SX.sym('column', 3)
    c_x = column[0]
    c_y = column[1]
    c_z = column[2]
    q = ca.SX.sym('q', 1)
    q = q[0]
    q_on = ca.SX.sym('q_on', 1)
    q_on = q_on[0]
    _x0 = q*q_on
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*c_x
    _out[1, 0] = _x0*c_y
    _out[2, 0] = _x0*c_z
    return ca.Function('signatures_cross_axis_signature', [column, q, q_on], [_out], ['column', 'q', 'q_on'], ['out'])


@functools.cache
def periodic_model():
    """periodic: positioning error + a_s sin(2 pi q / pitch) + a_c cos(2 pi q / pitch): the increment of the error function (mm or rad), for simulation.

    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    pitch (...): period of the periodic error, same unit as q
    params (..., 2): effect parameters [a_s, a_c]
        [a_s, a_c]
    returns (..., 1)
    """
    q = ca.SX.sym('q', 1)
    q = q[0]
    pitch = ca.SX.sym('pitch', 1)
    pitch = pitch[0]
    params = ca.SX.sym('params', 2)
    a_s = params[0]
    a_c = params[1]
    _x0 = 2*ca.pi*q/pitch
    _out = ca.SX.zeros(1, 1)
    _out[0, 0] = a_c*ca.cos(_x0) + a_s*ca.sin(_x0)
    return ca.Function('signatures_periodic_model', [q, pitch, params], [_out], ['q', 'pitch', 'params'], ['out'])


@functools.cache
def periodic_signature():
    """periodic: positioning error + a_s sin(2 pi q / pitch) + a_c cos(2 pi q / pitch): d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    pitch (...): period of the periodic error, same unit as q
    returns (..., 3, 2)
    """
    column = ca.SX.sym('column', 3)
    c_x = column[0]
    c_y = column[1]
    c_z = column[2]
    q = ca.SX.sym('q', 1)
    q = q[0]
    pitch = ca.SX.sym('pitch', 1)
    pitch = pitch[0]
    _x0 = 2*ca.pi*q/pitch
    _x1 = ca.sin(_x0)
    _x2 = ca.cos(_x0)
    _out = ca.SX.zeros(3, 2)
    _out[0, 0] = _x1*c_x
    _out[0, 1] = _x2*c_x
    _out[1, 0] = _x1*c_y
    _out[1, 1] = _x2*c_y
    _out[2, 0] = _x1*c_z
    _out[2, 1] = _x2*c_z
    return ca.Function('signatures_periodic_signature', [column, q, pitch], [_out], ['column', 'q', 'pitch'], ['out'])


@functools.cache
def thermal_drift_displacement():
    """thermal_drift: displacement A (1 - exp(-dt / tau)) of a drifting point, mm

    amplitude (..., 3): final displacement of the warm-up, mm
        [A_x, A_y, A_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 3)
    """
    amplitude = ca.SX.sym('amplitude', 3)
    A_x = amplitude[0]
    A_y = amplitude[1]
    A_z = amplitude[2]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    tau = ca.SX.sym('tau', 1)
    tau = tau[0]
    _x0 = 1 - ca.exp(-dt/tau)
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = A_x*_x0
    _out[1, 0] = A_y*_x0
    _out[2, 0] = A_z*_x0
    return ca.Function('signatures_thermal_drift_displacement', [amplitude, dt, tau], [_out], ['amplitude', 'dt', 'tau'], ['out'])


@functools.cache
def thermal_drift_signature():
    """thermal_drift: d point / d A (3 x 3), 1 (mm per mm)

    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 3, 3)
    """
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    tau = ca.SX.sym('tau', 1)
    tau = tau[0]
    _x0 = 1 - ca.exp(-dt/tau)
    _out = ca.SX.zeros(3, 3)
    _out[0, 0] = _x0
    _out[0, 1] = 0
    _out[0, 2] = 0
    _out[1, 0] = 0
    _out[1, 1] = _x0
    _out[1, 2] = 0
    _out[2, 0] = 0
    _out[2, 1] = 0
    _out[2, 2] = _x0
    return ca.Function('signatures_thermal_drift_signature', [dt, tau], [_out], ['dt', 'tau'], ['out'])


@functools.cache
def thermal_drift_dtau():
    """thermal_drift: d point / d tau at amplitude A, mm per s

    amplitude (..., 3): final displacement of the warm-up, mm
        [A_x, A_y, A_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 3)
    """
    amplitude = ca.SX.sym('amplitude', 3)
    A_x = amplitude[0]
    A_y = amplitude[1]
    A_z = amplitude[2]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    tau = ca.SX.sym('tau', 1)
    tau = tau[0]
    _x0 = dt*ca.exp(-dt/tau)/tau**2
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = -A_x*_x0
    _out[1, 0] = -A_y*_x0
    _out[2, 0] = -A_z*_x0
    return ca.Function('signatures_thermal_drift_dtau', [amplitude, dt, tau], [_out], ['amplitude', 'dt', 'tau'], ['out'])


@functools.cache
def tracker_scale_reading():
    """tracker_scale: the reading (mm) of a point when the tracker's distances scale by 1 + 1e-6 ppm about the tracker (refractive index of air wrong)

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    ppm (...): scale, 1e-6
    returns (..., 3)
    """
    xyz = ca.SX.sym('xyz', 3)
    x = xyz[0]
    y = xyz[1]
    z = xyz[2]
    tracker = ca.SX.sym('tracker', 3)
    tx = tracker[0]
    ty = tracker[1]
    tz = tracker[2]
    ppm = ca.SX.sym('ppm', 1)
    ppm = ppm[0]
    _x0 = (1/1000000)*ppm + 1
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*(-tx + x) + tx
    _out[1, 0] = _x0*(-ty + y) + ty
    _out[2, 0] = _x0*(-tz + z) + tz
    return ca.Function('signatures_tracker_scale_reading', [xyz, tracker, ppm], [_out], ['xyz', 'tracker', 'ppm'], ['out'])


@functools.cache
def tracker_scale_signature():
    """tracker_scale: d reading / d ppm (radial scaling about the tracker), mm per ppm

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    returns (..., 3)
    """
    xyz = ca.SX.sym('xyz', 3)
    x = xyz[0]
    y = xyz[1]
    z = xyz[2]
    tracker = ca.SX.sym('tracker', 3)
    tx = tracker[0]
    ty = tracker[1]
    tz = tracker[2]
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = -1/1000000*tx + (1/1000000)*x
    _out[1, 0] = -1/1000000*ty + (1/1000000)*y
    _out[2, 0] = -1/1000000*tz + (1/1000000)*z
    return ca.Function('signatures_tracker_scale_signature', [xyz, tracker], [_out], ['xyz', 'tracker'], ['out'])


@functools.cache
def thermal_temperature_displacement():
    """thermal_temperature: displacement c dT of a point of the drifting side, mm

    coefficient (..., 3): drift per kelvin of the temperature rise, mm/K
        [c_x, c_y, c_z]
    dT (...): temperature rise T - T_ref of the reading, K
    returns (..., 3)
    """
    coefficient = ca.SX.sym('coefficient', 3)
    c_x = coefficient[0]
    c_y = coefficient[1]
    c_z = coefficient[2]
    dT = ca.SX.sym('dT', 1)
    dT = dT[0]
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = c_x*dT
    _out[1, 0] = c_y*dT
    _out[2, 0] = c_z*dT
    return ca.Function('signatures_thermal_temperature_displacement', [coefficient, dT], [_out], ['coefficient', 'dT'], ['out'])


@functools.cache
def thermal_temperature_drift_signature():
    """thermal_temperature: d point / d c (3 x 3), mm per (mm/K)

    dT (...): temperature rise T - T_ref of the reading, K
    returns (..., 3, 3)
    """
    dT = ca.SX.sym('dT', 1)
    dT = dT[0]
    _out = ca.SX.zeros(3, 3)
    _out[0, 0] = dT
    _out[0, 1] = 0
    _out[0, 2] = 0
    _out[1, 0] = 0
    _out[1, 1] = dT
    _out[1, 2] = 0
    _out[2, 0] = 0
    _out[2, 1] = 0
    _out[2, 2] = dT
    return ca.Function('signatures_thermal_temperature_drift_signature', [dT], [_out], ['dT'], ['out'])


@functools.cache
def thermal_temperature_curve():
    """warm-up curve of the temperature channel: T0 + rise (1 - exp(-dt / tau)), degC

    start_c (...): temperature at the start, degC
    rise_c (...): final rise of the warm-up, K
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 1)
    """
    start_c = ca.SX.sym('start_c', 1)
    T0 = start_c[0]
    rise_c = ca.SX.sym('rise_c', 1)
    rise = rise_c[0]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    tau = ca.SX.sym('tau', 1)
    tau = tau[0]
    _out = ca.SX.zeros(1, 1)
    _out[0, 0] = T0 + rise*(1 - ca.exp(-dt/tau))
    return ca.Function('signatures_thermal_temperature_curve', [start_c, rise_c, dt, tau], [_out], ['start_c', 'rise_c', 'dt', 'tau'], ['out'])


@functools.cache
def nest_creep_model():
    """nest_creep: displacement v dt of the nest in its side's local frame, mm (for simulation: added to the reflector's local coordinates before the exact kinematics)

    velocity (..., 3): creep velocity of the nest in its side's local frame, mm/s
        [v_x, v_y, v_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    returns (..., 3)
    """
    velocity = ca.SX.sym('velocity', 3)
    v_x = velocity[0]
    v_y = velocity[1]
    v_z = velocity[2]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = dt*v_x
    _out[1, 0] = dt*v_y
    _out[2, 0] = dt*v_z
    return ca.Function('signatures_nest_creep_model', [velocity, dt], [_out], ['velocity', 'dt'], ['out'])


@functools.cache
def nest_creep_signature():
    """nest_creep: d reading / d v (3 x 3) = R dt, mm per (mm/s)

    rotation (..., 9): the side's rotation local -> machine frame, row-major (9,)
        [R_00, R_01, R_02, R_10, R_11, R_12, R_20, R_21, R_22]
    dt (...): time since the start of the warm-up, s (0 before it)
    returns (..., 3, 3)
    """
    rotation = ca.SX.sym('rotation', 9)
    R_00 = rotation[0]
    R_01 = rotation[1]
    R_02 = rotation[2]
    R_10 = rotation[3]
    R_11 = rotation[4]
    R_12 = rotation[5]
    R_20 = rotation[6]
    R_21 = rotation[7]
    R_22 = rotation[8]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    _out = ca.SX.zeros(3, 3)
    _out[0, 0] = R_00*dt
    _out[0, 1] = R_01*dt
    _out[0, 2] = R_02*dt
    _out[1, 0] = R_10*dt
    _out[1, 1] = R_11*dt
    _out[1, 2] = R_12*dt
    _out[2, 0] = R_20*dt
    _out[2, 1] = R_21*dt
    _out[2, 2] = R_22*dt
    return ca.Function('signatures_nest_creep_signature', [rotation, dt], [_out], ['rotation', 'dt'], ['out'])


@functools.cache
def tracker_settling_angle():
    """tracker_settling: tilt angle w dt + a (1 - exp(-dt / tau)), rad

    params (..., 2): [w (rad/s), a (rad)]
        [w, a]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 1)
    """
    params = ca.SX.sym('params', 2)
    w = params[0]
    a = params[1]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    tau = ca.SX.sym('tau', 1)
    tau = tau[0]
    _out = ca.SX.zeros(1, 1)
    _out[0, 0] = a*(1 - ca.exp(-dt/tau)) + dt*w
    return ca.Function('signatures_tracker_settling_angle', [params, dt, tau], [_out], ['params', 'dt', 'tau'], ['out'])


@functools.cache
def tracker_settling_reading():
    """tracker_settling: the reading (mm) of a point when the tracker has turned by theta about the axis u through it (exact rotation)

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    about (..., 3): unit vector of the rotation axis through the tracker, machine frame
        [u_x, u_y, u_z]
    theta (...): tilt, rad
    returns (..., 3)
    """
    xyz = ca.SX.sym('xyz', 3)
    x = xyz[0]
    y = xyz[1]
    z = xyz[2]
    tracker = ca.SX.sym('tracker', 3)
    tx = tracker[0]
    ty = tracker[1]
    tz = tracker[2]
    about = ca.SX.sym('about', 3)
    u_x = about[0]
    u_y = about[1]
    u_z = about[2]
    theta = ca.SX.sym('theta', 1)
    theta = theta[0]
    _x0 = -tx + x
    _x1 = ca.cos(theta)
    _x2 = 1 - _x1
    _x3 = -tz + z
    _x4 = ca.sin(theta)
    _x5 = _x4*u_y
    _x6 = _x2*u_x
    _x7 = _x6*u_z
    _x8 = -ty + y
    _x9 = _x4*u_z
    _x10 = _x6*u_y
    _x11 = _x4*u_x
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*(_x1 + _x2*u_x**2) + _x3*(_x5 + _x7) + _x8*(_x10 - _x9) + tx
    _out[1, 0] = _x0*(_x10 + _x9) + _x3*(-_x11 + _x2*u_y*u_z) + _x8*(_x1 + _x2*u_y**2) + ty
    _out[2, 0] = _x0*(-_x5 + _x7) + _x3*(_x1 + _x2*u_z**2) + _x8*(_x11 + _x2*u_y*u_z) + tz
    return ca.Function('signatures_tracker_settling_reading', [xyz, tracker, about, theta], [_out], ['xyz', 'tracker', 'about', 'theta'], ['out'])


@functools.cache
def tracker_settling_signature():
    """tracker_settling: d reading / d [w, a] (3 x 2) = u x (point - T) [dt, 1 - exp(-dt / tau)], mm per (rad/s) and mm per rad

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    about (..., 3): unit vector of the rotation axis through the tracker, machine frame
        [u_x, u_y, u_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 3, 2)
    """
    xyz = ca.SX.sym('xyz', 3)
    x = xyz[0]
    y = xyz[1]
    z = xyz[2]
    tracker = ca.SX.sym('tracker', 3)
    tx = tracker[0]
    ty = tracker[1]
    tz = tracker[2]
    about = ca.SX.sym('about', 3)
    u_x = about[0]
    u_y = about[1]
    u_z = about[2]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    tau = ca.SX.sym('tau', 1)
    tau = tau[0]
    _x0 = -tz + z
    _x1 = _x0*u_y
    _x2 = -ty + y
    _x3 = _x2*u_z
    _x4 = 1 - ca.exp(-dt/tau)
    _x5 = _x0*u_x
    _x6 = -tx + x
    _x7 = _x2*u_x
    _x8 = _x6*u_y
    _out = ca.SX.zeros(3, 2)
    _out[0, 0] = _x1*dt - _x3*dt
    _out[0, 1] = _x1*_x4 - _x3*_x4
    _out[1, 0] = -_x5*dt + _x6*dt*u_z
    _out[1, 1] = -_x4*_x5 + _x4*_x6*u_z
    _out[2, 0] = _x7*dt - _x8*dt
    _out[2, 1] = _x4*_x7 - _x4*_x8
    return ca.Function('signatures_tracker_settling_signature', [xyz, tracker, about, dt, tau], [_out], ['xyz', 'tracker', 'about', 'dt', 'tau'], ['out'])


@functools.cache
def tracker_spherical_coordinates():
    """tracker_spherical: the point's coordinates about the tracker, [rho (mm), az (rad), el (rad)]

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    returns (..., 3)
    """
    xyz = ca.SX.sym('xyz', 3)
    x = xyz[0]
    y = xyz[1]
    z = xyz[2]
    tracker = ca.SX.sym('tracker', 3)
    tx = tracker[0]
    ty = tracker[1]
    tz = tracker[2]
    _x0 = -tz + z
    _x1 = -tx + x
    _x2 = -ty + y
    _x3 = _x1**2 + _x2**2
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = ca.sqrt(_x0**2 + _x3)
    _out[1, 0] = ca.atan2(_x2, _x1)
    _out[2, 0] = ca.atan2(_x0, ca.sqrt(_x3))
    return ca.Function('signatures_tracker_spherical_coordinates', [xyz, tracker], [_out], ['xyz', 'tracker'], ['out'])


@functools.cache
def tracker_spherical_reading():
    """tracker_spherical: the reading (mm) of a point when the tracker's distance, azimuth and elevation read off by d_rho (mm), d_az and d_el (rad)

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    params (..., 3): [d_rho (mm), d_az (rad), d_el (rad)]
        [d_rho, d_az, d_el]
    returns (..., 3)
    """
    xyz = ca.SX.sym('xyz', 3)
    x = xyz[0]
    y = xyz[1]
    z = xyz[2]
    tracker = ca.SX.sym('tracker', 3)
    tx = tracker[0]
    ty = tracker[1]
    tz = tracker[2]
    params = ca.SX.sym('params', 3)
    d_rho = params[0]
    d_az = params[1]
    d_el = params[2]
    _x0 = -ty + y
    _x1 = -tx + x
    _x2 = d_az + ca.atan2(_x0, _x1)
    _x3 = -tz + z
    _x4 = _x0**2 + _x1**2
    _x5 = d_rho + ca.sqrt(_x3**2 + _x4)
    _x6 = d_el + ca.atan2(_x3, ca.sqrt(_x4))
    _x7 = _x5*ca.cos(_x6)
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x7*ca.cos(_x2) + tx
    _out[1, 0] = _x7*ca.sin(_x2) + ty
    _out[2, 0] = _x5*ca.sin(_x6) + tz
    return ca.Function('signatures_tracker_spherical_reading', [xyz, tracker, params], [_out], ['xyz', 'tracker', 'params'], ['out'])


@functools.cache
def tracker_spherical_signature():
    """tracker_spherical: d reading / d [d_rho, d_az, d_el] (3 x 3): the beam's unit vector, z x (point - T), and rho times the unit vector of rising elevation; mm per mm, mm per rad

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    returns (..., 3, 3)
    """
    xyz = ca.SX.sym('xyz', 3)
    x = xyz[0]
    y = xyz[1]
    z = xyz[2]
    tracker = ca.SX.sym('tracker', 3)
    tx = tracker[0]
    ty = tracker[1]
    tz = tracker[2]
    _x0 = tx - x
    _x1 = -_x0
    _x2 = tz - z
    _x3 = ty - y
    _x4 = _x0**2 + _x3**2
    _x5 = 1/ca.sqrt(_x2**2 + _x4)
    _x6 = ca.sqrt(_x4)
    _x7 = _x2/_x6
    _out = ca.SX.zeros(3, 3)
    _out[0, 0] = _x1*_x5
    _out[0, 1] = _x3
    _out[0, 2] = -_x0*_x7
    _out[1, 0] = -_x3*_x5
    _out[1, 1] = _x1
    _out[1, 2] = -_x3*_x7
    _out[2, 0] = -_x2*_x5
    _out[2, 1] = 0
    _out[2, 2] = _x6
    return ca.Function('signatures_tracker_spherical_signature', [xyz, tracker], [_out], ['xyz', 'tracker'], ['out'])


@functools.cache
def outlier_signature():
    """outlier: d reading / d displacement s (3 x 3) for a displaced reading (on = 1)

    on (...): 1 for the displaced readings, 0 otherwise
    returns (..., 3, 3)
    """
    on = ca.SX.sym('on', 1)
    on = on[0]
    _out = ca.SX.zeros(3, 3)
    _out[0, 0] = on
    _out[0, 1] = 0
    _out[0, 2] = 0
    _out[1, 0] = 0
    _out[1, 1] = on
    _out[1, 2] = 0
    _out[2, 0] = 0
    _out[2, 1] = 0
    _out[2, 2] = on
    return ca.Function('signatures_outlier_signature', [on], [_out], ['on'], ['out'])


@functools.cache
def air_index_drift_ramp_model():
    """air_index_drift (ramp): displacement 1e-6 e (dt / 3600 s) (point - tracker) of a reading, mm (e in ppm per hour: the tracker's distances scale as the air's refractive index drifts uncompensated)

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    dt (...): time since the start of the warm-up, s (0 before it)
    params (..., 1): parameters [e]
        [e]
    returns (..., 3)
    """
    xyz = ca.SX.sym('xyz', 3)
    x = xyz[0]
    y = xyz[1]
    z = xyz[2]
    tracker = ca.SX.sym('tracker', 3)
    tx = tracker[0]
    ty = tracker[1]
    tz = tracker[2]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    params = ca.SX.sym('params', 1)
    e = params[0]
    _x0 = (1/3600000000)*dt*e
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*(-tx + x)
    _out[1, 0] = _x0*(-ty + y)
    _out[2, 0] = _x0*(-tz + z)
    return ca.Function('signatures_air_index_drift_ramp_model', [xyz, tracker, dt, params], [_out], ['xyz', 'tracker', 'dt', 'params'], ['out'])


@functools.cache
def air_index_drift_ramp_signature():
    """air_index_drift (ramp): d reading / d e = 1e-6 (dt / 3600 s) (point - tracker), mm per (ppm/h)

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    dt (...): time since the start of the warm-up, s (0 before it)
    returns (..., 3)
    """
    xyz = ca.SX.sym('xyz', 3)
    x = xyz[0]
    y = xyz[1]
    z = xyz[2]
    tracker = ca.SX.sym('tracker', 3)
    tx = tracker[0]
    ty = tracker[1]
    tz = tracker[2]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    _x0 = (1/3600000000)*dt
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*(-tx + x)
    _out[1, 0] = _x0*(-ty + y)
    _out[2, 0] = _x0*(-tz + z)
    return ca.Function('signatures_air_index_drift_ramp_signature', [xyz, tracker, dt], [_out], ['xyz', 'tracker', 'dt'], ['out'])


@functools.cache
def air_index_drift_lag_model():
    """air_index_drift (lag): displacement 1e-6 e (1 - exp(-dt / tau)) (point - tracker), mm (e in ppm)

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    params (..., 1): parameters [e]
        [e]
    returns (..., 3)
    """
    xyz = ca.SX.sym('xyz', 3)
    x = xyz[0]
    y = xyz[1]
    z = xyz[2]
    tracker = ca.SX.sym('tracker', 3)
    tx = tracker[0]
    ty = tracker[1]
    tz = tracker[2]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    tau = ca.SX.sym('tau', 1)
    tau = tau[0]
    params = ca.SX.sym('params', 1)
    e = params[0]
    _x0 = (1/1000000)*e*(1 - ca.exp(-dt/tau))
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*(-tx + x)
    _out[1, 0] = _x0*(-ty + y)
    _out[2, 0] = _x0*(-tz + z)
    return ca.Function('signatures_air_index_drift_lag_model', [xyz, tracker, dt, tau, params], [_out], ['xyz', 'tracker', 'dt', 'tau', 'params'], ['out'])


@functools.cache
def air_index_drift_lag_signature():
    """air_index_drift (lag): d reading / d e = 1e-6 (1 - exp(-dt / tau)) (point - tracker), mm per ppm

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 3)
    """
    xyz = ca.SX.sym('xyz', 3)
    x = xyz[0]
    y = xyz[1]
    z = xyz[2]
    tracker = ca.SX.sym('tracker', 3)
    tx = tracker[0]
    ty = tracker[1]
    tz = tracker[2]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    tau = ca.SX.sym('tau', 1)
    tau = tau[0]
    _x0 = 1/1000000 - 1/1000000*ca.exp(-dt/tau)
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*(-tx + x)
    _out[1, 0] = _x0*(-ty + y)
    _out[2, 0] = _x0*(-tz + z)
    return ca.Function('signatures_air_index_drift_lag_signature', [xyz, tracker, dt, tau], [_out], ['xyz', 'tracker', 'dt', 'tau'], ['out'])


@functools.cache
def side_expansion_ramp_model():
    """side_expansion (ramp): displacement 1e-6 e (dt / 3600 s) (local - centroid) of a reflector in its side's local frame, mm (e in ppm per hour)

    offset (..., 3): reflector's local position less its side's layout centroid, mm, the side's local frame
        [o_x, o_y, o_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    params (..., 1): parameters [e]
        [e]
    returns (..., 3)
    """
    offset = ca.SX.sym('offset', 3)
    o_x = offset[0]
    o_y = offset[1]
    o_z = offset[2]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    params = ca.SX.sym('params', 1)
    e = params[0]
    _x0 = (1/3600000000)*dt*e
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*o_x
    _out[1, 0] = _x0*o_y
    _out[2, 0] = _x0*o_z
    return ca.Function('signatures_side_expansion_ramp_model', [offset, dt, params], [_out], ['offset', 'dt', 'params'], ['out'])


@functools.cache
def side_expansion_ramp_signature():
    """side_expansion (ramp): d reading / d e = 1e-6 (dt / 3600 s) R (local - centroid), mm per (ppm/h)

    rotation (..., 9): the side's rotation local -> machine frame, row-major (9,)
        [R_00, R_01, R_02, R_10, R_11, R_12, R_20, R_21, R_22]
    offset (..., 3): reflector's local position less its side's layout centroid, mm, the side's local frame
        [o_x, o_y, o_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    returns (..., 3)
    """
    rotation = ca.SX.sym('rotation', 9)
    R_00 = rotation[0]
    R_01 = rotation[1]
    R_02 = rotation[2]
    R_10 = rotation[3]
    R_11 = rotation[4]
    R_12 = rotation[5]
    R_20 = rotation[6]
    R_21 = rotation[7]
    R_22 = rotation[8]
    offset = ca.SX.sym('offset', 3)
    o_x = offset[0]
    o_y = offset[1]
    o_z = offset[2]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    _x0 = (1/3600000000)*dt
    _x1 = _x0*o_x
    _x2 = _x0*o_y
    _x3 = _x0*o_z
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = R_00*_x1 + R_01*_x2 + R_02*_x3
    _out[1, 0] = R_10*_x1 + R_11*_x2 + R_12*_x3
    _out[2, 0] = R_20*_x1 + R_21*_x2 + R_22*_x3
    return ca.Function('signatures_side_expansion_ramp_signature', [rotation, offset, dt], [_out], ['rotation', 'offset', 'dt'], ['out'])


@functools.cache
def side_expansion_lag_model():
    """side_expansion (lag): displacement 1e-6 e (1 - exp(-dt / tau)) (local - centroid), mm (e in ppm)

    offset (..., 3): reflector's local position less its side's layout centroid, mm, the side's local frame
        [o_x, o_y, o_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    params (..., 1): parameters [e]
        [e]
    returns (..., 3)
    """
    offset = ca.SX.sym('offset', 3)
    o_x = offset[0]
    o_y = offset[1]
    o_z = offset[2]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    tau = ca.SX.sym('tau', 1)
    tau = tau[0]
    params = ca.SX.sym('params', 1)
    e = params[0]
    _x0 = (1/1000000)*e*(1 - ca.exp(-dt/tau))
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = _x0*o_x
    _out[1, 0] = _x0*o_y
    _out[2, 0] = _x0*o_z
    return ca.Function('signatures_side_expansion_lag_model', [offset, dt, tau, params], [_out], ['offset', 'dt', 'tau', 'params'], ['out'])


@functools.cache
def side_expansion_lag_signature():
    """side_expansion (lag): d reading / d e = 1e-6 (1 - exp(-dt / tau)) R (local - centroid), mm per ppm

    rotation (..., 9): the side's rotation local -> machine frame, row-major (9,)
        [R_00, R_01, R_02, R_10, R_11, R_12, R_20, R_21, R_22]
    offset (..., 3): reflector's local position less its side's layout centroid, mm, the side's local frame
        [o_x, o_y, o_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 3)
    """
    rotation = ca.SX.sym('rotation', 9)
    R_00 = rotation[0]
    R_01 = rotation[1]
    R_02 = rotation[2]
    R_10 = rotation[3]
    R_11 = rotation[4]
    R_12 = rotation[5]
    R_20 = rotation[6]
    R_21 = rotation[7]
    R_22 = rotation[8]
    offset = ca.SX.sym('offset', 3)
    o_x = offset[0]
    o_y = offset[1]
    o_z = offset[2]
    dt = ca.SX.sym('dt', 1)
    dt = dt[0]
    tau = ca.SX.sym('tau', 1)
    tau = tau[0]
    _x0 = 1/1000000 - 1/1000000*ca.exp(-dt/tau)
    _x1 = _x0*o_x
    _x2 = _x0*o_y
    _x3 = _x0*o_z
    _out = ca.SX.zeros(3, 1)
    _out[0, 0] = R_00*_x1 + R_01*_x2 + R_02*_x3
    _out[1, 0] = R_10*_x1 + R_11*_x2 + R_12*_x3
    _out[2, 0] = R_20*_x1 + R_21*_x2 + R_22*_x3
    return ca.Function('signatures_side_expansion_lag_signature', [rotation, offset, dt, tau], [_out], ['rotation', 'offset', 'dt', 'tau'], ['out'])


@functools.cache
def backlash_travel_model():
    """backlash_travel: positioning error + d / 2 (b + g q): a reversal b + g q growing along the travel, mm (rad)

    d (...): approach direction, +1 or -1
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    params (..., 2): parameters [b, g]
        [b, g]
    returns (..., 1)
    """
    d = ca.SX.sym('d', 1)
    d = d[0]
    q = ca.SX.sym('q', 1)
    q = q[0]
    params = ca.SX.sym('params', 2)
    b = params[0]
    g = params[1]
    _x0 = (1/2)*d
    _out = ca.SX.zeros(1, 1)
    _out[0, 0] = _x0*b + _x0*g*q
    return ca.Function('signatures_backlash_travel_model', [d, q, params], [_out], ['d', 'q', 'params'], ['out'])


@functools.cache
def backlash_travel_signature():
    """backlash_travel: d reading / d [b, g] = column d / 2 [1, q], mm per mm and mm per (mm/mm)

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    d (...): approach direction, +1 or -1
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    returns (..., 3, 2)
    """
    column = ca.SX.sym('column', 3)
    c_x = column[0]
    c_y = column[1]
    c_z = column[2]
    d = ca.SX.sym('d', 1)
    d = d[0]
    q = ca.SX.sym('q', 1)
    q = q[0]
    _x0 = (1/2)*d
    _x1 = _x0*c_x
    _x2 = _x0*c_y
    _x3 = _x0*c_z
    _out = ca.SX.zeros(3, 2)
    _out[0, 0] = _x1
    _out[0, 1] = _x1*q
    _out[1, 0] = _x2
    _out[1, 1] = _x2*q
    _out[2, 0] = _x3
    _out[2, 1] = _x3*q
    return ca.Function('signatures_backlash_travel_signature', [column, d, q], [_out], ['column', 'd', 'q'], ['out'])


@functools.cache
def tracker_relevel_signature():
    """tracker_relevel: d reading / d [w_x, w_y] = on [e_x, e_y] x (point - tracker), mm per rad (a rotation step about horizontal axes through the tracker, from a round's first reading on)

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    on (...): 1 for the displaced readings, 0 otherwise
    returns (..., 3, 2)
    """
    xyz = ca.SX.sym('xyz', 3)
    x = xyz[0]
    y = xyz[1]
    z = xyz[2]
    tracker = ca.SX.sym('tracker', 3)
    tx = tracker[0]
    ty = tracker[1]
    tz = tracker[2]
    on = ca.SX.sym('on', 1)
    on = on[0]
    _x0 = on*(-tz + z)
    _out = ca.SX.zeros(3, 2)
    _out[0, 0] = 0
    _out[0, 1] = _x0
    _out[1, 0] = -_x0
    _out[1, 1] = 0
    _out[2, 0] = on*(-ty + y)
    _out[2, 1] = -on*(-tx + x)
    return ca.Function('signatures_tracker_relevel_signature', [xyz, tracker, on], [_out], ['xyz', 'tracker', 'on'], ['out'])
