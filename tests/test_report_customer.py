"""Issue 55: the report a customer reads (a machine builder's service engineer, a calibration lab's client), read
as the customer reads it -- the text chromium renders and the pages it prints, not the HTML source.

Page one is the summary (the machine, the report's and each calibration's date, the instrument, the verdict with
the volumetric error, the ranked errors in words, the change since the previous calibration with its size, what
to do next); every ISO 230-1 code has its words; no raw data structure, no filler, one caption per picture, a unit
on every number column and on every picture's axes; printed, every page is numbered and none is nearly empty."""
from __future__ import annotations

import base64
import datetime as dt
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from history_data import check_doc, diagnose_doc, iso_doc, model_doc, uncertainty_doc, write
from test_report_browser import browser  # noqa: F401  (the chromium fixture)

from mtcal.history import add
from mtcal.history.compare import words
from mtcal.report import pictures
from mtcal.report.run import write_report

CODE = re.compile(r"\bE_[A-Z]0?[A-Z]\b")
UNIT = re.compile(r"\((µm|µrad|mm|deg|°C|%)(\)|[ ,;/])")
CATEGORIES = ("ISO 230-1 error", "finding")  # the y axis of a bar chart: the bars' names
DATES = ("2024-01-15", "2024-06-15", "2024-11-20")


@pytest.fixture(scope="module")
def history_report(tmp_path_factory) -> Path:
    """Three calibrations of one DMU 50 with a crash before the third (E_C0Y +60 µrad), an ISO 230-2 test, a
    diagnosis, an uncertainty result and a ballbar test: the report of its history."""
    tmp = tmp_path_factory.mktemp("customer")
    db = str(tmp / "h.db")
    docs = [("m1.json", model_doc(noise=1, seed=1), DATES[0]), ("m2.json", model_doc(noise=1, seed=2), DATES[1]),
            ("iso.json", iso_doc(), DATES[1]), ("diag.json", diagnose_doc(), DATES[1]),
            ("unc.json", uncertainty_doc(), DATES[1]),
            ("m3.json", model_doc({"E_C0Y": 6e-5}, noise=1, seed=3), DATES[2]), ("ballbar.json", check_doc(), DATES[2])]
    for name, doc, d in docs:
        add(write(tmp / name, doc), "DMU50-7", dt.date.fromisoformat(d), db)
    write_report("DMU50-7", tmp / "r.html", db)
    return tmp / "r.html"


def _rendered(drv, path: Path) -> dict:
    drv.get(path.resolve().as_uri())
    return drv.execute_script("""
        const figs = Array.from(document.images).map(i => {
            const f = i.closest('figure');
            return f ? Array.from(f.querySelectorAll('figcaption')).map(c => c.innerText) : [];
        });
        const tables = Array.from(document.querySelectorAll('table')).map(t => ({
            head: Array.from(t.querySelectorAll('thead th')).map(h => h.innerText),
            rows: Array.from(t.querySelectorAll('tbody tr')).map(r => Array.from(r.cells).map(c => c.innerText))}));
        return {text: document.body.innerText, figs: figs, tables: tables};""")


def test_the_rendered_text_opens_with_the_summary(browser, history_report):  # noqa: F811
    page = _rendered(browser, history_report)
    text = page["text"]
    head = text[:2500]
    assert re.match(r"\s*Calibration report", text), text[:200]
    assert "DMU50-7" in head and "Deckel Maho DMU 50" in head
    assert re.search(rf"Report of\s+{dt.date.today().isoformat()}", head)
    assert all(d in head for d in DATES), head
    assert "AT960" in head  # the instrument
    assert re.search(r"volumetric error over the work volume[^.]*before compensation\s+\d+\.\d+ µm RMS", head,
                     re.I), head
    # the crash: E_C0Y +60 µrad, named with its size, its 95 % interval and its words, on page one
    m = re.search(r"E_C0Y\)? changed by ([+−-]\d+(?:\.\d+)?) ± (\d+(?:\.\d+)?) µrad", head)
    assert m, head
    size = float(m.group(1).replace("−", "-"))
    assert abs(size - 60.0) < float(m.group(2)) and 40 < size < 80
    assert words("E_C0Y", "dmu50")[0] in head
    assert re.search(r"What to do next", head)


def test_no_raw_data_structure_no_filler_no_markdown(browser, history_report):  # noqa: F811
    text = _rendered(browser, history_report)["text"]
    assert not re.search(r"\b[a-z]+_[a-z0-9_]+\b", text), re.findall(r"\b[a-z]+_[a-z0-9_]+\b", text)[:10]
    assert not re.search(r"[{}\[\]`]|\bTrue\b|\bFalse\b|\bNone\b|\bnan\b", text), re.findall(
        r".{30}(?:[{}\[\]`]|\bTrue\b|\bFalse\b|\bNone\b|\bnan\b).{30}", text)[:5]
    assert "not recorded in the result" not in text and "not named by the result" not in text


