# -----------------------------------------------------------------------------
# GENERATED FILE - DO NOT EDIT.
# Generator: python -m derive (signatures); source: derive/signatures.py
# Target: NumPy (vectorised, broadcasting).  Regenerate with `python -m derive`; CI runs `python -m derive --check`.
# Inputs (machine spec, SymPy/CasADi versions, hash of derive/) are in manifest.json.
# -----------------------------------------------------------------------------
"""Signatures of left-out effects in laser-tracker readings: d(measured point) / d(effect parameters).

NumPy implementation."""
import numpy

from mtcal._gensupport import as_arg, out_array

FUNCTIONS = ('backlash_model', 'backlash_signature', 'reversal_angular_model', 'reversal_angular_signature', 'thermal_temperature_model', 'thermal_temperature_signature', 'scale_model', 'scale_signature', 'second_order_model', 'second_order_signature', 'cross_axis_model', 'cross_axis_signature', 'periodic_model', 'periodic_signature', 'thermal_drift_displacement', 'thermal_drift_signature', 'thermal_drift_dtau', 'tracker_scale_reading', 'tracker_scale_signature', 'thermal_temperature_displacement', 'thermal_temperature_drift_signature', 'thermal_temperature_curve', 'nest_creep_model', 'nest_creep_signature', 'tracker_settling_angle', 'tracker_settling_reading', 'tracker_settling_signature', 'tracker_spherical_coordinates', 'tracker_spherical_reading', 'tracker_spherical_signature', 'outlier_signature', 'air_index_drift_ramp_model', 'air_index_drift_ramp_signature', 'air_index_drift_lag_model', 'air_index_drift_lag_signature', 'side_expansion_ramp_model', 'side_expansion_ramp_signature', 'side_expansion_lag_model', 'side_expansion_lag_signature', 'backlash_travel_model', 'backlash_travel_signature', 'tracker_relevel_signature')


def backlash_model(d, params):
    """backlash: positioning error + d b / 2 (b = error(+ approach) - error(- approach), mm or rad): the increment of the error function (mm or rad), for simulation.

    d (...): approach direction, +1 or -1
    params (..., 1): effect parameters [b]
        [b]
    returns (..., 1)
    """
    d = as_arg(d, 0, 'd', 'backlash_model')
    params = as_arg(params, 1, 'params', 'backlash_model')
    d = d
    b = params[..., 0]
    _out = out_array((d.shape, params.shape[:-1],), (1,))
    _out[..., 0] = (1/2)*b*d
    return _out


def backlash_signature(column, d):
    """backlash: positioning error + d b / 2 (b = error(+ approach) - error(- approach), mm or rad): d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    d (...): approach direction, +1 or -1
    returns (..., 3)
    """
    column = as_arg(column, 3, 'column', 'backlash_signature')
    d = as_arg(d, 0, 'd', 'backlash_signature')
    c_x = column[..., 0]
    c_y = column[..., 1]
    c_z = column[..., 2]
    d = d
    _x0 = (1/2)*d
    _out = out_array((column.shape[:-1], d.shape,), (3,))
    _out[..., 0] = _x0*c_x
    _out[..., 1] = _x0*c_y
    _out[..., 2] = _x0*c_z
    return _out


def reversal_angular_model(d, params):
    """reversal_angular: angular error of a linear axis + d r / 2 (r = angle(+ approach) - angle(- approach), rad): the increment of the error function (mm or rad), for simulation.

    d (...): approach direction, +1 or -1
    params (..., 1): effect parameters [r]
        [r]
    returns (..., 1)
    """
    d = as_arg(d, 0, 'd', 'reversal_angular_model')
    params = as_arg(params, 1, 'params', 'reversal_angular_model')
    d = d
    r = params[..., 0]
    _out = out_array((d.shape, params.shape[:-1],), (1,))
    _out[..., 0] = (1/2)*d*r
    return _out


def reversal_angular_signature(column, d):
    """reversal_angular: angular error of a linear axis + d r / 2 (r = angle(+ approach) - angle(- approach), rad): d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    d (...): approach direction, +1 or -1
    returns (..., 3)
    """
    column = as_arg(column, 3, 'column', 'reversal_angular_signature')
    d = as_arg(d, 0, 'd', 'reversal_angular_signature')
    c_x = column[..., 0]
    c_y = column[..., 1]
    c_z = column[..., 2]
    d = d
    _x0 = (1/2)*d
    _out = out_array((column.shape[:-1], d.shape,), (3,))
    _out[..., 0] = _x0*c_x
    _out[..., 1] = _x0*c_y
    _out[..., 2] = _x0*c_z
    return _out


def thermal_temperature_model(q, dT, params):
    """thermal_temperature: positioning error of a linear axis + 1e-6 k dT q (expansion, k in ppm/K, q in mm): the increment of the error function (mm or rad), for simulation.

    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    dT (...): temperature rise T - T_ref of the reading, K
    params (..., 1): effect parameters [k_ppm_per_K]
        [k_ppm_per_K]
    returns (..., 1)
    """
    q = as_arg(q, 0, 'q', 'thermal_temperature_model')
    dT = as_arg(dT, 0, 'dT', 'thermal_temperature_model')
    params = as_arg(params, 1, 'params', 'thermal_temperature_model')
    q = q
    dT = dT
    k_ppm_per_K = params[..., 0]
    _out = out_array((q.shape, dT.shape, params.shape[:-1],), (1,))
    _out[..., 0] = (1/1000000)*dT*k_ppm_per_K*q
    return _out


