"""False alarms of the diagnosis on clean campaigns of a generator we do not control (benchmarks/gen2), by the
tracker's noise shape, with the tracker position given (the CSV's tracker_x,y,z) and at the defaults (those
columns removed): `python benchmarks/diagnose_gen2.py [--n 120] [--seed 3] [--json]`.

A clean gen2 campaign carries the machine's geometry (which the quasi-static base models) and tracker noise of
its instrument (AT960-like, radial : transverse about 1 : 4, about 1 : 70, or isotropic) and nothing else; any
significant finding on it is a false alarm.  Data problems (mtcal.measurement.screen) count as false alarms too.
"""
from __future__ import annotations

import argparse
import csv
import io
import json
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from mtcal.diagnose import diagnose  # noqa: E402
from mtcal.measurement.recordings import parse_recording  # noqa: E402

TRACKER_COLUMNS = ("tracker_x", "tracker_y", "tracker_z")


def _without_tracker(text: str) -> str:
    rows = list(csv.reader(io.StringIO(text)))
    keep = [i for i, h in enumerate(rows[0]) if h not in TRACKER_COLUMNS]
    return "\n".join(",".join(r[i] for i in keep) for r in rows) + "\n"


def false_alarms(n: int = 120, seed: int = 3) -> dict:
    """{instrument: {"campaigns", "given": [alarms], "defaults": [alarms]}} over the clean campaigns."""
    out: dict = {}
    with tempfile.TemporaryDirectory() as d:
        subprocess.run([sys.executable, str(HERE / "gen2" / "gen2.py"), "--out", d, "--n", str(n), "--seed",
                        str(seed)], check=True, capture_output=True)
        for f in sorted(Path(d).glob("campaign_*.csv")):
            truth = json.loads(f.with_suffix(".truth.json").read_text())
            if not truth.get("clean"):
                continue
            inst = truth["tracker"]["noise"]["instrument"]
            row = out.setdefault(inst, {"campaigns": 0, "given": [], "defaults": []})
            row["campaigns"] += 1
            text = f.read_text()
            header = text.splitlines()[0].split(",")
            cases = [] if "station" in header else [("defaults", _without_tracker(text))]  # stations need them
            if "tracker_x" in header:
                cases.append(("given", text))
            for how, t in cases:
                d_ = diagnose(parse_recording(t, f.name))
                sig = [f"{e.name} {e.axis or ''}".strip() for e in d_.effects if e.significant]
                problems = getattr(d_, "data_problems", [])
                row[how + "_runs"] = row.get(how + "_runs", 0) + 1
                if sig or problems:
                    row[how].append(f"{f.name}: {', '.join(sig) or problems[0]['text']}")
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--n", type=int, default=120)
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    r = false_alarms(args.n, args.seed)
    if args.json:
        print(json.dumps(r))
        return 0
    for inst, row in sorted(r.items()):
        print(f"{inst:>12}: {row['campaigns']} clean campaigns; false alarms at the defaults "
              f"{len(row['defaults'])} of {row.get('defaults_runs', 0)}, with the tracker given "
              f"{len(row['given'])} of {row.get('given_runs', 0)}")
        for line in row["defaults"] + row["given"]:
            print("    " + line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
