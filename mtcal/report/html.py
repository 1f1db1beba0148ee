"""The customer's report: one self-contained HTML file (pictures inline as data: URIs, no external link, no
script, A4 print styles with numbered pages) from a machine's history (the latest result of each kind and the
changes between its calibrations) or from one result file, for a machine builder's service engineer or a
calibration lab's client.

Page one is the summary (mtcal.report.summary): the machine, the report's and every calibration's date, the
instrument, the verdict (what changed since the previous calibration and how significant, the volumetric error
over the work volume before and after compensation), the largest errors ranked, what to do next.  Then the
details: the calibrations and instruments, the identified errors, the ISO 230-2 tables, the check tests, the
diagnosis' findings, the compensation and what the tool tip is uncertain by, the history's changes, the glossary
of every ISO 230-1 code the report names (its words from mtcal.history.compare.words).
Values inside in mm and rad; shown in µm and µrad (ISO 230-2 in its own unit), every number with its unit.
"""
from __future__ import annotations

import datetime as dt
import html
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from mtcal.history.compare import SHOWN, Comparison, compare, trend, words
from mtcal.history.results import read_result
from mtcal.history.store import Record, Store

CSS = """
@page { size: A4; margin: 15mm 13mm 16mm;
  @top-left { content: "Calibration report: %(title)s"; font: 7.5pt "DejaVu Sans", Arial, sans-serif; color: #666; }
  @top-right { content: "report of %(date)s"; font: 7.5pt "DejaVu Sans", Arial, sans-serif; color: #666; }
  @bottom-center { content: "page " counter(page) " of " counter(pages);
                   font: 7.5pt "DejaVu Sans", Arial, sans-serif; color: #444; } }
body { font-family: "DejaVu Sans", Arial, sans-serif; font-size: 9.5pt; line-height: 1.35; color: #111;
       max-width: 184mm; margin: 8mm auto; }
h1 { font-size: 17pt; margin: 0 0 1mm; } .sub { color: #444; margin: 0 0 3mm; }
h2 { font-size: 12.5pt; border-bottom: 1.5px solid #446; margin: 6mm 0 2mm; padding-bottom: 0.5mm; color: #223; }
h3 { font-size: 10.5pt; margin: 4mm 0 1.5mm; }
h2, h3 { break-after: avoid; } p { margin: 1.5mm 0; }
section.summary { break-after: page; } section.summary.flows { break-after: auto; }
table { border-collapse: collapse; margin: 1.5mm 0 3mm; font-size: 8.5pt; }
thead { display: table-header-group; } tr, li, figure, .keep, table.short { break-inside: avoid; }
td, th { border: 1px solid #bbb; padding: 1.2px 5px; text-align: right; vertical-align: top; }
th { background: #e9ecf2; font-weight: 600; } td.t, th.t { text-align: left; } td.n { white-space: nowrap; }
table.facts td, table.facts th { border: none; border-bottom: 1px solid #ddd; text-align: left;
                                  padding: 2px 8px 2px 0; }
table.facts th { background: none; width: 40mm; color: #333; }
.verdict { border-left: 4px solid #a33; background: #fbf3f3; padding: 2mm 3mm; margin: 3mm 0; }
.verdict.ok { border-color: #3a7; background: #f2f9f5; }
figure { margin: 2mm 0 3mm; } img { max-width: 100%%; height: auto; display: block; }
figcaption { font-size: 8.5pt; color: #444; margin-top: 1mm; }
.note { color: #555; font-size: 7.5pt; } code { font-size: 8.5pt; }
ul { margin: 1mm 0 2mm; padding-left: 5mm; }
@media print { body { max-width: none; margin: 0; } }
"""

KINDS = {"model": "error model identified", "uncertainty": "tool-tip uncertainty (Monte Carlo)",
         "iso230-2": "ISO 230-2 positioning test", "check": "check test", "verify": "verification against the model",
         "diagnose": "diagnosis of the readings"}


@dataclass
class ReportData:
    """What the report shows: the machine ID (or the file's name), its spec, its records (oldest first, with their
    documents), the comparison of its calibrations (None with fewer than two), the trends of the changed errors,
    the report's date, and whether the records' dates are their files' (one result file, not a history)."""

    title: str
    spec: str | None
    records: list[Record]
    comparison: Comparison | None = None
    trends: list = field(default_factory=list)
    made: dt.date = field(default_factory=dt.date.today)
    dated_by_file: bool = False

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
    """The report of one result file (no history): dated by the file's modification day, and said so."""
    res = read_result(path)
    day = dt.date.fromtimestamp(Path(path).stat().st_mtime)
    rec = Record(0, Path(path).name, res.kind, day, "", res.spec, Path(path).name, res.file_sha256,
                 res.recording_sha256, res.model_sha256, "", res.instrument, res.environment, res.document,
                 res.quantities)
    return ReportData(Path(path).name, res.spec, [rec], dated_by_file=True)


