"""The customer's report: one self-contained HTML file (pictures inline as data: URIs, no external link, no
script, A4 print styles) from a machine's history (the latest result of each kind and the changes between its
calibrations) or from one result file.

Sections: the machine; the instrument and environment; the identified errors with their 95 % intervals; the ISO
230-2 tables; the check tests; the diagnosis' findings; the compensation and what the tool tip is uncertain by;
the history's changes.  Each section starts a page when printed.  Values inside in mm and rad; shown in µm and µrad
(ISO 230-2 in its own unit).
"""
from __future__ import annotations

import base64
import html
import math
from dataclasses import dataclass, field
from pathlib import Path

from mtcal.history.compare import SHOWN, Comparison, compare, trend
from mtcal.history.results import read_result
from mtcal.history.store import Record, Store
from mtcal.report import pictures

CSS = """
@page { size: A4; margin: 14mm 12mm; }
body { font-family: "DejaVu Sans", Arial, sans-serif; font-size: 10pt; color: #111; max-width: 186mm; margin: auto; }
h1 { font-size: 16pt; margin: 0 0 4mm; } h2 { font-size: 13pt; border-bottom: 1px solid #888; }
section.page { break-before: page; } section.page:first-of-type { break-before: auto; }
table { border-collapse: collapse; margin: 2mm 0; font-size: 8.5pt; }
td, th { border: 1px solid #bbb; padding: 1px 4px; text-align: right; } th { background: #eee; }
td.t, th.t { text-align: left; }
figure { margin: 2mm 0; break-inside: avoid; } img { max-width: 100%; height: auto; }
tr, li { break-inside: avoid; } .changed { color: #a00; font-weight: bold; } .note { color: #555; font-size: 8.5pt; }
@media print { body { max-width: none; } }
"""


@dataclass
class ReportData:
    """What the report shows: the machine ID (or the file's name), its spec, its records (oldest first, with their
    documents) and the comparison of its calibrations (None with fewer than two)."""

    title: str
    spec: str | None
    records: list[Record]
    comparison: Comparison | None = None
    trends: list = field(default_factory=list)

    def latest(self, kind: str) -> Record | None:
        rs = [r for r in self.records if r.kind == kind]
        return rs[-1] if rs else None


def from_history(machine: str, db: str | None = None) -> ReportData:
    """The report of ``machine``'s history in the store ``db``."""
    with Store(db) as store:
        recs = store.records(machine, with_documents=True)
        spec = store.spec_of(machine)
    models = [r for r in recs if r.kind == "model"]
    comp = compare(recs, machine, spec) if len({r.date for r in models}) >= 2 else None
    trends = []
    if comp:
        named = dict.fromkeys(c.name for s in comp.steps for c in s.changed)
        for name in named:
            pos = next(c.position for s in comp.steps for c in s.changed if c.name == name)
            trends.append(trend(models, machine, name, pos))
    return ReportData(machine, spec, recs, comp, trends)


def from_file(path: str | Path) -> ReportData:
    """The report of one result file (no history)."""
    import datetime as dt
    res = read_result(path)
    rec = Record(0, Path(path).name, res.kind, dt.date.today(), "", res.spec, Path(path).name, res.file_sha256,
                 res.recording_sha256, res.model_sha256, "", res.instrument, res.environment, res.document,
                 res.quantities)
    return ReportData(Path(path).name, res.spec, [rec])


def _e(x) -> str:
    return html.escape(str(x))


def _img(png: bytes, alt: str) -> str:
    return (f'<figure><img alt="{_e(alt)}" src="data:image/png;base64,{base64.b64encode(png).decode()}">'
            f"<figcaption class=note>{_e(alt)}</figcaption></figure>")


def _table(head: list[str], rows: list[list], left: int = 1) -> str:
    th = "".join(f'<th class="{"t" if i < left else ""}">{_e(h)}</th>' for i, h in enumerate(head))
    body = "".join("<tr>" + "".join(f'<td class="{"t" if i < left else ""}">{_e(c)}</td>' for i, c in enumerate(r))
                   + "</tr>" for r in rows)
    return f"<table><thead><tr>{th}</tr></thead><tbody>{body}</tbody></table>"


def _num(v, digits: int = 2) -> str:
    return "" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.{digits}f}"


def _section(title: str, body: str) -> str:
    return f'<section class="page"><h2>{_e(title)}</h2>{body}</section>'


def machine_section(d: ReportData) -> str:
    from mtcal.kinematics.machine import load_machine
    spec = f"{d.spec} ({load_machine(d.spec).title})" if d.spec else "not named by its results"
    rows = [[r.date.isoformat(), r.kind, r.source, r.file_sha256[:12], (r.recording_sha256 or "")[:12],
             (r.model_sha256 or "")[:12], r.tool_version] for r in d.records]
    return _section("Machine", f"<p>Machine <b>{_e(d.title)}</b>, spec {_e(spec)}.</p>" + _table(
        ["date", "result", "file", "file sha256", "recording sha256", "model sha256", "mtcal"], rows, 3))


