"""LinuxCNC's own motion controller loads mtcal's COMP_FILEs (type 0 on joint 0, type 1 on joint 1) in a headless
simulator configuration (trivkins, core_sim.hal, a Python 'display' that homes, moves by MDI and reads HAL pins);
the screw compensation it applies (joint.N.motor-pos-cmd - joint.N.pos-cmd - joint.N.motor-offset) must be the
correction written here from the test model's closed form: -E(x) - b/2 after moving up, -E(x) + b/2 after moving
down (control.c compute_screw_comp keeps the last direction's trim at standstill).  Skipped, with the reason, when
LinuxCNC (Debian package linuxcnc-uspace) is absent or cannot start here.  Started by tests/linuxcnc_sim.py under
the lock every LinuxCNC test holds."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from linuxcnc_sim import run_linuxcnc

from mtcal.export import export_model
from mtcal.kinematics.machine import load_machine
from mtcal.model.errormodel import model_from_dict
from mtcal.model.fits import Polynomial

LINUXCNC = shutil.which("linuxcnc")
pytestmark = pytest.mark.skipif(LINUXCNC is None or not Path("/usr/bin/python3").exists(),
                                reason="LinuxCNC (Debian package linuxcnc-uspace) is not installed")
C = [0.0, 0.002, 0.0, 0.0016]   # E(q) = sum c_k t^k, t = q / 200 (mm)
B = 0.004                       # mm, reversal from a diagnosis
TARGETS = [(-100.0, -1), (50.0, +1), (137.3, +1), (-31.7, -1), (183.9, +1), (-177.1, -1)]  # from 0, in order

JOINT = """[JOINT_{j}]
TYPE = LINEAR
HOME = 0.0
MAX_VELOCITY = 200
MAX_ACCELERATION = 2000
BACKLASH = 0.0
MIN_LIMIT = -300
MAX_LIMIT = 300
FERROR = 10
MIN_FERROR = 10
HOME_SEARCH_VEL = 0
HOME_LATCH_VEL = 0
HOME_SEQUENCE = 0
{comp}
"""
INI = """[EMC]
VERSION = 1.1
MACHINE = mtcal-comp-check
[DISPLAY]
DISPLAY = ./probe.py
[TASK]
TASK = milltask
CYCLE_TIME = 0.001
[RS274NGC]
PARAMETER_FILE = sim.var
[EMCMOT]
EMCMOT = motmod
COMM_TIMEOUT = 1.0
BASE_PERIOD = 0
SERVO_PERIOD = 1000000
[EMCIO]
EMCIO = io
CYCLE_TIME = 0.100
TOOL_TABLE = sim.tbl
[HAL]
HALFILE = core_sim.hal
[TRAJ]
COORDINATES = X Y Z
LINEAR_UNITS = mm
ANGULAR_UNITS = degree
MAX_LINEAR_VELOCITY = 200
MAX_LINEAR_ACCELERATION = 2000
[KINS]
KINEMATICS = trivkins
JOINTS = 3
""" + "".join(f"[AXIS_{a}]\nMAX_VELOCITY = 200\nMAX_ACCELERATION = 2000\nMIN_LIMIT = -300\nMAX_LIMIT = 300\n"
              for a in "XYZ")
PROBE = """#!/usr/bin/python3
import json, time
import hal, linuxcnc
s, c = linuxcnc.stat(), linuxcnc.command()
h = hal.component("mtcalprobe"); h.ready()  # hal.get_value needs a component of this process
out = {"error": None, "rows": []}
try:
    for st in (linuxcnc.STATE_ESTOP_RESET, linuxcnc.STATE_ON):
        c.state(st); c.wait_complete(5)
    c.mode(linuxcnc.MODE_MANUAL); c.wait_complete(5)
    c.home(-1); c.wait_complete(5)
    for _ in range(200):
        s.poll()
        if all(s.homed[:3]): break
        time.sleep(0.05)
    c.mode(linuxcnc.MODE_MDI); c.wait_complete(5)
    for q in json.load(open("targets.json")):
        c.mdi("G90 G1 F6000 X%.6f Y%.6f" % (q, q)); c.wait_complete(60)
        time.sleep(0.3)
        out["rows"].append([q] + [hal.get_value("joint.%d.%s" % (j, p)) for j in (0, 1)
                                  for p in ("pos-cmd", "motor-pos-cmd", "motor-offset")])
except Exception as e:
    out["error"] = repr(e)
json.dump(out, open("probe_out.json", "w"))
"""


def error(q):
    t = np.asarray(q) / 200.0
    return sum(c * t**k for k, c in enumerate(C))


@pytest.mark.slow
def test_linuxcnc_motion_applies_exported_comp_files(tmp_path):
    spec = {"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": {}, "functions": {
        n: {"axis": a, "positions": [-200, 0, 200], "values": Polynomial(C, [-200, 200])([-200, 0, 200]).tolist(),
            "fit": {"kind": "polynomial", "coefficients": C, "domain": [-200, 200]}} for n, a in
        (("E_XX", "X"), ("E_YY", "Y"))}}
    model, m = model_from_dict(spec), load_machine("dmu50")
    diag = {"effects": [{"name": "backlash", "axis": a, "significant": True, "estimate": B} for a in "XY"]}
    export_model(model, m, "linuxcnc", tmp_path / "t0", diagnosis=diag, file_type=0)
    export_model(model, m, "linuxcnc", tmp_path / "t1", diagnosis=diag, file_type=1)
    comp = ["COMP_FILE = t0/joint0_X.comp\nCOMP_FILE_TYPE = 0", "COMP_FILE = t1/joint1_Y.comp\nCOMP_FILE_TYPE = 1", ""]
    (tmp_path / "comp.ini").write_text(INI + "".join(JOINT.format(j=j, comp=comp[j]) for j in range(3)))
    (tmp_path / "probe.py").write_text(PROBE)
    (tmp_path / "probe.py").chmod(0o755)
    (tmp_path / "sim.tbl").write_text("T1 P1 D0 Z0 ;\n")
    (tmp_path / "sim.var").write_text("")
    (tmp_path / "targets.json").write_text(json.dumps([q for q, _ in TARGETS]))
    res = run_linuxcnc(tmp_path)
    assert res["error"] is None and len(res["rows"]) == len(TARGETS)
    rows = np.array(res["rows"])
    q = rows[:, 0]
    d = np.array([s for _, s in TARGETS])
    expected = -error(q) - d * B / 2           # correction = -(E + d b/2)
    step = 2.0                                 # default step over [-200, 200] with 256 points
    tol = step**2 / 8 * (6 * C[3] / 200**2) + 1e-8  # linear interpolation of the cubic + float storage
    for j in (0, 1):
        pos, motor, offset = rows[:, 1 + 3 * j], rows[:, 2 + 3 * j], rows[:, 3 + 3 * j]
        assert np.allclose(pos, q, atol=1e-9)
        applied = motor - pos - offset
        assert np.abs(applied - expected).max() < tol, (j, applied, expected)
        assert np.abs(applied + expected).max() > 1e-3   # the opposite sign would not pass
