"""`mtcal export`: every format is read back by an independent reader written here, applied the way the
controller's documentation says (linear interpolation, end values held outside, the documented sign), and the
reached tool pose — exact error-inclusive forward kinematics of the generated DMU 50 model, errors evaluated at
the joint positions the controller actually produces — must match the programmed pose within the table's
resolution.  The same check with the table negated must fail.

Tolerance per table: step^2/8 * max|c''| (linear interpolation of the correction c) + max|c'| * max|c| (the error
is evaluated where the compensated joint stands, not at the nominal position) + print resolution; the closed
forms of c'' and c' are written here from the test model's own polynomials/harmonics.
"""
from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from mtcal.cli import main
from mtcal.errors import InputError
from mtcal.export import export_model
from mtcal.kinematics.machine import available_machines, load_machine
from mtcal.model.errormodel import ErrorFunction, ErrorModel, model_from_dict
from mtcal.model.fits import fit_from_dict

M = load_machine("dmu50")
RNG = np.random.default_rng(7)
LIN = 200.0          # linear ranges [-200, 200] mm
A_C = 20e-6          # rad, amplitude of E_CC (first harmonic)
A_B = 15e-6          # rad, E_CB = A_B * (B/90)^2 over [0, 180]
B_REV = 0.004        # mm, backlash of X from a diagnosis


def poly(axis, coeffs, lo=-LIN, hi=LIN):
    """Polynomial in the axis position (no domain scaling: domain = window [-1, 1] identity is avoided by
    giving coefficients in the scaled variable t = x / LIN)."""
    pos = np.linspace(lo, hi, 9)
    return tabled({"axis": axis, "positions": pos.tolist(),
                   "fit": {"kind": "polynomial", "coefficients": coeffs, "domain": [lo, hi]}})


def tabled(func: dict) -> dict:
    """The function with its table: the fit at its positions (a model's values are the table its fit stands
    for; export refuses a fit that disagrees with them, mtcal.model.plausibility)."""
    return {**func, "values": fit_from_dict(func["fit"])(np.asarray(func["positions"], dtype=float)).tolist()}


def raw_model(constants=None, **funcs) -> dict:
    return {"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": constants or {},
            "functions": funcs}


# E_XX(x) = 2e-3 t + 1.6e-3 t^3 (t = x / 200): at most 3.6 um; E_YX, E_ZZ similar shapes
EXX = [0.0, 2e-3, 0.0, 1.6e-3]
EYX = [0.0, 0.0, 3e-3]                       # 3 um parabola (straightness)
EZZ = [0.0, -1.5e-3, 1e-3]
HARM = tabled({"axis": "C", "positions": [0.0, 90.0, 180.0, 270.0, 360.0],
               "fit": {"kind": "harmonic", "period": 360, "a0": 0.0, "cos": [0.0], "sin": [A_C]}})
QUAD_B = tabled({"axis": "B", "positions": [0.0, 90.0, 180.0],
                 "fit": {"kind": "polynomial", "coefficients": [A_B, 2 * A_B, A_B], "domain": [0.0, 180.0]}})
# E_CB(B) = A_B (1 + u)^2 with u = B/90 - 1, i.e. A_B (B/90)^2


def c2_poly(coeffs):
    """max |d^2 E / dx^2| (mm/mm^2) of sum c_k t^k, t = x / LIN, over |t| <= 1."""
    d2 = sum(k * (k - 1) * abs(c) for k, c in enumerate(coeffs))
    return d2 / LIN**2


def c1_poly(coeffs):
    return sum(k * abs(c) for k, c in enumerate(coeffs)) / LIN


def cmax_poly(coeffs):
    return sum(abs(c) for c in coeffs)


def tol_lin(coeffs, step, offset=0.0):
    """Bound of the tool-tip residual (mm) of one table; ``offset``: a constant part of the correction (b/2)."""
    return step**2 / 8 * c2_poly(coeffs) + c1_poly(coeffs) * (cmax_poly(coeffs) + offset) + 2e-9


DEG = math.pi / 180


