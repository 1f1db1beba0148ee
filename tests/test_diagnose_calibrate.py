"""`mtcal diagnose --calibrate N`: the whole diagnosis' level calibrated by a parametric bootstrap from its fitted
null (mtcal.diagnose.calibrate).

The oracles are written here, apart from the module: the recording's plan (every column but the readings) is
compared row by row; the simulated readings' scatter about the fitted null is measured along and across the beam
and compared with the law the diagnosis states (noise_model.law's MPE terms about noise_model.tracker, sigma =
MPE / k) times the base's sigma ratio; the Clopper-Pearson bound is the closed form 1 - (1 - 0.95)^(1/N) at zero
alarms and scipy's beta quantile otherwise.  A small clean campaign (one axis, 3 rounds) keeps it cheap.
"""
from __future__ import annotations

import json

import numpy as np
import pytest

from mtcal.campaign.simulate import simulate
from mtcal.cli import main
from mtcal.measurement.recordings import write_recording
from mtcal.measurement.tracker import TrackerSpec

SEED = 7  # the calibration's seed; the campaign's is 5 (development seeds)


@pytest.fixture(scope="module")
def clean():
    rec, _ = simulate(rounds=3, seed=5, plan={"axes": {"X": {}}})
    return rec


def _cli(capsys, *argv):
    rc = main(["diagnose", *map(str, argv)])
    cap = capsys.readouterr()
    return rc, cap.out, cap.err


def _upper(k: int, n: int) -> float:
    """One-sided 95 % Clopper-Pearson upper bound of a rate of k in n."""
    if k == 0:
        return 1.0 - 0.05 ** (1.0 / n)
    from scipy.stats import beta
    return 1.0 if k == n else float(beta.ppf(0.95, k + 1, n - k))


def test_calibrate_reports_rate_bound_and_is_reproducible(clean, tmp_path, capsys):
    path = tmp_path / "clean.csv"
    write_recording(clean, path)
    rc, out, _ = _cli(capsys, path, "--calibrate", 5, "--seed", SEED, "--json")
    assert rc == 0
    cal = json.loads(out)["level"]
    assert cal["calibrated"] is True and cal["campaigns"] == 5 and cal["seed"] == SEED
    assert cal["level"] == pytest.approx(0.005)
    k = cal["campaigns_with_claims"]
    assert 0 <= k <= 5 and cal["rate"] == pytest.approx(k / 5)
    assert cal["upper_95"] == pytest.approx(_upper(k, 5), rel=1e-9)
    assert sum(cal["claims"].values()) >= k and cal["cpu_s"] > 0
    assert cal["readings"] == len(clean)
    rc, text, _ = _cli(capsys, path, "--calibrate", 5, "--seed", SEED)  # the same seed: the same campaigns
    said = [line for line in text.splitlines() if line.startswith("level ")]
    assert rc == 0 and len(said) == 1 and "nominal" not in text
    assert said[0].split(": ", 1)[1].split("; ")[:-1] == cal["says"].split("; ")[:-1]  # all but the CPU-s
    assert f"claims in {k} of 5 campaigns" in said[0] and "95 % upper bound" in said[0]


def test_without_calibrate_the_level_is_said_nominal_once(clean, tmp_path, capsys):
    path = tmp_path / "clean.csv"
    write_recording(clean, path)
    rc, text, _ = _cli(capsys, path)
    assert rc == 0 and text.count("use --calibrate N") == 1 and "nominal" in text
    out = json.loads(_cli(capsys, path, "--json")[1])
    assert out["level"]["calibrated"] is False and "use --calibrate N" in out["level"]["says"]