class Html(str):
    """Text already in HTML (not escaped again by ``e``)."""


def e(x) -> str:
    """``x`` escaped for HTML, unless it is ``Html``."""
    return x if isinstance(x, Html) else html.escape(str(x))


def figure(png: bytes, caption: str) -> str:
    """A picture inline, with its one caption."""
    import base64
    return (f'<figure><img alt="{e(caption)}" src="data:image/png;base64,{base64.b64encode(png).decode()}">'
            f"<figcaption>{e(caption)}</figcaption></figure>")


def table(head: list[str], rows: list[list], left: int = 1, cls: str = "") -> str:
    """A table: the first ``left`` columns and every column of words are left-aligned, numbers right-aligned;
    short cells do not wrap; columns empty on every row are left out (no filler)."""
    keep = [j for j in range(len(head)) if any(str(r[j]).strip() for r in rows)]
    words = {j for j in keep if j < left or any(_is_words(r[j]) for r in rows)}

    def cell(tag: str, j: int, x) -> str:
        c = ("t" if j in words else "") + (" n" if len(str(x)) <= 24 else "")
        return f'<{tag} class="{c.strip()}">{e(x)}</{tag}>'
    th = "".join(cell("th", j, head[j]) for j in keep)
    body = "".join("<tr>" + "".join(cell("td", j, r[j]) for j in keep) + "</tr>" for r in rows)
    cls += " short" if len(rows) <= 12 else ""
    return f'<table class="{cls.strip()}"><thead><tr>{th}</tr></thead><tbody>{body}</tbody></table>'


def _is_words(x) -> bool:
    """Whether a cell is text rather than a number with its unit ('12.3 µm', 'X = 200 mm', '+91 µrad')."""
    return len(re.findall(r"[A-Za-z]{3,}", str(x))) > 1 or (bool(re.search(r"[A-Za-z]{4,}", str(x)))
                                                         and not re.search(r"\d", str(x)))


def mapping(x) -> dict:
    """A stored field that should be a mapping: itself, or {} when it is missing or of another type."""
    return x if isinstance(x, dict) else {}


def seq(x) -> list:
    """A stored field that should be a list: itself, or [] when it is missing or of another type."""
    return x if isinstance(x, list) else []


def text_of(x, default: str = "") -> str:
    """A stored field that should be words: itself, or ``default`` when it is missing or not a string."""
    return x if isinstance(x, str) and x.strip() else default


def num(v, digits: int | None = None) -> str:
    """A number for the text: '' when absent or not finite; ``digits`` after the point, or by its size."""
    if v is None or isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        return ""
    if digits is None:
        digits = 0 if abs(v) >= 100 else 1 if abs(v) >= 10 else 2
    return f"{v:.{digits}f}"


def shown(value: float | None, unit: str, digits: int | None = None, sign: bool = False) -> str:
    """A stored value (mm, rad or the result's own unit) as printed with its unit: '61.2 µrad'."""
    u, f = SHOWN.get(unit, ({"um": "µm", "urad": "µrad"}.get(unit, unit), 1.0))
    text = num(None if value is None else value * f, digits)
    if not text:
        return ""
    return f"{'+' if sign and value > 0 else ''}{text} {u}".strip()


def meaning(name: str, spec: str | None) -> str:
    """What an ISO 230-1 code is, in words (mtcal.history.compare.words)."""
    return words(name, spec)[0]


def where(axis: str | None, position: float | None, spec: str | None) -> str:
    """'X = 200 mm': a position of an error function with its axis' unit."""
    if axis is None or position is None:
        return ""
    return f"{axis} = {position:g} {axis_unit(axis, spec)}"


def axis_unit(axis: str, spec: str | None) -> str:
    """mm for a linear axis, deg for a rotary one, as the spec says."""
    from mtcal.kinematics.machine import load_machine
    try:
        return load_machine(spec).unit(axis) if spec else "mm"
    except (KeyError, ValueError):
        return "mm"


def section(title: str, body: str, cls: str = "", lead: str = "") -> str:
    """A section: its heading kept on one page with ``lead`` (its opening paragraph and table), then ``body``."""
    return f'<section class="{cls}"><div class="keep"><h2>{e(title)}</h2>{lead}</div>{body}</section>'


def css_text(s: str) -> str:
    """``s`` inside a CSS string (quotes and backslashes escaped, no markup)."""
    return "".join(c if c.isalnum() or c in " -_.:/()" else f"\\{ord(c):x} " for c in s)
