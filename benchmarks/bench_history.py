"""Timing of `mtcal history add` (issue 38: under 0.5 s): an identified DMU 50 model (the demo's: 27 error
functions and the squareness, about 420 values with their intervals) added to a SQLite history that already holds
``existing`` calibrations, in this process (the library call: read, hash, check, one transaction) and as the
command (a new Python process: start-up, the command line's parser with every subcommand's imports, the same); the
baseline is the same command asked only for its help (`mtcal history add --help`: start-up and parser, no work),
measured in the same run.  Wall and CPU seconds (the CPU time is what a loaded machine does not inflate).  No
asserts: `python benchmarks/bench_history.py`."""
from __future__ import annotations

import datetime as dt
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from timing import best_of


def _model_file(folder: Path, k: int) -> Path:
    """The bundled demo truth as a model with per-position intervals (u95 = 2 um or 2 urad), made distinct by k."""
    from mtcal.data import path
    doc = json.loads(path("demo_truth.json").read_text())
    doc["constants"] = {n: v + 1e-9 * k for n, v in doc["constants"].items()}
    for f in doc["functions"].values():
        n = len(f["values"])
        f["u95"] = [2e-3] * n
        f["std_mean"] = [2e-3 / 1.959963984540054] * n
        f.pop("fit", None)
    doc["squareness_sigma"] = {n: 1e-6 for n in doc["constants"]}
    p = folder / f"model_{k}.json"
    p.write_text(json.dumps(doc))
    return p


def run(existing: int = 20, repeat: int = 3) -> dict:
    from mtcal.history import add
    from mtcal.history.results import read_result
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        db = str(folder / "h.db")
        day = dt.date(2020, 1, 1)
        for k in range(existing):
            add(_model_file(folder, k), "M1", day + dt.timedelta(days=k), db)
        n_values = len(read_result(_model_file(folder, 0)).quantities)
        files = iter(_model_file(folder, existing + k) for k in range(3 * repeat + 1))
        lib = best_of(lambda: add(next(files), "M1", dt.date.today(), db), repeat)
        lib_cpu = _cpu(lambda: add(next(files), "M1", dt.date.today(), db), repeat)
        cmd = [sys.executable, "-m", "mtcal.cli", "history", "add"]
        cli, cli_cpu = _child(lambda: cmd + [str(next(files)), "--machine", "M1", "--db", db], repeat)
        base, base_cpu = _child(lambda: cmd + ["--help"], repeat)
    return {"history_add_library_s": lib, "history_add_library_cpu_s": lib_cpu, "history_add_command_s": cli,
            "history_add_command_cpu_s": cli_cpu, "baseline_help_s": base, "baseline_help_cpu_s": base_cpu,
            "history_add_command_minus_baseline_cpu_s": cli_cpu - base_cpu,
            "history_add_command_over_baseline_cpu": cli_cpu / base_cpu, "values_per_model": n_values,
            "existing_calibrations": existing}


def _cpu(fn, repeat: int) -> float:
    """Least CPU time (s, this process) of ``repeat`` calls."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.process_time()
        fn()
        best = min(best, time.process_time() - t0)
    return best


def _child(argv, repeat: int) -> tuple[float, float]:
    """Least wall and least CPU time (s, user + system of the child) of ``repeat`` runs of the command argv()."""
    import resource
    wall, cpu = float("inf"), float("inf")
    for _ in range(repeat):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        subprocess.run(argv(), check=True, capture_output=True)
        wall = min(wall, time.perf_counter() - t0)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = min(cpu, r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
    return wall, cpu


if __name__ == "__main__":
    t0 = time.perf_counter()
    print(run())
    print(f"({time.perf_counter() - t0:.1f} s)")