def pose_residual(model: ErrorModel, nominal: np.ndarray, physical: np.ndarray, add=None, mach=M) -> np.ndarray:
    """|reached - programmed| of the tool tip (mm): errors of ``model`` at the physical joints (+ ``add``)."""
    e = model.errors_at(mach, physical, "hold")
    if add is not None:
        e = e + add
    reached = mach.forward(physical, e)[..., :3]
    target = mach.forward(nominal)[..., :3]
    return np.linalg.norm(reached - target, axis=-1)


def interp_hold(x, xp, fp):
    return np.interp(x, xp, fp)  # np.interp holds the end values outside [xp0, xpn]


# ---------------------------------------------------------------- LinuxCNC

def read_linuxcnc(path):
    """The loader's reading (usrmotLoadComp): three numbers per line, stop silently at the first other line."""
    rows = []
    for line in open(path):
        parts = line.split()
        try:
            if len(parts) != 3:
                break
            rows.append([float(p) for p in parts])
        except ValueError:
            break
    return np.array(rows)


def linuxcnc_trims(rows, file_type):
    nom, fwd, rev = rows.T
    if file_type == 0:
        return nom, nom - fwd, nom - rev
    return nom, fwd, rev


LINUX_MODEL = raw_model(E_XX=poly("X", EXX), E_CC=HARM, E_CB=QUAD_B)


@pytest.mark.parametrize("file_type", [0, 1])
def test_linuxcnc_round_trip_with_backlash(tmp_path, file_type):
    model = model_from_dict(LINUX_MODEL)
    diag = {"effects": [{"name": "backlash", "axis": "X", "significant": True, "estimate": B_REV, "unit": "mm"}]}
    res = export_model(model, M, "linuxcnc", tmp_path, diagnosis=diag, file_type=file_type)
    assert "E_CC" in res.held and "E_XX" in res.held and res.not_held == []
    rows = read_linuxcnc(tmp_path / "joint0_X.comp")
    assert len(rows) == len(open(tmp_path / "joint0_X.comp").readlines()) <= 256  # every line is a triplet
    nom, fwd, rev = linuxcnc_trims(rows, file_type)
    assert np.all(np.diff(nom) > 0)
    step = nom[1] - nom[0]
    x = RNG.uniform(-LIN, LIN, 400)
    ix = M.axes.index("X")
    for d, trim in ((+1, fwd), (-1, rev)):
        phys = np.zeros((len(x), 5))
        phys[:, ix] = x + interp_hold(x, nom, trim)       # motor = joint command + trim (control.c)
        nomi = np.zeros_like(phys)
        nomi[:, ix] = x
        add = np.zeros(len(M.error_names))
        add[M.error_names.index("E_XX")] = d * B_REV / 2   # approach direction d: E + d b/2
        r = pose_residual(model, nomi, phys, add)
        assert r.max() < tol_lin(EXX, step, B_REV / 2), (d, r.max())
        phys[:, ix] = x - interp_hold(x, nom, trim)       # the wrong sign doubles the error
        assert pose_residual(model, nomi, phys, add).max() > 1e-3
    assert np.allclose(rev - fwd, B_REV, atol=1e-9)       # reversal: reverse trim exceeds forward trim by b
    ini = (tmp_path / "linuxcnc_comp.ini").read_text()
    assert "[JOINT_0]\n" in ini and f"COMP_FILE_TYPE = {file_type}" in ini and "COMP_FILE = joint0_X.comp" in ini


