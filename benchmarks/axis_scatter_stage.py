"""The axis-scatter test alone (mtcal.diagnose.scatter, run by prepare) over gen2 campaigns: its level on clean
ones and beside other classes, its power and size on planted ones -- seconds per campaign where a whole diagnosis
takes ~50 s.  One line per run (JSON) and a tally.

    python benchmarks/axis_scatter_stage.py --seed 9000 --n 40 --only none
    python benchmarks/axis_scatter_stage.py --seed 9001 --n 40 --only axis_scatter
    python benchmarks/axis_scatter_stage.py --seed 9003 --n 40 --mix v3

Runs: the defaults (one station, no tracker columns) and the tracker given, as benchmarks/diagnose_gen2_rates.py.
A planted axis_scatter is *found* when its axis is named, *sized* when its sigma is inside the 95 % interval; any
axis named where none was planted is a *false alarm*.  Seeds 3503-3599 are held out: do not run them here."""
from __future__ import annotations

import argparse
import json
import logging
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from diagnose_gen2_rates import GEN2, cases  # noqa: E402

from mtcal.diagnose.prepare import prepare  # noqa: E402
from mtcal.errors import InputError  # noqa: E402
from mtcal.measurement.recordings import parse_recording  # noqa: E402


def trackers(rec):
    """The given tracker position(s) of a recording with tracker columns, as prepare takes them."""
    st = rec.stations()
    if rec.station is None:
        return rec.tracker_xyz[0]
    return {s: rec.tracker_xyz[np.flatnonzero(st == s)[0]] for s in dict.fromkeys(st.tolist())}


def run_one(path: Path) -> list[dict]:
    truth = json.loads(path.with_suffix(".truth.json").read_text())
    planted = [e for e in truth["effects"] if e["name"] == "axis_scatter"]
    out = []
    for how, text in cases(path.read_text()):
        r = {"campaign": path.stem, "how": how, "classes": [e["name"] for e in truth["effects"]] or ["clean"],
             "instrument": truth["tracker"]["noise"]["instrument"], "stations": len(truth["tracker"]["stations"])}
        try:
            rec = parse_recording(text, path.name)
            t0 = time.perf_counter()
            sc = prepare(rec, "dmu50", tracker=trackers(rec) if how == "given" else None).noise.details
            r["seconds"] = round(time.perf_counter() - t0, 1)
        except InputError as exc:
            out.append({**r, "refused": str(exc)[:100]})
            continue
        sc = sc.get("axis_scatter") or {}
        f = sc.get("found") or {}
        r.update(found=f.get("axis"), sd_um=round(f.get("extra_sd_mm", 0.0) * 1e3, 2),
                 interval_um=[round(v * 1e3, 2) for v in f.get("interval_95_mm", [])],
                 p={t["axis"]: round(t["p_adjusted"], 4) for t in sc.get("tested", [])})
        if planted:
            e = planted[0]
            sigma = e["details"]["sigma_um"]
            r.update(planted_axis=e["where"]["axis"], sigma_um=round(sigma, 2),
                     status="found" if f.get("axis") == e["where"]["axis"] else ("wrong" if f else "missed"),
                     sized=bool(f) and r["interval_um"][0] <= sigma <= r["interval_um"][1])
        else:
            r["status"] = "false alarm" if f else "quiet"
        out.append(r)
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--start", type=int, default=0)
    ap.add_argument("--mix", default="v3")
    ap.add_argument("--only", default=None)
    a = ap.parse_args()
    if 3503 <= a.seed <= 3599:
        print("seeds 3503-3599 are held out", file=sys.stderr)
        return 2
    logging.getLogger("mtcal").setLevel(logging.ERROR)
    import subprocess
    runs = []
    with tempfile.TemporaryDirectory() as d:
        subprocess.run([sys.executable, str(GEN2), "--out", d, "--n", str(a.n), "--seed", str(a.seed), "--start",
                        str(a.start), "--mix", a.mix] + (["--only", a.only] if a.only else []),
                       check=True, capture_output=True)
        for p in sorted(Path(d).glob("campaign_*.csv")):
            for r in run_one(p):
                runs.append(r)
                print(json.dumps(r), flush=True)
    tally: dict = {}
    for r in runs:
        if "status" in r:
            key = (r["how"], "planted" if "planted_axis" in r else "not planted")
            tally.setdefault(key, {}).setdefault(r["status"], 0)
            tally[key][r["status"]] += 1
    sized = [r["sized"] for r in runs if r.get("status") == "found"]
    for k, v in sorted(tally.items()):
        print(f"# {k[0]:<8} {k[1]:<12} {v}")
    if sized:
        print(f"# sigma inside the 95 % interval: {sum(sized)} of {len(sized)} found")
    return 0


if __name__ == "__main__":
    sys.exit(main())
