"""`mtcal check predict --model M.json --circular PLANE,RADIUS[,X0,Y0,Z0]` and `mtcal check evaluate TEST.csv
--model M.json`: the field's check tests (ISO 230-4 circular tests, ISO 10791-6 R-test sweeps) predicted from a
model and measured ones evaluated against it (mtcal.check; this module parses arguments and formats)."""
from __future__ import annotations

import argparse

from mtcal.cli._options import integer, real
from mtcal.cli._words import warn_outside
from mtcal.errors import InputError
from mtcal.io import dumps, refuse_overwrite

NAME = "check"
HELP = ("check tests from a model: predict ISO 230-4 circular tests (G, H, F, polar plot, each error's share) and "
        "ISO 10791-6 R-test sweeps, or evaluate a measured one against the model (mm, deg)")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("action", choices=("predict", "evaluate"), help="predict from the model, or evaluate TEST.csv")
    p.add_argument("test", nargs="?", metavar="TEST.csv",
                   help="evaluate: a measured circular test (angle_deg,deviation_mm,direction) or R-test sweep "
                        "(position_deg,dx_mm,dy_mm,dz_mm); docs/guide/checks.md")
    p.add_argument("--model", required=True, metavar="M.json", help="the error model (mtcal identify -o)")
    p.add_argument("--circular", action="append", metavar="PLANE,RADIUS[,X0,Y0,Z0]",
                   help="predict: a circular test in PLANE (two linear axes, e.g. XY) of RADIUS mm about the centre "
                        "X0,Y0,Z0 (the linear axes' positions, mm; default the middle of their ranges); repeatable")
    p.add_argument("--rtest", action="append", metavar="AXIS[,X,Y,Z]",
                   help="predict: an R-test sweep of rotary AXIS with the sphere at X,Y,Z (workpiece mm; default 0)")
    p.add_argument("--direction", choices=("ccw", "cw", "both"), default="both",
                   help="circular: counter-clockwise, clockwise or both (default)")
    p.add_argument("--arc", type=real(0, 360, "deg", lo_open=True), default=360.0, metavar="DEG",
                   help="circular: the arc (deg, default 360) from --start")
    p.add_argument("--start", type=real(-360, 360, "deg"), default=0.0, metavar="DEG", help="circular: start angle")
    p.add_argument("--points", type=integer(8, 100000), default=360, help="circular: points per path (default 360)")
    p.add_argument("--positions", metavar="START:STOP:COUNT", default=None,
                   help="R-test: rotary positions (deg; default the axis' range in 15 deg steps, or 0:345:24)")
    p.add_argument("--fixed", metavar="AXIS=DEG,...", default="", help="the other rotary axes (deg; default 0)")
    p.add_argument("--tool-length", type=real(0, 1000, "mm"), default=0.0, metavar="MM",
                   help="the ball below the spindle gauge point (mm)")
    p.add_argument("--compensated", action="store_true",
                   help="predict: also the test after compensating the program with the model (exact kinematics)")
    p.add_argument("--plot", metavar="FILE.png", help="write the polar plot (circular tests)")


def run(args: argparse.Namespace) -> int:
    from mtcal.check import evaluate_check, read_check
    from mtcal.check.files import parse_fixed
    from mtcal.model.errormodel import load_model

    model = load_model(args.model)
    fixed = parse_fixed(args.fixed, "`fixed`")
    if args.plot:
        refuse_overwrite(args.plot, args.model, *([args.test] if args.test else []))
    if args.action == "evaluate":
        if not args.test:
            raise InputError("check evaluate needs TEST.csv")
        ev = evaluate_check(read_check(args.test), model, fixed=fixed or None, tool_length=args.tool_length or None)
        warn_outside(ev.outside)
        out = ev.to_dict()
        if args.plot and ev.kind == "circular":
            _plot_evaluation(ev, args.plot)
        print(dumps(out) if args.json else _evaluation_text(ev))
        return 0
    tests = _predict(args, model, fixed)
    for t in tests:
        warn_outside(t.get("outside_range") or {})
    if args.plot:
        _plot_predictions(tests, args.plot)
    print(dumps({"model": args.model, "tests": tests}) if args.json else "\n".join(_text(t) for t in tests))
    return 0


def _predict(args, model, fixed: dict[str, float]) -> list[dict]:
    from mtcal.check import RTestSetup, parse_circular, predict_circular, predict_circular_compensated, predict_rtest

    if not (args.circular or args.rtest):
        raise InputError("check predict needs --circular PLANE,RADIUS[,X0,Y0,Z0] or --rtest AXIS[,X,Y,Z]")
    m = model.kinematics
    tests = []
    for text in args.circular or []:
        s = parse_circular(text, m)
        s = type(s)(s.plane, s.radius_mm, s.centre_mm, args.direction, args.arc, args.start, args.points, fixed,
                    args.tool_length)
        t = predict_circular(model, s).to_dict()
        if args.compensated:
            t["compensated"] = predict_circular_compensated(model, s).to_dict()
        tests.append(t)
    for text in args.rtest or []:
        parts = [p.strip() for p in text.split(",")]
        if len(parts) not in (1, 4):
            raise InputError(f"--rtest {text!r}: give AXIS or AXIS,X,Y,Z (workpiece mm)")
        try:
            sphere = tuple(float(v) for v in parts[1:]) or (0.0, 0.0, 0.0)
        except ValueError:
            raise InputError(f"--rtest {text!r}: the sphere's X,Y,Z must be numbers (mm)") from None
        axis = parts[0].upper()
        tests.append(predict_rtest(model, RTestSetup(axis, _positions(args.positions, m, axis), sphere, fixed,
                                                     args.tool_length)).to_dict())
    return tests


