"""`mtcal demo [--machine NAME]`: the whole calibration story, through the same commands a user runs.

campaign (DMU 50: bundled, simulated with thesis-magnitude errors and one concealed effect; any other spec:
simulated now from a synthetic truth of the same magnitudes, mtcal.data.make_demo_data.build_for) -> identify
-> plan -> compensate a five-axis program (DMU 50: the bundled one; other machines: a tool path taken through
the machine's inverse kinematics, written in its axis words) -> diagnose -> NBS plate reversal; numbers
printed, PNG plots and a Markdown report written to DIR.  The truth behind the campaign is known, so the demo
says how close identification and compensation came to it.
"""
from __future__ import annotations

import datetime as dt
import json
import logging
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mtcal.campaign.plans import Plan
from mtcal.campaign.simulate import simulate, write_campaign
from mtcal.check import CircleSetup, evaluate_check, predict_circular, predict_circular_compensated, simulate_circular
from mtcal.check.plots import plot_circular
from mtcal.compensate.run import compensate_program
from mtcal.data import path
from mtcal.data.make_demo_data import DEMO_EFFECT, DEMO_PLAN, DEMO_SEED, build_for
from mtcal.demo.stations import plot_stations, report_lines, run_stations
from mtcal.diagnose import diagnose, diagnose_plate, plot_findings, plot_residuals
from mtcal.identify import fitting
from mtcal.identify.plots import plot_all
from mtcal.identify.run import identify
from mtcal.io import atomic_open, atomic_write_text, dumps, record_written, refuse_foreign, save_figure
from mtcal.kinematics.defaults import default_positions
from mtcal.kinematics.machine import Machine, load_machine
from mtcal.measurement.recordings import read_recording
from mtcal.model.errormodel import ErrorModel, load_model, save_model
from mtcal.nc.gcode import read_moves
from mtcal.planning.plan import plan_uncertainty, plot_placement_map
from mtcal.plate.reversal import fit_plate, plot_plate, read_plate_csv

STEPS = 9
log = logging.getLogger(__name__)


data_path = path  # mtcal.data.path


def _json(obj) -> dict:
    """A library answer as its command's JSON (the same numbers `mtcal ... --json` prints)."""
    return json.loads(dumps(obj))


class Progress:
    """Numbered steps through `logging` (logger mtcal.demo.run); the library logs its own progress unless
    ``quiet``."""

    def __init__(self):
        self.t0, self.k = time.perf_counter(), 0

    def step(self, msg: str) -> None:
        self.k += 1
        log.info("[%d/%d] %s (%.1f s)", self.k, STEPS, msg, time.perf_counter() - self.t0)


def _um(v: float) -> str:
    return f"{v * 1e3:.2f}"


def tool_tip_errors(machine, truth, q: np.ndarray, targets: np.ndarray, tool_length: float = 0.0) -> np.ndarray:
    """|tool tip - target| in mm when the axes q run on the true machine (exact kinematics, truth errors)."""
    pose = machine.forward(q, truth.errors_at(machine, q, extrapolate="hold"), tool_length)
    return np.linalg.norm(pose[:, :3] - targets[:, :3], axis=1)


BUNDLED = "dmu50"  # the machine whose campaign, truth and sample program ship in mtcal/data


def _copy(src: Path, dst: Path) -> None:
    """A bundled file copied into the demo's folder as every output is written (atomically; a file there that
    mtcal did not write is refused)."""
    with atomic_open(dst, "wb") as fh:
        fh.write(Path(src).read_bytes())


def _campaign(m, out: Path) -> tuple[Path, dict, object]:
    """(recording path, planted truth, truth model): the bundled campaign of the DMU 50, else a simulated one."""
    rec_path = out / "campaign.csv"
    if m.name == BUNDLED:
        _copy(data_path("demo_campaign.csv"), rec_path)
        return rec_path, json.loads(data_path("demo_campaign.truth.json").read_text()), load_model(
            data_path("demo_truth.json"))
    truth = build_for(m)
    effect = (DEMO_EFFECT[0], {**DEMO_EFFECT[1], "axis": m.linear_axes[0]})
    rec, planted = simulate(truth, machine=m, seed=DEMO_SEED, effects=[effect])
    write_campaign(rec, planted, rec_path)
    return rec_path, planted, truth


def _sample_grid(m, n: int, rng: np.random.Generator) -> np.ndarray:
    """Random axis positions (n, n_axes) inside the spec's campaign ranges (where the model was measured)."""
    pos = default_positions(m)
    return np.column_stack([rng.uniform(pos[a].min(), pos[a].max(), n) for a in m.axes])