def thermal_temperature_signature(column, q, dT):
    """thermal_temperature: positioning error of a linear axis + 1e-6 k dT q (expansion, k in ppm/K, q in mm): d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    dT (...): temperature rise T - T_ref of the reading, K
    returns (..., 3)
    """
    column = as_arg(column, 3, 'column', 'thermal_temperature_signature')
    q = as_arg(q, 0, 'q', 'thermal_temperature_signature')
    dT = as_arg(dT, 0, 'dT', 'thermal_temperature_signature')
    c_x = column[..., 0]
    c_y = column[..., 1]
    c_z = column[..., 2]
    q = q
    dT = dT
    _x0 = (1/1000000)*dT*q
    _out = out_array((column.shape[:-1], q.shape, dT.shape,), (3,))
    _out[..., 0] = _x0*c_x
    _out[..., 1] = _x0*c_y
    _out[..., 2] = _x0*c_z
    return _out


def scale_model(q, params):
    """scale: positioning error + 1e-6 ppm q (q in mm, or rad for rotary): the increment of the error function (mm or rad), for simulation.

    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    params (..., 1): effect parameters [ppm]
        [ppm]
    returns (..., 1)
    """
    q = as_arg(q, 0, 'q', 'scale_model')
    params = as_arg(params, 1, 'params', 'scale_model')
    q = q
    ppm = params[..., 0]
    _out = out_array((q.shape, params.shape[:-1],), (1,))
    _out[..., 0] = (1/1000000)*ppm*q
    return _out


def scale_signature(column, q):
    """scale: positioning error + 1e-6 ppm q (q in mm, or rad for rotary): d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    returns (..., 3)
    """
    column = as_arg(column, 3, 'column', 'scale_signature')
    q = as_arg(q, 0, 'q', 'scale_signature')
    c_x = column[..., 0]
    c_y = column[..., 1]
    c_z = column[..., 2]
    q = q
    _x0 = (1/1000000)*q
    _out = out_array((column.shape[:-1], q.shape,), (3,))
    _out[..., 0] = _x0*c_x
    _out[..., 1] = _x0*c_y
    _out[..., 2] = _x0*c_z
    return _out


def second_order_model(q, params):
    """second_order: error function + c q^2 (per mm^2 or deg^2): the increment of the error function (mm or rad), for simulation.

    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    params (..., 1): effect parameters [c2]
        [c2]
    returns (..., 1)
    """
    q = as_arg(q, 0, 'q', 'second_order_model')
    params = as_arg(params, 1, 'params', 'second_order_model')
    q = q
    c2 = params[..., 0]
    _out = out_array((q.shape, params.shape[:-1],), (1,))
    _out[..., 0] = c2*q**2
    return _out


def second_order_signature(column, q):
    """second_order: error function + c q^2 (per mm^2 or deg^2): d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    returns (..., 3)
    """
    column = as_arg(column, 3, 'column', 'second_order_signature')
    q = as_arg(q, 0, 'q', 'second_order_signature')
    c_x = column[..., 0]
    c_y = column[..., 1]
    c_z = column[..., 2]
    q = q
    _x0 = q**2
    _out = out_array((column.shape[:-1], q.shape,), (3,))
    _out[..., 0] = _x0*c_x
    _out[..., 1] = _x0*c_y
    _out[..., 2] = _x0*c_z
    return _out


def cross_axis_model(q, q_on, params):
    """cross_axis: error function + c q_own q_on: the increment of the error function (mm or rad), for simulation.

    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    q_on (...): position of the other axis, mm or deg
    params (..., 1): effect parameters [cx]
        [cx]
    returns (..., 1)
    """
    q = as_arg(q, 0, 'q', 'cross_axis_model')
    q_on = as_arg(q_on, 0, 'q_on', 'cross_axis_model')
    params = as_arg(params, 1, 'params', 'cross_axis_model')
    q = q
    q_on = q_on
    cx = params[..., 0]
    _out = out_array((q.shape, q_on.shape, params.shape[:-1],), (1,))
    _out[..., 0] = cx*q*q_on
    return _out


def cross_axis_signature(column, q, q_on):
    """cross_axis: error function + c q_own q_on: d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    q_on (...): position of the other axis, mm or deg
    returns (..., 3)
    """
    column = as_arg(column, 3, 'column', 'cross_axis_signature')
    q = as_arg(q, 0, 'q', 'cross_axis_signature')
    q_on = as_arg(q_on, 0, 'q_on', 'cross_axis_signature')
    c_x = column[..., 0]
    c_y = column[..., 1]
    c_z = column[..., 2]
    q = q
    q_on = q_on
    _x0 = q*q_on
    _out = out_array((column.shape[:-1], q.shape, q_on.shape,), (3,))
    _out[..., 0] = _x0*c_x
    _out[..., 1] = _x0*c_y
    _out[..., 2] = _x0*c_z
    return _out


def periodic_model(q, pitch, params):
    """periodic: positioning error + a_s sin(2 pi q / pitch) + a_c cos(2 pi q / pitch): the increment of the error function (mm or rad), for simulation.

    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    pitch (...): period of the periodic error, same unit as q
    params (..., 2): effect parameters [a_s, a_c]
        [a_s, a_c]
    returns (..., 1)
    """
    q = as_arg(q, 0, 'q', 'periodic_model')
    pitch = as_arg(pitch, 0, 'pitch', 'periodic_model')
    params = as_arg(params, 2, 'params', 'periodic_model')
    q = q
    pitch = pitch
    a_s = params[..., 0]
    a_c = params[..., 1]
    _x0 = 2*numpy.pi*q/pitch
    _out = out_array((q.shape, pitch.shape, params.shape[:-1],), (1,))
    _out[..., 0] = a_c*numpy.cos(_x0) + a_s*numpy.sin(_x0)
    return _out


