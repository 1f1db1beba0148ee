"""The LinuxCNC kinematics module (mtcal export --format linuxcnc-kins) in its userspace harness (the .comp as
halcompile --preprocess writes it, gcc with the module's flags; tests/linuxcnc_sim.py): CPU ns per call of
kinematicsInverse and kinematicsForward on the demo model (scope position and full), and the same C as a batch
forward kinematics (poses per CPU second) beside today's NumPy path (ErrorEvaluator + the generated
forward_errors, vectorised), one run.  Empty when halcompile or gcc is absent."""
from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import mtcal
from mtcal.data import path
from mtcal.export.linuxcnc_kins import export_kins
from mtcal.model.errormodel import ErrorEvaluator

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
import linuxcnc_sim  # noqa: E402  (the one harness builder)

N = 100_000


def _harness(exe: Path, mode: str, rows: np.ndarray, reps: int) -> float:
    src, dst = exe.parent / "in.bin", exe.parent / "out.bin"
    np.ascontiguousarray(rows).tofile(src)
    r = subprocess.run([str(exe), mode, "0", "10", str(src), str(dst), str(reps)], capture_output=True, text=True,
                       check=True, timeout=600)
    return float(r.stdout)


def run() -> dict:
    if not (shutil.which("halcompile") and shutil.which("gcc")):
        return {}
    model = mtcal.load_model(path("demo_truth.json"))
    m = model.kinematics
    rng = np.random.default_rng(0)
    q = np.column_stack([rng.uniform(0, 500, N), rng.uniform(0, 450, N), rng.uniform(0, 400, N),
                         rng.uniform(0, 180, N), rng.uniform(-340, 340, N)])
    pose = np.zeros((N, 9))
    pose[:, [0, 1, 2, 4, 5]] = q
    ns = {}
    for scope in ("position", "full"):
        with tempfile.TemporaryDirectory() as d:
            export_kins(model, m, Path(d), name="mtcal_bench", scope=scope)
            exe = linuxcnc_sim.build_harness(Path(d) / "mtcal_bench.comp")
            reps = 3 if scope == "position" else 1
            ns[scope] = (_harness(exe, "inverse", pose, 1), _harness(exe, "forward", q, reps))
    inv_ns, fwd_ns = ns["position"]
    ev = ErrorEvaluator(model, m)
    t0 = time.process_time()
    for _ in range(3):
        m.forward(q, ev(q), check=False)
    numpy_s = (time.process_time() - t0) / 3
    return {"kins_inverse_ns": inv_ns, "kins_forward_ns": fwd_ns, "kins_full_inverse_ns": ns["full"][0],
            "kins_full_forward_ns": ns["full"][1], "kins_c_forward_poses_per_s": 1e9 / fwd_ns,
            "kins_numpy_forward_poses_per_s": N / numpy_s, "kins_c_vs_numpy_forward": numpy_s / (N * fwd_ns * 1e-9)}
