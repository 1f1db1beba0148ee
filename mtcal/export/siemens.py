"""Siemens SINUMERIK 840D sl: LEC (`$AA_ENC_COMP`) and CEC (`$AN_CEC`) tables as one MPF part program.

Source: SINUMERIK Function Manual Extended Functions, K3 Compensations (6FC5397-1BP40-3BA1, 03/2013), sec. 4.4.2
(LEC: $AA_ENC_COMP[0,N,axis], $AA_ENC_COMP_STEP/_MIN/_MAX/_IS_MODULO, linear interpolation between interpolation
points) and sec. 4.4.3 (CEC: $AN_CEC[t,N], $AN_CEC_INPUT_AXIS, _OUTPUT_AXIS, _STEP, _MIN, _MAX, _DIRECTION
(0 both, 1 positive, -1 negative traversing direction of the basic axis), _MULT_BY_TABLE, _IS_MODULO; below MIN the
value of point 0, above MAX the value of the last point); SINUMERIK 808D Function Manual (01/2017) LEC: "the
axis-specific position actual value is modified by the compensation value ... a positive compensation value causes
the machine axis to move in the negative direction".
Units and spacing: mm for linear and deg for rotary axes (metric basic system), regular step, MAX = MIN + n STEP.
Layout: as K3's examples, `%_N_AX_EEC_INI` / `CHANDATA(1)` / assignments / `M17` (LEC) and `%_N_NC_CEC_INI` ... `M17`
(CEC) in one file; the header comments name every machine datum to set (MD38000 / MD18342 sizing, MD32700 /
MD32710 enable, SD41300 / SD41310 table enable and weight, MD32450 backlash). Measuring system: index e of
$AA_ENC_COMP[e,N,AXi], 0 by default (K3's example), 1 for tables on the second encoder. Unlimited rotary axes:
tables over one full turn with IS_MODULO = 1. Controls: 840D sl sized by machine data; 808D / 828D 200 points per
table, 828D at most 8 CEC tables (``CONTROLS``).
Sign: every table value is the measured error (joint-equivalent deviation actual - nominal, = minus the
correction), added by the NC to the axis' actual value so that the axis moves by minus the value; for CEC the same
convention as LEC is ASSUMED (K3 treats both as interpolatory compensation of the compensation axis position).
Reversal: the LEC table is unidirectional; a backlash finding is written as two CEC tables of the axis on itself
(+b/2 with DIRECTION 1 and -b/2 with DIRECTION -1), the direction-dependent use K3 names.
"""
from __future__ import annotations

from dataclasses import replace

from mtcal.errors import InputError
from mtcal.export import sampling
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


CONTROLS = {  # control -> (points per table, CEC tables): fixed limits of the smaller controls
    "840d": (None, None),  # sized by MD38000 / MD18342 (the header names the value needed)
    "828d": (200, 8),      # issue 21 (808D/828D function manuals: 200 interpolation points; 828D: 8 CEC tables)
    "808d": (200, None),   # 808D Function Manual 01/2017: "Up to 200 interpolation points (N = 0...199)"
}


def _fmt(v: float) -> str:
    if v == 0:
        return "0"
    text = f"{v:.9f}".rstrip("0").rstrip(".")
    return "0" if float(text) == 0 else text  # no "-0"


def _ax(machine, axis: str) -> str:
    return f"AX{machine.axes.index(axis) + 1}"


def modulo_table(tab: AxisTable, machine, max_points: int | None = None, step_given: bool = True,
                 control: str = "840d") -> AxisTable:
    """An unlimited rotary axis' table as a modulo table over the whole turn 0..360 deg (808D Function Manual
    01/2017 p. 109: "the compensation table is repeated cyclically ... program 0 deg as the starting position and 360
    deg as the end position"; K3: the values at MIN and MAX agree): mtcal.export.sampling.modulo_table with the
    control's points per table.  Other tables unchanged."""
    return sampling.modulo_table(tab, machine, max_points, step_given, CONTROLS[control][0],
                                 f"SINUMERIK {control.upper()}")


