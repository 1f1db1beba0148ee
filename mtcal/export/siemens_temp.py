"""SINUMERIK temperature compensation from a thermal model: a part program (subprogram, ``M17``) that the PLC calls
every ``period_s`` seconds with the temperatures (and the spindle speed) in R parameters; it advances the model's
lags and writes the axes' temperature compensation setting data.

Source: SINUMERIK 840D sl / 828D Function Manual Extended Functions, K3 Compensations (03/2013, 6FC5397-1BP40-3BA1),
sec. 4.2 "Temperature compensation": the compensation value of an axis at position P_x is
dK_x = K_0 + tan(beta) (P_x - P_0), with
* SD43900 $SA_TEMP_COMP_ABS_VALUE: K_0, the position-independent value (mm);
* SD43910 $SA_TEMP_COMP_SLOPE: tan(beta), the position-dependent gradient;
* SD43920 $SA_TEMP_COMP_REF_POSITION: P_0, the reference position of the position-dependent term (mm);
* MD32750 $MA_TEMP_COMP_TYPE: bit 0 position-independent (SD43900), bit 1 position-dependent (SD43910, SD43920),
  bit 2 in the tool direction (MD20390); MD32760 $MA_COMP_ADD_VELO_FACTOR limits the change per IPO cycle (and
  the gradient tan(beta)).
The manual: the temperature changes slowly, so the PLC acquires the temperature profile (e.g. in a minutes cycle)
and derives the parameters from it. A thermal test at one position gives no gradient: SD43910 and SD43920 are
written 0 and MD32750 = 1 (bit 0 only); say so where the model comes from such a test.
Not verified against the manual (the search found K3 sec. 4.2's table of MD32750 but not these): that a part
program may write the SD43900 family (setting data are writable from part programs in general), the sign of
K_0 (ASSUMED as the LEC's, mtcal.export.siemens: the value is the measured error, actual - nominal, and the axis
moves by minus it) and the R parameter range (R10.. R99 within the default MD28050 $MC_MM_NUM_R_PARAM = 100).
"""
from __future__ import annotations

from mtcal.errors import InputError
from mtcal.thermal.features import SPEED, warm_up

NAME = "siemens"
KIND = "file"
SIGN = ("SD43900 is the channel's drift (the axis' error, actual - nominal) in mm, ASSUMED applied as the LEC's "
        "values are (the axis moves by minus it); source: SINUMERIK K3 Compensations 03/2013 sec. 4.2")
NOTES = ["siemens: the PLC must write the temperatures (degC) and the spindle speed (rpm) into the R parameters "
         "the program's header names before each call, every --period seconds"]
R_INPUTS, R_STATES, R_LAST = 10, 50, 99


def _fmt(v: float) -> str:
    text = f"{v:.9g}"
    return "0" if float(text) == 0 else text


def _registers(placed) -> tuple[dict[str, int], dict, list]:
    inputs = sorted({t.input for p in placed for t in p.channel.terms}, key=lambda k: (k == SPEED, k))
    regs = {k: R_INPUTS + i for i, k in enumerate(inputs)}
    lags = sorted({t for p in placed for t in p.channel.terms if t.tau_s is not None},
                  key=lambda t: (t.input, t.tau_s))
    states = {t: R_STATES + i for i, t in enumerate(lags)}
    if (regs and max(regs.values()) >= R_STATES) or (states and max(states.values()) > R_LAST):
        raise InputError(f"the model needs {len(regs)} inputs and {len(states)} lag states: more R parameters than "
                         f"R{R_INPUTS}..R{R_LAST} hold")
    return regs, states, lags


def _input(term, regs, reference_c) -> str:
    if term.input == SPEED:
        return f"(R{regs[SPEED]}/1000)"
    return f"(R{regs[term.input]}-{_fmt(reference_c[term.input])})"


def render(model, placed, machine, model_path: str, period_s: float, name: str) -> dict[str, str]:
    """{name: the part program} (module docstring)."""
    regs, states, lags = _registers(placed)
    ax = {a: f"AX{machine.axes.index(a) + 1}" for a in machine.axes}
    head = [f"; mtcal thermal export {model_path} --format siemens --period {period_s:g}",
            f"; from the thermal test {model.source} (sha256 {model.sha256[:12]}), judged on its last "
            f"{model.holdout:.0%} in time",
            f"; sign: {SIGN}",
            "; SINUMERIK temperature compensation (K3 Compensations 03/2013, 6FC5397-1BP40-3BA1, sec. 4.2):",
            ";   dK = K0 + tan(beta) (Px - P0); K0 = SD43900 $SA_TEMP_COMP_ABS_VALUE (mm),",
            ";   tan(beta) = SD43910 $SA_TEMP_COMP_SLOPE, P0 = SD43920 $SA_TEMP_COMP_REF_POSITION (mm)",
            "; MACHINE DATA TO SET (then NEWCONF):"]
    head += [f"; * MD32750 $MA_TEMP_COMP_TYPE[{ax[p.axis]}] = 1 (bit 0: position-independent, SD43900; bit 1 "
             f"position-dependent not set: a test at one position gives no gradient)" for p in placed]
    head += ["; * MD32760 $MA_COMP_ADD_VELO_FACTOR: the largest change per IPO cycle (K3 sec. 4.2)",
             f"; CALL this program from the PLC every {period_s:g} s, the inputs written first:"]
    head += [f";   R{r} = " + ("spindle speed (rpm)" if k == SPEED else f"temperature {k} (degC)")
             for k, r in regs.items()]
    if lags:
        head += [f"; STATE: R{states[lags[0]]}..R{states[lags[-1]]} the lags, set to 0 at power on (the machine at "
                 "its reference temperatures " + ", ".join(f"{k} {_fmt(v)} degC" for k, v in
                                                         model.reference_c.items() if k in regs) +
                 ", the spindle at rest)"]
    body = []
    for t in lags:
        w = float(warm_up(period_s, t.tau_s))
        body.append(f"R{states[t]}=R{states[t]}+{_fmt(w)}*({_input(t, regs, model.reference_c)}-R{states[t]})"
                    f" ; {t.label}")
    for p in placed:
        c = p.channel
        parts = [_fmt(c.intercept_um)] + [
            f"{_fmt(k)}*" + (f"R{states[t]}" if t.tau_s is not None else _input(t, regs, model.reference_c))
            for k, t in zip(c.coefficients, c.terms)]
        body += [f"; {c.channel} -> {'-' if p.sign < 0 else ''}{p.axis}: {c.model}; out of sample RMSE "
                 f"{c.rmse_um:.3g} um (constant {c.constant_rmse_um:.3g}, time only {c.time_only_rmse_um:.3g})",
                 f"$SA_TEMP_COMP_SLOPE[{ax[p.axis]}]=0", f"$SA_TEMP_COMP_REF_POSITION[{ax[p.axis]}]=0",
                 f"$SA_TEMP_COMP_ABS_VALUE[{ax[p.axis]}]={_fmt(0.001 * p.sign)}*({'+'.join(parts)})"]
    text = "\n".join([f"%_N_{name.upper().replace('.', '_')}", *head, *body, "M17", ""])
    return {name: text.replace("+-", "-")}
