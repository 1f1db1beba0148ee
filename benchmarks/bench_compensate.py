"""Benchmark (issue 6): compensating a 10^6-line five-axis G-code program vs a plain line copy of the same file.

Figures: compensate_lines_per_s (scope position, first order, default tolerance and precision) and
compensate_vs_line_copy = that rate / the rate of a plain Python line-by-line read + write of the same file,
measured in the same run (target >= 0.05); also the peak resident-memory growth during compensation (MB).
The program is generated in a temporary folder at run time (not committed).
"""
from __future__ import annotations

import resource
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

N_LINES = 1_000_000


def write_program(path: Path, n: int) -> None:
    """A five-axis program: smooth X Y Z B C motion, N on every block, a feed now and then (3 decimals)."""
    with open(path, "w") as f:
        f.write("%\nO6000 (BENCHMARK)\nN1 G90 G21 G17\nN2 G0 X0 Y0 Z50 B0 C0\nN3 G1 F1000\n")
        for s in range(0, n, 50_000):
            t = np.arange(s, min(n, s + 50_000))
            q = np.column_stack([120 * np.sin(t / 5000), 90 * np.cos(t / 7000), 20 + 30 * np.sin(t / 3000),
                                 45 + 40 * np.sin(t / 9000), (t * 0.01) % 720 - 360])
            f.write("".join(f"N{k + 10} X{a:.3f} Y{b:.3f} Z{c:.3f} B{d:.3f} C{e:.3f}" +
                            (" F800\n" if k % 1000 == 0 else "\n")
                            for k, (a, b, c, d, e) in zip(t.tolist(), q.tolist())))
        f.write("M30\n%\n")


def line_copy(src: Path, dst: Path) -> float:
    t = time.perf_counter()
    with open(src, encoding="latin-1", newline="") as fi, open(dst, "w", encoding="latin-1", newline="") as fo:
        for line in fi:
            fo.write(line)
    return time.perf_counter() - t


def run(n_lines: int = N_LINES) -> dict:
    from mtcal import load_machine
    from mtcal.compensate.examples import example_model
    from mtcal.compensate.program import ProgramCompensator
    from mtcal.compensate.solver import Compensator

    m = load_machine("dmu50")
    model = example_model(m)
    with tempfile.TemporaryDirectory() as d:
        src = Path(d) / "bench.nc"
        print(f"bench_compensate: writing a {n_lines}-line program", file=sys.stderr)
        write_program(src, n_lines)
        lines = n_lines + 7
        t_copy = line_copy(src, Path(d) / "copy.nc")
        comp = Compensator(model, m, "position")

        def progress(done, total):
            print(f"bench_compensate: {done / total:6.1%}", file=sys.stderr)

        pc = ProgramCompensator(comp, progress=progress)
        rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        t = time.perf_counter()
        rep = pc.run(src, Path(d) / "out.nc")
        t_comp = time.perf_counter() - t
        rss1 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        t_copy = min(t_copy, line_copy(src, Path(d) / "copy2.nc"))  # best of two for the reference
    return {
        "compensate_lines": lines,
        "compensate_seconds": round(t_comp, 3),
        "compensate_lines_per_s": round(lines / t_comp),
        "line_copy_lines_per_s": round(lines / t_copy),
        "compensate_vs_line_copy": round(t_copy / t_comp, 4),
        "compensate_peak_rss_growth_mb": round((rss1 - rss0) / 1024, 1),
        "compensate_residual_max_um": rep.position.as_dict(1e3)["max"],
        "compensate_uncompensated_max_um": rep.before_position.as_dict(1e3)["max"],
    }


if __name__ == "__main__":
    import json
    print(json.dumps(run(int(sys.argv[1]) if len(sys.argv) > 1 else N_LINES), indent=2))
