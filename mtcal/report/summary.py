"""The report's first page: the machine, the dates, the instrument, the verdict in words and numbers, the largest
errors ranked, what to do next (mtcal.report.html's module docstring; the figures from mtcal.report.verdict)."""
from __future__ import annotations

import re
from dataclasses import dataclass

from mtcal.history.compare import Step, words
from mtcal.history.store import Record
from mtcal.report import pictures
from mtcal.report.html import (
    KINDS,
    Html,
    ReportData,
    e,
    figure,
    mapping,
    meaning,
    num,
    seq,
    shown,
    table,
    text_of,
    where,
)
from mtcal.report.verdict import Volume, volume

RANKED = 5  # the largest errors named on page one


@dataclass
class Facts:
    """What page one rests on, computed once: the latest model, its volumetric error and worth, the latest
    uncertainty result when it is of that model, the latest step of the history."""

    model: Record | None
    volume: Volume | None
    worth: dict | None
    uncertainty: Record | None
    other_uncertainty: Record | None
    step: Step | None
    previous: tuple | None = None  # (date, Volume) of the model before the latest

    @classmethod
    def of(cls, d: ReportData) -> Facts:
        m, u = d.latest("model"), d.latest("uncertainty")
        own = u if (u is not None and (m is None or of_model(u, m))) else None
        worth = (m.document or {}).get("worth") if m else None
        step = d.comparison.steps[-1] if d.comparison else None
        before = [r for r in d.records if r.kind == "model" and step and r.date == step.date_from]
        return cls(m, volume(d.spec, m.document) if m else None, worth if isinstance(worth, dict) else None, own,
                   u if own is None else None, step,
                   (before[-1].date, volume(d.spec, before[-1].document)) if before else None)


def of_model(u: Record, m: Record) -> bool:
    """Whether the uncertainty result ``u`` was drawn about the model ``m``: its provenance names the model's
    ``ErrorModel.digest`` (a result without provenance, of an older mtcal, cannot be paired and is not)."""
    from mtcal.errors import InputError
    from mtcal.model.errormodel import model_from_dict
    theirs = ((u.document or {}).get("provenance") or {}).get("model_sha256")
    try:
        return bool(theirs) and theirs == model_from_dict(m.document).digest()
    except (InputError, TypeError, ValueError, KeyError):
        return False


def tool_tip_u95(u: Record) -> str:
    """'up to ±3.10 µm (95 %) over 1000 poses of the work volume, 300 Monte Carlo trials' ('' when the result
    does not hold the figure)."""
    doc = mapping(u.document)
    vol = mapping(doc.get("volumetric"))
    if not num(vol.get("u95_max_mm")):
        return ""
    place = f"the moves of {vol['program']}" if text_of(vol.get("program")) else "poses of the work volume"
    trials = f", {doc['trials']} Monte Carlo trials" if isinstance(doc.get("trials"), int) else ""
    return f"up to ±{vol['u95_max_mm'] * 1e3:.2f} µm (95 %) over {len(seq(vol.get('poses')))} {place}{trials}"


def summary_section(d: ReportData, f: Facts) -> str:
    """Page one (module docstring)."""
    body = _facts_table(d) + _verdict(d, f) + _volume_text(f) + _ranked(d, f) + _tests(d) + _next(d, f)
    # page one alone when it holds a model's figures; a summary of a test or two flows on into the details
    return f'<section class="summary{"" if f.model else " flows"}"><h2>Summary</h2>{body}</section>'


def _facts_table(d: ReportData) -> str:
    from mtcal.kinematics.machine import load_machine
    machine = f"{d.title}: {load_machine(d.spec).title} (kinematic spec {d.spec})" if d.spec else d.title
    dates: dict = {}
    for r in d.records:
        dates.setdefault(r.date, []).append(_what(r))
    how = " (the file's date: a result file, not a history)" if d.dated_by_file else ""
    cal = Html("<br>".join(f"{x.isoformat()}{how}: {e(', '.join(dict.fromkeys(w)))}" for x, w in dates.items()))
    instruments = ", ".join(dict.fromkeys(r.instrument for r in d.records if r.instrument and r.kind != "uncertainty"))
    rows = [("Machine", machine), ("Report of", d.made.isoformat()), ("Calibrations", cal)]
    rows += [("Instruments", instruments)] if instruments else []
    return _facts(rows)


def _facts(rows: list[tuple[str, str]]) -> str:
    """A two-column table of labelled facts."""
    return '<table class="facts">' + "".join(f"<tr><th>{e(k)}</th><td>{e(x)}</td></tr>" for k, x in rows) + "</table>"


def _what(r: Record) -> str:
    if r.kind == "check":
        return r.instrument or KINDS["check"]
    return KINDS.get(r.kind, r.kind)


