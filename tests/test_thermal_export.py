"""Issue 56: a thermal model's compensation written for a controller and read back by a reader that follows the
controller's manual, not mtcal's writer.

* SINUMERIK (K3 Compensations 03/2013 sec. 4.2): the reader here runs the part program as the PLC would call it,
  once per period with the inputs in R parameters, keeps the R parameters between calls, and evaluates the
  temperature compensation value dK = K0 + tan(beta) (Px - P0) from SD43900 / SD43910 / SD43920, the terms MD32750
  enables (bit 0 position-independent, bit 1 position-dependent).
* LinuxCNC: the generated HAL component builds with LinuxCNC's own ``halcompile`` (skipped when absent), and its
  function body, compiled by gcc in a harness that plays the servo thread, gives the offsets.
Both against the model's own prediction on the real test (FL_THERMAL extract, read every 120 s)."""
from __future__ import annotations

import ast
import json
import operator
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from mtcal.cli import main
from mtcal.thermal import read_thermal_test
from mtcal.thermal.features import temperature_rise

DATA = Path(__file__).resolve().parent / "data" / "fl_thermal" / "fl_thermal_2min.csv"


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    d = tmp_path_factory.mktemp("thermal")
    assert main(["thermal", "fit", str(DATA), "-o", str(d / "m.json"), "-q"]) == 0
    return d, json.loads((d / "m.json").read_text())


def _prediction(model_json: dict, channel: str) -> np.ndarray:
    from mtcal.thermal.model import model_from_dict
    m = model_from_dict(model_json)
    t = read_thermal_test(DATA)
    rise = {k: temperature_rise(t.time_s, v, m.reference_c[k]) for k, v in t.temperatures.items()}
    return m.channel(channel).predict(t.time_s, rise, t.spindle_rpm), t


_OPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv}


def _arith(expr: str, R: dict) -> float:
    """An NC arithmetic expression of numbers, R parameters, + - * / and brackets."""
    def ev(n):
        if isinstance(n, ast.Constant):
            return float(n.value)
        if isinstance(n, ast.Subscript) and n.value.id == "R":
            return R.get(n.slice.value, 0.0)
        if isinstance(n, ast.BinOp):
            return _OPS[type(n.op)](ev(n.left), ev(n.right))
        if isinstance(n, ast.UnaryOp) and isinstance(n.op, ast.USub):
            return -ev(n.operand)
        raise ValueError(ast.dump(n))
    return ev(ast.parse(re.sub(r"R(\d+)", r"R[\1]", expr), mode="eval").body)


def read_sinumerik(text: str):
    """The program as the manual has it: MD32750 per axis (from the set-up lines), the inputs' R parameters, the
    statements run in order at each call."""
    md = {m.group(1): int(m.group(2)) for m in re.finditer(r"MD32750 \$MA_TEMP_COMP_TYPE\[(AX\d+)\] = (\d+)", text)}
    inputs = {m.group(2) or "spindle": int(m.group(1)) for m in
              re.finditer(r";\s+R(\d+) = (?:temperature (\S+) \(degC\)|spindle speed \(rpm\))", text)}
    body = [ln.split(";")[0].strip() for ln in text.splitlines() if not ln.startswith(("%", ";"))]
    return md, inputs, [s for s in body if s and s != "M17"]


def run_sinumerik(text: str, readings: list[dict], positions: dict) -> dict[str, list[float]]:
    """dK per axis at each call (mm), at the axis position ``positions[axis]``."""
    md, inputs, body = read_sinumerik(text)
    R, SD, out = {}, {}, {}
    for reading in readings:
        for name, r in inputs.items():
            R[r] = reading[name]
        for s in body:
            lhs, rhs = s.split("=", 1)
            m = re.match(r"\$SA_TEMP_COMP_(ABS_VALUE|SLOPE|REF_POSITION)\[(AX\d+)\]", lhs)
            if m:
                SD[(m.group(1), m.group(2))] = _arith(rhs, R)
            else:
                R[int(lhs[1:])] = _arith(rhs, R)
        for ax, typ in md.items():
            k0 = SD.get(("ABS_VALUE", ax), 0.0) if typ & 1 else 0.0
            slope = SD.get(("SLOPE", ax), 0.0) * (positions[ax] - SD.get(("REF_POSITION", ax), 0.0)) if typ & 2 else 0
            out.setdefault(ax, []).append(k0 + slope)
    return out


def test_sinumerik_temperature_compensation_read_back_as_the_manual_says(fitted):
    d, model = fitted
    out = d / "THERMAL.SPF"
    assert main(["thermal", "export", str(d / "m.json"), "--format", "siemens", "-o", str(out), "--axes",
                 "ch3=Z,ch4=-X", "--period", "120", "-q"]) == 0
    text = out.read_text()
    for name in ("SD43900", "SD43910", "SD43920", "MD32750", "$SA_TEMP_COMP_ABS_VALUE", "$SA_TEMP_COMP_SLOPE",
                 "$SA_TEMP_COMP_REF_POSITION", "$MA_TEMP_COMP_TYPE"):
        assert name in text
    z, t = _prediction(model, "ch3")
    x, _ = _prediction(model, "ch4")
    readings = [{**{k: float(v[i]) for k, v in t.temperatures.items()}, "spindle": float(t.spindle_rpm[i])}
                for i in range(len(t))]
    got = run_sinumerik(text, readings, {"AX1": 250.0, "AX3": -80.0})
    np.testing.assert_allclose(got["AX3"], z / 1000.0, atol=1e-6)    # mm; Z = +ch3
    np.testing.assert_allclose(got["AX1"], -x / 1000.0, atol=1e-6)   # X = -ch4
    assert np.ptp(got["AX3"]) > 0.05                                 # a real compensation: 90 um over the test