def test_linuxcnc_rotary_sign_follows_the_chain(tmp_path):
    """C turns with sign -1 in the DMU 50 chain (docs/design.md), so its trim is +E_CC in degrees; B (sign +1) -E_CB."""
    model = model_from_dict(LINUX_MODEL)
    export_model(model, M, "linuxcnc", tmp_path, file_type=1)
    tables = {ax: linuxcnc_trims(read_linuxcnc(tmp_path / f"joint{M.axes.index(ax)}_{ax}.comp"), 1)
              for ax in ("X", "B", "C")}
    for ax, amp in (("C", A_C), ("B", A_B * 4)):
        nom = tables[ax][0]
        q = RNG.uniform(nom[0], nom[-1], 200)
        cfg = np.tile([120.0, 60.0, 40.0, 30.0, 0.0], (len(q), 1))
        cfg[:, M.axes.index(ax)] = q
        phys = cfg.copy()
        for r, (n, f, _) in tables.items():  # every joint gets its own trim (forward direction)
            k = M.axes.index(r)
            phys[:, k] = cfg[:, k] + interp_hold(cfg[:, k], n, f)
        step = nom[1] - nom[0]
        lever_mm = 300.0  # the tool tip is within 300 mm of both rotary axes here
        x_step = tables["X"][0][1] - tables["X"][0][0]
        tol = lever_mm * (step**2 / 8 * amp * DEG**2 * 2 + amp**2 * 4) + tol_lin(EXX, x_step)
        assert pose_residual(model, cfg, phys).max() < tol
        k = M.axes.index(ax)
        phys[:, k] = q - interp_hold(q, nom, tables[ax][1])
        assert pose_residual(model, cfg, phys).max() > 50 * tol
    c_nom, c_fwd, _ = linuxcnc_trims(read_linuxcnc(tmp_path / "joint4_C.comp"), 1)
    assert np.allclose(c_fwd, A_C * np.sin(np.radians(c_nom)) / DEG, atol=1e-9)  # +E_CC in deg


# ---------------------------------------------------------------- Siemens

CROSS_MODEL = raw_model({"E_C0Y": 2e-5, "E_B0Z": -1e-5}, E_XX=poly("X", EXX), E_YX=poly("X", EYX),
                        E_ZZ=poly("Z", EZZ), E_YY=poly("Y", EZZ))


def read_siemens(path):
    """LEC per axis and CEC tables from the MPF assignments."""
    lec, cec = {}, {}
    for line in open(path):
        line = line.split(";")[0].strip()
        if m := re.fullmatch(r"\$AA_ENC_COMP\[0,(\d+),(AX\d+)\]=(\S+)", line):
            lec.setdefault(m[2], {}).setdefault("v", {})[int(m[1])] = float(m[3])
        elif m := re.fullmatch(r"\$AA_ENC_COMP_(STEP|MIN|MAX)\[0,(AX\d+)\]=(\S+)", line):
            lec.setdefault(m[2], {})[m[1]] = float(m[3])
        elif m := re.fullmatch(r"\$AN_CEC\[(\d+),(\d+)\]=(\S+)", line):
            cec.setdefault(int(m[1]), {}).setdefault("v", {})[int(m[2])] = float(m[3])
        elif m := re.fullmatch(r"\$AN_CEC_(INPUT_AXIS|OUTPUT_AXIS)\[(\d+)\]=\((AX\d+)\)", line):
            cec.setdefault(int(m[2]), {})[m[1]] = m[3]
        elif m := re.fullmatch(r"\$AN_CEC_(STEP|MIN|MAX|DIRECTION)\[(\d+)\]=(\S+)", line):
            cec.setdefault(int(m[2]), {})[m[1]] = float(m[3])
    return lec, cec


def _table_eval(t, q):
    v = np.array([t["v"][i] for i in range(len(t["v"]))])
    xp = t["MIN"] + t["STEP"] * np.arange(len(v))
    assert math.isclose(xp[-1], t["MAX"], abs_tol=1e-9)
    return interp_hold(q, xp, v)


def siemens_physical(lec, cec, cmd, direction=+1, sign=+1):
    """The NC adds each value to the axis' actual value, so the axis stands at command - value (K3 / 808D)."""
    phys = cmd.copy()
    for ax, t in lec.items():
        k = int(ax[2:]) - 1
        phys[:, k] -= sign * _table_eval(t, cmd[:, k])
    for t in cec.values():
        if t["DIRECTION"] not in (0, direction):
            continue
        i, o = int(t["INPUT_AXIS"][2:]) - 1, int(t["OUTPUT_AXIS"][2:]) - 1
        phys[:, o] -= sign * _table_eval(t, cmd[:, i])
    return phys


