"""The report's details after page one (mtcal.report.html's module docstring): each section a function of the
report's data and page one's facts, '' when the history holds nothing for it."""
from __future__ import annotations

import re

from mtcal.history.compare import SHOWN, words
from mtcal.report import pictures
from mtcal.report.html import (
    ReportData,
    axis_unit,
    e,
    figure,
    mapping,
    meaning,
    num,
    section,
    seq,
    shown,
    table,
    text_of,
    where,
)
from mtcal.report.summary import Facts, _digits, _what, tool_tip_u95


def calibrations_section(d: ReportData, f: Facts) -> str:
    rows = [[r.date.isoformat(), _what(r), r.instrument or "", _temperature(r.environment), r.source,
             r.file_sha256[:12], (r.recording_sha256 or "")[:12], r.tool_version] for r in d.records]
    law = (f.model.document or {}).get("noise_law") if f.model else None
    extra = ""
    if isinstance(law, dict) and all(num(law.get(k)) for k in ("radial_um", "radial_um_per_m", "transverse_um",
                                                                 "transverse_um_per_m", "k")):
        extra = (f"<p>The readings of {f.model.date.isoformat()} were weighted by the {e(law.get('instrument', ''))} "
                 f"law: ±({law['radial_um']:g} µm + {law['radial_um_per_m']:g} µm/m) along the beam and "
                 f"±({law['transverse_um']:g} µm + {law['transverse_um_per_m']:g} µm/m) across it (maximum "
                 f"permissible error, k = {law['k']:g}; from {e(_law_source(law.get('source')))}).</p>")
    return section("Calibrations and instruments", extra, lead=table(
        ["date", "result", "instrument", "temperature during the measurement (°C)", "file", "file SHA-256",
         "recording SHA-256", "mtcal release"], rows, 3)
        + '<p class="note">Each result by its file, the first 12 hex digits of its SHA-256 and of its recording\'s, '
          "and the mtcal release that wrote it.</p>")


def _law_source(s) -> str:
    return {"prior": "the instrument's specification", None: "the instrument's specification"}.get(s, str(s))


def _temperature(env: dict) -> str:
    t = (env or {}).get("temperature_c")
    if isinstance(t, dict) and num(t.get("mean")) and num(t.get("min")) and num(t.get("max")):
        spread = f" (from {t['min']:.1f} to {t['max']:.1f})" if f"{t['min']:.1f}" != f"{t['max']:.1f}" else ""
        return f"{t['mean']:.1f}{spread}"
    return ""


def errors_section(d: ReportData, f: Facts) -> str:
    m = f.model
    if m is None:
        return ""
    share = dict(f.volume.by_error) if f.volume else {}
    zero = f.volume.zero if f.volume else frozenset()
    consts = sorted((q for q in m.quantities if q.position is None), key=lambda q: -share.get(q.name, 0.0))
    rows = [[q.name, meaning(q.name, d.spec), shown(q.value, q.unit), shown(q.u95, q.unit),
             num(share.get(q.name), 1)] for q in consts]
    funcs: dict[str, list] = {}
    for q in m.quantities:
        if q.position is not None:
            funcs.setdefault(q.name, []).append(q)
    frows = []
    for n, qs in sorted(funcs.items(), key=lambda kv: -share.get(kv[0], 0.0)):
        big = max(qs, key=lambda q: abs(q.value))
        u95 = max((q.u95 or 0.0) for q in qs)
        frows.append([n, meaning(n, d.spec), shown(big.value, big.unit), where(big.axis, big.position, d.spec),
                      shown(u95 or None, big.unit), "none: fitted as zero" if n in zero else num(share.get(n, 0.0), 1)])
    head = "tool-tip error alone (µm RMS)"
    body = (f"<p>The error model identified from the readings of {m.date.isoformat()} ({e(m.source)}), largest "
            "first by what each error alone moves the tool tip over the work volume; each value with its 95 % "
            "interval (± U95). An error function fitted as zero is one the data do not tell from zero: the model "
            "(and a compensation with it) holds none of it.</p>")
    lead, body = body + ("<h3>Constant errors</h3>" + table(["code", "what it is", "value", "± U95", head], rows, 2)
                         if rows else ""), ""
    if frows:
        body += ("<h3>Error functions of the axes' positions</h3>" + table(
            ["code", "what it is", "largest value", "where", "largest ± U95", head], frows, 2))
    for ax in sorted({q.axis for q in m.quantities if q.axis}):
        qs = [q for q in m.quantities if q.axis == ax and q.position is not None]
        if qs:
            body += figure(pictures.error_functions(ax, qs, axis_unit(ax, d.spec)),
                           f"The error functions of axis {ax} identified on {m.date.isoformat()}, each with its 95 % "
                           "band: translations (µm) left, angles (µrad) right.")
    return section("Identified errors", body, lead=lead)