def periodic_signature(column, q, pitch):
    """periodic: positioning error + a_s sin(2 pi q / pitch) + a_c cos(2 pi q / pitch): d point / d parameters at zero effect = column x d increment / d parameters, mm per parameter unit.

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    pitch (...): period of the periodic error, same unit as q
    returns (..., 3, 2)
    """
    column = as_arg(column, 3, 'column', 'periodic_signature')
    q = as_arg(q, 0, 'q', 'periodic_signature')
    pitch = as_arg(pitch, 0, 'pitch', 'periodic_signature')
    c_x = column[..., 0]
    c_y = column[..., 1]
    c_z = column[..., 2]
    q = q
    pitch = pitch
    _x0 = 2*numpy.pi*q/pitch
    _x1 = numpy.sin(_x0)
    _x2 = numpy.cos(_x0)
    _out = out_array((column.shape[:-1], q.shape, pitch.shape,), (3, 2))
    _out[..., 0, 0] = _x1*c_x
    _out[..., 0, 1] = _x2*c_x
    _out[..., 1, 0] = _x1*c_y
    _out[..., 1, 1] = _x2*c_y
    _out[..., 2, 0] = _x1*c_z
    _out[..., 2, 1] = _x2*c_z
    return _out


def thermal_drift_displacement(amplitude, dt, tau):
    """thermal_drift: displacement A (1 - exp(-dt / tau)) of a drifting point, mm

    amplitude (..., 3): final displacement of the warm-up, mm
        [A_x, A_y, A_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 3)
    """
    amplitude = as_arg(amplitude, 3, 'amplitude', 'thermal_drift_displacement')
    dt = as_arg(dt, 0, 'dt', 'thermal_drift_displacement')
    tau = as_arg(tau, 0, 'tau', 'thermal_drift_displacement')
    A_x = amplitude[..., 0]
    A_y = amplitude[..., 1]
    A_z = amplitude[..., 2]
    dt = dt
    tau = tau
    _x0 = 1 - numpy.exp(-dt/tau)
    _out = out_array((amplitude.shape[:-1], dt.shape, tau.shape,), (3,))
    _out[..., 0] = A_x*_x0
    _out[..., 1] = A_y*_x0
    _out[..., 2] = A_z*_x0
    return _out


def thermal_drift_signature(dt, tau):
    """thermal_drift: d point / d A (3 x 3), 1 (mm per mm)

    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 3, 3)
    """
    dt = as_arg(dt, 0, 'dt', 'thermal_drift_signature')
    tau = as_arg(tau, 0, 'tau', 'thermal_drift_signature')
    dt = dt
    tau = tau
    _x0 = 1 - numpy.exp(-dt/tau)
    _out = out_array((dt.shape, tau.shape,), (3, 3))
    _out[..., 0, 0] = _x0
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = _x0
    _out[..., 1, 2] = 0
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = _x0
    return _out


def thermal_drift_dtau(amplitude, dt, tau):
    """thermal_drift: d point / d tau at amplitude A, mm per s

    amplitude (..., 3): final displacement of the warm-up, mm
        [A_x, A_y, A_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 3)
    """
    amplitude = as_arg(amplitude, 3, 'amplitude', 'thermal_drift_dtau')
    dt = as_arg(dt, 0, 'dt', 'thermal_drift_dtau')
    tau = as_arg(tau, 0, 'tau', 'thermal_drift_dtau')
    A_x = amplitude[..., 0]
    A_y = amplitude[..., 1]
    A_z = amplitude[..., 2]
    dt = dt
    tau = tau
    _x0 = dt*numpy.exp(-dt/tau)/tau**2
    _out = out_array((amplitude.shape[:-1], dt.shape, tau.shape,), (3,))
    _out[..., 0] = -A_x*_x0
    _out[..., 1] = -A_y*_x0
    _out[..., 2] = -A_z*_x0
    return _out


def tracker_scale_reading(xyz, tracker, ppm):
    """tracker_scale: the reading (mm) of a point when the tracker's distances scale by 1 + 1e-6 ppm about the tracker (refractive index of air wrong)

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    ppm (...): scale, 1e-6
    returns (..., 3)
    """
    xyz = as_arg(xyz, 3, 'xyz', 'tracker_scale_reading')
    tracker = as_arg(tracker, 3, 'tracker', 'tracker_scale_reading')
    ppm = as_arg(ppm, 0, 'ppm', 'tracker_scale_reading')
    x = xyz[..., 0]
    y = xyz[..., 1]
    z = xyz[..., 2]
    tx = tracker[..., 0]
    ty = tracker[..., 1]
    tz = tracker[..., 2]
    ppm = ppm
    _x0 = (1/1000000)*ppm + 1
    _out = out_array((xyz.shape[:-1], tracker.shape[:-1], ppm.shape,), (3,))
    _out[..., 0] = _x0*(-tx + x) + tx
    _out[..., 1] = _x0*(-ty + y) + ty
    _out[..., 2] = _x0*(-tz + z) + tz
    return _out


def tracker_scale_signature(xyz, tracker):
    """tracker_scale: d reading / d ppm (radial scaling about the tracker), mm per ppm

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    returns (..., 3)
    """
    xyz = as_arg(xyz, 3, 'xyz', 'tracker_scale_signature')
    tracker = as_arg(tracker, 3, 'tracker', 'tracker_scale_signature')
    x = xyz[..., 0]
    y = xyz[..., 1]
    z = xyz[..., 2]
    tx = tracker[..., 0]
    ty = tracker[..., 1]
    tz = tracker[..., 2]
    _out = out_array((xyz.shape[:-1], tracker.shape[:-1],), (3,))
    _out[..., 0] = -1/1000000*tx + (1/1000000)*x
    _out[..., 1] = -1/1000000*ty + (1/1000000)*y
    _out[..., 2] = -1/1000000*tz + (1/1000000)*z
    return _out