def test_siemens_lec_cec_round_trip(tmp_path):
    model = model_from_dict(CROSS_MODEL)
    out = tmp_path / "COMP.MPF"
    res = export_model(model, M, "siemens", out)
    assert {"E_XX", "E_YX", "E_C0Y", "E_B0Z"} <= set(res.held)
    lec, cec = read_siemens(out)
    assert {"AX1", "AX2", "AX3"} <= set(lec) and len(cec) >= 3
    step = lec["AX1"]["STEP"]
    cmd = np.zeros((500, 5))
    cmd[:, :3] = RNG.uniform(-LIN, LIN, (500, 3))
    tol = (tol_lin(EXX, step) + tol_lin(EYX, step) + 2 * tol_lin(EZZ, step)
           + LIN * 3e-5 * 5e-3)   # squareness x straightness cross terms (second order)
    assert pose_residual(model, cmd, siemens_physical(lec, cec, cmd)).max() < tol
    assert pose_residual(model, cmd, siemens_physical(lec, cec, cmd, sign=-1)).max() > 1e-3


def test_siemens_direction_dependent_reversal(tmp_path):
    model = model_from_dict(raw_model(E_XX=poly("X", EXX)))
    diag = {"effects": [{"name": "backlash", "axis": "X", "significant": True, "estimate": B_REV}]}
    out = tmp_path / "COMP.MPF"
    export_model(model, M, "siemens", out, diagnosis=diag)
    lec, cec = read_siemens(out)
    assert sorted(t["DIRECTION"] for t in cec.values()) == [-1, 1]
    cmd = np.zeros((100, 5))
    cmd[:, 0] = RNG.uniform(-LIN, LIN, 100)
    for d in (1, -1):
        add = np.zeros(len(M.error_names))
        add[M.error_names.index("E_XX")] = d * B_REV / 2
        r = pose_residual(model, cmd, siemens_physical(lec, cec, cmd, d), add)
        assert r.max() < tol_lin(EXX, lec["AX1"]["STEP"], B_REV / 2)


# ---------------------------------------------------------------- Heidenhain

def read_tnc_table(path):
    """Fixed-width TNC table: each field starts where its header name starts; blank fields are absent."""
    lines = open(path).read().splitlines()
    assert lines[0].startswith("BEGIN") and lines[-1] == "[END]"
    starts = [(m.start(), m.group()) for m in re.finditer(r"\S+", lines[1])]
    bounds = [(a, starts[i + 1][0] if i + 1 < len(starts) else None, n) for i, (a, n) in enumerate(starts)]
    return [{n: r[a:b].strip() for a, b, n in bounds if r[a:b].strip()} for r in lines[2:-1]]


def heidenhain_physical(folder, cmd, sign=+1, direction=+1):
    """CMA: [axis column of the COM] = F(CMA column the COM is entered in); the control subtracts the error."""
    cma = read_tnc_table(folder / "CONFIG.CMA")
    active = [r for r in cma if r.get("ACTIVE") == "*"][0]
    phys = cmd.copy()
    for inp, com in active.items():
        if inp in ("NR", "ACTIVE") or not com.endswith(".COM"):
            continue
        rows = read_tnc_table(folder / com)
        pos = np.array([float(r["AXISPOS"]) for r in rows])
        i = M.axes.index(inp)
        for out in rows[0]:
            if out in M.axes:
                col = "BACKLASH" if (direction < 0 and out == inp and "BACKLASH" in rows[0]) else out
                v = np.array([float(r[col]) for r in rows])
                phys[:, M.axes.index(out)] -= sign * interp_hold(cmd[:, i], pos, v)
    return phys


def test_heidenhain_com_cma_round_trip(tmp_path):
    model = model_from_dict(CROSS_MODEL)
    export_model(model, M, "heidenhain", tmp_path)
    assert (tmp_path / "CONFIG.CMA").exists() and (tmp_path / "X.COM").exists()
    pos = [float(r["AXISPOS"]) for r in read_tnc_table(tmp_path / "X.COM")]
    step = pos[1] - pos[0]
    assert len(pos) <= 256
    cmd = np.zeros((500, 5))
    cmd[:, :3] = RNG.uniform(-LIN, LIN, (500, 3))
    tol = (tol_lin(EXX, step) + tol_lin(EYX, step) + 2 * tol_lin(EZZ, step) + LIN * 3e-5 * 5e-3
           + 5 * 5e-7)  # 6 decimals (mm) in the tables: up to 0.5 nm rounding per table entry used
    assert pose_residual(model, cmd, heidenhain_physical(tmp_path, cmd)).max() < tol
    assert pose_residual(model, cmd, heidenhain_physical(tmp_path, cmd, sign=-1)).max() > 1e-3


