"""Every benchmark in one run: `python benchmarks/run.py [--json] [--save]`.

Figures are measured in this run on this machine (ratios against baselines timed in the same run); the last
line is one JSON object.  Each benchmarks/bench_*.py exposes run() -> dict of named figures.
"""
from __future__ import annotations

import argparse
import importlib
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def derive_seconds() -> float:
    """Wall time of `python -m derive --check` (a full derivation of every target, nothing written)."""
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "derive", "--check"], cwd=ROOT, check=True, capture_output=True)
    return time.perf_counter() - t0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--json", action="store_true", help="print only the JSON line on stdout")
    ap.add_argument("--only", nargs="*", help="bench module names (e.g. bench_kinematics)")
    ap.add_argument("--save", action="store_true",
                    help="also write benchmarks/results.json, which docs/reference/benchmarks.md quotes")
    args = ap.parse_args()
    sys.path.insert(0, str(HERE))
    results: dict = {"machine": f"{platform.machine()} {os.cpu_count()} cores, Python {platform.python_version()}"}
    names = sorted(p.stem for p in HERE.glob("bench_*.py"))
    if args.only:
        names = [n for n in names if n in args.only]
    for name in names:
        print(f"[bench] {name} ...", file=sys.stderr, flush=True)
        t0 = time.perf_counter()
        res = importlib.import_module(name).run()
        results.update(res)
        print(f"[bench] {name}: {time.perf_counter() - t0:.1f} s  " +
              "  ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in res.items()),
              file=sys.stderr, flush=True)
    if not args.only:
        print("[bench] derive ...", file=sys.stderr, flush=True)
        results["derive_seconds"] = derive_seconds()
    print(json.dumps(results, sort_keys=True))
    if args.save:  # --only updates its figures and keeps the others'
        results["date"] = time.strftime("%Y-%m-%d")
        path = HERE / "results.json"
        old = json.loads(path.read_text()) if args.only and path.exists() else {}
        path.write_text(json.dumps({**old, **results}, sort_keys=True, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
