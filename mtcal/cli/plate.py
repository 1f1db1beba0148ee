"""`mtcal plate POS.csv`: Hocken-Borchardt plate reversal (alpha, beta, gamma, offsets, corrected points)."""
from __future__ import annotations

import argparse
import math

from mtcal.cli._options import probability
from mtcal.io import dumps, refuse_overwrite

NAME = "plate"
HELP = ("2-D plate reversal (Hocken & Borchardt, NBSIR 79-1752): non-orthogonality, turn, scale difference "
        "and offsets from a plate measured at 0 and ~90 deg clockwise; corrected points; flagged points")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("csv", metavar="POS.csv", help="plate file: point,x1,y1,x2,y2[,x3,y3,x4,y4] (any length unit)")
    p.add_argument("--metric", choices=("split", "x", "y", "none"), default="split",
                   help="where the scale difference goes in the corrected points: split (paper option 3, "
                        "default), x (1), y (2), none (4)")
    p.add_argument("--no-offsets", action="store_true", help="neglect the offsets ex, ey (paper ALBE2)")
    p.add_argument("--no-scale", action="store_true",
                   help="hold gamma at 0 (metric of eq. 2, as Reeve's multiple redundancy)")
    p.add_argument("--exact", action="store_true",
                   help="exact model for any turn angle (default: first order, switched to exact when the "
                        "turn is too far from 90 deg for the data's noise)")
    p.add_argument("--origin", metavar="POINT", help="point placed at (0, 0) in the gage frame (default: first)")
    p.add_argument("--align", metavar="POINT[:x|y]",
                   help="point placed on the x axis (or y with ':y'); default: the point farthest along +x")
    p.add_argument("--level", type=probability, default=0.01,
                   help="family-wise level of the outlier test (Bonferroni), default 0.01")
    p.add_argument("--plot", metavar="PNG", help="write a plot of the plate with magnified residual vectors")
    p.add_argument("--diagnose", action="store_true", help="name the effect the fitted model leaves out "
                   "(scale, squareness, offset held at 0; outlying points): adds \"diagnosis\" as in mtcal diagnose")


def run(args: argparse.Namespace) -> int:
    from mtcal.plate.reversal import fit_plate, plot_plate, read_plate_csv

    align, axis = args.align, "x"
    if align and ":" in align:
        align, axis = align.rsplit(":", 1)
    refuse_overwrite([args.plot], args.csv)
    data = read_plate_csv(args.csv)
    fit = fit_plate(data, metric=args.metric, offsets=not args.no_offsets, exact=True if args.exact else None,
                    origin=args.origin, align=align, align_axis=axis, level=args.level,
                    scale=not args.no_scale)
    out = fit.to_dict()
    if args.plot:
        out["plot"] = {"file": args.plot, "magnification": plot_plate(fit, args.plot)}
    if args.diagnose:
        from mtcal.diagnose import diagnose_plate
        out["diagnosis"] = diagnose_plate(fit, level=args.level)
    if args.json:
        print(dumps(out))
        return 0
    print(_text(out))
    if args.diagnose:
        from mtcal.diagnose import format_plate_diagnosis
        print(format_plate_diagnosis(out["diagnosis"]))
    return 0


def _text(d: dict) -> str:
    u = "(input unit)"
    lines = [f"{d['file']}: {d['n_points']} points, {d['n_positions']} positions, metric {d['metric']} "
             f"(paper option {d['paper_option']}), {'with' if d['offsets'] else 'without'} offsets, "
             f"{d['method'].replace('_', ' ')} fit, dof {d['dof']}",
             "measured turn(s): " + ", ".join(f"{t:.6f} deg" for t in d["turn_deg"])]
    se = d["standard_errors"]
    for n, unit in (("alpha", "rad"), ("beta", "rad"), ("gamma", ""), ("ex", u), ("ey", u)):
        if n in se:
            lines.append(f"  {n:6s} = {d[n]: .4e} +- {se[n]:.2e} {unit}")
    for n, v in d.get("parameters_extra", {}).items():
        lines.append(f"  {n:6s} = {v: .4e} +- {se[n]:.2e}")
    lines.append(f"  sigma  = {d['sigma']:.4e} {u}   (eq. 16)")
    g = d["gage_frame"]
    lines.append(f"corrected points (gage frame: origin {g['origin']}, {g['align']} on the {g['axis']} axis):")
    res = {r["point"]: r["r"] for r in d["residuals"]}
    for c in d["corrected"]:
        r = res[c["point"]]
        lines.append(f"  {c['point']:>6s} {c['x']:14.6f} {c['y']:14.6f}   residual " +
                     " ".join(f"{v: .2e}" for v in r))
    if d["flagged"]:
        lines.append("flagged (inconsistent with the rest): " + ", ".join(
            f"{f['point']} (F = {f['F']:.1f}, p = {f['p_bonferroni']:.2g})" for f in d["flagged"]))
    else:
        lines.append("flagged: none")
    lines.append(f"  rule: {d['flag_rule']}")
    for n in d["notes"]:
        lines.append(f"note: {n}")
    if "plot" in d:
        lines.append(f"plot: {d['plot']['file']} (residuals x{d['plot']['magnification']:g})")
    if not math.isfinite(d["sigma"]):
        lines.append("note: no degrees of freedom left; sigma undefined")
    return "\n".join(lines)