# ---------------------------------------------------------------- TF5280 (ISG CSV, Etalon)

def read_isg_csv(path):
    """Blocks separated by '#', '//' comments; first header name is the argument (axis) or all are constants."""
    consts, funcs, head = {}, {}, None
    for line in open(path):
        line = line.split("//")[0].strip()
        if not line:
            continue
        if line == "#":
            head = None
            continue
        if head is None:
            head = line.split()
            continue
        vals = [float(v) for v in line.split()]
        if head[0] in M.axes:
            for n, v in zip(head[1:], vals[1:]):
                funcs.setdefault(n, (head[0], []))[1].append((vals[0], v))
        else:
            consts.update(zip(head, vals))
    return consts, funcs


def read_etalon(path):
    consts, funcs, name, pts = {}, {}, None, None
    for line in open(path):
        line = line.split("//")[0].strip()
        if m := re.fullmatch(r"\[(\w+)\]", line):
            name = m[1]
        elif m := re.fullmatch(r"VALUE = (\S+)", line):
            consts[name] = float(m[1])
        elif line.startswith("Gridpoints"):
            pts = []
        elif line.startswith("}"):
            funcs[name] = (name[2], pts)
            pts = None
        elif pts is not None and line:
            pts.append(tuple(float(v) for v in line.split()))
    return consts, funcs


def iso_to_model(consts, funcs, sign=1.0) -> ErrorModel:
    def full(n):
        return f"E_{n}" if n[1] == "0" else f"E_{n[1:]}"
    fs = {}
    for n, (ax, pts) in funcs.items():
        p = np.array(pts)
        fs[full(n)] = ErrorFunction(ax, p[:, 0], sign * p[:, 1])
    return ErrorModel("dmu50", {full(n): sign * v for n, v in consts.items()}, fs)


FULL_MODEL = raw_model({"E_C0Y": 2e-5, "E_X0C": 0.01, "E_A0B": 9e-6}, E_XX=poly("X", EXX), E_YX=poly("X", EYX),
                       E_AX=poly("X", [0.0, 1e-5, 1e-5]), E_ZZ=poly("Z", EZZ), E_CC=HARM)


@pytest.mark.parametrize("fmt,reader", [("tf5280", read_isg_csv), ("etalon", read_etalon)])
def test_tf5280_round_trip(tmp_path, fmt, reader):
    """TF5280 computes the compensation (-deviation) from the errors read: the deviation predicted from the file
    must equal the model's within the grid interpolation tolerance; negated values must not."""
    model = model_from_dict(FULL_MODEL)
    out = tmp_path / "vc.txt"
    res = export_model(model, M, fmt, out)
    assert res.not_held == []
    consts, funcs = reader(out)
    assert set(consts) == {"C0Y", "X0C", "A0B"} and {"EXX", "EYX", "EAX", "EZZ", "ECC"} <= set(funcs)
    back = iso_to_model(consts, funcs)
    cfg = np.column_stack([RNG.uniform(-LIN, LIN, (300, 3)), RNG.uniform(0, 90, 300), RNG.uniform(0, 360, 300)])
    dev_model = M.deviation(cfg, model.errors_at(M, cfg, "hold"), order=None)[:, :3]
    dev_file = M.deviation(cfg, back.errors_at(M, cfg, "hold"), order=None)[:, :3]
    step = funcs["EXX"][1][1][0] - funcs["EXX"][1][0][0]
    tol = 4 * (step**2 / 8) * (c2_poly(EXX) + c2_poly(EYX) + 400 * 2e-5 / LIN**2 * 2) + 1e-8
    assert np.abs(dev_model - dev_file).max() < tol
    neg = iso_to_model(consts, funcs, -1.0)
    assert np.abs(dev_model - M.deviation(cfg, neg.errors_at(M, cfg, "hold"), order=None)[:, :3]).max() > 1e-3


# ---------------------------------------------------------------- refusals and CLI

