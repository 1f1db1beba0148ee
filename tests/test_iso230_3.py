"""Issue 56: `mtcal iso230-3` against the standard's definitions, evaluated here independently (plain Python over
the file's numbers, not mtcal.thermal):

* ISO 230-3:2007 clause 6 (thermal distortion caused by rotating spindles): each direction's thermal drift is its
  displacement from the first reading; reported the range over the test (max - min), the drift at the end, the
  largest |drift|, and per spindle-speed stage the range within the stage and the drift at its end; the tilt of a
  pair of sensors l apart along the mandrel is their difference over l (X1 - X2 and Y1 - Y2, 1 nearer the
  spindle nose; urad), from its first value;
* clause 5 (environmental temperature variation error): with the machine at rest, the ETVE of a direction is the
  range (max - min) of its relative displacement over the test.
Unsure (said in mtcal/thermal/iso230_3.py): the sign convention of the tilts and which sensor of a pair gives the
direction's drift; the ETVE over the whole test rather than per environmental cycle."""
from __future__ import annotations

import json
import math

import pytest

from mtcal.cli import main

SPACING = 120.0  # mm
STAGES = [(0, 30), (2000, 180), (0, 120), (4000, 180), (0, 90)]  # (rpm, minutes)


def _test_file(path, at_rest=False, names=("X1", "X2", "Y1", "Y2", "Z")):
    """A 10 h spindle test read every minute: each sensor a warm-up following the speed, plus an offset (the
    sensor's zero) and a slow wave, written with the header naming directions and units; the rows as written."""
    rows, t, state = [], 0, [0.0] * 5
    gains = [0.004, 0.003, -0.006, -0.0045, 0.008]  # um per rpm at equilibrium
    zero = [12.0, -3.5, 40.0, 7.25, -18.0]
    for rpm, minutes in STAGES:
        rpm = 0 if at_rest else rpm
        for _ in range(minutes):
            w = 1 - math.exp(-60.0 / 2400.0)
            state = [s + w * (g * rpm - s) for s, g in zip(state, gains)]
            wave = 2.5 * math.sin(2 * math.pi * t / (6 * 3600.0))
            temps = [22.0 + 0.5 * wave, 22.0 + 0.001 * rpm + 0.2 * wave]
            rows.append([round(v, 6) for v in [t, rpm] + [z + s + (k + 1) * 0.3 * wave for k, (z, s) in
                                                          enumerate(zip(zero, state))] + temps])
            t += 60
    head = ["time (s)"] + ([] if at_rest else ["spindle (rpm)"]) + [f"{n} (um)" for n in names] + \
        ["room (degC)", "spindle housing (degC)"]
    with open(path, "w") as fh:
        fh.write(",".join(head) + "\n")
        for r in rows:
            r = r[:1] + r[2:] if at_rest else r
            fh.write(",".join(f"{v:.6f}" for v in r) + "\n")
    return rows


def _iso(capsys, *argv):
    assert main(["iso230-3", *map(str, argv), "--json", "-q"]) == 0
    return json.loads(capsys.readouterr().out)


def _stage_bounds(rows):
    """Runs of one spindle speed: (first, last) row indices."""
    out, a = [], 0
    for i in range(1, len(rows) + 1):
        if i == len(rows) or rows[i][1] != rows[a][1]:
            out.append((a, i - 1))
            a = i
    return out


def test_clause_6_drift_per_direction_per_stage_and_tilts(tmp_path, capsys):
    p = tmp_path / "spindle.csv"
    rows = _test_file(p)
    got = _iso(capsys, p, "--spacing", SPACING)
    assert got["kind"] == "spindle" and "clause 6" in got["clause"]
    col = {"X": 2, "Y": 4, "Z": 6}  # X1, Y1 (nearer the nose), Z
    series = {d: [r[c] - rows[0][c] for r in rows] for d, c in col.items()}
    for name, (a, b) in (("B (ZX)", (2, 3)), ("A (YZ)", (4, 5))):
        tilt = [(r[a] - r[b]) / SPACING * 1000.0 for r in rows]
        series[name] = [v - tilt[0] for v in tilt]
    assert set(got["figures"]) == set(series)
    stages = _stage_bounds(rows)
    assert [s["rpm"] for s in got["stages"]] == [rows[a][1] for a, _ in stages] == [0, 2000, 0, 4000, 0]
    for name, v in series.items():
        f = got["figures"][name]
        assert f["range"] == pytest.approx(max(v) - min(v), abs=1e-6)
        assert f["at_end"] == pytest.approx(v[-1], abs=1e-6)
        assert f["max_abs"] == pytest.approx(max(abs(x) for x in v), abs=1e-6)
        for s, (a, b) in zip(f["stages"], stages):
            part = v[a:b + 1]
            assert s["range"] == pytest.approx(max(part) - min(part), abs=1e-6)
            assert s["at_end"] == pytest.approx(v[b], abs=1e-6)
    assert got["temperature_range_c"]["room"] == pytest.approx(max(r[-2] for r in rows) - min(r[-2] for r in rows),
                                                               abs=1e-5)


def test_clause_5_etve_of_a_machine_at_rest(tmp_path, capsys):
    p = tmp_path / "etve.csv"
    rows = _test_file(p, at_rest=True)
    got = _iso(capsys, p)
    assert got["kind"] == "etve" and "clause 5" in got["clause"]
    for d, c in {"X": 2, "Y": 4, "Z": 6}.items():
        v = [r[c] for r in rows]
        assert got["figures"][d]["etve"] == pytest.approx(max(v) - min(v), abs=1e-6)
    assert any("no sensor spacing" in n for n in got["notes"])  # pairs without a spacing: no tilt, said


def test_without_directions_each_channel_is_its_own_and_no_tilt(tmp_path, capsys):
    p = tmp_path / "plain.csv"
    rows = _test_file(p, names=("ch1", "ch2", "ch3", "ch4", "ch5"))
    got = _iso(capsys, p, "--spacing", SPACING)
    assert set(got["figures"]) == {"ch1", "ch2", "ch3", "ch4", "ch5"}
    v = [r[3] - rows[0][3] for r in rows]
    assert got["figures"]["ch2"]["range"] == pytest.approx(max(v) - min(v), abs=1e-6)
    assert any("directions are not given" in n for n in got["notes"])
    got = _iso(capsys, p, "--spacing", SPACING, "--directions", "ch1=X1,ch2=X2,ch3=Y1,ch4=Y2,ch5=Z")
    assert "B (ZX)" in got["figures"] and "A (YZ)" in got["figures"]


def test_channels_without_directions_are_refused_and_nothing_written(tmp_path, capsys):
    p = tmp_path / "plain.csv"
    _test_file(p, names=("ch1", "ch2", "ch3", "ch4", "ch5"))
    out = tmp_path / "report"
    assert main(["iso230-3", str(p), "--directions", "ch1=X1,ch2=X2", "-o", str(out)]) == 2
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(err) == 1 and f"{p}:" in err[0] and "without a direction: ch3, ch4, ch5" in err[0], err
    assert not out.exists()


def test_the_report_and_its_pictures_are_written(tmp_path, capsys):
    p = tmp_path / "spindle.csv"
    _test_file(p)
    out = tmp_path / "report"
    assert main(["iso230-3", str(p), "--spacing", str(SPACING), "-o", str(out), "-q"]) == 0
    assert sorted(f.name for f in out.iterdir()) == ["iso230-3.md", "iso230-3_drift.png",
                                                     "iso230-3_drift_temperature.png"]
    text = (out / "iso230-3.md").read_text()
    assert "clause 6" in text and "| 2 | 2000 |" in text
