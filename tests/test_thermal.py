"""Issue 56: a thermal error model judged out of sample in time, on the real 46 h spindle test FL_THERMAL
(tests/data/fl_thermal, every 8th row of CAIVIAC/FL_THERMAL data/data.xlsx, MIT) and on tests' own files.

The independent figures are computed here with numpy from the issue's definitions, not with mtcal.thermal:
the sixteen-sensor OLS on the first 60 % (the issue's measurement), the constant baseline (the training mean)."""
from __future__ import annotations

import json
import zipfile
from pathlib import Path

import numpy as np
import pytest

from mtcal.cli import main
from mtcal.thermal import fit_thermal, read_thermal_test
from mtcal.thermal.features import first_order_lag, temperature_rise

DATA = Path(__file__).resolve().parent / "data" / "fl_thermal" / "fl_thermal_2min.csv"
RESULTS = Path(__file__).resolve().parents[1] / "benchmarks" / "results.json"
GUIDE = Path(__file__).resolve().parents[1] / "docs" / "guide" / "thermal.md"


def contract_csv(path: Path, rows: slice = slice(None)) -> Path:
    """The extract with the issue's header style: ``time (s), spindle (rpm), ch1 (um), ..., t16 (degC)``."""
    a = np.loadtxt(DATA, delimiter=",", skiprows=1)[rows]
    head = ["time (s)", "spindle (rpm)"] + [f"ch{k} (um)" for k in range(1, 6)] + [f"t{k} (degC)" for k in
                                                                                  range(1, 17)]
    np.savetxt(path, a, delimiter=",", header=",".join(head), comments="", fmt="%.6g")
    return path