def test_refuses_what_a_format_cannot_hold(tmp_path):
    model = model_from_dict(FULL_MODEL)
    with pytest.raises(InputError, match="cannot hold E_AX"):
        export_model(model, M, "linuxcnc", tmp_path / "lc", require=["E_AX"])
    assert not (tmp_path / "lc").exists()  # refused before writing anything
    with pytest.raises(InputError, match="at most 256 points"):
        export_model(model, M, "linuxcnc", tmp_path / "lc", max_points=300)
    with pytest.raises(InputError, match="holds at most 256"):
        export_model(model, M, "linuxcnc", tmp_path / "lc", step=1.0)
    res = export_model(model, M, "linuxcnc", tmp_path / "lc2", require=["E_XX"])
    assert {"E_AX", "E_YX", "E_C0Y", "E_X0C"} <= set(res.not_held)


@pytest.mark.filterwarnings("ignore:overflow")
def test_refuses_non_finite_and_never_overwrites_the_model(tmp_path, capsys):
    bad = raw_model(E_XX={**poly("X", [0.0, 1e308, 0.0, 1e308]), "values": [0.0] * 9})  # a finite table, its fit not
    p = tmp_path / "bad.json"
    p.write_text(json.dumps(bad))
    for fmt in ("siemens", "tf5280"):
        assert main(["export", str(p), "--format", fmt, "-o", str(tmp_path / "x.out")]) == 2
        assert "not finite" in capsys.readouterr().err and not (tmp_path / "x.out").exists()
    good = tmp_path / "m.json"
    good.write_text(json.dumps(CROSS_MODEL))
    before = good.read_text()
    assert main(["export", str(good), "--format", "tf5280", "-o", str(good)]) == 2
    assert good.read_text() == before


