"""The diagnosis' calibrated level (``mtcal diagnose --calibrate N``, mtcal.diagnose.calibrate) on clean development
campaigns: gen3 (seed 3, campaigns 0 and 1, --only none), gen2 (seed 0, campaign 12, --only none: two stations)
and mtcal's own simulator (the default campaign, seed 11), each diagnosed at the defaults as the command line
does (the recording's tracker columns where it has them) and calibrated by N null campaigns.

Run: python benchmarks/calibrate_level.py [N] (default 20); one line per campaign, then a JSON summary (claims in
K of N, the one-sided 95 % Clopper-Pearson bound, CPU seconds of the calibration and of one diagnosis).
"""
from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def campaigns(tmp: Path) -> dict[str, Path]:
    """The clean development campaigns, written to ``tmp`` by their own generators."""
    for gen, seed, start, n in (("gen3", 3, 0, 2), ("gen2", 0, 12, 1)):
        subprocess.run([sys.executable, str(HERE / gen / f"{gen}.py"), "--out", str(tmp / gen), "--n", str(n),
                        "--seed", str(seed), "--start", str(start), "--only", "none"], check=True,
                       capture_output=True)
    import mtcal
    from mtcal.campaign.simulate import write_campaign

    rec, truth = mtcal.simulate(seed=11)
    write_campaign(rec, truth, tmp / "mtcal_seed11.csv")
    return {"gen3 seed 3 #0": tmp / "gen3" / "campaign_0000.csv", "gen3 seed 3 #1": tmp / "gen3" / "campaign_0001.csv",
            "gen2 seed 0 #12": tmp / "gen2" / "campaign_0012.csv", "mtcal seed 11": tmp / "mtcal_seed11.csv"}


def main(n: int = 20) -> dict:
    import mtcal
    from mtcal.diagnose import diagnose
    from mtcal.diagnose.calibrate import calibrate

    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        for label, path in campaigns(Path(tmp)).items():
            rec = mtcal.read_recording(path)
            c0 = time.process_time()
            d = diagnose(rec)
            one = time.process_time() - c0
            cal = calibrate(d, n, seed=0)
            out[label] = {"readings": len(rec), "diagnosis_cpu_s": one, **cal.to_dict()}
            print(f"{label:<16} {len(rec):5d} readings, one diagnosis {one:.1f} CPU-s: {cal.says()}", flush=True)
    return {k: {f: v[f] for f in ("readings", "campaigns", "campaigns_with_claims", "upper_95", "claims", "cpu_s",
                                  "diagnosis_cpu_s", "noise_scale")} for k, v in out.items()}


if __name__ == "__main__":
    print(json.dumps(main(int(sys.argv[1]) if len(sys.argv) > 1 else 20), indent=1))