ISO_SYMBOLS = {"_up": " ↑", "_down": " ↓", "_mean": " (mean)"}


def iso_section(d: ReportData, f: Facts) -> str:
    r = d.latest("iso230-2")
    if r is None:
        return ""
    body = f"<p>Positioning test of {r.date.isoformat()} ({e(r.source)}) evaluated as ISO 230-2 says.</p>"
    for ax, ev in mapping(mapping(r.document).get("axes")).items():
        body += _iso_axis(ax, mapping(ev))
    return section("ISO 230-2 positioning test", body)


def _iso_axis(ax: str, ev: dict) -> str:
    from mtcal.iso230_2.evaluation import PARAMETERS
    unit, pu = pictures._unit(ev.get("unit") or "um"), pictures._unit(ev.get("position_unit") or "mm")
    meant = mapping(ev.get("parameter_meaning"))
    body = f"<h3>Axis {e(ax)}</h3>" + table(["parameter", f"value ({unit})", "meaning"], [
        [_iso_symbol(k), num(v), meant.get(k) or PARAMETERS.get(k, "")]
        for k, v in mapping(ev.get("parameters")).items() if num(v)], 1)
    t, xs = mapping(ev.get("targets")), seq(ev.get("positions"))
    cols = ("mean_up", "mean_down", "reversal", "R")
    rows = [[f"{x:g}", *(num(_at(t.get(c), i)) for c in cols)]
            for i, x in enumerate(xs) if num(x)]
    body += table([f"target ({pu})", f"mean deviation ↑ ({unit})", f"mean deviation ↓ ({unit})",
                   f"reversal B ({unit})", f"repeatability R ({unit})"], rows, 0) if rows else ""
    if rows and all(len(seq(t.get(f"{m}_{s}"))) == len(xs) for m in ("mean", "s") for s in ("up", "down")):
        body += figure(pictures.iso230_2_axis(ev), f"ISO 230-2 test of axis {ax}: the mean positional deviation at "
                                                   f"each target, approached from below and from above, with ±2 s.")
    return body


def _at(values, i: int):
    return values[i] if isinstance(values, list) and i < len(values) else None


def _iso_symbol(k: str) -> str:
    return re.sub("_(up|down|mean)$", lambda m: ISO_SYMBOLS["_" + m.group(1)], k)


CIRCULAR = {"G_mm": "circular deviation G, both directions", "G_ccw_mm": "circular deviation G, counter-clockwise",
            "G_cw_mm": "circular deviation G, clockwise", "H_mm": "circular hysteresis H",
            "F_mm": "largest radial deviation F", "F_max_mm": "largest radial deviation outward",
            "F_min_mm": "largest radial deviation inward"}


def check_section(d: ReportData, f: Facts) -> str:
    checks = [r for r in d.records if r.kind in ("check", "verify")]
    body = ""
    for r in checks:
        doc = r.document or {}
        if r.kind == "verify":
            left = [x.get("text", "") for x in doc.get("errors", []) if not x.get("within")]
            body += (f"<h3>Verification of {r.date.isoformat()} ({e(r.source)}): "
                     f"{'passed' if doc.get('passed') else 'not passed'}</h3>"
                     + ("<ul>" + "".join(f"<li>{e(t)}</li>" for t in left) + "</ul>" if left else ""))
            doc = doc.get("check") or {}
            if not doc:
                continue
        body += _check(r, doc)
    return section("Check tests", body) if body else ""