def test_every_code_has_its_words_and_every_number_column_a_unit(browser, history_report):  # noqa: F811
    page = _rendered(browser, history_report)
    glossary = next(t for t in page["tables"] if t["head"][:2] == ["code", "meaning"])
    meaning = {r[0]: r[1] for r in glossary["rows"]}
    codes = set(CODE.findall(page["text"]))
    assert codes and codes <= set(meaning), codes - set(meaning)
    for c in codes:
        assert meaning[c] == words(c, "dmu50")[0], (c, meaning[c])
    for t in page["tables"]:
        for j, h in enumerate(t["head"]):
            cells = [r[j] for r in t["rows"] if j < len(r) and r[j].strip()]
            if cells and all(re.fullmatch(r"[+−-]?\d+(\.\d+)?", c.strip()) for c in cells):
                assert UNIT.search(h) or h in ("rank", "calibrations", "poses", "trials"), (h, t["head"])
    for t in page["tables"]:  # no filler: no column holds one same text on every row
        if len(t["rows"]) > 2:
            for j, h in enumerate(t["head"]):
                assert len({r[j] for r in t["rows"] if j < len(r)}) > 1 or not re.search("[a-z]{4}", t["rows"][0][j]), h


def test_one_caption_per_picture(browser, history_report):  # noqa: F811
    figs = _rendered(browser, history_report)["figs"]
    assert len(figs) >= 5 and all(len(f) == 1 and f[0].strip() for f in figs), figs
    assert len({f[0] for f in figs}) == len(figs)


def test_every_picture_axis_has_a_unit_and_no_second_caption(tmp_path, monkeypatch):
    """The caption is the HTML's (one per picture); inside the picture no title, and every axis its unit."""
    seen = []
    png = pictures._png

    def spy(plt, fig):
        seen.append(([(a.get_xlabel(), a.get_ylabel(), a.get_title()) for a in fig.axes if a.get_visible()],
                     fig._suptitle.get_text() if fig._suptitle else ""))
        return png(plt, fig)
    monkeypatch.setattr(pictures, "_png", spy)
    db = str(tmp_path / "h.db")
    for name, doc, d in (("m1.json", model_doc(noise=1, seed=1), DATES[0]), ("iso.json", iso_doc(), DATES[0]),
                         ("diag.json", diagnose_doc(), DATES[0]), ("ballbar.json", check_doc(), DATES[0]),
                         ("m3.json", model_doc({"E_C0Y": 6e-5}, noise=1, seed=3), DATES[2])):
        add(write(tmp_path / name, doc), "M1", dt.date.fromisoformat(d), db)
    write_report("M1", tmp_path / "r.html", db)
    assert len(seen) >= 5
    for axes, sup in seen:
        assert sup == "", sup
        for x, y, title in axes:
            assert title == "", title
            assert UNIT.search(y) or y in CATEGORIES, y
            assert UNIT.search(x) or x == "calibration date", x


def _pdf(drv, path: Path, out: Path) -> Path:
    from selenium.webdriver.common.print_page_options import PrintOptions
    drv.get(path.resolve().as_uri())
    po = PrintOptions()
    po.page_width, po.page_height = 21.0, 29.7
    out.write_bytes(base64.b64decode(drv.print_page(po)))
    return out


def _pages(pdf: Path) -> int:
    info = subprocess.run(["pdfinfo", str(pdf)], capture_output=True, text=True, check=True).stdout
    return int(re.search(r"Pages:\s+(\d+)", info).group(1))


def _filled(pdf: Path, page: int, tmp: Path) -> float:
    """How far down the page's body its content reaches (0 top margin .. 1 bottom margin), the footer's page
    number aside: the page rendered in grey at 30 dpi."""
    stem = tmp / f"p{page}"
    subprocess.run(["pdftoppm", "-gray", "-r", "30", "-f", str(page), "-l", str(page), "-singlefile", str(pdf),
                    str(stem)], check=True)
    raw = (tmp / f"p{page}.pgm").read_bytes()
    w, h = (int(v) for v in raw.split(b"\n")[1].split())
    img = np.frombuffer(raw[-w * h:], dtype=np.uint8).reshape(h, w)
    ink = np.flatnonzero((img < 200).sum(axis=1) > 0)
    body = ink[ink < 0.93 * h]  # the bottom margin holds the page number
    top, bottom = 0.05 * h, 0.93 * h
    return 0.0 if body.size == 0 else float((body.max() - top) / (bottom - top))