def as_written(tables: list[AxisTable], machine, control: str, max_points: int | None,
               step_given: bool) -> tuple[list[AxisTable], list[str]]:
    """The tables as the file holds them (the command prints these): unlimited rotary axes as full-turn modulo
    tables (``modulo_table``); on the 808D, whose Function Manual (01/2017) describes LEC ($AA_ENC_COMP) but no
    CEC ($AN_CEC), the own-axis LEC tables only, the cross and reversal tables left out and said."""
    if control not in CONTROLS:
        raise InputError(f"`control` must be one of {', '.join(CONTROLS)}, got {control!r}")
    notes, out = [], []
    for t in tables:
        if control == "808d" and (set(t.corrections) - {t.axis} or t.reversal):
            dropped = [f"{o} = F({t.axis}) from {', '.join(t.sources[o])}" for o in t.corrections if o != t.axis]
            dropped += [f"the reversal of {t.axis}"] if t.reversal else []
            notes.append(f"SINUMERIK 808D: not written (no CEC / sag compensation in the 808D Function Manual "
                         f"01/2017; compensate these with `mtcal compensate` or another control): {'; '.join(dropped)}")
            keep = {o: c for o, c in t.corrections.items() if o == t.axis}
            if not keep:
                continue
            t = replace(t, corrections=keep, sources={t.axis: t.sources[t.axis]}, reversal=0.0)
        out.append(modulo_table(t, machine, max_points, step_given, control))
    notes += [t.note for t in out if t.note]
    return out, notes


def _cec(lines: list[str], t: int, inp: str, out: str, values, tab: AxisTable, direction: int, modulo: int) -> None:
    lines += [f"$AN_CEC[{t},{i}]={_fmt(v)}" for i, v in enumerate(values)]
    lines += [f"$AN_CEC_INPUT_AXIS[{t}]=({inp})", f"$AN_CEC_OUTPUT_AXIS[{t}]=({out})",
              f"$AN_CEC_STEP[{t}]={_fmt(tab.step)}", f"$AN_CEC_MIN[{t}]={_fmt(tab.positions[0])}",
              f"$AN_CEC_MAX[{t}]={_fmt(tab.positions[-1])}", f"$AN_CEC_DIRECTION[{t}]={direction}",
              f"$AN_CEC_MULT_BY_TABLE[{t}]=0", f"$AN_CEC_IS_MODULO[{t}]={modulo}"]


def _machine_data(lec_points: dict[str, int], cec_points: list[int], e: int, backlash: list[str],
                  control: str = "840d") -> list[str]:
    """The comment lines naming every machine datum to set (K3; G2; 808D/828D function manuals)."""
    out = ["; MACHINE DATA TO SET before loading (K3 Compensations; check each against your machine's archive):",
           "; * units: metric basic system, MD10240 $MN_SCALING_SYSTEM_IS_METRIC = 1 (with 0 the table positions are "
           "read in inches: 808D Function Manual 01/2017 p. 109)"]
    if cec_points:
        out += ["; * CEC tables in metric: MD32711 $MA_CEC_SCALING_SYSTEM_METRIC = 1 on each CEC input axis (G2 "
                "Function Manual 01/2015, 6FC5397-0BP40-5BA2, p. 331: the system of units of sag compensation)"]
    out += ["; * sizing, reformats the NC user memory at the next POWER ON: BACK UP FIRST (series start-up archive)"]
    out += [f";   MD38000 $MA_MM_ENC_COMP_MAX_POINTS[{e},{a}] >= {n}" for a, n in lec_points.items()]
    if control == "828d" and cec_points:
        out += ["; * SINUMERIK 828D: the CEC tables are fixed, 8 tables of 200 interpolation points each once the "
                "option 'sag compensation, multi-dimensional' is enabled; they cannot be extended and are not sized "
                "by machine data (K3 Compensations 03/2013, 6FC5397-1BP40-3BA1, sec. 4.4.4.3, note)"]
    else:
        out += [f";   MD18342 $MN_MM_CEC_MAX_POINTS[{t}] >= {n}" for t, n in enumerate(cec_points)]
    out += [f"; * while loading: MD32700 $MA_ENC_COMP_ENABLE[{e},AXn] = 0 and MD32710 $MA_CEC_ENABLE[AXn] = 0; "
            f"then 1, NEWCONF, reference the axes"]
    if cec_points:
        out += [f"; * SD41300 $SN_CEC_TABLE_ENABLE[{t}] = 1, SD41310 $SN_CEC_TABLE_WEIGHT[{t}] = 1.0"
                for t in range(len(cec_points))]
    if backlash:
        out += [f"; * a direction-dependent (backlash) table is written for {', '.join(backlash)}: MD32450 "
                f"$MA_BACKLASH[{e},AXn] = 0 on that axis, else the reversal is compensated twice"]
    return out