def test_null_campaigns_have_the_recordings_plan_and_the_stated_law(clean):
    from mtcal.diagnose import diagnose
    from mtcal.diagnose.calibrate import null_campaign, null_fit

    d = diagnose(clean)
    null = null_fit(d)
    sims = [null_campaign(null, np.random.default_rng(s)) for s in (1, 2, 3)]
    for sim in sims:
        assert len(sim) == len(clean)
        for col in ("axis", "round", "position", "point", "direction", "line"):
            assert np.array_equal(getattr(sim, col), getattr(clean, col)), col
        for col in ("time_s", "temperature_c"):
            assert np.array_equal(getattr(sim, col), getattr(clean, col), equal_nan=True), col
        assert np.array_equal(sim.stations(), clean.stations())
        assert not np.allclose(sim.xyz, clean.xyz)
    assert np.array_equal(null_campaign(null, np.random.default_rng(1)).xyz, sims[0].xyz)  # reproducible
    # the scatter about the fitted null, along and across the beam, against the law the diagnosis states
    law, t = d.noise.law, np.asarray(d.noise.tracker)
    spec = TrackerSpec(law["radial_um"], law["radial_um_per_m"], law["transverse_um"], law["transverse_um_per_m"],
                       law["k"])
    ray = null.xyz - t
    dist = np.linalg.norm(ray, axis=1)
    u = ray / dist[:, None]
    s_r, s_t = spec.sigmas(dist)
    e = np.concatenate([s.xyz - null.xyz for s in sims])
    u3, sr3, st3 = np.tile(u, (3, 1)), np.tile(s_r, 3), np.tile(s_t, 3)
    along = np.einsum("ij,ij->i", e, u3)
    across = e - along[:, None] * u3
    scale = d.base_sigma_ratio
    ratio_along = np.sqrt(np.mean((along / sr3) ** 2))
    ratio_across = np.sqrt(np.mean(np.sum(across**2, axis=1) / st3**2) / 2)
    assert ratio_along == pytest.approx(scale, rel=0.08) and ratio_across == pytest.approx(scale, rel=0.08)
    assert null.scale == pytest.approx(scale)
    # the fitted null is the base's prediction: the recording less the base's residuals
    assert np.sqrt(np.mean(np.sum((clean.xyz - null.xyz) ** 2, axis=1))) < 3 * np.sqrt(np.mean(s_t**2 * 2))


@pytest.mark.parametrize("bad", ["0", "-1", "x", "2.5"])
def test_bad_campaign_count_is_one_line_exit_2(clean, tmp_path, capsys, bad):
    path = tmp_path / "clean.csv"
    write_recording(clean, path)
    rc, out, err = _cli(capsys, path, f"--calibrate={bad}")
    assert rc == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "--calibrate" in lines[0] and bad in lines[0] and "whole number" in lines[0]


def test_bare_calibrate_simulates_the_default_count(clean, tmp_path):
    from mtcal.cli._main import parse_args
    from mtcal.cli.diagnose import campaigns
    from mtcal.diagnose.calibrate import CAMPAIGNS

    args = parse_args(["diagnose", str(tmp_path / "r.csv"), "--calibrate"])
    assert campaigns(args) == CAMPAIGNS == 20 and args.seed is None
    assert campaigns(parse_args(["diagnose", "r.csv", "--calibrate", "3"])) == 3
    assert campaigns(parse_args(["diagnose", "r.csv"])) is None


def test_interrupted_calibration_says_what_was_done(clean, tmp_path, capsys, monkeypatch):
    import mtcal.diagnose.run as run

    path = tmp_path / "clean.csv"
    write_recording(clean, path)
    real, calls = run.diagnose, []

    def second_interrupts(*a, **k):  # the calibration's own diagnoses (the command's first one is not run's)
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(*a, **k)
    monkeypatch.setattr(run, "diagnose", second_interrupts)
    rc, out, err = _cli(capsys, path, "--calibrate", 3, "-q")
    assert rc == 130 and out == "" and "interrupted: 1 of 3 null campaigns diagnosed" in err


def test_claims_are_counted_per_kind_and_name():
    from mtcal.diagnose.calibrate import Calibration

    c = Calibration(0.005, 20, 0, 2, {"named": 2, "located": 1, "unexplained": 0, "axis_scatter": 0},
                    {"backlash": 1, "outlier": 1}, 0, 100, 1.0, 3.0, 3.0)
    assert c.rate == pytest.approx(0.1) and c.upper == pytest.approx(_upper(2, 20))
    assert "claims in 2 of 20" in c.says() and "named 2 (backlash 1, outlier 1), located 1" in c.says()


def test_seed_without_calibrate_is_refused(clean, tmp_path, capsys):
    path = tmp_path / "clean.csv"
    write_recording(clean, path)
    rc, out, err = _cli(capsys, path, "--seed", "3")
    assert rc == 2 and out == "" and len(err.strip().splitlines()) == 1 and "--calibrate" in err