def test_cli_json(tmp_path, capsys):
    p = tmp_path / "m.json"
    p.write_text(json.dumps(CROSS_MODEL))
    assert main(["export", str(p), "--format", "linuxcnc", "-o", str(tmp_path / "lc"), "--step", "5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    x = [t for t in out["tables"] if t["axis"] == "X"][0]
    assert x["step"] == 5 and x["points"] == 81 and x["from"] == -200 and x["to"] == 200
    assert "E_YX" in out["not_held"] and "E_C0Y" in out["not_held"]
    assert "COMP_FILE_TYPE" not in out["sign"] and "usrmotLoadComp" in out["sign"]


@pytest.mark.parametrize("machine", available_machines())
def test_linuxcnc_every_joint_of_every_machine(tmp_path, machine):
    """Machines are data: each joint's positioning error (linear E_JJ; rotary E_CJ, the rotation about the axis'
    own stator z, docs/design.md) is cancelled by its exported trim at random configurations, whatever the chain's
    joint signs (xyzac: A and C turn with sign -1); negated trims double the error."""
    m = load_machine(machine)
    funcs, shape, spans, rng = {}, {}, {}, np.random.default_rng(3)
    for ax, kind, lim in zip(m.axes, m.axis_kinds, m.limits):
        lo, hi = (-200.0, 200.0) if kind == "linear" else (lim or (0.0, 360.0))
        amp = 5e-3 if kind == "linear" else 20e-6      # mm or rad: E = amp (t + t^2 / 2), t in [-1, 1]
        name = f"E_{ax}{ax}" if kind == "linear" else f"E_C{ax}"
        funcs[name] = tabled({"axis": ax, "positions": [lo, hi],
                              "fit": {"kind": "polynomial", "coefficients": [0.0, amp, amp / 2], "domain": [lo, hi]}})
        spans[ax], shape[ax] = (lo, hi), (kind, amp, (hi - lo) / 2)
    model = model_from_dict({"machine": machine, "units": {"length": "mm", "angle": "rad"}, "functions": funcs})
    export_model(model, m, "linuxcnc", tmp_path, file_type=1)
    cfg = np.column_stack([rng.uniform(*spans[a], 300) for a in m.axes])
    phys, wrong, tol = cfg.copy(), cfg.copy(), 2e-9
    for k, ax in enumerate(m.axes):
        nom, fwd, _ = linuxcnc_trims(read_linuxcnc(tmp_path / f"joint{k}_{ax}.comp"), 1)
        kind, amp, half = shape[ax]
        interp, shift = (nom[1] - nom[0])**2 / 8 * amp / half**2, (2 * amp / half) * 1.5 * amp
        tol += interp + shift if kind == "linear" else 600.0 * (interp + shift * 180 / math.pi)  # 600 mm lever
        phys[:, k] += interp_hold(cfg[:, k], nom, fwd)
        wrong[:, k] -= interp_hold(cfg[:, k], nom, fwd)
    lo, hi = [s[0] for s in spans.values()], [s[1] for s in spans.values()]
    assert pose_residual(model, cfg, np.clip(phys, lo, hi), mach=m).max() < tol
    assert pose_residual(model, cfg, np.clip(wrong, lo, hi), mach=m).max() > 1e-3


def test_heidenhain_kinematics_comp_columns(tmp_path):
    """KC_X.COM: C1..C6 = E_XX, E_YX, E_ZX (mm), E_AX, E_BX, E_CX (deg) at AXISPOS (iTNC 530 recommendation)."""
    model = model_from_dict(FULL_MODEL)
    res = export_model(model, M, "heidenhain", tmp_path, kinematics_comp=True, require=["E_AX"])
    rows = read_tnc_table(tmp_path / "KC_X.COM")
    x = np.array([float(r["AXISPOS"]) for r in rows])
    t = x / LIN
    assert np.allclose([float(r["C1"]) for r in rows], sum(c * t**k for k, c in enumerate(EXX)), atol=1e-9)
    assert np.allclose([float(r["C4"]) for r in rows], np.degrees(1e-5 * t + 1e-5 * t**2), atol=1e-9)
    assert np.allclose([float(r["C6"]) for r in rows], 0.0) and "E_AX" in res.held


def test_siemens_modulo_only_for_a_full_turn_of_an_unlimited_rotary_axis(tmp_path):
    model = model_from_dict(raw_model(E_CC=HARM, E_CB=QUAD_B))
    export_model(model, M, "siemens", tmp_path / "c.mpf")
    text = (tmp_path / "c.mpf").read_text()
    assert "$AA_ENC_COMP_IS_MODULO[0,AX5]=1" in text and "$AA_ENC_COMP_IS_MODULO[0,AX4]=0" in text


def test_backlash_without_a_table_is_reported_not_dropped(tmp_path):
    model = model_from_dict(raw_model(E_XX=poly("X", EXX)))
    diag = {"effects": [{"name": "backlash", "axis": "Z", "significant": True, "estimate": B_REV}]}
    res = export_model(model, M, "linuxcnc", tmp_path, diagnosis=diag)
    assert any("axis Z" in w for w in res.warnings)
    with pytest.raises(InputError, match="not of machine dmu50"):
        export_model(model, M, "linuxcnc", tmp_path / "q", diagnosis={"effects": [
            {"name": "backlash", "axis": "Q", "significant": True, "estimate": B_REV}]})


def test_heidenhain_reversal_and_blank_cma_cells(tmp_path):
    """X and Z have tables, Y has none (its CMA cell stays blank); the X table carries a backlash: own column
    = error moving positive, BACKLASH = error moving negative."""
    model = model_from_dict(raw_model(E_XX=poly("X", EXX), E_ZZ=poly("Z", EZZ)))
    diag = {"effects": [{"name": "backlash", "axis": "X", "significant": True, "estimate": B_REV}]}
    export_model(model, M, "heidenhain", tmp_path, diagnosis=diag)
    active = read_tnc_table(tmp_path / "CONFIG.CMA")[0]
    assert active["X"] == "X.COM" and active["Z"] == "Z.COM" and "Y" not in active
    cmd = np.zeros((300, 5))
    cmd[:, [0, 2]] = RNG.uniform(-LIN, LIN, (300, 2))
    step = 2.0
    for d in (1, -1):
        add = np.zeros(len(M.error_names))
        add[M.error_names.index("E_XX")] = d * B_REV / 2
        r = pose_residual(model, cmd, heidenhain_physical(tmp_path, cmd, direction=d), add)
        assert r.max() < tol_lin(EXX, step, B_REV / 2) + tol_lin(EZZ, step) + 2 * 5e-7
        assert pose_residual(model, cmd, heidenhain_physical(tmp_path, cmd, -1, d), add).max() > 1e-3