def instrument_section(d: ReportData) -> str:
    rows = []
    for r in d.records:
        env = "; ".join(f"{k}: {_env(v)}" for k, v in r.environment.items()) or "not recorded in the result"
        rows.append([r.date.isoformat(), r.kind, r.instrument or "not named by the result", env])
    m = d.latest("model")
    law = (m.document or {}).get("noise_law") if m else None
    extra = ""
    if law:
        extra = (f"<p>The model's readings were weighted by the {_e(law.get('instrument', ''))} law: ±("
                 f"{law['radial_um']:g} µm + {law['radial_um_per_m']:g} µm/m) along the beam, "
                 f"±({law['transverse_um']:g} µm + {law['transverse_um_per_m']:g} µm/m) across (MPE, "
                 f"k = {law['k']:g}; {_e(law.get('source'))}).</p>")
    return _section("Instrument and environment", _table(["date", "result", "instrument", "environment"], rows, 4)
                    + extra)


def _env(v) -> str:
    if isinstance(v, dict):
        return ", ".join(f"{k} {_num(x) if isinstance(x, float) else x}" for k, x in v.items())
    return str(v)


def errors_section(d: ReportData) -> str:
    m = d.latest("model")
    if m is None:
        return ""
    consts = [q for q in m.quantities if q.position is None]
    rows = [[q.name, SHOWN[q.unit][0], _num(q.value * SHOWN[q.unit][1]),
             _num(None if q.u95 is None else q.u95 * SHOWN[q.unit][1])] for q in consts]
    funcs: dict[str, list] = {}
    for q in m.quantities:
        if q.position is not None:
            funcs.setdefault(q.name, []).append(q)
    frows = []
    for n, qs in sorted(funcs.items()):
        big = max(qs, key=lambda q: abs(q.value))
        unit, f = SHOWN[big.unit]
        frows.append([n, big.axis, unit, f"{big.position:g}", _num(big.value * f),
                      _num(max((q.u95 or 0.0) for q in qs) * f)])
    pics = "".join(_img(pictures.error_functions(ax, [q for q in m.quantities if q.axis == ax and q.position
                                                      is not None]), f"identified errors of axis {ax}")
                   for ax in sorted({q.axis for q in m.quantities if q.axis}))
    return _section(f"Identified errors ({m.date.isoformat()}, {m.source})",
                    "<p>Constants with their 95 % intervals (± U95):</p>"
                    + _table(["error", "unit", "value", "± U95"], rows)
                    + "<p>Error functions: the largest value in size, where, and the largest U95 over the positions:"
                      "</p>" + _table(["error", "axis", "unit", "at", "value", "largest U95"], frows, 2) + pics)


def iso_section(d: ReportData) -> str:
    r = d.latest("iso230-2")
    if r is None:
        return ""
    body = ""
    for ax, ev in r.document["axes"].items():
        p = ev["parameters"]
        body += f"<h3>Axis {_e(ax)} ({_e(ev['kind'])}, {_e(ev['unit'])})</h3>"
        body += _table(["parameter", ev["unit"], "meaning"], [[k, _num(v), ev.get("parameter_meaning", {}).get(k, "")]
                                                              for k, v in p.items()], 1)
        t = ev["targets"]
        body += _table(["target", "x̄↑", "x̄↓", "B_i", "R_i"], [
            [f"{x:g}", _num(t["mean_up"][i]), _num(t["mean_down"][i]), _num(t["reversal"][i]), _num(t["R"][i])]
            for i, x in enumerate(ev["positions"])])
        body += _img(pictures.iso230_2_axis(ev), f"ISO 230-2 axis {ax}")
    return _section(f"ISO 230-2 ({r.date.isoformat()}, {r.source})", body)


def check_section(d: ReportData) -> str:
    checks = [r for r in d.records if r.kind in ("check", "verify")]
    if not checks:
        return ""
    body = ""
    for r in checks:
        doc = r.document
        if r.kind == "verify":
            body += (f"<h3>Verification {r.date.isoformat()} ({_e(r.source)}): "
                     f"{'PASSED' if doc['passed'] else 'NOT PASSED'}</h3><ul>"
                     + "".join(f"<li>{_e(e['text'])}</li>" for e in doc.get("errors", []) if not e.get("within"))
                     + "</ul>")
            doc = doc.get("check") or {}
            if not doc:
                continue
        body += f"<h3>{_e(doc['kind'])} test {r.date.isoformat()} ({_e(doc.get('source', r.source))})</h3>"
        figs = [k for k in doc["measured"] if isinstance(doc["measured"][k], (int, float))]
        body += _table(["figure", "measured µm", "predicted µm"], [
            [k, _num(doc["measured"][k] * 1e3), _num(doc["predicted"].get(k, float("nan")) * 1e3)] for k in figs])
        body += (f"<p>{'Agrees with' if doc['agrees'] else 'Differs from'} the model's prediction (worst reading "
                 f"{doc['worst_z']:.1f} combined sigma; the prediction's U95 {doc['prediction_u95_mm'] * 1e3:.2f} µm)"
                 "</p><ul>" + "".join(f"<li>{_e(f.get('text', f))}</li>" for f in doc.get("findings", [])) + "</ul>")
        if doc.get("trace"):
            draw = pictures.circular_trace if doc["kind"] == "circular" else pictures.rtest_trace
            body += _img(draw(doc), f"{doc['kind']} test of {r.date.isoformat()}")
    return _section("Check tests", body)


