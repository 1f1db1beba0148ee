"""mtcal report (issue 38) in a real browser: Debian's chromium, headless, driven by Selenium through Debian's
chromedriver (apt chromium chromium-driver; nothing is downloaded: the driver and the browser are given by path).
The page loads with no console error, every picture has a non-zero size, nothing is fetched from outside the file,
and printing to PDF gives A4 pages (the summary of a model alone on page one; tests/test_report_customer.py
reads them)."""
from __future__ import annotations

import base64
import datetime as dt
import json
import os
import re
import shutil
from pathlib import Path

import pytest
from history_data import check_doc, diagnose_doc, iso_doc, model_doc, uncertainty_doc, write

from mtcal.cli import main
from mtcal.history import add

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
DRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"


@pytest.fixture(scope="module")
def browser():
    webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed (pip install mtcal[test])")
    if not (Path(CHROMIUM).exists() and Path(DRIVER).exists()):
        pytest.skip("Debian's chromium and chromium-driver are not installed "
                    "(apt-get install chromium chromium-driver)")
    os.environ["SE_OFFLINE"] = "true"  # Selenium Manager must not fetch anything
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for a in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu"):
        opts.add_argument(a)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    drv = webdriver.Chrome(service=webdriver.ChromeService(executable_path=DRIVER), options=opts)
    yield drv
    drv.quit()


def _pdf_pages(drv) -> list[tuple[float, float]]:
    """Print the page to PDF (A4, the page's own @page margins); (width, height) in points of every page."""
    from selenium.webdriver.common.print_page_options import PrintOptions
    po = PrintOptions()
    po.page_width, po.page_height = 21.0, 29.7
    pdf = base64.b64decode(drv.print_page(po))
    assert pdf[:5] == b"%PDF-"
    boxes = re.findall(rb"/Type\s*/Page[^s].*?/MediaBox\s*\[\s*([\d.]+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)\s*\]", pdf,
                       re.S)
    if not boxes:  # MediaBox before /Type
        boxes = re.findall(rb"/MediaBox\s*\[\s*([\d.]+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)\s*\]", pdf)
    n = len(re.findall(rb"/Type\s*/Page(?!s)", pdf))
    sizes = [(float(c) - float(a), float(d) - float(b)) for a, b, c, d in boxes]
    return sizes if len(sizes) == n else [sizes[0]] * n


def _open(drv, path: Path) -> dict:
    drv.get(path.resolve().as_uri())
    imgs = drv.execute_script("return Array.from(document.images).map(i => [i.complete, i.naturalWidth, "
                              "i.naturalHeight, i.getBoundingClientRect().width, i.getBoundingClientRect().height])")
    resources = drv.execute_script("return performance.getEntriesByType('resource').map(r => r.name)")
    errors = [e for e in drv.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]
    sections = drv.execute_script("return document.querySelectorAll('section').length")
    return {"imgs": imgs, "resources": resources, "errors": errors, "sections": sections}


def test_one_result_report_prints_on_one_page(browser, tmp_path, capsys):
    f = write(tmp_path / "ballbar.json", check_doc())
    assert main(["report", str(f), "-o", str(tmp_path / "r.html"), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    page = _open(browser, tmp_path / "r.html")
    assert page["errors"] == [] and page["resources"] == []
    assert len(page["imgs"]) == info["pictures"] == 1
    assert all(c and w > 0 and h > 0 and bw > 0 and bh > 0 for c, w, h, bw, bh in page["imgs"])
    assert page["sections"] == info["sections"] == 3  # summary, calibrations and instruments, check tests
    pages = _pdf_pages(browser)
    assert len(pages) == 1  # a summary without a model flows on into the details
    assert all(abs(w - 595.3) < 2 and abs(h - 841.9) < 2 for w, h in pages)  # A4 in points


def test_history_report_in_the_browser(browser, tmp_path, capsys):
    db = str(tmp_path / "h.db")
    docs = [("m1.json", model_doc(noise=1, seed=1), "2024-01-15"), ("m2.json", model_doc(noise=1, seed=2),
                                                                    "2024-06-15"),
            ("iso.json", iso_doc(), "2024-06-15"), ("diag.json", diagnose_doc(), "2024-06-15"),
            ("unc.json", uncertainty_doc(), "2024-06-15"),
            ("m3.json", model_doc({"E_C0Y": 6e-5}, noise=1, seed=3), "2024-11-20"),
            ("ballbar.json", check_doc(), "2024-11-20")]
    for name, doc, d in docs:
        add(write(tmp_path / name, doc), "DMU50-7", dt.date.fromisoformat(d), db)
    assert main(["report", "DMU50-7", "-o", str(tmp_path / "r.html"), "--db", db, "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    text = (tmp_path / "r.html").read_text()
    assert not re.search(r"(src|href)\s*=\s*[\"']?(https?:|//|file:)", text)  # self-contained
    for words in ("Identified errors", "ISO 230-2", "Check tests", "Diagnosis", "tool tip is uncertain by",
                  "(E_C0Y) changed by", "a squareness of Y to X"):
        assert words in text
    page = _open(browser, tmp_path / "r.html")
    assert page["errors"] == [] and page["resources"] == []
    # summary, calibrations, errors, ISO 230-2, check tests, diagnosis, compensation, changes, glossary
    assert page["sections"] == info["sections"] == 9
    # pictures: axis X errors, ISO 230-2 X, circular test, findings, trend of E_C0Y (one error moves the tool tip:
    # no ranking picture)
    assert len(page["imgs"]) == info["pictures"] == 5
    assert all(c and w > 0 and h > 0 and bw > 0 and bh > 0 for c, w, h, bw, bh in page["imgs"])
    pages = _pdf_pages(browser)
    assert 3 <= len(pages) <= 6 and all(abs(w - 595.3) < 2 and abs(h - 841.9) < 2 for w, h in pages)
