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
from mtcal.measurement.tracker import AT960, TrackerSpec

SEED = 7  # the calibration's seed; the campaign's is 5 (development seeds)


@pytest.fixture(scope="module")
def clean():
    """A clean campaign whose tracker is 1.6 times noisier than the AT960's law (the diagnosis' prior): the fitted
    null's scale is then far from 1, and the scatter check below sees whether it is simulated."""
    rec, _ = simulate(rounds=3, seed=5, plan={"axes": {"X": {}}}, spec=AT960.scaled(1.6, 1.6))
    return rec


def _law_ratios(sims, null, tracker, spec, on=slice(None)):
    """(along, across): the RMS of the simulated readings' deviations from the fitted null along the beam and per
    direction across it, in units of the law's sigmas about ``tracker``."""
    ray = null.xyz[on] - tracker
    dist = np.linalg.norm(ray, axis=1)
    u = np.tile(ray / dist[:, None], (len(sims), 1))
    s_r, s_t = (np.tile(s, len(sims)) for s in spec.sigmas(dist))
    e = np.concatenate([s.xyz[on] - null.xyz[on] for s in sims])
    along = np.einsum("ij,ij->i", e, u)
    across = e - along[:, None] * u
    return np.sqrt(np.mean((along / s_r) ** 2)), np.sqrt(np.mean(np.sum(across**2, axis=1) / s_t**2) / 2)


def _spec(law: dict) -> TrackerSpec:
    return TrackerSpec(law["radial_um"], law["radial_um_per_m"], law["transverse_um"], law["transverse_um_per_m"],
                       law["k"])


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
    spec, scale = _spec(d.noise.law), d.base_sigma_ratio
    assert scale > 1.3  # the campaign's noise, 1.6 times the law's
    along, across = _law_ratios(sims, null, np.asarray(d.noise.tracker), spec)
    assert along == pytest.approx(scale, rel=0.08) and across == pytest.approx(scale, rel=0.08)
    assert null.scale == pytest.approx(scale)
    # the fitted null is the base's prediction: the recording less it is the base's residual, whose whitened RMS
    # is the sigma ratio (over 3n - p degrees of freedom, p a few per cent of 3n here)
    white = np.einsum("nij,nj->ni", d.prep.W, clean.xyz - null.xyz)
    assert np.sqrt(np.mean(white**2)) == pytest.approx(scale, rel=0.1)


def test_null_campaigns_of_two_stations_have_each_stations_law():
    """Each station's readings scatter about its own tracker by the law scaled to that station (per_station)."""
    import sys
    from pathlib import Path

    from mtcal.diagnose import diagnose
    from mtcal.diagnose.calibrate import null_campaign, null_fit

    sys.path.insert(0, str(Path(__file__).parent))
    from test_diagnose_multistation import campaign

    rec, _ = campaign(3)
    d = diagnose(rec)
    factors = d.noise.details["per_station"]["factors"]
    null = null_fit(d)
    sims = [null_campaign(null, np.random.default_rng(s)) for s in (1, 2, 3)]
    assert np.array_equal(sims[0].stations(), rec.stations()) and len(factors) == 2
    assert np.array_equal(sims[0].tracker_xyz, rec.tracker_xyz)
    for label, tracker in d.noise.details["trackers"].items():
        on = rec.stations() == label
        along, across = _law_ratios(sims, null, np.asarray(tracker), _spec(d.noise.law), on)
        f = factors[label]
        assert along == pytest.approx(f["radial"] * d.base_sigma_ratio, rel=0.08)
        assert across == pytest.approx(f["transverse"] * d.base_sigma_ratio, rel=0.08)


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
    import mtcal.diagnose.calibrate as cal

    path = tmp_path / "clean.csv"
    write_recording(clean, path)
    real, calls = cal.diagnose, []

    def second_interrupts(*a, **k):  # the calibration's own diagnoses (the command's own first one is not these)
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(*a, **k)
    monkeypatch.setattr(cal, "diagnose", second_interrupts)
    rc, out, err = _cli(capsys, path, "--calibrate", 3, "-q")
    assert rc == 130 and out == "" and "interrupted: 1 of 3 null campaigns diagnosed" in err


def test_claims_are_counted_per_kind_and_name():
    from mtcal.diagnose.calibrate import Calibration

    c = Calibration(0.005, 20, 0, 2, {"named": 2, "located": 1, "unexplained": 0, "beyond_family": 0,
                                              "axis_scatter": 0},
                    {"backlash": 1, "outlier": 1}, 0, 100, 1.0, 3.0, 3.0)
    assert c.rate == pytest.approx(0.1) and c.upper == pytest.approx(_upper(2, 20))
    assert "claims in 2 of 20" in c.says() and "named 2 (backlash 1, outlier 1), located 1" in c.says()


def test_a_diagnosis_that_names_something_counts_as_a_claim(clean):
    from mtcal.diagnose import diagnose
    from mtcal.diagnose.calibrate import KINDS, _tally, claims

    rec, _ = simulate(rounds=3, seed=5, plan={"axes": {"X": {}}}, effects=["backlash:axis=X,amount=0.008"])
    found = diagnose(rec, tracker=(250, -1500, 150))
    assert claims(found)["named"] == ["backlash"]
    tally = {"alarms": 0, "screen": 0, "claims": dict.fromkeys(KINDS, 0), "named": {}}
    for d in (found, diagnose(clean, tracker=(250, -1500, 150))):
        _tally(tally, d)
    assert tally["alarms"] == 1 and tally["claims"]["named"] == 1 and tally["named"] == {"backlash": 1}


def test_seed_without_calibrate_is_refused(clean, tmp_path, capsys):
    path = tmp_path / "clean.csv"
    write_recording(clean, path)
    rc, out, err = _cli(capsys, path, "--seed", "3")
    assert rc == 2 and out == "" and len(err.strip().splitlines()) == 1 and "--calibrate" in err