def thermal_temperature_displacement(coefficient, dT):
    """thermal_temperature: displacement c dT of a point of the drifting side, mm

    coefficient (..., 3): drift per kelvin of the temperature rise, mm/K
        [c_x, c_y, c_z]
    dT (...): temperature rise T - T_ref of the reading, K
    returns (..., 3)
    """
    coefficient = as_arg(coefficient, 3, 'coefficient', 'thermal_temperature_displacement')
    dT = as_arg(dT, 0, 'dT', 'thermal_temperature_displacement')
    c_x = coefficient[..., 0]
    c_y = coefficient[..., 1]
    c_z = coefficient[..., 2]
    dT = dT
    _out = out_array((coefficient.shape[:-1], dT.shape,), (3,))
    _out[..., 0] = c_x*dT
    _out[..., 1] = c_y*dT
    _out[..., 2] = c_z*dT
    return _out


def thermal_temperature_drift_signature(dT):
    """thermal_temperature: d point / d c (3 x 3), mm per (mm/K)

    dT (...): temperature rise T - T_ref of the reading, K
    returns (..., 3, 3)
    """
    dT = as_arg(dT, 0, 'dT', 'thermal_temperature_drift_signature')
    dT = dT
    _out = out_array((dT.shape,), (3, 3))
    _out[..., 0, 0] = dT
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = dT
    _out[..., 1, 2] = 0
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = dT
    return _out


def thermal_temperature_curve(start_c, rise_c, dt, tau):
    """warm-up curve of the temperature channel: T0 + rise (1 - exp(-dt / tau)), degC

    start_c (...): temperature at the start, degC
    rise_c (...): final rise of the warm-up, K
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 1)
    """
    start_c = as_arg(start_c, 0, 'start_c', 'thermal_temperature_curve')
    rise_c = as_arg(rise_c, 0, 'rise_c', 'thermal_temperature_curve')
    dt = as_arg(dt, 0, 'dt', 'thermal_temperature_curve')
    tau = as_arg(tau, 0, 'tau', 'thermal_temperature_curve')
    T0 = start_c
    rise = rise_c
    dt = dt
    tau = tau
    _out = out_array((start_c.shape, rise_c.shape, dt.shape, tau.shape,), (1,))
    _out[..., 0] = T0 + rise*(1 - numpy.exp(-dt/tau))
    return _out


def nest_creep_model(velocity, dt):
    """nest_creep: displacement v dt of the nest in its side's local frame, mm (for simulation: added to the reflector's local coordinates before the exact kinematics)

    velocity (..., 3): creep velocity of the nest in its side's local frame, mm/s
        [v_x, v_y, v_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    returns (..., 3)
    """
    velocity = as_arg(velocity, 3, 'velocity', 'nest_creep_model')
    dt = as_arg(dt, 0, 'dt', 'nest_creep_model')
    v_x = velocity[..., 0]
    v_y = velocity[..., 1]
    v_z = velocity[..., 2]
    dt = dt
    _out = out_array((velocity.shape[:-1], dt.shape,), (3,))
    _out[..., 0] = dt*v_x
    _out[..., 1] = dt*v_y
    _out[..., 2] = dt*v_z
    return _out


def nest_creep_signature(rotation, dt):
    """nest_creep: d reading / d v (3 x 3) = R dt, mm per (mm/s)

    rotation (..., 9): the side's rotation local -> machine frame, row-major (9,)
        [R_00, R_01, R_02, R_10, R_11, R_12, R_20, R_21, R_22]
    dt (...): time since the start of the warm-up, s (0 before it)
    returns (..., 3, 3)
    """
    rotation = as_arg(rotation, 9, 'rotation', 'nest_creep_signature')
    dt = as_arg(dt, 0, 'dt', 'nest_creep_signature')
    R_00 = rotation[..., 0]
    R_01 = rotation[..., 1]
    R_02 = rotation[..., 2]
    R_10 = rotation[..., 3]
    R_11 = rotation[..., 4]
    R_12 = rotation[..., 5]
    R_20 = rotation[..., 6]
    R_21 = rotation[..., 7]
    R_22 = rotation[..., 8]
    dt = dt
    _out = out_array((rotation.shape[:-1], dt.shape,), (3, 3))
    _out[..., 0, 0] = R_00*dt
    _out[..., 0, 1] = R_01*dt
    _out[..., 0, 2] = R_02*dt
    _out[..., 1, 0] = R_10*dt
    _out[..., 1, 1] = R_11*dt
    _out[..., 1, 2] = R_12*dt
    _out[..., 2, 0] = R_20*dt
    _out[..., 2, 1] = R_21*dt
    _out[..., 2, 2] = R_22*dt
    return _out


def tracker_settling_angle(params, dt, tau):
    """tracker_settling: tilt angle w dt + a (1 - exp(-dt / tau)), rad

    params (..., 2): [w (rad/s), a (rad)]
        [w, a]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 1)
    """
    params = as_arg(params, 2, 'params', 'tracker_settling_angle')
    dt = as_arg(dt, 0, 'dt', 'tracker_settling_angle')
    tau = as_arg(tau, 0, 'tau', 'tracker_settling_angle')
    w = params[..., 0]
    a = params[..., 1]
    dt = dt
    tau = tau
    _out = out_array((params.shape[:-1], dt.shape, tau.shape,), (1,))
    _out[..., 0] = a*(1 - numpy.exp(-dt/tau)) + dt*w
    return _out