SEEDS = 8  # other campaigns of the demo's design: the spread of its headline figure (one campaign is one draw)


def _over_seeds(m, truth, planted: dict, volumetric, keep: list | None = None) -> dict:
    """model - truth RMS (um, as ``volumetric``) of SEEDS more campaigns of the same design, truth and planted
    effect, identified as the demo does (default estimator, tracker given): {"n", "median", "min", "max"}; the
    models are appended to ``keep`` (the history step reuses the first)."""
    v = []
    for seed in range(1, SEEDS + 1):
        model = _campaign_model(m, truth, planted, seed)
        v.append(volumetric(model))
        if keep is not None:
            keep.append(model)
    return {"n": SEEDS, "median": float(np.median(v)), "min": float(np.min(v)), "max": float(np.max(v))}


def _campaign_model(m, truth, planted: dict, seed: int) -> ErrorModel:
    """The model identified (default estimator, tracker given) from another campaign of the demo's design, truth
    and planted effect, drawn with ``seed``."""
    plan = DEMO_PLAN if m.name == BUNDLED else None
    effects = [(e["name"], e["params"]) for e in planted.get("effects", [])]
    rec, _ = simulate(truth, machine=m, plan=plan, seed=seed, effects=effects, rounds=planted["rounds"],
                      tracker=planted["tracker"])
    return identify(rec, tracker=planted["tracker"], machine=m, worth=False).model


@dataclass
class _Story:
    """What the demo's steps share: the machine (mm, deg), the output folders, the campaign and its truth, the
    tracker as a user types it (mm), a grid of poses over the travel and the true tool-tip deviations there (mm)."""

    m: Machine
    out: Path
    plots: Path
    rec_path: Path
    planted: dict
    truth: ErrorModel
    xyz: list[float]
    rng: np.random.Generator
    grid: np.ndarray
    dev_true: np.ndarray
    seed_models: list = field(default_factory=list)  # the models of _over_seeds (the history step reuses one)

    @property
    def model_path(self) -> Path:
        return self.out / "model.json"

    def volumetric(self, mdl) -> float:
        """Model - truth over the grid: RMS of the tool-tip deviation difference, um."""
        d = self.m.deviation(self.grid, mdl.errors_at(self.m, self.grid, "hold"), order=None)[:, :3] - self.dev_true
        return float(np.sqrt(np.mean(np.sum(d**2, axis=1))) * 1e3)


def _story(m: Machine, out: Path) -> _Story:
    """The campaign (bundled or simulated now) and the grid the demo judges models on."""
    plots = out / "plots"
    plots.mkdir(exist_ok=True)
    rec_path, planted, truth = _campaign(m, out)
    xyz = [float(f"{c:g}") for c in planted["tracker"]]  # as a user types it (6 significant digits)
    rng = np.random.default_rng(0)
    if m.name == BUNDLED:  # travel centred on the C axis, as the bundled campaign
        grid = np.column_stack([rng.uniform(-200, 200, 2000), rng.uniform(-180, 180, 2000),
                                rng.uniform(-150, 150, 2000), rng.uniform(0, 120, 2000), rng.uniform(0, 360, 2000)])
    else:
        grid = _sample_grid(m, 2000, rng)
    dev_true = m.deviation(grid, truth.errors_at(m, grid, "hold"), order=None)[:, :3]
    return _Story(m, out, plots, rec_path, planted, truth, xyz, rng, grid, dev_true)