def _limits(tables: list[AxisTable], cec: list[str], control: str) -> None:
    pts, cec_max = CONTROLS[control]
    for t in tables:
        if pts is not None and len(t.positions) > pts:
            raise InputError(f"SINUMERIK {control.upper()} holds {pts} interpolation points per table; axis {t.axis} "
                             f"needs {len(t.positions)} at step {t.step:g} {t.unit} (`step` or `max_points` {pts})")
    if cec_max is not None and len(cec) > cec_max:
        raise InputError(f"SINUMERIK {control.upper()} holds at most {cec_max} CEC (sag / cross) tables; this model "
                         f"needs {len(cec)} ({'; '.join(cec)}); the {control.upper()}'s tables are fixed (K3 03/2013 "
                         f"sec. 4.4.4.3) and this export does not leave tables out: compensate the cross errors with "
                         f"`mtcal compensate`, or export for a control whose CEC tables are sized by MD18342 (840D sl)")


def render(tables: list[AxisTable], machine, model_path: str, name: str, measuring_system: int = 0,
           control: str = "840d") -> dict[str, str]:
    """{name: text}: the LEC tables (`%_N_AX_EEC_INI`) for each axis' own positioning and the CEC tables
    (`%_N_NC_CEC_INI`) for cross terms and reversal, each section CHANDATA(1) ... M17 as K3's examples;
    ``measuring_system``: the index e of $AA_ENC_COMP[e, N, AXi] (0 = the first measuring system).  ``tables``
    as the file holds them (``as_written``)."""
    if control not in CONTROLS:
        raise InputError(f"`control` must be one of {', '.join(CONTROLS)}, got {control!r}")
    if measuring_system not in (0, 1):
        raise InputError(f"`measuring_system` must be 0 or 1 (the axis' first or second encoder), got "
                         f"{measuring_system}")
    e = measuring_system
    lec, cec, cec_points, lec_points, backlash, cec_names = [], [], [], {}, [], []
    for tab in tables:
        ax = _ax(machine, tab.axis)
        modulo = int(sampling.unlimited_rotary(machine, tab.axis))
        if tab.axis in tab.corrections:
            lec.append(f"; LEC {tab.axis} = F({tab.axis}) from {', '.join(tab.sources[tab.axis])}: "
                       f"{len(tab.positions)} points, step {tab.step:g} {tab.unit}")
            lec += [f"; {tab.note}"] if tab.note else []
            lec += [f"$AA_ENC_COMP[{e},{i},{ax}]={_fmt(-v)}" for i, v in enumerate(tab.corrections[tab.axis])]
            lec += [f"$AA_ENC_COMP_STEP[{e},{ax}]={_fmt(tab.step)}",
                    f"$AA_ENC_COMP_MIN[{e},{ax}]={_fmt(tab.positions[0])}",
                    f"$AA_ENC_COMP_MAX[{e},{ax}]={_fmt(tab.positions[-1])}",
                    f"$AA_ENC_COMP_IS_MODULO[{e},{ax}]={modulo}"]
            lec_points[ax] = len(tab.positions)
        for out, c in tab.corrections.items():
            if out == tab.axis:
                continue
            cec.append(f"; CEC table {len(cec_points)}: {out} = F({tab.axis}) from {', '.join(tab.sources[out])}")
            cec_names.append(f"{out} = F({tab.axis})")
            _cec(cec, len(cec_points), ax, _ax(machine, out), -c, tab, 0, modulo)
            cec_points.append(len(tab.positions))
        if tab.reversal:
            backlash.append(tab.axis)
            for d in (1, -1):
                cec.append(f"; CEC table {len(cec_points)}: reversal of {tab.axis} "
                           f"({'positive' if d > 0 else 'negative'} direction)")
                _cec(cec, len(cec_points), ax, ax, [d * tab.reversal / 2] * len(tab.positions), tab, d, modulo)
                cec_points.append(len(tab.positions))
                cec_names.append(f"reversal of {tab.axis} ({'+' if d > 0 else '-'})")
    _limits(tables, cec_names, control)
    head = [f"; mtcal export {model_path} --format siemens --control {control} --measuring-system {e}",
            f"; sign: {SIGN}", "; units: mm (linear axes), deg (rotary axes), metric basic system",
            "; axes: " + ", ".join(f"{a} = {_ax(machine, a)}" for a in machine.axes) +
            " (general machine axis names; edit if yours differ)",
            *_machine_data(lec_points, cec_points, e, backlash, control)]
    sections = []
    if lec:
        sections += ["%_N_AX_EEC_INI", "CHANDATA(1)", *head, *lec, "M17"]
    if cec:
        sections += ["%_N_NC_CEC_INI", "CHANDATA(1)", *([] if lec else head), *cec, "M17"]
    return {name: "\n".join(sections + [""])}