def tracker_settling_reading(xyz, tracker, about, theta):
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
    xyz = as_arg(xyz, 3, 'xyz', 'tracker_settling_reading')
    tracker = as_arg(tracker, 3, 'tracker', 'tracker_settling_reading')
    about = as_arg(about, 3, 'about', 'tracker_settling_reading')
    theta = as_arg(theta, 0, 'theta', 'tracker_settling_reading')
    x = xyz[..., 0]
    y = xyz[..., 1]
    z = xyz[..., 2]
    tx = tracker[..., 0]
    ty = tracker[..., 1]
    tz = tracker[..., 2]
    u_x = about[..., 0]
    u_y = about[..., 1]
    u_z = about[..., 2]
    theta = theta
    _x0 = -tx + x
    _x1 = numpy.cos(theta)
    _x2 = 1 - _x1
    _x3 = -tz + z
    _x4 = numpy.sin(theta)
    _x5 = _x4*u_y
    _x6 = _x2*u_x
    _x7 = _x6*u_z
    _x8 = -ty + y
    _x9 = _x4*u_z
    _x10 = _x6*u_y
    _x11 = _x4*u_x
    _out = out_array((xyz.shape[:-1], tracker.shape[:-1], about.shape[:-1], theta.shape,), (3,))
    _out[..., 0] = _x0*(_x1 + _x2*u_x**2) + _x3*(_x5 + _x7) + _x8*(_x10 - _x9) + tx
    _out[..., 1] = _x0*(_x10 + _x9) + _x3*(-_x11 + _x2*u_y*u_z) + _x8*(_x1 + _x2*u_y**2) + ty
    _out[..., 2] = _x0*(-_x5 + _x7) + _x3*(_x1 + _x2*u_z**2) + _x8*(_x11 + _x2*u_y*u_z) + tz
    return _out


def tracker_settling_signature(xyz, tracker, about, dt, tau):
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
    xyz = as_arg(xyz, 3, 'xyz', 'tracker_settling_signature')
    tracker = as_arg(tracker, 3, 'tracker', 'tracker_settling_signature')
    about = as_arg(about, 3, 'about', 'tracker_settling_signature')
    dt = as_arg(dt, 0, 'dt', 'tracker_settling_signature')
    tau = as_arg(tau, 0, 'tau', 'tracker_settling_signature')
    x = xyz[..., 0]
    y = xyz[..., 1]
    z = xyz[..., 2]
    tx = tracker[..., 0]
    ty = tracker[..., 1]
    tz = tracker[..., 2]
    u_x = about[..., 0]
    u_y = about[..., 1]
    u_z = about[..., 2]
    dt = dt
    tau = tau
    _x0 = -tz + z
    _x1 = _x0*u_y
    _x2 = -ty + y
    _x3 = _x2*u_z
    _x4 = 1 - numpy.exp(-dt/tau)
    _x5 = _x0*u_x
    _x6 = -tx + x
    _x7 = _x2*u_x
    _x8 = _x6*u_y
    _out = out_array((xyz.shape[:-1], tracker.shape[:-1], about.shape[:-1], dt.shape, tau.shape,), (3, 2))
    _out[..., 0, 0] = _x1*dt - _x3*dt
    _out[..., 0, 1] = _x1*_x4 - _x3*_x4
    _out[..., 1, 0] = -_x5*dt + _x6*dt*u_z
    _out[..., 1, 1] = -_x4*_x5 + _x4*_x6*u_z
    _out[..., 2, 0] = _x7*dt - _x8*dt
    _out[..., 2, 1] = _x4*_x7 - _x4*_x8
    return _out


def tracker_spherical_coordinates(xyz, tracker):
    """tracker_spherical: the point's coordinates about the tracker, [rho (mm), az (rad), el (rad)]

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    returns (..., 3)
    """
    xyz = as_arg(xyz, 3, 'xyz', 'tracker_spherical_coordinates')
    tracker = as_arg(tracker, 3, 'tracker', 'tracker_spherical_coordinates')
    x = xyz[..., 0]
    y = xyz[..., 1]
    z = xyz[..., 2]
    tx = tracker[..., 0]
    ty = tracker[..., 1]
    tz = tracker[..., 2]
    _x0 = -tz + z
    _x1 = -tx + x
    _x2 = -ty + y
    _x3 = _x1**2 + _x2**2
    _out = out_array((xyz.shape[:-1], tracker.shape[:-1],), (3,))
    _out[..., 0] = numpy.sqrt(_x0**2 + _x3)
    _out[..., 1] = numpy.arctan2(_x2, _x1)
    _out[..., 2] = numpy.arctan2(_x0, numpy.sqrt(_x3))
    return _out


def tracker_spherical_reading(xyz, tracker, params):
    """tracker_spherical: the reading (mm) of a point when the tracker's distance, azimuth and elevation read off by d_rho (mm), d_az and d_el (rad)

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    params (..., 3): [d_rho (mm), d_az (rad), d_el (rad)]
        [d_rho, d_az, d_el]
    returns (..., 3)
    """
    xyz = as_arg(xyz, 3, 'xyz', 'tracker_spherical_reading')
    tracker = as_arg(tracker, 3, 'tracker', 'tracker_spherical_reading')
    params = as_arg(params, 3, 'params', 'tracker_spherical_reading')
    x = xyz[..., 0]
    y = xyz[..., 1]
    z = xyz[..., 2]
    tx = tracker[..., 0]
    ty = tracker[..., 1]
    tz = tracker[..., 2]
    d_rho = params[..., 0]
    d_az = params[..., 1]
    d_el = params[..., 2]
    _x0 = -ty + y
    _x1 = -tx + x
    _x2 = d_az + numpy.arctan2(_x0, _x1)
    _x3 = -tz + z
    _x4 = _x0**2 + _x1**2
    _x5 = d_rho + numpy.sqrt(_x3**2 + _x4)
    _x6 = d_el + numpy.arctan2(_x3, numpy.sqrt(_x4))
    _x7 = _x5*numpy.cos(_x6)
    _out = out_array((xyz.shape[:-1], tracker.shape[:-1], params.shape[:-1],), (3,))
    _out[..., 0] = _x7*numpy.cos(_x2) + tx
    _out[..., 1] = _x7*numpy.sin(_x2) + ty
    _out[..., 2] = _x5*numpy.sin(_x6) + tz
    return _out