def _check(r, doc: dict) -> str:
    kind = {"circular": "Ballbar circular test (ISO 230-4)", "rtest": "R-test (ISO 10791-6)"}.get(doc.get("kind"),
                                                                                                 "Check test")
    rows, pred = [], mapping(doc.get("predicted"))
    for k, v in mapping(doc.get("measured")).items():
        if isinstance(v, dict):  # an R-test's range per direction
            rows += [[f"range in {c}", num(x * 1e3) if num(x) else "", _um(mapping(pred.get(k)).get(c))]
                     for c, x in v.items()]
        elif num(v):
            rows.append([CIRCULAR.get(k, k.removesuffix("_mm")), _um(v), _um(pred.get(k))])
    body = (f"<h3>{kind} of {r.date.isoformat()} ({e(text_of(doc.get('source'), r.source))})</h3>"
            + (table(["figure", "measured (µm)", "predicted by the model (µm)"], rows) if rows else ""))
    said = []
    if isinstance(doc.get("agrees"), bool):
        said.append(f"The test {'agrees with' if doc['agrees'] else 'differs from'} the model's prediction"
                    + (f": its worst reading is {num(doc['worst_z'], 1)} combined standard deviations off"
                       if num(doc.get("worst_z")) else ""))
    if _um(doc.get("prediction_u95_mm")):
        said.append(f"the prediction is uncertain by {_um(doc['prediction_u95_mm'])} µm (U95)")
    body += f"<p>{e('; '.join(said))}.</p>" if said else ""
    found = [x.get("text", "") if isinstance(x, dict) else str(x) for x in seq(doc.get("findings"))]
    body += "<ul>" + "".join(f"<li>{e(t)}</li>" for t in found) + "</ul>" if found else ""
    width = {"circular": 5, "rtest": 7}.get(doc.get("kind"))
    trace = seq(doc.get("trace"))
    if width and trace and all(isinstance(p, list) and len(p) == width and all(num(x) for x in p) for p in trace):
        draw = pictures.circular_trace if doc.get("kind") == "circular" else pictures.rtest_trace
        if doc.get("kind") == "circular":
            what = " ".join(filter(None, (text_of(doc.get("plane")) and f"in the {doc['plane']} plane",
                                          num(doc.get("radius_mm")) and f"of radius {doc['radius_mm']:g} mm")))
        else:
            what = text_of(doc.get("axis")) and f"of axis {doc['axis']}"
        what = f" {what}" if what else ""
        body += figure(draw(doc), f"{kind} of {r.date.isoformat()}{what}: measured and predicted deviations (µm), "
                                  "the prediction's 95 % band shaded.")
    return body


def _um(v) -> str:
    """A stored length in mm as µm ('' when it is not a finite number)."""
    return num(v * 1e3) if num(v) else ""


def diagnosis_section(d: ReportData, f: Facts) -> str:
    r = d.latest("diagnose")
    if r is None:
        return ""
    doc = mapping(r.document)
    eff = [x for x in seq(doc.get("effects")) if mapping(x).get("significant")]
    body = f"<p>The readings of {r.date.isoformat()} ({e(r.source)}) against the quasi-static error model"
    if num(doc.get("base_sigma_ratio")) and num(doc.get("sigma_ratio_after")):
        body += (f": they scatter {doc['base_sigma_ratio']:.2f} times what the instrument's specification allows "
                 f"about the model, {doc['sigma_ratio_after']:.2f} times once the findings below are added "
                 "(1.00: as the specification)")
    body += ".</p>"
    if eff:
        body += table(["finding", "axis", "size", "95 % interval", "note"], [_finding(x) for x in eff], 2)
        body += figure(pictures.findings(eff), f"The findings of the diagnosis of {r.date.isoformat()}, each with "
                                               "its 95 % interval.")
    else:
        body += "<p>Nothing beyond the quasi-static model was found.</p>"
    if seq(doc.get("unexplained")):
        body += (f"<p>{len(doc['unexplained'])} located mismatch(es) that no candidate explains are left "
                 "unnamed.</p>")
    return section("Diagnosis", body)


def _finding(x: dict) -> list:
    unit = x.get("unit") or "mm"
    iv = x.get("interval_95")
    ci = (f"{shown(iv[0], unit)} to {shown(iv[1], unit)}" if isinstance(iv, list) and len(iv) == 2 else "")
    return [x.get("name", "").replace("_", " "), x.get("axis") or "", shown(x.get("estimate"), unit), ci,
            x.get("note") or ""]


