"""A real NC stack: LinuxCNC's standalone interpreter `rs274` (Debian package linuxcnc-uspace) reads mtcal's
compensated programs; its canonical moves (STRAIGHT_FEED / STRAIGHT_TRAVERSE, printed with 4 decimals) must be the
program text's end points and mtcal's own block ends (mtcal.nc.gcode.read_moves) to the printed resolution.
Skipped, with the reason, when rs274 is not installed (CI installs it when it can: .ci/run)."""
from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from linuxcnc_sim import linuxcnc_lock

import mtcal
from mtcal.cli import main
from mtcal.nc.gcode import read_moves

RS274 = shutil.which("rs274")
pytestmark = pytest.mark.skipif(RS274 is None, reason="rs274 (LinuxCNC, Debian package linuxcnc-uspace) is not "
                                                      "installed: apt-get install -y linuxcnc-uspace")
DATA = Path(mtcal.__file__).parent / "data"
MOVE = re.compile(r"STRAIGHT_(?:FEED|TRAVERSE)\(([^)]*)\)")
RES = 5e-5 + 1e-9  # rs274 prints 4 decimals


def canonical(program: Path, tmp: Path) -> np.ndarray:
    """X Y Z (A) B C of every straight move rs274 emits, in order."""
    out = tmp / (program.name + ".canon")
    with linuxcnc_lock():  # one LinuxCNC program at a time (tests/linuxcnc_sim.py)
        r = subprocess.run([RS274, "-g", str(program), str(out)], stdin=subprocess.DEVNULL, capture_output=True,
                           text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    rows = [[float(v) for v in m[1].split(",")] for m in MOVE.finditer(out.read_text())]
    a = np.array(rows)
    return a[:, [0, 1, 2, 4, 5]]  # x y z (a) b c: the DMU 50 has no A


def text_moves(program: Path) -> np.ndarray:
    """End points read from the program text here, independently: absolute mm/deg words carried modally."""
    pos, out = {}, []
    for line in program.read_text(encoding="latin-1").splitlines():
        code = re.sub(r"\([^)]*\)|;.*", "", line)
        words = dict((w.upper(), float(v)) for w, v in re.findall(r"([XYZBCxyzbc])\s*([-+]?\d*\.?\d+)", code))
        if words:
            pos.update(words)
            if all(k in pos for k in "XYZ"):
                out.append([pos[k] if k in pos else 0.0 for k in "XYZBC"])
    return np.array(out)


LONG = """%
(long feed moves across the workspace: subdivided by mtcal compensate)
G90 G21 G17
G0 X0 Y0 Z50 B0 C0
G1 X-200 Y-150 Z-100 B20 C0 F1000
X200 Y150 Z100 B60 C90
X-150 Y100 Z20 B45 C200
G0 Z120
M30
%
"""


@pytest.mark.parametrize("scope", ["position", "full"])
@pytest.mark.parametrize("source", ["sample", "long"])
def test_rs274_reads_compensated_programs(tmp_path, scope, source, capsys):
    src = DATA / "sample_5axis.nc"
    if source == "long":
        src = tmp_path / "long.nc"
        src.write_text(LONG)
    prog = tmp_path / f"comp_{scope}.nc"
    assert main(["compensate", str(src), "--model", str(DATA / "demo_truth.json"),
                 "-o", str(prog), "--scope", scope, "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    if source == "long":
        assert rep["subdivided_moves"] >= 3 and rep["lines_inserted"] > 6  # subdivision exercised
    canon = canonical(prog, tmp_path)
    ours = read_moves(prog)
    text = text_moves(prog)
    assert len(ours) == len(text) and len(canon) >= len(ours)
    tail = canon[len(canon) - len(ours):]  # rs274 also emits moves before X Y Z are all known
    assert np.abs(tail - ours).max() <= RES
    assert np.abs(tail - text).max() <= RES
    if source == "sample":
        assert np.abs(ours - read_moves(src)).max() > 1e-3  # the compensation moved the end points