def run_demo(out: Path, machine: str | None = None) -> dict:
    """The demo into ``out``; progress through logging (mtcal.demo.run and the library; `mtcal -q` silences it)."""
    m = load_machine(machine or BUNDLED)  # before anything is written: a bad name writes nothing
    out.mkdir(parents=True, exist_ok=True)
    prog = Progress()
    s = _story(m, out)
    tracker = ",".join(f"{c:g}" for c in s.planted["tracker"])
    prog.step(f"campaign: {s.rec_path.name} ({'bundled' if m.name == BUNDLED else 'simulated now'}: {m.name}, "
              f"{len(m.axes)} axes x {s.planted['rounds']} rounds, tracker at {tracker} mm; one effect concealed)")
    summary: dict = {"out": str(out), "machine": m.name, "title": m.title}
    summary["identify"], ident = _identify_step(s)
    prog.step("identify: six error motions per axis and position, squareness, fitted error functions")
    summary["plan"] = _plan_step(s, ident)
    prog.step("plan: predicted uncertainty of one round at this tracker placement, and a placement map")
    summary["compensate"] = _compensate_step(s)
    prog.step("compensate: sample five-axis program corrected with the identified model, checked on the true machine")
    summary["checks"] = _checks_step(s)
    prog.step("checks: the ISO 230-4 circular test predicted from the model before and after compensation, and the "
              "true machine's (simulated ballbar) read against it")
    summary["stations"] = st = _stations_step(s)
    prog.step(f"stations: model - truth {st['one_station_three_point']['model_minus_true_rms_um']:.1f} um (one "
              f"station, three-point) -> {st['four_stations_joint']['model_minus_true_rms_um']:.1f} um (four "
              f"stations, joint fit) at equal measuring time")
    summary["diagnose"] = _diagnose_step(s)
    prog.step("diagnose: what the quasi-static model leaves out, where, and how much")
    summary["plate"] = _plate_step(s.plots)
    prog.step("plate: Hocken-Borchardt reversal of NBS Table 1 (ALBE3), and the model without the scale term")
    summary["history"] = h = history_step(s)
    prog.step(f"history: three calibrations, a crash planted before the third; compare named "
              f"{', '.join(h['named']) or 'nothing'} (planted: {', '.join(h['planted'])}); {h['report']}")
    summary["seconds"] = time.perf_counter() - prog.t0
    atomic_write_text(out / "summary.json", dumps(summary) + "\n")
    atomic_write_text(out / "report.md", report(summary, out))
    return summary


def _identify_step(s: _Story) -> tuple[dict, dict]:
    """identify's default with a tracker position, the joint fit (the stations step sets the three-point method);
    the model written and plotted; squareness and model - truth against the known truth."""
    res = identify(read_recording(s.rec_path, s.m.name), tracker=s.xyz, machine=s.m.name, method="joint")
    for w in res.warnings:
        log.warning("warning: %s", w)
    save_model(res.model, s.model_path)
    plot_all(res, s.plots)
    ident = _json({**res.to_json(), "tracker": s.xyz})
    model = load_model(s.model_path)
    return {
        "squareness_urad": {k: v * 1e6 for k, v in ident["squareness"].items()},
        "squareness_std_mean_urad": {k: v.get("std_mean", float("nan")) * 1e6
                                     for k, v in ident.get("squareness_type_a", {}).items()},
        "squareness_true_urad": {k: v * 1e6 for k, v in true_squareness(s.truth, ident).items()},
        "volumetric_true_max_um": float(np.linalg.norm(s.dev_true, axis=1).max() * 1e3),
        "volumetric_model_minus_true_rms_um": s.volumetric(model),
        "over_seeds": _over_seeds(s.m, s.truth, s.planted, s.volumetric, s.seed_models),
        "worth": model.meta.get("worth"),
        "warnings": ident.get("warnings", []),
    }, ident


def _plan_step(s: _Story, ident: dict) -> dict:
    """The predicted one-round sigma at mid-travel beside the observed std over the rounds; the placement map."""
    plan = _json(plan_uncertainty(s.xyz, Plan(s.m)).to_dict())
    plot_placement_map(s.plots / "plan_map.png", Plan(s.m), tracker=plan["tracker"], z=plan["tracker"][2])
    observed = {}  # std over rounds at the plan's mid-travel position (the same machine coordinates)
    for ax, res in ident["axes"].items():
        k = int(np.argmin(np.abs(np.asarray(res["positions"], dtype=float) - plan["mid_travel"][ax])))
        observed[ax] = {n: float(v["std"][k]) for n, v in res["errors"].items()}
    return {ax: {n: {"position": plan["mid_travel"][ax], "predicted": sg,
                     "observed_std_over_rounds": observed.get(ax, {}).get(n)}
                 for n, sg in plan["axes"][ax].items()} for ax in plan["axes"]}


def _compensate_step(s: _Story) -> dict:
    """The sample program compensated with the identified model; tool-tip errors on the true machine (um)."""
    before, after, comp = _compensate_program(s.m, s.truth, s.model_path, s.out, s.rng)
    _plot_compensation(s.plots / "compensation_before_after.png", before, after)
    return {"iso_16907": comp["iso_16907"], "lines_changed": comp["lines_changed"],
            "true_error_before_max_um": float(before.max() * 1e3),
            "true_error_before_rms_um": float(np.sqrt(np.mean(before**2)) * 1e3),
            "true_error_after_max_um": float(after.max() * 1e3),
            "true_error_after_rms_um": float(np.sqrt(np.mean(after**2)) * 1e3),
            "predicted_residual_um": comp["residual"]}


