"""``write_report``: the report of a machine's history or of one result file, written atomically."""
from __future__ import annotations

from pathlib import Path

from mtcal.history.store import check_machine_id
from mtcal.io import atomic_write_text, refuse_overwrite
from mtcal.report import details, summary
from mtcal.report.html import CSS, ReportData, css_text, e, from_file, from_history


def render(d: ReportData) -> str:
    """The report's HTML text (mtcal.report.html's module docstring): page one, the details, the appendix."""
    facts = summary.Facts.of(d)
    body = summary.summary_section(d, facts) + "".join(s(d, facts) for s in details.SECTIONS)
    body += details.appendix(d, facts, body)
    css = CSS % {"title": css_text(d.title), "date": d.made.isoformat()}
    return ("<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8>"
            f"<title>Calibration report: {e(d.title)}</title><style>{css}</style></head><body>"
            f"<h1>Calibration report</h1>{body}</body></html>\n")


def write_report(target: str, out: str | Path, db: str | None = None) -> dict:
    """Write the self-contained HTML report of a machine's history or of one result file (atomically).

    Parameters
    ----------
    target : str
        A machine ID in the history ``db``, or a result file (a path that exists or ends in .json).
    out : str or Path
        The HTML file to write (never one of the inputs).
    db : str, optional
        The history database (mtcal.history.store.database_url).

    Returns
    -------
    dict
        {"report": path, "sections": printed sections, "pictures": inline pictures, "bytes": size}.

    Examples
    --------
    >>> import os, tempfile
    >>> from mtcal.data import path
    >>> from mtcal.report.run import write_report
    >>> out = os.path.join(tempfile.mkdtemp(), "report.html")
    >>> info = write_report(path("demo_truth.json"), out)
    >>> info["sections"] >= 1, info["pictures"] >= 1, 'src="http' in open(out).read()
    (True, True, False)
    """
    is_file = Path(target).is_file() or target.endswith(".json")
    refuse_overwrite(out, target if is_file else None)
    if is_file:
        data = from_file(target)
    else:
        check_machine_id(target)
        data = from_history(target, db)
    text = render(data)
    atomic_write_text(out, text)
    return {"report": str(out), "sections": text.count("<section"),
            "pictures": text.count("data:image/png;base64,"), "bytes": len(text.encode())}