def tracker_spherical_signature(xyz, tracker):
    """tracker_spherical: d reading / d [d_rho, d_az, d_el] (3 x 3): the beam's unit vector, z x (point - T), and rho times the unit vector of rising elevation; mm per mm, mm per rad

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    returns (..., 3, 3)
    """
    xyz = as_arg(xyz, 3, 'xyz', 'tracker_spherical_signature')
    tracker = as_arg(tracker, 3, 'tracker', 'tracker_spherical_signature')
    x = xyz[..., 0]
    y = xyz[..., 1]
    z = xyz[..., 2]
    tx = tracker[..., 0]
    ty = tracker[..., 1]
    tz = tracker[..., 2]
    _x0 = tx - x
    _x1 = -_x0
    _x2 = tz - z
    _x3 = ty - y
    _x4 = _x0**2 + _x3**2
    _x5 = 1/numpy.sqrt(_x2**2 + _x4)
    _x6 = numpy.sqrt(_x4)
    _x7 = _x2/_x6
    _out = out_array((xyz.shape[:-1], tracker.shape[:-1],), (3, 3))
    _out[..., 0, 0] = _x1*_x5
    _out[..., 0, 1] = _x3
    _out[..., 0, 2] = -_x0*_x7
    _out[..., 1, 0] = -_x3*_x5
    _out[..., 1, 1] = _x1
    _out[..., 1, 2] = -_x3*_x7
    _out[..., 2, 0] = -_x2*_x5
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = _x6
    return _out


def outlier_signature(on):
    """outlier: d reading / d displacement s (3 x 3) for a displaced reading (on = 1)

    on (...): 1 for the displaced readings, 0 otherwise
    returns (..., 3, 3)
    """
    on = as_arg(on, 0, 'on', 'outlier_signature')
    on = on
    _out = out_array((on.shape,), (3, 3))
    _out[..., 0, 0] = on
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = on
    _out[..., 1, 2] = 0
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = on
    return _out


def air_index_drift_ramp_model(xyz, tracker, dt, params):
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
    xyz = as_arg(xyz, 3, 'xyz', 'air_index_drift_ramp_model')
    tracker = as_arg(tracker, 3, 'tracker', 'air_index_drift_ramp_model')
    dt = as_arg(dt, 0, 'dt', 'air_index_drift_ramp_model')
    params = as_arg(params, 1, 'params', 'air_index_drift_ramp_model')
    x = xyz[..., 0]
    y = xyz[..., 1]
    z = xyz[..., 2]
    tx = tracker[..., 0]
    ty = tracker[..., 1]
    tz = tracker[..., 2]
    dt = dt
    e = params[..., 0]
    _x0 = (1/3600000000)*dt*e
    _out = out_array((xyz.shape[:-1], tracker.shape[:-1], dt.shape, params.shape[:-1],), (3,))
    _out[..., 0] = _x0*(-tx + x)
    _out[..., 1] = _x0*(-ty + y)
    _out[..., 2] = _x0*(-tz + z)
    return _out


def air_index_drift_ramp_signature(xyz, tracker, dt):
    """air_index_drift (ramp): d reading / d e = 1e-6 (dt / 3600 s) (point - tracker), mm per (ppm/h)

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    dt (...): time since the start of the warm-up, s (0 before it)
    returns (..., 3)
    """
    xyz = as_arg(xyz, 3, 'xyz', 'air_index_drift_ramp_signature')
    tracker = as_arg(tracker, 3, 'tracker', 'air_index_drift_ramp_signature')
    dt = as_arg(dt, 0, 'dt', 'air_index_drift_ramp_signature')
    x = xyz[..., 0]
    y = xyz[..., 1]
    z = xyz[..., 2]
    tx = tracker[..., 0]
    ty = tracker[..., 1]
    tz = tracker[..., 2]
    dt = dt
    _x0 = (1/3600000000)*dt
    _out = out_array((xyz.shape[:-1], tracker.shape[:-1], dt.shape,), (3,))
    _out[..., 0] = _x0*(-tx + x)
    _out[..., 1] = _x0*(-ty + y)
    _out[..., 2] = _x0*(-tz + z)
    return _out


def air_index_drift_lag_model(xyz, tracker, dt, tau, params):
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
    xyz = as_arg(xyz, 3, 'xyz', 'air_index_drift_lag_model')
    tracker = as_arg(tracker, 3, 'tracker', 'air_index_drift_lag_model')
    dt = as_arg(dt, 0, 'dt', 'air_index_drift_lag_model')
    tau = as_arg(tau, 0, 'tau', 'air_index_drift_lag_model')
    params = as_arg(params, 1, 'params', 'air_index_drift_lag_model')
    x = xyz[..., 0]
    y = xyz[..., 1]
    z = xyz[..., 2]
    tx = tracker[..., 0]
    ty = tracker[..., 1]
    tz = tracker[..., 2]
    dt = dt
    tau = tau
    e = params[..., 0]
    _x0 = (1/1000000)*e*(1 - numpy.exp(-dt/tau))
    _out = out_array((xyz.shape[:-1], tracker.shape[:-1], dt.shape, tau.shape, params.shape[:-1],), (3,))
    _out[..., 0] = _x0*(-tx + x)
    _out[..., 1] = _x0*(-ty + y)
    _out[..., 2] = _x0*(-tz + z)
    return _out