def _checks_step(s: _Story) -> dict:
    """The circular test in the plane of the first two linear axes (R 150 mm about the axes' zero, both directions):
    predicted from the identified model before and after compensating with it, the true machine's (a simulated
    ballbar: exact kinematics, the planted effects that act on a circle) before and after, and the true machine's
    test before compensation evaluated against the model; the polar plot."""
    model = load_model(s.model_path)
    lin = s.m.linear_axes
    setup = CircleSetup(lin[0] + lin[1], 150.0, (0.0,) * len(lin))
    backlash = {e["params"]["axis"]: e["params"]["amount"] for e in s.planted.get("effects", [])
                if e["name"] == "backlash"}
    pred, pred_after = predict_circular(model, setup), predict_circular_compensated(model, setup)
    true_after = predict_circular_compensated(model, setup, errors_of=s.truth)
    measured = simulate_circular(s.truth, setup, backlash=backlash, seed=1)
    ev = evaluate_check(measured, model)
    th, dr, d = (measured.data[k] for k in ("angle_deg", "deviation_mm", "direction"))
    plot_circular([("predicted", pred.theta_deg, pred.dr, pred.direction),
                   ("true machine (simulated ballbar)", th, dr, d),
                   ("true machine after compensation", true_after.theta_deg, true_after.dr, true_after.direction)],
                  f"{s.m.name}: circular test {setup.plane}, R 150 mm", s.plots / "circular_test.png")
    um = lambda f: {k: v * 1e3 for k, v in f.items() if k in ("G_mm", "H_mm", "F_mm")}  # noqa: E731
    return {"plane": setup.plane, "radius_mm": setup.radius_mm, "predicted_um": um(pred.figures),
            "predicted_after_compensation_um": um(pred_after.figures), "true_machine_um": um(ev.measured),
            "true_machine_after_compensation_um": um(true_after.figures),
            "largest_shares_um": {k: v * 1e3 for k, v in list(pred.contributions.items())[:4]},
            "evaluation": {"agrees": ev.agrees, "worst_z": ev.worst_z, "prediction_u95_um": ev.prediction_u95_mm * 1e3,
                           "findings": [f.text for f in ev.findings]}}


def _checks_lines(k: dict | None) -> list[str]:
    """The report's section on the circular test (``_checks_step``)."""
    if not k:
        return []
    row = lambda name, f: f"| {name} | {f['G_mm']:.2f} | {f['H_mm']:.2f} | {f['F_mm']:.2f} |"  # noqa: E731
    ev = k["evaluation"]
    return [f"## Check: ISO 230-4 circular test {k['plane']}, R {k['radius_mm']:g} mm", "",
            "`mtcal check predict` from the identified model, before and after compensating with it; the true "
            "machine's test (a simulated ballbar: exact kinematics, the campaign's planted effects) before and after; "
            "G circular deviation, H hysteresis, F radial deviation (ISO 230-4), um.", "",
            "| circular test | G | H | F |", "|---|---|---|---|",
            row("predicted from the model", k["predicted_um"]),
            row("predicted after compensation", k["predicted_after_compensation_um"]),
            row("true machine", k["true_machine_um"]),
            row("true machine after compensation", k["true_machine_after_compensation_um"]), "",
            "Largest shares of the predicted G: " + ", ".join(f"{n} {v:.2f} um" for n, v in
                                                              k["largest_shares_um"].items()) + ".", "",
            f"The true machine's test read against the model (`mtcal check evaluate`): "
            f"{'agrees' if ev['agrees'] else 'differs'} (worst reading {ev['worst_z']:.1f} combined sigma, the "
            f"prediction's U95 {ev['prediction_u95_um']:.2f} um)"
            + (": " + "; ".join(ev["findings"]) if ev["findings"] else "") + ".", "",
            "![circular test](plots/circular_test.png)", ""]


def _stations_step(s: _Story) -> dict:
    """One station against four at equal measuring time (mtcal.demo.stations), the same sample program."""

    def compensate(mdl, name: str):  # the same sample program, in out/stations/ (the step's own files)
        (s.out / "stations").mkdir(exist_ok=True)
        p = s.out / "stations" / f"model_{name}.json"
        save_model(mdl, p)
        return compensate_file(s.m, s.truth, p, s.out / "sample_5axis.nc",
                               s.out / "stations" / f"sample_5axis_compensated_{name}.nc")[:2]

    st = run_stations(s.m, s.truth, s.planted, s.volumetric, compensate)
    plot_stations(st, s.plots / "stations.png")
    return st


def _diagnose_step(s: _Story) -> dict:
    """The diagnosis of the campaign (tracker given) beside what was planted."""
    d = diagnose(read_recording(s.rec_path, s.m.name), None, machine=s.m.name, tracker=s.xyz)
    plot_residuals(d, s.plots)
    plot_findings(d, s.plots)
    diag = _json(d.to_dict())
    return {"base_sigma": diag["base_sigma"],
            "effects": [e for e in diag["effects"] if e.get("significant")],
            "not_significant": len([e for e in diag["effects"] if not e.get("significant")]),
            "located": diag.get("located", [])[:5],
            "planted": [{"name": e["name"], **e.get("params", {})} for e in s.planted.get("effects", [])]}