def diagnosis_section(d: ReportData) -> str:
    r = d.latest("diagnose")
    if r is None:
        return ""
    eff = [e for e in r.document.get("effects", []) if e.get("significant")]
    items = "".join(f"<li><b>{_e(e['name'])}</b> {_e(e.get('axis') or '')}: estimate {_e(_num(e.get('estimate'), 5))}"
                    f"{' — ' + _e(e['note']) if e.get('note') else ''}</li>" for e in eff)
    unexpl = r.document.get("unexplained") or []
    body = (f"<p>Base sigma ratio {r.document.get('base_sigma_ratio', float('nan')):.2f} → "
            f"{r.document.get('sigma_ratio_after', float('nan')):.2f} after the findings (1 = the tracker's "
            "specification).</p>" + (f"<ul>{items}</ul>" if eff else "<p>No finding beyond the quasi-static "
                                                                   "model.</p>"))
    if unexpl:
        body += f"<p>{len(unexpl)} located mismatch(es) no candidate explains (left unnamed).</p>"
    if eff:
        body += _img(pictures.findings(eff), "the diagnosis' findings with their 95 % intervals")
    return _section(f"Diagnosis ({r.date.isoformat()}, {r.source})", body)


def compensation_section(d: ReportData) -> str:
    m, u = d.latest("model"), d.latest("uncertainty")
    if m is None and u is None:
        return ""
    body = ""
    worth = (m.document or {}).get("worth") if m else None
    if worth:
        body += f"<p>The model's worth (split-half): {_e(_worth(worth))}</p>"
    if u is not None and m is not None and not _of_model(u, m):
        body += (f"<p>The latest uncertainty result ({u.date.isoformat()}) is of another model than the latest "
                 f"identified one ({m.date.isoformat()}): what this model's tool tip is uncertain by is not known "
                 "here (run `mtcal uncertainty` on its recording).</p>")
        u = None
    if u is not None:
        vol = u.document.get("volumetric", {})
        where = f"the moves of {vol['program']}" if vol.get("program") else "poses of the work volume"
        body += (f"<p>What the tool tip is uncertain by ({u.date.isoformat()}, {u.document.get('trials')} Monte "
                 f"Carlo trials): up to ±{vol.get('u95_max_mm', float('nan')) * 1e3:.2f} µm (95 %) over "
                 f"{len(vol.get('poses', []))} {_e(where)}.</p>")
    if not body:
        body = ("<p>No uncertainty result in the history: what the compensated tool tip is uncertain by is not "
                "known here (`mtcal uncertainty` gives it).</p>")
    return _section("Compensation and tool-tip uncertainty", body)


def _of_model(u: Record, m: Record) -> bool:
    """Whether the uncertainty result ``u`` was drawn about the model ``m``: its provenance names the model's
    ``ErrorModel.digest`` (a result without provenance, of an older mtcal, cannot be paired and is not)."""
    from mtcal.errors import InputError
    from mtcal.model.errormodel import model_from_dict
    theirs = ((u.document or {}).get("provenance") or {}).get("model_sha256")
    try:
        return bool(theirs) and theirs == model_from_dict(m.document).digest()
    except (InputError, TypeError, ValueError, KeyError):
        return False


def _worth(w) -> str:
    if isinstance(w, dict):
        return "; ".join(f"{k}: {_num(v) if isinstance(v, float) else v}" for k, v in w.items()
                         if not isinstance(v, (dict, list)))
    return str(w)


def history_section(d: ReportData) -> str:
    if d.comparison is None:
        return ""
    c = d.comparison
    body = (f"<p>Changes beyond their 95 % interval, family-wise level {c.level:g} (Holm over every error and "
            "position of a step).</p>")
    for s in c.steps:
        body += (f"<h3>{s.date_from.isoformat()} → {s.date_to.isoformat()}: {len(s.changed)} changed, "
                 f"{s.unchanged} unchanged</h3><ul>"
                 + "".join(f"<li class=changed>{_e(ch.text)}</li>" for ch in s.changed) + "</ul>")
    for t in d.trends:
        body += _img(pictures.trend_png(t), f"trend of {t.name}")
    return _section("The history's changes", body)


SECTIONS = (machine_section, instrument_section, errors_section, iso_section, check_section, diagnosis_section,
            compensation_section, history_section)


def render(d: ReportData) -> str:
    """The report's HTML text (module docstring)."""
    body = "".join(s(d) for s in SECTIONS)
    return ("<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8>"
            f"<title>mtcal report: {_e(d.title)}</title><style>{CSS}</style></head><body>"
            f"<h1>Calibration report: {_e(d.title)}</h1>{body}</body></html>\n")