def air_index_drift_lag_signature(xyz, tracker, dt, tau):
    """air_index_drift (lag): d reading / d e = 1e-6 (1 - exp(-dt / tau)) (point - tracker), mm per ppm

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 3)
    """
    xyz = as_arg(xyz, 3, 'xyz', 'air_index_drift_lag_signature')
    tracker = as_arg(tracker, 3, 'tracker', 'air_index_drift_lag_signature')
    dt = as_arg(dt, 0, 'dt', 'air_index_drift_lag_signature')
    tau = as_arg(tau, 0, 'tau', 'air_index_drift_lag_signature')
    x = xyz[..., 0]
    y = xyz[..., 1]
    z = xyz[..., 2]
    tx = tracker[..., 0]
    ty = tracker[..., 1]
    tz = tracker[..., 2]
    dt = dt
    tau = tau
    _x0 = 1/1000000 - 1/1000000*numpy.exp(-dt/tau)
    _out = out_array((xyz.shape[:-1], tracker.shape[:-1], dt.shape, tau.shape,), (3,))
    _out[..., 0] = _x0*(-tx + x)
    _out[..., 1] = _x0*(-ty + y)
    _out[..., 2] = _x0*(-tz + z)
    return _out


def side_expansion_ramp_model(offset, dt, params):
    """side_expansion (ramp): displacement 1e-6 e (dt / 3600 s) (local - centroid) of a reflector in its side's local frame, mm (e in ppm per hour)

    offset (..., 3): reflector's local position less its side's layout centroid, mm, the side's local frame
        [o_x, o_y, o_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    params (..., 1): parameters [e]
        [e]
    returns (..., 3)
    """
    offset = as_arg(offset, 3, 'offset', 'side_expansion_ramp_model')
    dt = as_arg(dt, 0, 'dt', 'side_expansion_ramp_model')
    params = as_arg(params, 1, 'params', 'side_expansion_ramp_model')
    o_x = offset[..., 0]
    o_y = offset[..., 1]
    o_z = offset[..., 2]
    dt = dt
    e = params[..., 0]
    _x0 = (1/3600000000)*dt*e
    _out = out_array((offset.shape[:-1], dt.shape, params.shape[:-1],), (3,))
    _out[..., 0] = _x0*o_x
    _out[..., 1] = _x0*o_y
    _out[..., 2] = _x0*o_z
    return _out


def side_expansion_ramp_signature(rotation, offset, dt):
    """side_expansion (ramp): d reading / d e = 1e-6 (dt / 3600 s) R (local - centroid), mm per (ppm/h)

    rotation (..., 9): the side's rotation local -> machine frame, row-major (9,)
        [R_00, R_01, R_02, R_10, R_11, R_12, R_20, R_21, R_22]
    offset (..., 3): reflector's local position less its side's layout centroid, mm, the side's local frame
        [o_x, o_y, o_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    returns (..., 3)
    """
    rotation = as_arg(rotation, 9, 'rotation', 'side_expansion_ramp_signature')
    offset = as_arg(offset, 3, 'offset', 'side_expansion_ramp_signature')
    dt = as_arg(dt, 0, 'dt', 'side_expansion_ramp_signature')
    R_00 = rotation[..., 0]
    R_01 = rotation[..., 1]
    R_02 = rotation[..., 2]
    R_10 = rotation[..., 3]
    R_11 = rotation[..., 4]
    R_12 = rotation[..., 5]
    R_20 = rotation[..., 6]
    R_21 = rotation[..., 7]
    R_22 = rotation[..., 8]
    o_x = offset[..., 0]
    o_y = offset[..., 1]
    o_z = offset[..., 2]
    dt = dt
    _x0 = (1/3600000000)*dt
    _x1 = _x0*o_x
    _x2 = _x0*o_y
    _x3 = _x0*o_z
    _out = out_array((rotation.shape[:-1], offset.shape[:-1], dt.shape,), (3,))
    _out[..., 0] = R_00*_x1 + R_01*_x2 + R_02*_x3
    _out[..., 1] = R_10*_x1 + R_11*_x2 + R_12*_x3
    _out[..., 2] = R_20*_x1 + R_21*_x2 + R_22*_x3
    return _out


def side_expansion_lag_model(offset, dt, tau, params):
    """side_expansion (lag): displacement 1e-6 e (1 - exp(-dt / tau)) (local - centroid), mm (e in ppm)

    offset (..., 3): reflector's local position less its side's layout centroid, mm, the side's local frame
        [o_x, o_y, o_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    params (..., 1): parameters [e]
        [e]
    returns (..., 3)
    """
    offset = as_arg(offset, 3, 'offset', 'side_expansion_lag_model')
    dt = as_arg(dt, 0, 'dt', 'side_expansion_lag_model')
    tau = as_arg(tau, 0, 'tau', 'side_expansion_lag_model')
    params = as_arg(params, 1, 'params', 'side_expansion_lag_model')
    o_x = offset[..., 0]
    o_y = offset[..., 1]
    o_z = offset[..., 2]
    dt = dt
    tau = tau
    e = params[..., 0]
    _x0 = (1/1000000)*e*(1 - numpy.exp(-dt/tau))
    _out = out_array((offset.shape[:-1], dt.shape, tau.shape, params.shape[:-1],), (3,))
    _out[..., 0] = _x0*o_x
    _out[..., 1] = _x0*o_y
    _out[..., 2] = _x0*o_z
    return _out


