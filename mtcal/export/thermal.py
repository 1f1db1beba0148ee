"""Thermal compensation from a thermal model (mtcal.thermal.model): the controller's place for a
temperature-dependent offset, one module per controller.

Public entry: ``export_thermal(model, fmt, out, ...) -> ThermalExportResult`` and ``THERMAL_FORMATS``.

Refused before anything is written: a channel the model does not predict (its out-of-sample test failed: no
compensation is offered for it, ``force`` or not), a channel without a machine axis, two channels on one axis, an
axis the machine does not have or that is not linear; and, through the plausibility guard of every export
(mtcal.model.plausibility.translation_bound), a channel whose largest offset over the temperatures and speeds of
its test exceeds what a machine's error can be (``force`` writes it with a loud warning).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from mtcal.errors import InputError
from mtcal.export import linuxcnc_thermal, siemens_temp
from mtcal.io import atomic_write_text, refuse_overwrite
from mtcal.model.plausibility import translation_bound
from mtcal.thermal.model import ThermalModel
from mtcal.thermal.readings import parse_mapping

THERMAL_FORMATS = {"siemens": siemens_temp, "linuxcnc": linuxcnc_thermal}


@dataclass
class Placed:
    """A channel placed on a machine axis: the axis' error is ``sign`` x the channel's drift."""

    channel: object  # ChannelModel
    axis: str
    sign: int


@dataclass
class ThermalExportResult:
    """What ``export_thermal`` wrote.

    Attributes
    ----------
    format : str
    files : list of str
    channels : list of dict
        channel, axis, sign, largest offset (um), the model and its out-of-sample RMSE.
    sign : str
        The format's sign convention with its source.
    warnings : list of str
    """

    format: str
    files: list[str]
    channels: list[dict]
    sign: str
    warnings: list[str] = field(default_factory=list)


def _placed(model: ThermalModel, axes: dict[str, str], machine) -> list[Placed]:
    if not axes:  # the channels' own directions (X1 -> X), the predictable ones
        axes = {c.channel: c.direction.rstrip("12") for c in model.channels if c.predictable and c.direction}
        if not axes:
            raise InputError("no channel has both a direction and a model that predicts it; name the axes "
                             "(`axes` ch3=Z,...) of predictable channels: " +
                             (", ".join(c.channel for c in model.channels if c.predictable) or "none is"))
    out = []
    for name, ax in axes.items():
        c = model.channel(name)
        if not c.predictable:
            raise InputError(f"{name}: {c.reason}; nothing was written")
        sign, axis = (-1, ax[1:]) if ax.startswith("-") else (1, ax.lstrip("+"))
        axis = axis.upper()
        if axis not in machine.axes or machine.kind(axis) != "linear":
            raise InputError(f"{name}={ax}: {axis} is not a linear axis of machine {machine.name} "
                             f"({', '.join(machine.linear_axes)})")
        out.append(Placed(c, axis, sign))
    dup = sorted({p.axis for p in out if [q.axis for q in out].count(p.axis) > 1})
    if dup:
        raise InputError(f"more than one channel on axis {', '.join(dup)}: one temperature compensation per axis")
    return out


def _guard(placed: list[Placed], machine, force: bool, what: str) -> list[str]:
    bound_um = translation_bound(machine) * 1000.0
    problems = []
    for p in placed:
        c = p.channel
        worst = c.largest_offset_um()
        if not all(math.isfinite(v) for v in [c.intercept_um, *c.coefficients]):
            problems.append(f"{c.channel}: a coefficient is not finite")
        elif worst > bound_um:
            problems.append(f"{c.channel}: the offset reaches {worst:.6g} um over its test, beyond {bound_um:.6g} um "
                            f"(a translational error of machine {machine.name})")
    if problems and not force:
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        raise InputError(f"{what}: {problems[0]}{more}; nothing was written (`force` writes it anyway)")
    return [f"FORCED past the plausibility guard: {p}" for p in problems]


def export_thermal(model: ThermalModel, fmt: str, out: str | Path, machine, axes: str | dict | None = None,
                   period_s: float = 60.0, force: bool = False, model_path: str = "MODEL.json",
                   protect: tuple = ()) -> ThermalExportResult:
    """Write the temperature compensation of ``model``'s predictable channels for controller ``fmt``.

    Parameters
    ----------
    model : ThermalModel
    fmt : {"siemens", "linuxcnc"}
        siemens: one part program setting the temperature compensation's setting data (SD43900/SD43910/SD43920);
        linuxcnc: a HAL component (.comp) driving the external axis offsets, and its HAL and INI lines.
    out : str or pathlib.Path
        The file (siemens) or folder (linuxcnc).
    machine : Machine
        The machine whose axes the channels are placed on (its travel bounds the offsets).
    axes : str or dict, optional
        ``ch3=Z,ch4=-X``: each channel's machine axis, ``-`` where the channel reads against the axis' direction
        (default: the predictable channels' own directions).
    period_s : float, optional
        siemens: the period (s) at which the PLC calls the program (the lags' step); linuxcnc uses its thread's.
    force : bool, optional
        Write past the plausibility guard, with a loud warning (never a channel that is not predictable).
    model_path : str, optional
        The model's name in the files and messages.
    protect : tuple, optional
        Paths never written over (the inputs).

    Returns
    -------
    ThermalExportResult

    Raises
    ------
    mtcal.errors.InputError
        Module docstring.
    """
    if fmt not in THERMAL_FORMATS:
        raise InputError(f"unknown thermal format {fmt!r}; known: {', '.join(THERMAL_FORMATS)}")
    if not (math.isfinite(period_s) and period_s > 0):
        raise InputError(f"`period_s` must be a positive number of seconds, got {period_s!r}")
    placed = _placed(model, parse_mapping(axes, "axes"), machine)
    warnings = _guard(placed, machine, force, model_path)
    mod = THERMAL_FORMATS[fmt]
    files = mod.render(model, placed, machine, model_path, period_s, Path(out).name)
    paths = [Path(out) / n for n in files] if mod.KIND == "dir" else [Path(out)]
    for p in paths:
        refuse_overwrite(p, *protect)
    for p, text in zip(paths, files.values()):
        p.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_text(p, text)
    chans = [{"channel": p.channel.channel, "axis": p.axis, "sign": p.sign, "model": p.channel.model,
              "rmse_um": p.channel.rmse_um, "largest_offset_um": p.channel.largest_offset_um()} for p in placed]
    return ThermalExportResult(fmt, [str(p) for p in paths], chans, mod.SIGN, warnings + mod.NOTES)