def compensation_section(d: ReportData, f: Facts) -> str:
    if f.model is None and f.uncertainty is None and f.other_uncertainty is None:
        return ""
    body = ""
    w = f.worth
    if w and num(w.get("corrects_rms_um")) and num(w.get("predicted_error_rms_um")):
        body += (f"<p>Over {w.get('poses')} poses inside the measured ranges, the model of {f.model.date.isoformat()} "
                 f"corrects {w['corrects_rms_um']:.1f} µm RMS of tool-tip error and is itself uncertain by "
                 f"{w['predicted_error_rms_um']:.1f} µm RMS (the same estimator on two halves of the rounds): "
                 + ("compensating with it may make the machine worse." if w.get("may_worsen") else
                    "compensating with it is expected to help.") + "</p>")
    if f.other_uncertainty is not None and f.model is not None:
        body += (f"<p>The latest uncertainty result ({f.other_uncertainty.date.isoformat()}) is of another model than "
                 f"the latest identified one ({f.model.date.isoformat()}): what this model's tool tip is uncertain "
                 "by is not known here (run <code>mtcal uncertainty</code> on its recording).</p>")
    said = tool_tip_u95(f.uncertainty) if f.uncertainty is not None else ""
    if said:
        body += f"<p>What the tool tip is uncertain by ({f.uncertainty.date.isoformat()}): {e(said)}.</p>"
    return section("Compensation and tool-tip uncertainty", body) if body else ""


def history_section(d: ReportData, f: Facts) -> str:
    if d.comparison is None:
        return ""
    c = d.comparison
    body = (f"<p>Each step compares two consecutive calibrations. An error is named as changed when the change is "
            f"beyond its 95 % interval at the family-wise level {c.level:.0%} (Holm over every error and position "
            "of a step): on an unchanged machine a step names nothing with 99 % probability.</p>")
    rows = []
    for s in c.steps:
        span = f"{s.date_from.isoformat()} to {s.date_to.isoformat()}"
        if not s.changed:
            rows.append([span, "nothing changed", f"{s.unchanged} errors compared", "", "", ""])
        for ch in s.changed:
            rows.append([span, ch.name, meaning(ch.name, d.spec), f"{ch.change:+.{_digits(ch.u95)}f} {ch.unit}",
                         f"{ch.u95:.{_digits(ch.u95)}f} {ch.unit}", words(ch.name, d.spec)[1]])
    lead = body + table(["calibrations", "code", "what it is", "change", "± U95", "possible cause"], rows, 3)
    body = ""
    for t in d.trends:
        at = "" if t.position is None else f" at {where(t.axis, t.position, d.spec)}"
        body += figure(pictures.trend_png(t), f"{t.name} ({meaning(t.name, d.spec)}){at} at every calibration, "
                                              f"with its 95 % interval ({t.unit}).")
    return section("Changes between calibrations", body, lead=lead)


CODE = re.compile(r"\bE_[A-Z]0?[A-Z]\b")


def glossary_section(d: ReportData, f: Facts, text: str = "") -> str:
    codes = sorted({q.name for r in d.records if r.kind in ("model", "uncertainty") for q in r.quantities
                    if CODE.fullmatch(q.name)} | set(CODE.findall(text)))
    if not codes:
        return ""
    unit = {q.name: SHOWN.get(q.unit, (q.unit,))[0] for r in d.records for q in r.quantities}
    rows = [[c, meaning(c, d.spec), unit.get(c, "")] for c in codes]
    return section("Glossary of the ISO 230-1 error codes", "<p>ISO 230-1 names an error E, then the direction "
                   "it acts in (X, Y, Z for a translation, A, B, C for a rotation about x, y, z), then the axis it "
                   "belongs to; a 0 before the axis marks a constant (a squareness or an axis' location).</p>"
                   + table(["code", "meaning", "unit"], rows, 2), "keep")


SECTIONS = (calibrations_section, errors_section, iso_section, check_section, diagnosis_section,
            compensation_section, history_section)


def appendix(d: ReportData, f: Facts, text: str) -> str:
    """The glossary of every code in ``text`` (the report before it)."""
    return glossary_section(d, f, text)