def side_expansion_lag_signature(rotation, offset, dt, tau):
    """side_expansion (lag): d reading / d e = 1e-6 (1 - exp(-dt / tau)) R (local - centroid), mm per ppm

    rotation (..., 9): the side's rotation local -> machine frame, row-major (9,)
        [R_00, R_01, R_02, R_10, R_11, R_12, R_20, R_21, R_22]
    offset (..., 3): reflector's local position less its side's layout centroid, mm, the side's local frame
        [o_x, o_y, o_z]
    dt (...): time since the start of the warm-up, s (0 before it)
    tau (...): warm-up time constant, s
    returns (..., 3)
    """
    rotation = as_arg(rotation, 9, 'rotation', 'side_expansion_lag_signature')
    offset = as_arg(offset, 3, 'offset', 'side_expansion_lag_signature')
    dt = as_arg(dt, 0, 'dt', 'side_expansion_lag_signature')
    tau = as_arg(tau, 0, 'tau', 'side_expansion_lag_signature')
    R_00 = rotation[..., 0]
    R_01 = rotation[..., 1]
    R_02 = rotation[..., 2]
    R_10 = rotation[..., 3]
    R_11 = rotation[..., 4]
    R_12 = rotation[..., 5]
    R_20 = rotation[..., 6]
    R_21 = rotation[..., 7]
    R_22 = rotation[..., 8]
    o_x = offset[..., 0]
    o_y = offset[..., 1]
    o_z = offset[..., 2]
    dt = dt
    tau = tau
    _x0 = 1/1000000 - 1/1000000*numpy.exp(-dt/tau)
    _x1 = _x0*o_x
    _x2 = _x0*o_y
    _x3 = _x0*o_z
    _out = out_array((rotation.shape[:-1], offset.shape[:-1], dt.shape, tau.shape,), (3,))
    _out[..., 0] = R_00*_x1 + R_01*_x2 + R_02*_x3
    _out[..., 1] = R_10*_x1 + R_11*_x2 + R_12*_x3
    _out[..., 2] = R_20*_x1 + R_21*_x2 + R_22*_x3
    return _out


def backlash_travel_model(d, q, params):
    """backlash_travel: positioning error + d / 2 (b + g q): a reversal b + g q growing along the travel, mm (rad)

    d (...): approach direction, +1 or -1
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    params (..., 2): parameters [b, g]
        [b, g]
    returns (..., 1)
    """
    d = as_arg(d, 0, 'd', 'backlash_travel_model')
    q = as_arg(q, 0, 'q', 'backlash_travel_model')
    params = as_arg(params, 2, 'params', 'backlash_travel_model')
    d = d
    q = q
    b = params[..., 0]
    g = params[..., 1]
    _x0 = (1/2)*d
    _out = out_array((d.shape, q.shape, params.shape[:-1],), (1,))
    _out[..., 0] = _x0*b + _x0*g*q
    return _out


def backlash_travel_signature(column, d, q):
    """backlash_travel: d reading / d [b, g] = column d / 2 [1, q], mm per mm and mm per (mm/mm)

    column (..., 3): point Jacobian column of the affected error, mm per error unit (mm or rad)
        [c_x, c_y, c_z]
    d (...): approach direction, +1 or -1
    q (...): axis position: mm (linear) or rad (rotary) for scale; mm or deg otherwise
    returns (..., 3, 2)
    """
    column = as_arg(column, 3, 'column', 'backlash_travel_signature')
    d = as_arg(d, 0, 'd', 'backlash_travel_signature')
    q = as_arg(q, 0, 'q', 'backlash_travel_signature')
    c_x = column[..., 0]
    c_y = column[..., 1]
    c_z = column[..., 2]
    d = d
    q = q
    _x0 = (1/2)*d
    _x1 = _x0*c_x
    _x2 = _x0*c_y
    _x3 = _x0*c_z
    _out = out_array((column.shape[:-1], d.shape, q.shape,), (3, 2))
    _out[..., 0, 0] = _x1
    _out[..., 0, 1] = _x1*q
    _out[..., 1, 0] = _x2
    _out[..., 1, 1] = _x2*q
    _out[..., 2, 0] = _x3
    _out[..., 2, 1] = _x3*q
    return _out


def tracker_relevel_signature(xyz, tracker, on):
    """tracker_relevel: d reading / d [w_x, w_y] = on [e_x, e_y] x (point - tracker), mm per rad (a rotation step about horizontal axes through the tracker, from a round's first reading on)

    xyz (..., 3): measured point, machine frame, mm
        [x, y, z]
    tracker (..., 3): tracker position, machine frame, mm
        [tx, ty, tz]
    on (...): 1 for the displaced readings, 0 otherwise
    returns (..., 3, 2)
    """
    xyz = as_arg(xyz, 3, 'xyz', 'tracker_relevel_signature')
    tracker = as_arg(tracker, 3, 'tracker', 'tracker_relevel_signature')
    on = as_arg(on, 0, 'on', 'tracker_relevel_signature')
    x = xyz[..., 0]
    y = xyz[..., 1]
    z = xyz[..., 2]
    tx = tracker[..., 0]
    ty = tracker[..., 1]
    tz = tracker[..., 2]
    on = on
    _x0 = on*(-tz + z)
    _out = out_array((xyz.shape[:-1], tracker.shape[:-1], on.shape,), (3, 2))
    _out[..., 0, 0] = 0
    _out[..., 0, 1] = _x0
    _out[..., 1, 0] = -_x0
    _out[..., 1, 1] = 0
    _out[..., 2, 0] = on*(-ty + y)
    _out[..., 2, 1] = -on*(-tx + x)
    return _out
