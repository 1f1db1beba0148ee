"""The main job: `mtcal demo` end to end on the bundled data, and the bundled data reproducible."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from mtcal.campaign.simulate import simulate
from mtcal.cli import main
from mtcal.data import make_demo_data as mk
from mtcal.demo.run import data_path
from mtcal.io import dumps
from mtcal.measurement.recordings import format_recording


@pytest.fixture(scope="module")
def demo(tmp_path_factory) -> tuple[Path, dict]:
    out = tmp_path_factory.mktemp("demo") / "out"
    assert main(["demo", "--out", str(out), "--quiet"]) == 0
    return out, json.loads((out / "summary.json").read_text())


@pytest.mark.slow
def test_demo_writes_report_plots_and_outputs(demo):
    out, _ = demo
    report = (out / "report.md").read_text()
    for png in ("plan_map.png", "compensation_before_after.png", "plate_table1.png", "identify_X.png",
                "residuals_before.png", "residuals_after.png"):
        assert (out / "plots" / png).stat().st_size > 10_000, png
        assert png in report or png.startswith("residuals") or png == "identify_X.png"
    assert (out / "model.json").exists() and (out / "sample_5axis_compensated.nc").exists()


@pytest.mark.slow
def test_every_file_the_demo_writes_is_known_as_mtcals(demo):
    """The demo's folder holds only files mtcal's ledger knows (so running the demo again into it replaces them,
    while a folder of the user's is refused: the next test)."""
    from mtcal.io import written_by_mtcal
    out, _ = demo
    files = [p for p in out.rglob("*") if p.is_file()]
    assert files and [str(p.relative_to(out)) for p in files if not written_by_mtcal(p)] == []


def test_a_folder_holding_a_file_mtcal_did_not_write_is_refused_untouched(tmp_path, capsys):
    """Review: the demo copied its campaign and program and moved its history over whatever was in --out."""
    out = tmp_path / "work"
    out.mkdir()
    (out / "campaign.csv").write_text("the user's own campaign\n")
    assert main(["demo", "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "campaign.csv: exists and was not written by mtcal" in err
    assert [p.name for p in out.iterdir()] == ["campaign.csv"]
    assert (out / "campaign.csv").read_text() == "the user's own campaign\n"


@pytest.mark.slow
def test_demo_compensation_helps_on_the_true_machine(demo):
    """The identified model (not the truth) corrects the sample program: checked with the truth's exact kinematics."""
    c = demo[1]["compensate"]
    assert c["true_error_before_max_um"] > 15
    assert c["true_error_after_rms_um"] < 0.5 * c["true_error_before_rms_um"]


@pytest.mark.slow
def test_demo_diagnosis_finds_the_concealed_effect(demo):
    """demo_campaign.truth.json: backlash on X, 6 um reversal, hidden in the campaign."""
    d = demo[1]["diagnose"]
    first = d["effects"][0]
    assert (first["name"], first["axis"]) == ("backlash", "X")
    assert first["estimate"] == pytest.approx(mk.DEMO_EFFECT[1]["amount"], rel=0.2)


@pytest.mark.slow
def test_demo_identification_and_plate_numbers(demo):
    s = demo[1]
    i = s["identify"]
    for k, v in i["squareness_urad"].items():  # within 3 std of the mean of the truth's ISO squareness
        assert abs(v - i["squareness_true_urad"][k]) < 3 * i["squareness_std_mean_urad"][k], k
    p = s["plate"]  # NBSIR 79-1752 Table 1, ALBE3 column: alpha 4.81, beta -131.24, gamma 13.69 (x 1e-6)
    assert p["alpha"] == pytest.approx(4.81e-6, abs=0.01e-6)
    assert p["beta"] == pytest.approx(-131.24e-6, abs=0.01e-6)
    assert p["gamma"] == pytest.approx(13.69e-6, abs=0.01e-6)
    assert p["without_scale"]["sigma"] == pytest.approx(75e-6, rel=0.02)
    assert p["without_scale"]["diagnosis"]["effects"][0]["name"] == "scale"


def test_bundled_demo_data_are_what_the_script_makes():
    assert data_path("demo_truth.json").read_text() == dumps(mk.build().to_dict()) + "\n"
    rec, _ = simulate(mk.build(), plan=mk.DEMO_PLAN, rounds=None, seed=mk.DEMO_SEED, effects=[mk.DEMO_EFFECT])
    assert data_path("demo_campaign.csv").read_text() == format_recording(rec)


@pytest.mark.slow
def test_demo_runs_on_another_machine(tmp_path):
    """`mtcal demo --machine headbc`: the same story on the head-table spec, campaign simulated from a synthetic
    truth (no bundled data): identification, a tool path through its inverse kinematics compensated and checked
    on the true machine, the concealed backlash of its first linear axis found."""
    out = tmp_path / "h"
    assert main(["demo", "--machine", "headbc", "--out", str(out), "--quiet"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["machine"] == "headbc" and (out / "campaign.csv").exists() and (out / "report.md").exists()
    c = s["compensate"]
    assert c["true_error_after_rms_um"] < 0.8 * c["true_error_before_rms_um"]
    found = [(e["name"], e["axis"]) for e in s["diagnose"]["effects"]]
    assert found == [("backlash", "X")], found
    assert abs(s["diagnose"]["effects"][0]["estimate"] - 0.006) < 3 * s["diagnose"]["effects"][0]["uncertainty"]


@pytest.mark.slow
def test_demo_history_names_exactly_the_crash(demo):
    """Three calibrations of the simulated machine, a crash (two squareness errors +-80 urad) before the third:
    `history compare` names nothing between the first two and exactly the two planted errors after the crash,
    each change within its 95 % interval of the planted size; the HTML report is beside the others."""
    out, s = demo
    h = s["history"]
    first, second = h["steps"]
    assert first["changed"] == []
    named = {c["name"]: c for c in second["changed"]}
    assert sorted(named) == sorted(h["planted"]) == h["named"]
    for n, planted in h["planted"].items():
        assert abs(named[n]["change"] - planted) < named[n]["u95"] and named[n]["unit"] == "µrad"
    html = (out / "report.html").read_text()
    assert html.count("data:image/png;base64,") == h["report_pictures"] >= 5 and "http" not in html
    assert (out / "history.db").exists() and not list(out.glob(".history.*"))