CRASH_URAD = (80.0, -80.0)  # the demo's crash: the first two squareness errors of the spec change by these
CALIBRATIONS = ("2024-01-15", "2024-06-15", "2024-11-20")


def history_step(s: _Story) -> dict:
    """Three calibrations of the same simulated machine into a history (out/history.db, written whole): another
    campaign of the demo's design (a model _over_seeds identified), the demo's own model, and a campaign after a
    crash that changed the spec's first two squareness errors by CRASH_URAD; `history compare` on it and the
    HTML report (out/report.html)."""
    import os
    import tempfile

    from mtcal.history import add, compare_history
    from mtcal.report import write_report

    names = list(s.m.error_groups.get("squareness", ()))[:2]
    crashed = ErrorModel(s.truth.machine, dict(s.truth.constants), s.truth.functions, s.truth.meta)
    for n, d in zip(names, CRASH_URAD):
        crashed.constants[n] = crashed.constants.get(n, 0.0) + d * 1e-6
    models = [s.seed_models[0] if s.seed_models else _campaign_model(s.m, s.truth, s.planted, 1),
              load_model(s.model_path), _campaign_model(s.m, crashed, s.planted, SEEDS + 1)]
    folder = s.out / "history"
    folder.mkdir(exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".history.", suffix=".db", dir=s.out)
    os.close(fd)
    os.unlink(tmp)  # the store creates it
    try:
        for k, (mdl, date) in enumerate(zip(models, CALIBRATIONS), 1):
            save_model(mdl, folder / f"calibration_{k}.json")
            add(folder / f"calibration_{k}.json", "demo-machine", dt.date.fromisoformat(date), tmp)
        comp = compare_history("demo-machine", db=tmp).to_dict()
        report = write_report("demo-machine", s.out / "report.html", tmp)
        refuse_foreign(s.out / "history.db")
        os.replace(tmp, s.out / "history.db")
        record_written(s.out / "history.db")
    finally:
        Path(tmp).unlink(missing_ok=True)
    named = sorted({c["name"] for st in comp["steps"] for c in st["changed"]})
    return {"planted": {n: d for n, d in zip(names, CRASH_URAD)}, "dates": list(CALIBRATIONS),
            "named": named, "steps": comp["steps"], "level": comp["level"], "report": "report.html",
            "report_pictures": report["pictures"]}


def _history_lines(h: dict | None) -> list[str]:
    """The report's section on the history step."""
    if not h:
        return []
    lines = ["## History: three calibrations, a crash before the third", "",
             f"Calibrations of {', '.join(h['dates'])} in `history.db`; a crash planted between the second and the "
             "third: " + ", ".join(f"{n} {d:+g} urad" for n, d in h["planted"].items()) + ". `mtcal history "
             f"compare` (95 % intervals of the differences, family-wise level {h['level']:g}, Holm):", ""]
    for st in h["steps"]:
        lines.append(f"- {st['from']} -> {st['to']}: " + ("; ".join(c["text"] for c in st["changed"]) or
                                                          f"nothing changed ({st['unchanged']} errors compared)"))
    return lines + ["", f"The customer's report: [{h['report']}]({h['report']}) (one self-contained HTML file).", ""]


def _plate_step(plots: Path) -> dict:
    """NBS Table 1 by Hocken-Borchardt reversal (ALBE3), and the model without the scale term, diagnosed."""
    nbs = read_plate_csv(data_path("nbs_table1_corrected.csv"))
    fit = fit_plate(nbs, exact=None)
    plot_plate(fit, plots / "plate_table1.png")
    plate = _json(fit.to_dict())
    no_scale = fit_plate(nbs, exact=None, scale=False)
    reeve = _json({**no_scale.to_dict(), "diagnosis": diagnose_plate(no_scale)})
    out = {k: plate[k] for k in ("alpha", "beta", "gamma", "ex", "ey", "sigma")}
    out["without_scale"] = {"sigma": reeve["sigma"], "diagnosis": reeve.get("diagnosis")}
    return out