def _verdict(d: ReportData, f: Facts) -> str:
    s = f.step
    if s is None:
        n = len({r.date for r in d.records if r.kind == "model"})
        text = ("One calibration with an identified model: there is no earlier one to compare it with." if n == 1
                else "No identified error model: nothing to compare between calibrations.")
        return f'<p class="verdict ok">{e(text)}</p>'
    head = (f"Between {s.date_from.isoformat()} and {s.date_to.isoformat()} ")
    if not s.changed:
        return (f'<p class="verdict ok">{e(head)}no error changed beyond its uncertainty ({s.tests} values of '
                f"{s.unchanged} errors compared; family-wise level {d.comparison.level:.0%}).</p>")
    items = "".join(f"<li>{e(_change(c, d.spec))}</li>" for c in s.changed)
    return (f'<div class="verdict"><p><b>{e(head)}the machine changed</b>: {len(s.changed)} of '
            f"{len(s.changed) + s.unchanged} compared errors moved beyond their uncertainty (each change with its "
            f"95 % interval; family-wise level {d.comparison.level:.0%} over {s.tests} compared values, "
            f"Holm):</p><ul>{items}</ul></div>")


def _change(c, spec: str | None) -> str:
    """'a squareness of Y to X (E_C0Y) changed by +61 ± 10 µrad (p = 2e-09)', with the change's place."""
    at = where(c.axis, c.position, spec)
    return (f"{meaning(c.name, spec)} ({c.name}) changed by {c.change:+.{_digits(c.u95)}f} ± "
            f"{c.u95:.{_digits(c.u95)}f} {c.unit}{' at ' + at if at else ''} ({_p(c.p)})")


def _p(p: float) -> str:
    """A change's p-value as a reader takes it in."""
    return "p < 0.0001" if p < 1e-4 else f"p = {p:.2g}"


def _digits(half: float) -> int:
    return 0 if half >= 10 else 1 if half >= 1 else 2


def _volume_text(f: Facts) -> str:
    v = f.volume
    if f.model is None or v is None:
        return ""
    before = f"{v.rms_um:.1f} µm RMS, largest {v.max_um:.1f} µm"
    if f.previous is not None and f.previous[1] is not None:
        before += f" (at the calibration of {f.previous[0].isoformat()}: {f.previous[1].rms_um:.1f} µm RMS)"
    w = f.worth
    after = (f"about {w['predicted_error_rms_um']:.1f} µm RMS: what the model itself is uncertain by (the same "
             "estimator on two halves of its rounds)" if w and num(w.get("predicted_error_rms_um")) else
             "not predicted when the model was identified")
    u95 = tool_tip_u95(f.uncertainty) if f.uncertainty is not None else ""
    u95 = u95 or "not known: no uncertainty result of this model"
    rows = [("Before compensation", before), ("After compensation", after), ("Tool tip's U95", u95)]
    return (f"<h3>Volumetric error over the work volume ({e(f.model.date.isoformat())})</h3>"
            f"<p>The tool tip's error at {v.poses} poses inside the measured ranges of {e(', '.join(v.axes))}, the "
            "part's set-up removed:</p>"
            + _facts(rows))


def _ranked(d: ReportData, f: Facts) -> str:
    if f.volume is None or not f.volume.by_error:
        return ""
    top = [(n, rms) for n, rms in f.volume.by_error if rms >= 0.05][:RANKED]
    if not top:
        return ""
    peaks = _peaks(f.model)
    rows = [[str(i), n, meaning(n, d.spec), num(rms, 1), peaks.get(n, ("", "", ""))[0],
             peaks.get(n, ("", "", ""))[1], peaks.get(n, ("", "", ""))[2]] for i, (n, rms) in enumerate(top, 1)]
    return ("<h3>The largest errors, ranked by what each alone moves the tool tip</h3>"
            + table(["rank", "code", "what it is", "tool-tip error (µm RMS)", "largest value", "± U95", "where"],
                    rows, 3)
            + (figure(pictures.ranked(top), f"The {len(top)} largest errors of {f.model.date.isoformat()}: the tool "
                                            "tip's error over the work volume that each causes alone (µm RMS).")
               if len(top) > 1 else ""))


def _peaks(m: Record) -> dict[str, tuple[str, str, str]]:
    """{code: (largest value, its U95, where)} of a model's quantities, with units."""
    out: dict[str, tuple] = {}
    for q in m.quantities:
        if q.name not in out or abs(q.value) > out[q.name][0]:
            out[q.name] = (abs(q.value), q)
    return {n: (shown(q.value, q.unit), shown(q.u95, q.unit), where(q.axis, q.position, m.spec))
            for n, (_, q) in out.items()}