def _positions(text: str | None, m, axis: str) -> tuple[float, ...]:
    import numpy as np

    if text is None:
        lim = m.limits[m.index(axis)] if axis in m.axes else None
        return tuple(np.arange(lim[0], lim[1] + 1e-9, 15.0)) if lim else tuple(np.arange(0.0, 360.0, 15.0))
    try:
        a, b, n = text.split(":")
        v = np.linspace(float(a), float(b), int(n))
    except ValueError:
        raise InputError(f"--positions must be START:STOP:COUNT (deg), got {text!r}") from None
    if len(v) < 3 or not np.isfinite(v).all():
        raise InputError(f"--positions needs at least 3 finite positions, got {text!r}")
    return tuple(float(x) for x in v)


def _text(t: dict) -> str:
    if t["kind"] == "circular":
        c = ",".join(f"{v:g}" for v in t["centre_mm"])
        lines = [f"circular test {t['plane']} R = {t['radius_mm']:g} mm about ({c}) mm, {t['direction']}: "
                 f"G = {t['G_mm'] * 1e3:.2f} um, H = {t['H_mm'] * 1e3:.2f} um, F = {t['F_mm'] * 1e3:.2f} um "
                 f"(F_max {t['F_max_mm'] * 1e3:+.2f}, F_min {t['F_min_mm'] * 1e3:+.2f})"]
        if "compensated" in t:
            a = t["compensated"]
            lines.append(f"  after compensation: G = {a['G_mm'] * 1e3:.3f} um, F = {a['F_mm'] * 1e3:.3f} um")
    else:
        r = t["range_mm"]
        lines = [f"R-test sweep of {t['axis']} (sphere at {','.join(f'{v:g}' for v in t['sphere_mm'])} mm): largest "
                 f"difference X {r['X'] * 1e3:.2f}, Y {r['Y'] * 1e3:.2f}, Z {r['Z'] * 1e3:.2f} um"]
    share = list(t["contributions"].items())[:5]
    if share:
        lines.append("  largest shares: " + ", ".join(f"{n} {v * 1e3:.2f} um" for n, v in share))
    return "\n".join(lines)


def _evaluation_text(ev) -> str:
    if ev.kind == "circular":
        f = ("G_mm", "H_mm", "F_mm")
        row = lambda d: ", ".join(f"{k[0]} = {d[k] * 1e3:.2f}" for k in f if d[k] is not None)  # noqa: E731
    else:
        row = lambda d: ", ".join(f"{k} {v * 1e3:.2f}" for k, v in d["range_mm"].items())  # noqa: E731
    lines = [f"{ev.source}: {ev.kind} test against the model (um)"]
    if ev.kind == "circular":
        off = ev.setup["setup_offset_mm"]
        lines.append(f"  set-up: the ballbar's centre {ev.setup['setup_offset_size_mm']:.3f} mm off the circle's "
                     f"({ev.setup['plane'][0]} {off[0]:+.3f}, {ev.setup['plane'][1]} {off[1]:+.3f} mm), fitted "
                     f"exactly and taken out (ISO 230-4; F about that centre)")
        if ev.setup["directions"] == 1:
            lines.append("  one direction: no hysteresis H measured (a test both ways gives it)")
    lines += [f"  measured : {row(ev.measured)}",
             f"  predicted: {row(ev.predicted)}  (U95 {ev.prediction_u95_mm * 1e3:.2f})",
             f"  residual : {row(ev.residual)}  noise sd {ev.noise_sd_mm * 1e3:.2f}",
             f"  {'agrees with the model' if ev.agrees else 'DIFFERS from the model'} (worst reading "
             f"{ev.worst_z:.1f} combined sigma)"]
    lines += [f"  {'found' if f.quasi_static else 'dynamic'}: {f.text} (t = {f.t:.1f})" for f in ev.findings]
    return "\n".join(lines)


def _plot_predictions(tests: list[dict], path: str) -> None:
    import numpy as np

    from mtcal.check.plots import plot_circular
    traces = []
    for t in tests:
        if t["kind"] != "circular":
            continue
        for label, d in (("predicted", t), ("after compensation", t.get("compensated"))):
            if d:
                a = np.asarray(d["trace"], dtype=float)
                traces.append((f"{t['plane']} {label}", a[:, 0], a[:, 1], a[:, 2]))
    if not traces:
        raise InputError("--plot draws circular tests: give --circular")
    plot_circular(traces, "circular test predicted from the model", path)


def _plot_evaluation(ev, path: str) -> None:
    import numpy as np

    from mtcal.check.plots import plot_circular
    a = np.asarray(ev.trace, dtype=float)
    plot_circular([("measured", a[:, 0], a[:, 1], a[:, 4]), ("predicted", a[:, 0], a[:, 2], a[:, 4])],
                  f"{ev.source}: measured and predicted", path)