def fit_json(capsys, *argv) -> dict:
    assert main(["thermal", "fit", *map(str, argv), "--json", "-q"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.fixture(scope="module")
def fl():
    return np.loadtxt(DATA, delimiter=",", skiprows=1)


def test_both_header_styles_and_a_workbook_read_alike(tmp_path, fl):
    a = read_thermal_test(DATA)
    b = read_thermal_test(contract_csv(tmp_path / "c.csv"))
    assert list(b.channels) == [f"ch{k}" for k in range(1, 6)] and list(b.temperatures) == list(a.temperatures)
    np.testing.assert_allclose(b.channels["ch3"], fl[:, 4], atol=1e-3)
    np.testing.assert_allclose(b.temperatures["t16"], a.temperatures["t16"], atol=1e-3)
    # the source's own header style, in a workbook: ch1(um), t1(°C), 時間(s) (shared strings, inline numbers)
    heads = ["時間(s) ", "spindle(RPM)", "ch1(um)", "t1(°C)"]
    xl = tmp_path / "d.xlsx"
    cells = "".join(f'<c r="{chr(65 + k)}1" t="s"><v>{k}</v></c>' for k in range(4))
    rows = [f'<row r="1">{cells}</row>'] + [
        f'<row r="{i + 2}">' + "".join(f'<c r="{chr(65 + k)}{i + 2}"><v>{v}</v></c>' for k, v in
                                       enumerate(fl[i, [0, 1, 2, 7]])) + "</row>" for i in range(30)]
    ns = 'xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main"'
    with zipfile.ZipFile(xl, "w") as z:
        z.writestr("xl/sharedStrings.xml", f"<sst {ns}>" + "".join(f"<si><t>{h}</t></si>" for h in heads) + "</sst>")
        z.writestr("xl/worksheets/sheet1.xml", f"<worksheet {ns}><sheetData>{''.join(rows)}</sheetData></worksheet>")
    c = read_thermal_test(xl)
    assert list(c.channels) == ["ch1"] and list(c.temperatures) == ["t1"]
    np.testing.assert_allclose(c.time_s, fl[:30, 0])
    np.testing.assert_allclose(c.temperatures["t1"], fl[:30, 7])


def test_kelvin_and_fahrenheit_are_converted_when_the_header_says_so(tmp_path, fl):
    head = "time (min),spindle (rpm),ch1 (mm),t1 (K),t2 (degF)\n"
    rows = [f"{t / 60},{r},{c / 1000},{k + 273.15},{f * 9 / 5 + 32}" for t, r, c, k, f in fl[:, [0, 1, 2, 7, 8]]]
    p = tmp_path / "k.csv"
    p.write_text(head + "\n".join(rows) + "\n")
    t = read_thermal_test(p)
    np.testing.assert_allclose(t.time_s, fl[:, 0], atol=1e-9)
    np.testing.assert_allclose(t.channels["ch1"], fl[:, 2], atol=1e-9)
    np.testing.assert_allclose(t.temperatures["t1"], fl[:, 7], atol=1e-9)
    np.testing.assert_allclose(t.temperatures["t2"], fl[:, 8], atol=1e-9)
    assert any("t1: in K" in n for n in t.notes)


@pytest.fixture(scope="module")
def fl_fit(tmp_path_factory):
    path = contract_csv(tmp_path_factory.mktemp("fl") / "fl.csv")
    return path, {c["channel"]: c for c in _fit_cli(path)["channels"]}


def _fit_cli(path: Path) -> dict:
    import contextlib
    import io
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["thermal", "fit", str(path), "--holdout", "0.4", "--json", "-q"]) == 0
    return json.loads(buf.getvalue())


def test_fl_thermal_out_of_sample_against_the_independent_ols_and_the_baselines(fl_fit, fl):
    """Done when: ch3 and ch4 RMSE <= 11.0 um on the last 40 % (the issue's sixteen-sensor OLS; here, computed
    independently on the extract, 10.30 / 10.36); every channel compared with both baselines; a channel offered a
    compensation beats the constant out of sample. Measured: ch3 7.02, ch4 3.88 um; ch1 4.09 (constant 5.56, not
    shown better: not predictable), ch2 4.97 (5.65), ch5 9.62 (10.80)."""
    _, ch = fl_fit
    n = len(fl)
    k = round(0.6 * n)
    X = np.column_stack([np.ones(n), fl[:, 7:]])
    for j, name in enumerate(["ch1", "ch2", "ch3", "ch4", "ch5"]):
        y = fl[:, 2 + j]
        p = np.linalg.lstsq(X[:k], y[:k], rcond=None)[0]
        ols = np.sqrt(np.mean((y[k:] - X[k:] @ p) ** 2))
        const = np.sqrt(np.mean((y[k:] - y[:k].mean()) ** 2))
        c = ch[name]
        assert set(c) >= {"channel", "model", "rmse_um", "r2", "constant_rmse_um", "time_only_rmse_um",
                          "predictable"}
        assert c["constant_rmse_um"] == pytest.approx(const, abs=2e-3)
        r2 = 1 - c["rmse_um"] ** 2 / np.mean((y[k:] - y[k:].mean()) ** 2)
        assert c["r2"] == pytest.approx(r2, abs=1e-3)
        if name in ("ch3", "ch4"):
            assert c["rmse_um"] <= 11.0 and c["rmse_um"] < ols, (name, c["rmse_um"], ols)
            assert c["predictable"] and c["rmse_um"] < 0.5 * min(c["constant_rmse_um"], c["time_only_rmse_um"])
        if c["predictable"]:
            assert c["rmse_um"] < c["constant_rmse_um"] and c["rmse_um"] < c["time_only_rmse_um"]
    assert not ch["ch1"]["predictable"] and not ch["ch2"]["predictable"] and not ch["ch5"]["predictable"]
    assert ch["ch3"]["rmse_um"] == pytest.approx(7.02, abs=0.05) and ch["ch4"]["rmse_um"] == pytest.approx(3.88,
                                                                                                        abs=0.05)


def test_the_hold_out_never_decides_the_model(tmp_path):
    """Selection and fit see only the first part in time: the hold-out's readings replaced by other numbers leave
    the model's terms and coefficients as they were (only its judgement changes)."""
    t = read_thermal_test(DATA)
    a = fit_thermal(t, 0.4)
    k = round(0.6 * len(t))
    rng = np.random.default_rng(5)
    for v in t.channels.values():
        v[k:] = rng.normal(0.0, 30.0, len(v) - k)
    b = fit_thermal(t, 0.4)
    for ca, cb in zip(a.channels, b.channels):
        assert ca.terms == cb.terms and ca.coefficients == cb.coefficients
        assert ca.rmse_um != cb.rmse_um


def test_channels_without_a_thermal_cause_are_not_predictable(tmp_path, fl):
    """Forty random walks independent of the temperatures, on FL_THERMAL's temperatures and speed: the forward
    selection finds terms for them and some beat the constant's RMSE on the hold-out by chance (13 of 40 here: a
    rule 'RMSE below the constant's' would compensate them), but the test offers none of them a compensation (0 of
    40 here; at its level, about 2 could be)."""
    t = read_thermal_test(DATA)
    rng = np.random.default_rng(2026)
    t.channels = {f"w{k}": np.cumsum(rng.normal(0.0, 0.5, len(t))) for k in range(40)}
    m = fit_thermal(t, 0.4)
    beat = sum(c.rmse_um < c.constant_rmse_um for c in m.channels)
    offered = [c.channel for c in m.channels if c.predictable]
    assert beat >= 8 and len(offered) <= 4, (beat, offered)
    assert all("not predictable" in c.reason for c in m.channels if not c.predictable)


def test_the_lag_is_the_generated_warm_up(fl):
    """first_order_lag of a unit step first read at t_i is 1 - exp(-(t - t_(i-1))/tau) from t_i on (the reading held
    over the period that ends at it; the step response is the thermal_drift signature's);
    temperature_rise is T - T(first reading in time), as the diagnosis builds dT from temperature_c."""
    t = fl[:, 0]
    step = (t >= t[100]).astype(float)
    y = first_order_lag(t, step, 1800.0)
    np.testing.assert_allclose(y, np.where(t >= t[100], 1 - np.exp(-(t - t[99]) / 1800.0), 0.0), atol=1e-12)
    order = np.arange(len(t))[::-1]  # readings stored newest first
    np.testing.assert_allclose(temperature_rise(t[order], fl[order, 10]), fl[order, 10] - fl[0, 10])


def test_the_guide_quotes_the_benchmark(fl_fit):
    """docs/guide/thermal.md's table is benchmarks/results.json's, which is what the command prints."""
    _, ch = fl_fit
    res = json.loads(RESULTS.read_text())
    text = GUIDE.read_text()
    for name, c in ch.items():
        assert res[f"thermal_fl_{name}_rmse_um"] == pytest.approx(c["rmse_um"], abs=0.005)
        assert res[f"thermal_fl_{name}_constant_rmse_um"] == pytest.approx(c["constant_rmse_um"], abs=0.005)
        assert res[f"thermal_fl_{name}_time_only_rmse_um"] == pytest.approx(c["time_only_rmse_um"], abs=0.005)
        row = (f"| {name} | {c['rmse_um']:.2f} | {c['r2']:.2f} | {c['constant_rmse_um']:.2f} | "
               f"{c['time_only_rmse_um']:.2f} |")
        assert row in text, row
    assert (f"40 random walks without a thermal cause: {res['thermal_random_walks_beat_constant']} of them"
            in " ".join(text.split()) and f"offered {res['thermal_random_walks_predictable']} of them" in text)


BAD = [  # (what, how the file is spoiled, extra options, line named, words)
    ("time not increasing", lambda L: L[:50] + [L[49]] + L[50:], [], 52, "time not increasing"),
    ("stuck sensor", None, [], None, "stuck"),
    ("missing value", lambda L: L[:20] + [L[20].rsplit(",", 1)[0] + ","] + L[21:], [], 22, "missing value"),
    ("kelvin said to be degC", "K", [], 2, "K or degF"),
    ("fahrenheit room said to be degC", "F", [], 1, "Fahrenheit"),
    ("temperature without a unit", "nounit", [], 1, "no unit"),
    ("too short for the lags", None, ["--lags", "40000"], None, "too short for lag"),
    ("hold-out too short", None, ["--holdout", "0.02"], None, "hold-out too short"),
]


def _spoil(path: Path, how) -> None:
    lines = path.read_text().splitlines()
    head, body = lines[0], lines[1:]
    if callable(how):
        body = how(body)
    elif how == "K":
        body = [",".join(f[:-1] + [str(float(f[-1]) + 273.15)]) for f in (ln.split(",") for ln in body)]
    elif how == "F":
        body = [",".join(f[:7] + [f"{float(v) * 9 / 5 + 32:.3f}" for v in f[7:]]) for f in (ln.split(",") for ln in
                                                                                            body)]
    elif how == "nounit":
        head = head.replace("t16 (degC)", "t16")
    elif how is None:
        pass
    path.write_text("\n".join([head] + body) + "\n")


@pytest.mark.parametrize("what,how,opts,line,words", BAD, ids=[b[0] for b in BAD])
def test_bad_input_is_one_line_exit_2_nothing_written(tmp_path, capsys, what, how, opts, line, words):
    p = contract_csv(tmp_path / "bad.csv", slice(0, 300))
    if what == "stuck sensor":
        lines = p.read_text().splitlines()
        body = [ln.split(",") for ln in lines[1:]]
        for f in body[100:260]:
            f[12] = "27.5"
        p.write_text("\n".join([lines[0]] + [",".join(f) for f in body]) + "\n")
        line = 102
    else:
        _spoil(p, how)
    out = tmp_path / "m.json"
    assert main(["thermal", "fit", str(p), "-o", str(out), "-q", *opts]) == 2
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(err) == 1 and words in err[0], err
    assert f"{p}:{line}:" in err[0] if line else str(p) in err[0]
    assert not out.exists() and sorted(x.name for x in tmp_path.iterdir()) == ["bad.csv"]


def test_a_tracker_recordings_temperature_is_read_with_the_same_model(tmp_path, fl):
    """One thermal vocabulary: a model fitted on a thermal test whose sensor is the recording's temperature_c
    predicts a tracker recording's readings from its time_s and temperature_c, as it predicts the test's."""
    from mtcal.errors import InputError
    from mtcal.measurement.recordings import make_recording
    from mtcal.thermal import recording_rise
    p = tmp_path / "one.csv"
    p.write_text("time_s,spindle_rpm,ch3_um,temperature_c (degC)\n" + "\n".join(
        f"{r[0]:g},{r[1]:g},{r[4]:.3f},{r[10]:.3f}" for r in fl) + "\n")
    test = read_thermal_test(p)
    model = fit_thermal(test, 0.4, lags_s=(1800.0,))
    ch = model.channel("ch3")
    assert ch.terms and {t.input for t in ch.terms} <= {"temperature_c", "spindle"}
    n = len(fl)
    rec = make_recording(["X"] * n, [1] * n, np.arange(n), ["p"] * n, np.zeros((n, 3)), time_s=fl[:, 0],
                         temperature_c=fl[:, 10])
    t, rise = recording_rise(rec)
    np.testing.assert_allclose(ch.predict(t, {"temperature_c": rise}, test.spindle_rpm), ch.fitted_um, atol=1e-6)
    rec.temperature_c[7] = np.nan
    with pytest.raises(InputError, match=r":9: a thermal model needs time_s and temperature_c"):
        recording_rise(rec)
