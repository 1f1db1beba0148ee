"""Issue 55, item 4: what the commands print on stderr is for people -- every line carries its command's prefix
(``mtcal compensate:``), a count is words, not a Python dict or list ("{'E_AX': 79, ...}", "lines [8]"), and a line
the run would repeat is said once."""
from __future__ import annotations

import json
import re

from mtcal.cli import main
from mtcal.data import path

REPR = re.compile(r"[{}\[\]]|'[A-Z_0-9]+':")


def _small_model(tmp_path):
    m = {"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": {},
         "functions": {n: {"axis": "X", "positions": [-50.0, 50.0], "values": [-0.001, 0.001]}
                       for n in ("E_XX", "E_YX", "E_ZX")}}
    (tmp_path / "m.json").write_text(json.dumps(m))
    return tmp_path / "m.json"


def _lines(err: str) -> list[str]:
    return [x for x in err.splitlines() if x.strip()]


def test_compensate_warns_with_its_prefix_and_in_words(tmp_path, capsys):
    assert main(["compensate", str(path("sample_5axis.nc")), "--model", str(_small_model(tmp_path)), "-o",
                 str(tmp_path / "o.nc")]) == 0
    err = capsys.readouterr().err
    lines = _lines(err)
    warns = [x for x in lines if "warning" in x]
    assert any("outside the measured range (end values held)" in x for x in warns), err
    assert any("rapid moves before all linear axes were known passed uncompensated (lines 8)" in x
               for x in warns), err
    assert all(x.startswith("mtcal compensate: ") for x in lines), err
    assert not any(REPR.search(x) for x in warns), warns
    total = int(re.search(r"(\d+) error evaluations outside", err).group(1))
    per = dict((n, int(c)) for n, c in re.findall(r"\b(E_[A-Z]{2}) (\d+)", err))
    assert set(per) == {"E_XX", "E_YX", "E_ZX"} and sum(per.values()) == total > 0


def test_check_warns_as_compensate_does(tmp_path, capsys):
    assert main(["check", "predict", "--model", str(_small_model(tmp_path)), "--circular", "XY,150,0,0,0"]) == 0
    lines = _lines(capsys.readouterr().err)
    warns = [x for x in lines if "warning" in x]
    assert warns and all(x.startswith("mtcal check: warning: ") for x in warns)
    assert not any(REPR.search(x) for x in warns), warns


def test_a_repeated_line_is_said_once_with_its_count(capsys):
    """The demo's stderr said "joint weighted fit of 1680 readings from 1 station(s)" nine times in a row."""
    import logging

    from mtcal.cli._main import _logging
    log = logging.getLogger("mtcal.identify.run")
    with _logging("demo", False):
        for _ in range(9):
            log.info("joint weighted fit of %d readings from %d station(s)", 1680, 1)
        log.info("[2/9] identify")
        log.info("joint weighted fit of %d readings from %d station(s)", 1680, 1)
        log.info("joint weighted fit of %d readings from %d station(s)", 1680, 1)
    assert _lines(capsys.readouterr().err) == [
        "mtcal demo: joint weighted fit of 1680 readings from 1 station(s)", "mtcal demo: the line above 8 more times",
        "mtcal demo: [2/9] identify", "mtcal demo: joint weighted fit of 1680 readings from 1 station(s)",
        "mtcal demo: the line above 1 more time"]


def test_one_progress_bar_and_none_in_a_log(capsys):
    """`mtcal uncertainty --trials 300` piped to a log left three bar lines ("0/300", then "300/300" twice) after
    its "trials to run" line; the bar is drawn on a terminal only, the same one for `plan --monte-carlo`."""
    import argparse
    import logging

    from mtcal.cli import uncertainty
    from mtcal.cli._main import _logging
    from mtcal.cli._words import Bar
    bar = uncertainty._progress(argparse.Namespace(quiet=False, json=False, trials=300))
    assert isinstance(bar, Bar) and bar.total == 300
    with _logging("uncertainty", False):
        bar.update(200)
        logging.getLogger("mtcal.uncertainty.run").info("the rest")
        bar.update(100)
        bar.close()
    assert _lines(capsys.readouterr().err) == ["mtcal uncertainty: the rest"]