def test_linuxcnc_component_builds_and_gives_minus_the_drift(fitted, tmp_path):
    d, model = fitted
    out = d / "lcnc"
    assert main(["thermal", "export", str(d / "m.json"), "--format", "linuxcnc", "-o", str(out), "--axes",
                 "ch3=Z", "-q"]) == 0
    comp = (out / "mtcal_thermal.comp").read_text()
    hal = (out / "mtcal_thermal.hal").read_text()
    assert "net thermal-z mtcal_thermal.0.counts-z => axis.z.eoffset-counts" in hal
    assert "OFFSET_AV_RATIO" in (out / "mtcal_thermal.ini").read_text()
    if shutil.which("halcompile"):
        shutil.copy(out / "mtcal_thermal.comp", tmp_path)
        r = subprocess.run(["halcompile", "--compile", "mtcal_thermal.comp"], cwd=tmp_path, capture_output=True,
                           text=True, timeout=120)
        assert r.returncode == 0 and (tmp_path / "mtcal_thermal.so").exists(), r.stderr
    if not shutil.which("gcc"):
        pytest.skip("no gcc to run the component's function")
    pins = re.findall(r"^pin (in|out) (float|s32) (\w+)", comp, re.M)
    variables = re.findall(r"^variable double (\w+) = 0;", comp, re.M)
    body = comp.split("FUNCTION(_) {", 1)[1].rsplit("}", 1)[0]
    ins = [n for io, _, n in pins if io == "in"]
    c = ["#include <math.h>", "#include <stdio.h>", "double fperiod, scale = 1e-6;"]
    c += [f"{'int' if ty == 's32' else 'double'} {n};" for _, ty, n in pins] + [f"double {v} = 0;" for v in variables]
    c += ["int main(void) {", "  while (scanf(\"%lf" + " %lf" * len(ins) + "\", &fperiod, " +
          ", ".join(f"&{n}" for n in ins) + f") == {len(ins) + 1}) {{", body,
          '    printf("%.12g %d\\n", offset_z, counts_z);', "  }", "  return 0;", "}"]
    (tmp_path / "h.c").write_text("\n".join(c))
    subprocess.run(["gcc", "-O0", "-o", str(tmp_path / "h"), str(tmp_path / "h.c"), "-lm"], check=True)
    z, t = _prediction(model, "ch3")
    period = np.diff(t.time_s, prepend=t.time_s[0] - 120.0)
    cols = [t.spindle_rpm if n == "spindle_rpm" else t.temperatures[n.removeprefix("temp_")] for n in ins]
    stdin = "\n".join(" ".join(f"{v:.17g}" for v in [period[i]] + [col[i] for col in cols]) for i in range(len(t)))
    r = subprocess.run([str(tmp_path / "h")], input=stdin, capture_output=True, text=True, check=True)
    got = np.array([[float(v) for v in ln.split()] for ln in r.stdout.splitlines()])
    np.testing.assert_allclose(got[:, 0], -z / 1000.0, atol=1e-9)     # mm: the offset is minus the drift
    np.testing.assert_allclose(got[:, 1], np.rint(-z / 1000.0 / 1e-6), atol=1)


def test_a_channel_the_model_does_not_predict_is_refused(fitted, capsys):
    d, model = fitted
    assert [c["channel"] for c in model["channels"] if not c["predictable"]] == ["ch1", "ch2", "ch5"]
    for fmt, out in (("siemens", d / "NO.SPF"), ("linuxcnc", d / "no")):
        assert main(["thermal", "export", str(d / "m.json"), "--format", fmt, "-o", str(out), "--axes",
                     "ch3=Z,ch1=X", "--force"]) == 2
        err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
        assert len(err) == 1 and "ch1: not predictable" in err[0] and "nothing was written" in err[0], err
        assert not out.exists()


def test_the_plausibility_guard_refuses_an_offset_beyond_a_machine_error(fitted, capsys):
    """A model whose coefficient was written in nm as um (x1000) commands millimetres over its own test."""
    d, model = fitted
    bad = json.loads(json.dumps(model))
    ch3 = next(c for c in bad["channels"] if c["channel"] == "ch3")
    ch3["coefficients_um"] = [v * 1000.0 for v in ch3["coefficients_um"]]
    (d / "bad.json").write_text(json.dumps(bad))
    out = d / "BAD.SPF"
    assert main(["thermal", "export", str(d / "bad.json"), "--format", "siemens", "-o", str(out), "--axes",
                 "ch3=Z"]) == 2
    err = capsys.readouterr().err
    assert "plausibility" not in err and "beyond" in err and "nothing was written" in err and not out.exists()
    assert main(["thermal", "export", str(d / "bad.json"), "--format", "siemens", "-o", str(out), "--axes",
                 "ch3=Z", "--force"]) == 0
    assert "FORCED past the plausibility guard" in capsys.readouterr().err and out.exists()