@pytest.mark.skipif(not (shutil.which("pdftotext") and shutil.which("pdftoppm")), reason="poppler-utils not installed")
def test_printed_pages_are_numbered_and_none_is_nearly_empty(browser, history_report, tmp_path):  # noqa: F811
    pdf = _pdf(browser, history_report, tmp_path / "r.pdf")
    n = _pages(pdf)
    assert 2 <= n <= 6, n
    for i in range(1, n + 1):
        text = subprocess.run(["pdftotext", "-f", str(i), "-l", str(i), "-layout", str(pdf), "-"],
                              capture_output=True, text=True, check=True).stdout
        assert re.search(rf"page {i} of {n}\b", text), (i, text[-300:])
        # the old report: four of eight pages a heading and a line (under 15 %); a page ends where the next
        # section, table or picture does not fit, the last where the report does
        assert _filled(pdf, i, tmp_path) > (0.15 if i == n else 0.55), (i, _filled(pdf, i, tmp_path))
    first = subprocess.run(["pdftotext", "-f", "1", "-l", "1", str(pdf), "-"], capture_output=True, text=True,
                           check=True).stdout
    assert "Summary" in first and "E_C0Y" in first and "What to do next" in first


@pytest.mark.parametrize("spec", ["dmu50", "headbc", "xyzac"])
def test_every_code_of_every_machine_has_its_own_words(spec):
    """The glossary's words (mtcal.history.compare.words): each of a machine's 41 ISO 230-1 codes its own (the
    location errors of a rotary axis read alike, "a location of B's axis (X)" for E_X0B and E_A0B), none the
    fallback."""
    from mtcal.kinematics.machine import load_machine
    names = load_machine(spec).error_names
    said = [words(n, spec)[0] for n in names]
    assert len(set(said)) == len(names) == 41 and not any(s.startswith("the error") for s in said)
    rot = load_machine(spec).rotary_axes[0]
    assert words(f"E_X0{rot}", spec)[0] == f"an offset of {rot}'s axis in X"
    assert words(f"E_A0{rot}", spec)[0] == f"a tilt of {rot}'s axis about X"


def _records(docs):
    from mtcal.history.store import Record
    out = []
    for i, (kind, doc) in enumerate(docs):
        out.append(Record(i, "M1", kind, dt.date(2024, 1, 1 + i), "", "dmu50", f"{kind}.json", "0" * 64, None, None,
                          "0.1", None, {}, doc, []))
    return out


@pytest.mark.parametrize("kind,make", [("iso230-2", iso_doc), ("check", check_doc), ("diagnose", diagnose_doc),
                                       ("uncertainty", uncertainty_doc)])
def test_a_missing_or_not_finite_stored_field_is_left_out_not_shown_raw(kind, make):
    """A stored result with a field missing, None or NaN (an older mtcal's, a hand-edited file) renders: what it
    lacks is left out or said in words, never "nan", "None" or a traceback."""
    from mtcal.report.html import ReportData
    from mtcal.report.run import render
    base = make()
    for key in base:
        for bad in (None, float("nan")):
            doc = dict(base, **{key: bad})
            text = re.sub(r"<style>.*?</style>|<[^>]+>|data:image/png;base64,[^\"]+", " ",
                          render(ReportData("M1", "dmu50", _records([(kind, doc)]))),
                          flags=re.S)
            assert not re.search(r"\bnan\b|\bNone\b|\binf\b", text), (key, bad)


@pytest.mark.skipif(not shutil.which("pdftoppm"), reason="poppler-utils not installed")
def test_one_ballbar_result_summary_says_the_test_and_no_page_is_nearly_empty(browser, tmp_path):  # noqa: F811
    """A report of one ballbar test: page one held the facts and "Nothing." (a quarter of a page) and broke."""
    write_report(str(write(tmp_path / "ballbar.json", check_doc())), tmp_path / "r.html")
    text = _rendered(browser, tmp_path / "r.html")["text"]
    head = text[:text.index("Calibrations and instruments")]
    assert re.search(r"circular deviation G 4\.00 µm \(the model predicts 3\.80 µm\)", head), head
    assert "agrees with the model" in head and "Nothing." not in head
    pdf = _pdf(browser, tmp_path / "r.html", tmp_path / "r.pdf")
    n = _pages(pdf)
    assert all(_filled(pdf, i, tmp_path) > (0.15 if i == n else 0.55) for i in range(1, n + 1))