def _compensate_program(m, truth, model_path: Path, out: Path, rng: np.random.Generator
                        ) -> tuple[np.ndarray, np.ndarray, dict]:
    """`mtcal compensate` on a five-axis program (DMU 50: the bundled one; other machines: ``_sample_program``);
    tool-tip errors on the true machine before / after."""
    nc_in = out / "sample_5axis.nc"
    if m.name == BUNDLED:
        _copy(data_path("sample_5axis.nc"), nc_in)
    else:
        atomic_write_text(nc_in, _sample_program(m, rng))
    return compensate_file(m, truth, model_path, nc_in, out / "sample_5axis_compensated.nc")


def compensate_file(m, truth, model_path: Path, nc_in: Path, nc_out: Path) -> tuple[np.ndarray, np.ndarray, dict]:
    """`mtcal compensate` NC_IN -> NC_OUT with a model; tool-tip errors (mm) on the true machine before / after."""
    comp = _json(compensate_program(nc_in, nc_out, model_path))
    q_nom, q_cmd = read_moves(nc_in, machine=m), read_moves(nc_out, machine=m)
    targets = m.forward(q_nom)
    return tool_tip_errors(m, truth, q_nom, targets), tool_tip_errors(m, truth, q_cmd, targets), comp


def _sample_program(m, rng: np.random.Generator, n: int = 400) -> str:
    """A five-axis G-code program in the machine's own axis words: a smooth motion between two random axis
    configurations inside the measured ranges, taken through the forward and the inverse kinematics (so it is
    what a post-processor would write for that tool path)."""
    t = np.linspace(0.0, 1.0, n)[:, None]
    q = _sample_grid(m, 2, rng)
    path = q[0] + (q[1] - q[0]) * (0.5 - 0.5 * np.cos(np.pi * t))
    q_nom = m.inverse(m.forward(path), hint=path)
    lines = ["(mtcal demo: five-axis tool path of " + m.name + ", machine axes, mm and deg)", "G90 G21"]
    lines += ["G1 " + " ".join(f"{a}{v:.4f}" for a, v in zip(m.axes, row)) for row in q_nom]
    return "\n".join(lines + ["M30", ""])


def true_squareness(truth, ident: dict) -> dict[str, float]:
    """ISO squareness of the truth model as identify defines it: the constants plus what the slopes of the
    truth's straightness reference lines (over the measured positions) contribute."""
    slopes = {}
    for name, f in truth.functions.items():
        ax = f.axis
        if ax in ident["axes"] and ident["axes"][ax].get("reference_lines", {}).get(name) is not None:
            x = np.asarray(ident["axes"][ax]["positions"], dtype=float)
            slopes[name] = fitting.reference_line(x, f(x))[1]
    lines = fitting.squareness(slopes)
    return {k: truth.constants.get(k, 0.0) + v for k, v in lines.items()}


def _plot_compensation(path: Path, before: np.ndarray, after: np.ndarray) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 3.5))
    ax.plot(before * 1e3, label="nominal program on the true machine")
    ax.plot(after * 1e3, label="compensated with the identified model")
    ax.set_xlabel("move")
    ax.set_ylabel("tool-tip error (um)")
    ax.set_title("Sample five-axis program: tool-tip error before/after compensation")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def report(s: dict, out: Path) -> str:
    """The Markdown report (links to the PNGs beside it)."""
    lines = ["# mtcal demo report", "",
             f"A simulated {s.get('title', 'DMU 50 eVolution')} with errors of the magnitudes measured in the "
             "thesis, measured with a laser tracker (AT960 noise) in 4 rounds, with one effect concealed in the "
             "campaign that the "
             "quasi-static model does not contain. Units: um, urad unless stated.", ""]
    lines += _identify_lines(s["identify"], out)
    if "stations" in s:
        lines += report_lines(s["stations"])
    lines += _plan_lines(s["plan"])
    lines += _compensation_lines(s["compensate"], s.get("machine", BUNDLED))
    lines += [*_checks_lines(s.get("checks")), *_diagnosis_lines(s["diagnose"], out), *_plate_lines(s["plate"]),
              *_history_lines(s.get("history")), f"Run time: {s['seconds']:.1f} s.", ""]
    return "\n".join(lines)


