"""ISO 230-2 on the public real data sets of anderssandstrom/ecmc_target_muts_logger (`*_ISO230.dat`: motion axes
measured against a reference sensor), mtcal against the standard's definitions evaluated independently
(tests/iso230_2_oracle.py): `python benchmarks/iso230_2_public.py [MIRROR]`.

MIRROR is a git directory of that repository (default: /work/.mirror/anderssandstrom+ecmc_target_muts_logger/repo,
where the search tool's `fetch` puts it); the data are read from it and not shipped (the repository states no
licence; tests/data ships the readings of one axis).  Prints one row per file and the largest difference (um).
"""
from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))
from iso230_2_oracle import evaluate as oracle  # noqa: E402
from iso230_2_oracle import read_dat  # noqa: E402

from mtcal.iso230_2.evaluation import evaluate_runs  # noqa: E402
from mtcal.iso230_2.readings import read_readings  # noqa: E402

MIRROR = "/work/.mirror/anderssandstrom+ecmc_target_muts_logger/repo"
KEYS = ("A", "E", "M", "R", "B", "B_mean")


def _git(mirror: str, *args: str) -> str:
    return subprocess.run(["git", "-C", mirror, *args], check=True, capture_output=True, text=True).stdout


def run(mirror: str = MIRROR) -> dict:
    files = [f for f in _git(mirror, "ls-tree", "-r", "--name-only", "HEAD").splitlines() if f.endswith("_ISO230.dat")]
    rows, worst = [], 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for name in files:
            targets, readings, unit = read_dat(_git(mirror, "show", f"HEAD:{name}"))
            csv = Path(tmp) / "r.csv"
            csv.write_text(f"target_{unit},run,direction,measured_{unit}\n" + "".join(
                f"{targets[i]!r},{j},{d},{v!r}\n" for (i, j, d), v in sorted(readings.items())))
            runs, kind = read_readings(csv)[:2]
            ours = evaluate_runs(runs, "axis", kind).parameters
            ref = {k: v * 1e3 for k, v in oracle(targets, readings).items()}  # mm -> um
            diff = max(abs(ours[k] - ref[k]) for k in ref)
            worst = max(worst, diff)
            rows.append({"file": name, "targets": len(targets), "readings": len(readings),
                         **{k: round(ours[k], 2) for k in KEYS}, "max_diff_um": diff})
    return {"files": rows, "max_diff_um": worst}


def main() -> int:
    res = run(sys.argv[1] if len(sys.argv) > 1 else MIRROR)
    print("| file | targets x readings | A | E | M | R | B | B_mean | mtcal - independent (um) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in res["files"]:
        print(f"| {r['file']} | {r['targets']} x {r['readings']} | " + " | ".join(f"{r[k]:.1f}" for k in KEYS)
              + f" | {r['max_diff_um']:.1e} |")
    print(json.dumps({"max_diff_um": res["max_diff_um"], "files": len(res["files"])}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
