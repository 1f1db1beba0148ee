"""Siemens SINUMERIK 840D sl: LEC (`$AA_ENC_COMP`) and CEC (`$AN_CEC`) tables as one MPF part program.

Source: SINUMERIK Function Manual Extended Functions, K3 Compensations (6FC5397-1BP40-3BA1, 03/2013), sec. 4.4.2
(LEC: $AA_ENC_COMP[0,N,axis], $AA_ENC_COMP_STEP/_MIN/_MAX/_IS_MODULO, linear interpolation between interpolation
points) and sec. 4.4.3 (CEC: $AN_CEC[t,N], $AN_CEC_INPUT_AXIS, _OUTPUT_AXIS, _STEP, _MIN, _MAX, _DIRECTION
(0 both, 1 positive, -1 negative traversing direction of the basic axis), _MULT_BY_TABLE, _IS_MODULO; below MIN the
value of point 0, above MAX the value of the last point); SINUMERIK 808D Function Manual (01/2017) LEC: "the
axis-specific position actual value is modified by the compensation value ... a positive compensation value causes
the machine axis to move in the negative direction".
Units and spacing: mm for linear and deg for rotary axes (metric basic system), regular step, MAX = MIN + n STEP.
Sign: every table value is the measured error (joint-equivalent deviation actual - nominal, = minus the
correction), added by the NC to the axis' actual value so that the axis moves by minus the value; for CEC the same
convention as LEC is ASSUMED (K3 treats both as interpolatory compensation of the compensation axis position).
Reversal: the LEC table is unidirectional; a backlash finding is written as two CEC tables of the axis on itself
(+b/2 with DIRECTION 1 and -b/2 with DIRECTION -1), the direction-dependent use K3 names.
"""
from __future__ import annotations

from mtcal.export.sampling import AxisTable

NAME = "siemens"
MAX_POINTS = 256
HARD_LIMIT = False  # the point limit is configurable on the controller
CROSS = True
FILES = "*.MPF"
BACKLASH_NOTE = ("set the axis' own backlash compensation $MA_BACKLASH (MD32450) to 0 so the reversal is not "
                 "compensated twice")
SIGN = ("each value is the measured error (actual - nominal, joint-equivalent; = -correction) that the NC adds to "
        "the axis' actual value, so the axis moves by -value; source: SINUMERIK K3 Compensations / 808D Function "
        "Manual LEC; CEC: same convention assumed")


def _fmt(v: float) -> str:
    return f"{v:.9f}".rstrip("0").rstrip(".") if v != 0 else "0"


def _ax(machine, axis: str) -> str:
    return f"AX{machine.axes.index(axis) + 1}"


def _modulo(machine, tab: AxisTable) -> int:
    """1 for a rotary axis without limits whose table spans exactly one turn (K3: the table repeats cyclically)."""
    k = machine.axes.index(tab.axis)
    span = tab.positions[-1] - tab.positions[0]
    return int(machine.axis_kinds[k] == "rotary" and machine.limits[k] is None and abs(span - 360.0) < 1e-9)


def _cec(lines: list[str], t: int, inp: str, out: str, values, tab: AxisTable, direction: int) -> None:
    lines += [f"$AN_CEC[{t},{i}]={_fmt(v)}" for i, v in enumerate(values)]
    lines += [f"$AN_CEC_INPUT_AXIS[{t}]=({inp})", f"$AN_CEC_OUTPUT_AXIS[{t}]=({out})",
              f"$AN_CEC_STEP[{t}]={_fmt(tab.step)}", f"$AN_CEC_MIN[{t}]={_fmt(tab.positions[0])}",
              f"$AN_CEC_MAX[{t}]={_fmt(tab.positions[-1])}", f"$AN_CEC_DIRECTION[{t}]={direction}",
              f"$AN_CEC_MULT_BY_TABLE[{t}]=0", f"$AN_CEC_IS_MODULO[{t}]=0"]


def render(tables: list[AxisTable], machine, model_path: str, name: str) -> dict[str, str]:
    """{name: MPF text}: LEC tables for each axis' own positioning, CEC tables for cross terms and reversal."""
    head = [f"; mtcal export {model_path} --format siemens", f"; sign: {SIGN}",
            "; units: mm (linear axes), deg (rotary axes); load with MD32700 ENC_COMP_ENABLE = 0 and "
            "MD32710 CEC_ENABLE = 0, then enable, NEWCONF and reference the axes",
            "; axes: " + ", ".join(f"{a} = {_ax(machine, a)}" for a in machine.axes) +
            " (general machine axis names; edit if yours differ)", "CHANDATA(1)"]
    lec, cec, t = [], [], 0
    for tab in tables:
        ax = _ax(machine, tab.axis)
        if tab.axis in tab.corrections:
            lec.append(f"; LEC {tab.axis} = F({tab.axis}) from {', '.join(tab.sources[tab.axis])}: "
                       f"{len(tab.positions)} points, step {tab.step:g} {tab.unit}")
            lec += [f"$AA_ENC_COMP[0,{i},{ax}]={_fmt(-v)}" for i, v in enumerate(tab.corrections[tab.axis])]
            lec += [f"$AA_ENC_COMP_STEP[0,{ax}]={_fmt(tab.step)}", f"$AA_ENC_COMP_MIN[0,{ax}]={_fmt(tab.positions[0])}",
                    f"$AA_ENC_COMP_MAX[0,{ax}]={_fmt(tab.positions[-1])}",
                    f"$AA_ENC_COMP_IS_MODULO[0,{ax}]={_modulo(machine, tab)}"]
        for out, c in tab.corrections.items():
            if out == tab.axis:
                continue
            cec.append(f"; CEC table {t}: {out} = F({tab.axis}) from {', '.join(tab.sources[out])}")
            _cec(cec, t, ax, _ax(machine, out), -c, tab, 0)
            t += 1
        if tab.reversal:
            for d in (1, -1):
                cec.append(f"; CEC table {t}: reversal of {tab.axis} ({'positive' if d > 0 else 'negative'} direction)")
                _cec(cec, t, ax, ax, [d * tab.reversal / 2] * len(tab.positions), tab, d)
                t += 1
    return {name: "\n".join(head + lec + cec + ["M30", ""])}