def _identify_lines(i: dict, out: Path) -> list[str]:
    lines = ["## Identification", "",
             "Squareness (right-hand ISO 230-1 convention; the thesis' eq. 3.16 prints the opposite signs), "
             "identified +- std of the mean over rounds, and the truth's ISO squareness (its constants plus the "
             "slopes of its straightness reference lines):", "",
             "| squareness | identified (urad) | truth (urad) |", "|---|---|---|",
             *[f"| {k} | {v:.1f} +- {i['squareness_std_mean_urad'].get(k, float('nan')):.1f} | "
               f"{i['squareness_true_urad'].get(k, float('nan')):.1f} |" for k, v in i["squareness_urad"].items()],
             "",
             f"Volumetric error of the true machine over 2000 random poses: max {i['volumetric_true_max_um']:.1f} um; "
             f"identified model minus truth: RMS {i['volumetric_model_minus_true_rms_um']:.1f} um; "
             f"{_seeds_text(i['over_seeds'])}."
             + (f" Predicted from the data (the estimator on two halves of the rounds): "
                f"{i['worth']['predicted_error_rms_um']:.1f} um, against {i['worth']['corrects_rms_um']:.1f} um "
                f"corrected." if i.get("worth") else ""), ""]
    for png in sorted((out / "plots").glob("identify_*.png")):
        lines.append(f"![{png.stem}](plots/{png.name})")
    return lines


def _plan_lines(plan: dict) -> list[str]:
    lines = ["", "## Plan: predicted vs observed uncertainty of one round", "",
             "`mtcal plan` at the campaign's tracker position predicts the standard uncertainty of one round; the "
             "campaign's experimental standard deviation over its 4 rounds (itself uncertain by about 40 %) at the "
             "same position is beside it.", "",
             "| axis | position | error | predicted | observed std over rounds |", "|---|---|---|---|---|"]
    for ax, errs in plan.items():
        for n, v in errs.items():
            scale, unit = (1e3, "um") if n[2] in "XYZ" else (1e6, "urad")
            obs = v["observed_std_over_rounds"]
            lines.append(f"| {ax} | {v['position']:g} | {n} | {v['predicted'] * scale:.2f} {unit} | "
                         f"{'' if obs is None else f'{obs * scale:.2f} {unit}'} |")
    return lines


def _compensation_lines(c: dict, machine: str) -> list[str]:
    what = ("the sample five-axis program" if machine == BUNDLED
            else "a five-axis program (a tool path through the inverse kinematics)")
    return ["", "![plan map](plots/plan_map.png)", "", f"## Compensation of {what}", "",
            f"ISO/TR 16907 types covered: {', '.join(c['iso_16907'].get('covered', []))}; partial: "
            f"{', '.join(c['iso_16907'].get('partial', [])) or 'none'}. Lines changed: {c['lines_changed']}.", "",
            "| tool-tip error on the true machine | max | RMS |", "|---|---|---|",
            f"| nominal program | {c['true_error_before_max_um']:.2f} | {c['true_error_before_rms_um']:.2f} |",
            f"| compensated with the identified model | {c['true_error_after_max_um']:.2f} | "
            f"{c['true_error_after_rms_um']:.2f} |", "",
            "What is left is the identification uncertainty (see the plan table): compensation is only as good "
            "as the model.", "", "![compensation](plots/compensation_before_after.png)", ""]


def _diagnosis_lines(d: dict, out: Path) -> list[str]:
    lines = ["## Diagnosis", "", f"Base model sigma: {d['base_sigma'] * 1e3:.2f} um.", "",
             "| rank | effect | axis | significant | estimate | sigma after | evidence |",
             "|---|---|---|---|---|---|---|"]
    for k, e in enumerate(d["effects"], 1):
        ev = e.get("evidence") or {}
        evs = ", ".join(f"{a} = {b:.3g}" for a, b in ev.items() if isinstance(b, (int, float)))
        lines.append(f"| {k} | {e['name']} | {e.get('axis') or ''} | {e.get('significant')} | {_estimate(e)} | "
                     f"{e['sigma_after'] * 1e3:.3f} um | {evs} |")
    lines += ["", f"{d['not_significant']} further candidate effects tested and not significant.", "",
              "Planted in the campaign (hidden from the analysis): " + "; ".join(_planted(e) for e in d["planted"]) +
              ".", ""]
    lines += ["Each finding in the readings (partial residual along the effect: a reversal split by the direction of "
              "approach, a drift or knock against time, a periodic error against position):", ""]
    for png in sorted((out / "plots").glob("finding_*.png")):
        lines.append(f"![{png.stem}](plots/{png.name})")
    return lines + ["", "The residuals of the quasi-static model alone, in time order (the findings are hard to see "
                    "here):", "", "![residuals before](plots/residuals_before.png)"]


def _plate_lines(p: dict) -> list[str]:
    return ["", "## Plate reversal: NBS Table 1 (Hocken & Borchardt 1979)", "",
            f"alpha = {p['alpha'] * 1e6:.2f}e-6 rad, beta = {p['beta'] * 1e6:.2f}e-6 rad, gamma = "
            f"{p['gamma'] * 1e6:.2f}e-6, ex = {p['ex'] * 1e6:.2f} uin, ey = {p['ey'] * 1e6:.2f} uin, sigma = "
            f"{p['sigma'] * 1e6:.2f} uin (paper: 4.81, -131.24, 13.69, -14.04, 9.45, 0.5).", "",
            f"Without the scale term (Reeve's model): sigma = {p['without_scale']['sigma'] * 1e6:.1f} uin; "
            f"diagnosis: {_plate_diag(p['without_scale']['diagnosis'])}.", "",
            "![plate](plots/plate_table1.png)", ""]