def _tests(d: ReportData) -> str:
    """One line for the latest test of each kind: a check test's figure, an ISO 230-2 test's, a verification's
    verdict, the diagnosis' findings."""
    lines = [_check_line(r) for r in (d.latest("check"),) if r is not None]
    iso = d.latest("iso230-2")
    for ax, ev in mapping(mapping(iso.document).get("axes") if iso else None).items():
        p, unit = mapping(mapping(ev).get("parameters")), pictures._unit(mapping(ev).get("unit") or "um")
        said = [f"{w} {k} {num(p[k])} {unit}" for k, w in (("A", "accuracy"), ("E", "systematic deviation"),
                                                              ("R", "repeatability"), ("B", "reversal"))
                if num(p.get(k))]
        if said:
            lines.append(f"ISO 230-2 test of {iso.date.isoformat()}, axis {ax}: " + ", ".join(said))
    v = d.latest("verify")
    if v is not None and isinstance(mapping(v.document).get("passed"), bool):
        lines.append(f"Verification of {v.date.isoformat()}: {'passed' if v.document['passed'] else 'not passed'}")
    diag = d.latest("diagnose")
    found = [x for x in seq(mapping(diag.document).get("effects")) if mapping(x).get("significant")] if diag else []
    if diag is not None:
        lines.append(f"Diagnosis of {diag.date.isoformat()}: " + (", ".join(
            f"{finding_name(x)} {shown(x.get('estimate'), x.get('unit') or 'mm')}" for x in found)
            if found else "nothing beyond the quasi-static model"))
    return ("<h3>The latest tests</h3><ul>" + "".join(f"<li>{e(t)}.</li>" for t in lines) + "</ul>") if lines else ""


def finding_name(x: dict) -> str:
    """'backlash X': a diagnosis finding's name in words, with its axis."""
    return f"{text_of(x.get('name')).replace('_', ' ')} {text_of(x.get('axis'))}".strip()


def _check_line(r: Record) -> str:
    doc = mapping(r.document)
    what = {"circular": "Ballbar circular test (ISO 230-4)", "rtest": "R-test (ISO 10791-6)"}.get(doc.get("kind"),
                                                                                                "Check test")
    g, pg = mapping(doc.get("measured")).get("G_mm"), mapping(doc.get("predicted")).get("G_mm")
    line = f"{what} of {r.date.isoformat()}"
    if num(g):
        line += f": circular deviation G {g * 1e3:.2f} µm" + (f" (the model predicts {pg * 1e3:.2f} µm)"
                                                              if num(pg) else "")
    if isinstance(doc.get("agrees"), bool):
        line += "; it " + ("agrees with the model's prediction" if doc["agrees"] else "differs from the model's "
                           "prediction beyond their uncertainties")
    return line


def _next(d: ReportData, f: Facts) -> str:
    todo = []
    if f.step and f.step.changed:
        causes = dict.fromkeys(words(c.name, d.spec)[1] for c in f.step.changed)
        todo.append(f"Find the cause of the change before compensating again ({' '.join(causes)}); then replace "
                    f"the controller's compensation by the model of {f.step.date_to.isoformat()}.")
    w = f.worth
    if w and w.get("may_worsen") is True and num(w.get("corrects_rms_um")) and num(w.get("predicted_error_rms_um")):
        todo.append(f"Do not compensate with the latest model yet: it corrects {w['corrects_rms_um']:.1f} µm RMS and "
                    f"is itself uncertain by {w['predicted_error_rms_um']:.1f} µm RMS. Measure more rounds (four or "
                    "more), or plan the tracker's stations for the errors that matter (mtcal plan).")
    elif w and num(w.get("predicted_error_rms_um")) and not (f.step and f.step.changed):
        todo.append("Compensate with the latest model (mtcal compensate or mtcal export for the controller's tables).")
    if f.model is not None and f.uncertainty is None:
        todo.append(f"To state the compensated tool tip's U95, run mtcal uncertainty on the recording of "
                    f"{f.model.date.isoformat()}.")
    diag = d.latest("diagnose")
    found = [x for x in seq(mapping(diag.document).get("effects")) if mapping(x).get("significant")] if diag else []
    if found:
        todo.append(f"The diagnosis of {diag.date.isoformat()} found {len(found)} effect(s) the error model does "
                    "not hold (see Diagnosis): correct them at the machine; compensation does not.")
    if f.step and not f.step.changed:
        todo.append("Nothing changed beyond its uncertainty: calibrate again at the usual interval.")
    if f.model is None:
        todo.append("To rank the machine's errors, compare calibrations and compensate, identify an error model "
                    "from a laser-tracker campaign (mtcal identify) and add it to the machine's history "
                    "(mtcal history add).")
    items = (re.sub(r"\bmtcal [a-z0-9-]+", lambda m: f"<code>{m.group(0)}</code>", e(t)) for t in todo or ["Nothing."])
    return "<h3>What to do next</h3><ul>" + "".join(f"<li>{t}</li>" for t in items) + "</ul>"
