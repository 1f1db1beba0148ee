"""Monte Carlo files and the environment they are made in (issue 54 items 5 and 7): `compensate --uncertainty`
matches the file to the program by content hash and by its moves (a byte-identical copy under another name is
the same program; a file cut to half its moves with its hashes intact is refused), and a Dask cluster that fails
to start ("Nanny failed to start" under load) is said on its own line with the trials run in this process."""
from __future__ import annotations

import json
import logging
import shutil

import numpy as np
import pytest
import test_uncertainty_fast as fixtures

from mtcal.cli import main
from mtcal.uncertainty import monte_carlo

T = fixtures.T
truth, rec_x, mc_files = fixtures.truth, fixtures.rec_x, fixtures.mc_files  # a demo campaign of X, its model and
# the Monte Carlo of sample_5axis.nc's moves (tests/test_uncertainty_fast.py)


def _compensate(d, capsys, program, mcfile, out="c.nc"):
    code = main(["compensate", str(program), "--model", str(d / "m.json"), "-o", str(d / out), "--uncertainty",
                 str(mcfile), "--json"])
    cap = capsys.readouterr()
    return code, (json.loads(cap.out) if code == 0 else cap.err)


def test_a_byte_identical_copy_under_another_name_is_the_same_program(mc_files, capsys):
    """Main refused it ("not the Monte Carlo of this program"): programs were matched by file name, the docs say by
    content hash."""
    copy = mc_files / "renamed.nc"
    shutil.copy(mc_files / "part.nc", copy)
    code, out = _compensate(mc_files, capsys, copy, mc_files / "mc.json", "r.nc")
    assert code == 0, out
    tu = out["task_uncertainty"]
    assert tu["moves"] == 274 and tu["computed_for"] == "part.nc" and 0 < tu["u95_max_um"] < 100
    code, same = _compensate(mc_files, capsys, mc_files / "part.nc", mc_files / "mc.json", "p.nc")
    assert code == 0 and same["task_uncertainty"]["u95_max_um"] == tu["u95_max_um"]


@pytest.mark.parametrize("cut", ["both", "intervals", "poses", "moved"])
def test_a_monte_carlo_file_cut_short_with_its_hashes_intact_is_refused(mc_files, tmp_path, capsys, cut):
    """Main accepted half the moves: "U95 ... over 137 moves" of a 274-move program."""
    d = json.loads((mc_files / "mc.json").read_text())
    vol = d["volumetric"]
    n = len(vol["poses"])
    assert n == 274
    if cut in ("both", "intervals"):
        vol["deviation_xyz_mm"] = {k: v[: n // 2] for k, v in vol["deviation_xyz_mm"].items()}
    if cut in ("both", "poses"):
        vol["poses"] = vol["poses"][: n // 2]
    if cut == "moved":
        vol["poses"][5][0] += 1.0
    bad = tmp_path / "mc.json"
    bad.write_text(json.dumps(d))
    code = main(["compensate", str(mc_files / "part.nc"), "--model", str(mc_files / "m.json"), "-o",
                 str(tmp_path / "c.nc"), "--uncertainty", str(bad)])
    err = capsys.readouterr().err
    assert code == 2 and "mc.json" in err and len(err.strip().splitlines()) == 1, err
    assert ("pose 6" in err) if cut == "moved" else ("274" in err and "137" in err), err
    assert not (tmp_path / "c.nc").exists()


def _no_cluster(*a, **k):
    raise RuntimeError("Nanny failed to start.")


def test_a_cluster_that_fails_to_start_is_said_and_the_trials_run_here(rec_x, monkeypatch, caplog):
    """Main: "internal error (RuntimeError: Nanny failed to start.) ... this is a bug in mtcal".  The same trials
    in this process: the result is the in-process run's, exactly (trial k seeded from (seed, k))."""
    import dask.distributed
    monkeypatch.setattr(dask.distributed, "LocalCluster", _no_cluster)
    with caplog.at_level(logging.WARNING, logger="mtcal"):
        got = monte_carlo(rec_x, trials=4, seed=3, workers=2, tracker=T)
    said = [r.getMessage() for r in caplog.records if "Nanny failed to start" in r.getMessage()]
    assert len(said) == 1 and "in this process" in said[0] and "--workers 0" in said[0], said
    here = monte_carlo(rec_x, trials=4, seed=3, workers=0, tracker=T)
    assert all(np.array_equal(got.stats[k], here.stats[k]) for k in here.stats)


def test_the_cli_says_the_fall_back_on_stderr(rec_x, tmp_path, capsys, monkeypatch):
    import dask.distributed

    from mtcal.measurement.recordings import write_recording
    monkeypatch.setattr(dask.distributed, "LocalCluster", _no_cluster)
    f = tmp_path / "rec.csv"
    write_recording(rec_x, f)
    code = main(["uncertainty", str(f), "--trials", "2", "--workers", "999", "--tracker", "250,-1500,150", "--json"])
    cap = capsys.readouterr()
    assert code == 0 and json.loads(cap.out)["trials"] == 2, cap.err
    assert "Nanny failed to start" in cap.err and "in this process" in cap.err and "internal error" not in cap.err