def _planted(e: dict) -> str:
    return f"{e['name']} " + ", ".join(f"{k}={v}" for k, v in e.items() if k != "name")


def _estimate(e: dict) -> str:
    est, u, unit = e.get("estimate"), e.get("uncertainty"), e.get("unit") or ""
    if not isinstance(est, (int, float)):
        return str(est)
    if unit == "mm":
        est, u, unit = est * 1e3, (u or 0) * 1e3, "um"
    elif unit == "rad":
        est, u, unit = est * 1e6, (u or 0) * 1e6, "urad"
    return f"{est:.3g} +- {u:.2g} {unit}" if u else f"{est:.4g} {unit}"


def _plate_diag(diag) -> str:
    if not diag or not diag.get("effects"):
        return "nothing left out"
    e = diag["effects"][0]
    return f"{e['name']} left out (sigma after {e.get('sigma_after', float('nan')) * 1e6:.2f} uin)"


def _seeds_text(o: dict) -> str:
    return f"{o['n']} more campaigns of this design: median {o['median']:.1f} um, {o['min']:.1f}-{o['max']:.1f}"


def print_summary(s: dict) -> None:
    i, c, d, p = s["identify"], s["compensate"], s["diagnose"], s["plate"]
    print(f"mtcal demo -> {s['out']} ({s['seconds']:.1f} s)")
    print("  identify : squareness " + ", ".join(f"{k} {v:.1f} urad" for k, v in i["squareness_urad"].items())
          + f"; model - truth RMS {i['volumetric_model_minus_true_rms_um']:.1f} um ({_seeds_text(i['over_seeds'])}; "
            f"true volumetric error up to {i['volumetric_true_max_um']:.1f} um)")
    print(f"  compensate: tool tip on the true machine max {c['true_error_before_max_um']:.1f} -> "
          f"{c['true_error_after_max_um']:.1f} um, RMS {c['true_error_before_rms_um']:.1f} -> "
          f"{c['true_error_after_rms_um']:.1f} um ({', '.join(c['iso_16907'].get('covered', []))})")
    if "checks" in s:
        k = s["checks"]
        print(f"  check    : circular test {k['plane']} R {k['radius_mm']:g} mm, G predicted "
              f"{k['predicted_um']['G_mm']:.1f} um, true machine {k['true_machine_um']['G_mm']:.1f} -> "
              f"{k['true_machine_after_compensation_um']['G_mm']:.1f} um after compensation; the true test read "
              f"against the model: " + ("; ".join(k["evaluation"]["findings"]) or "agrees"))
    if "stations" in s:
        st = s["stations"]
        print("  stations : model - truth RMS " + ", ".join(
            f"{lab} {st[k]['model_minus_true_rms_um']:.1f} um" for lab, k in (
                ("one station three-point", "one_station_three_point"), ("joint", "one_station_joint"),
                ("four stations", "four_stations_joint")))
              + f"; compensated program RMS {st['one_station_three_point']['compensated_rms_um']:.1f} -> "
                f"{st['four_stations_joint']['compensated_rms_um']:.1f} um")
    print(f"  diagnose : base sigma {d['base_sigma'] * 1e3:.2f} um; "
          + ("; ".join(f"{e['name']} {e.get('axis') or ''} {_estimate(e)}" for e in d["effects"]) or
             "nothing significant") + "  (planted: " + "; ".join(_planted(e) for e in d["planted"]) + ")")
    print(f"  plate    : NBS Table 1 alpha {p['alpha'] * 1e6:.2f}, beta {p['beta'] * 1e6:.2f}, gamma "
          f"{p['gamma'] * 1e6:.2f} (x1e-6), sigma {p['sigma'] * 1e6:.2f} uin; without scale sigma "
          f"{p['without_scale']['sigma'] * 1e6:.1f} uin -> {_plate_diag(p['without_scale']['diagnosis'])}")
    if "history" in s:
        h = s["history"]
        print(f"  history  : crash planted ({', '.join(f'{n} {d:+g} urad' for n, d in h['planted'].items())}); "
              f"compare named {', '.join(h['named']) or 'nothing'}")
    print(f"  report   : {Path(s['out']) / 'report.md'}, {Path(s['out']) / 'report.html'}")
