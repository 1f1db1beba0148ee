"""LinuxCNC thermal compensation from a thermal model: a HAL component (``mtcal_thermal.comp``, built with
``halcompile --install``) whose inputs are the temperatures and the spindle speed and whose outputs drive the
external axis offsets, with the HAL and INI lines that connect it.

Source: LinuxCNC documentation, "External Axis Offsets" (2.8+): ``axis.L.eoffset-enable`` (bit),
``axis.L.eoffset-scale`` (float, machine units per count), ``axis.L.eoffset-counts`` (s32) -- the offset is
counts x scale, added to the axis' commanded position -- and ``[AXIS_L]OFFSET_AV_RATIO`` (the share of the axis'
velocity and acceleration kept for the offset; must be > 0 to enable it). ``halcompile``: the component's
function runs every period of its thread, ``fperiod`` its period in seconds (used for the lags' step).
Sign: the offset moves the axis, so it is minus the drift: a drift of the tool of +d along the axis is met by an
offset of -d. Units: the machine's linear units (mm unless ``[TRAJ]LINEAR_UNITS`` says inch: then edit SCALE).
"""
from __future__ import annotations

import re

from mtcal.thermal.features import SPEED

NAME = "linuxcnc"
KIND = "dir"
COMP = "mtcal_thermal"
SIGN = ("offset = -drift (mm): the external axis offset moves the axis against the tool's thermal drift; source: "
        "LinuxCNC External Axis Offsets (axis.L.eoffset-counts x axis.L.eoffset-scale is added to the position)")
NOTES = ["linuxcnc: build with `halcompile --install mtcal_thermal.comp`; connect the temperature and speed pins "
         "(mtcal_thermal.hal) and set [AXIS_L]OFFSET_AV_RATIO (mtcal_thermal.ini)"]
SCALE = 1e-6  # mm per count: 1 nm


def _g(v: float) -> str:
    return repr(float(v))


def _pin(inp: str) -> str:
    return "spindle_rpm" if inp == SPEED else "temp_" + re.sub(r"\W", "_", inp, flags=re.ASCII).lower()


def _var(t) -> str:
    return f"lag_{_pin(t.input)}_{int(t.tau_s)}"


def _x(t, ref) -> str:
    return f"({_pin(t.input)} / 1000.0)" if t.input == SPEED else f"({_pin(t.input)} - {_g(ref[t.input])})"


def render(model, placed, machine, model_path: str, period_s: float, name: str) -> dict[str, str]:
    """{file name: text}: the component, the HAL lines, the INI lines (module docstring)."""
    ref = model.reference_c
    inputs = sorted({t.input for p in placed for t in p.channel.terms}, key=lambda k: (k == SPEED, k))
    lags = sorted({t for p in placed for t in p.channel.terms if t.tau_s is not None}, key=lambda t: (t.input, t.tau_s))
    src = [f'component {COMP} "thermal drift compensation from mtcal thermal export {model_path}: external axis '
           f'offsets";']
    src += [f'pin in float {_pin(k)} "' + ("spindle speed, rpm" if k == SPEED else f"temperature {k}, degC") + '";'
            for k in inputs]
    for p in placed:
        a = p.axis.lower()
        src += [f'pin out float offset_{a} "offset of axis {p.axis}, mm (minus the drift of {p.channel.channel})";',
                f'pin out s32 counts_{a} "offset_{a} / scale, to axis.{a}.eoffset-counts";']
    src += [f'param rw float scale = {_g(SCALE)} "mm per count, as axis.L.eoffset-scale";']
    src += [f"variable double {_var(t)} = 0;" for t in lags]
    src += ["function _;", 'license "MIT";', 'author "mtcal";', ";;", "#include <rtapi_math.h>", "", "FUNCTION(_) {"]
    src += [f"    {_var(t)} += (1.0 - exp(-fperiod / {_g(t.tau_s)})) * ({_x(t, ref)} - {_var(t)});  // {t.label}"
            for t in lags]
    for p in placed:
        c, a = p.channel, p.axis.lower()
        terms = " + ".join([_g(c.intercept_um)] + [f"{_g(k)} * " + (_var(t) if t.tau_s is not None else _x(t, ref))
                                                  for k, t in zip(c.coefficients, c.terms)])
        src += [f"    // {c.channel} -> {'-' if p.sign < 0 else ''}{p.axis}: {c.model}; out of sample RMSE "
                f"{c.rmse_um:.3g} um",
                f"    offset_{a} = {_g(-0.001 * p.sign)} * ({terms});",
                f"    counts_{a} = (int)rint(offset_{a} / scale);"]
    src += ["}", ""]
    hal = [f"# mtcal thermal export {model_path} --format linuxcnc: connect the inputs to your sensors' pins",
           f"loadrt {COMP}", f"addf {COMP}.0 servo-thread"]
    hal += [f"# net <your-signal> => {COMP}.0.{_pin(k).replace('_', '-')}" for k in inputs]
    hal += [f"setp {COMP}.0.scale {_g(SCALE)}"]
    for p in placed:
        a, pin = p.axis.lower(), f"{COMP}.0.counts-{p.axis.lower()}"
        hal += [f"setp axis.{a}.eoffset-scale {_g(SCALE)}", f"net thermal-{a} {pin} => axis.{a}.eoffset-counts",
                f"setp axis.{a}.eoffset-enable 1"]
    ini = ["# mtcal thermal export: add to each compensated axis' section"]
    ini += [f"[AXIS_{p.axis}]\nOFFSET_AV_RATIO = 0.1" for p in placed]
    return {f"{COMP}.comp": "\n".join(src), f"{COMP}.hal": "\n".join(hal) + "\n", f"{COMP}.ini": "\n".join(ini) + "\n"}
