"""The real spindle drift of FL_THERMAL against the diagnosis' two thermal models, out of sample
(benchmarks/real_thermal.py, quoted by docs/guide/real-data-thermal.md): per channel and model the RMS of the
residual in µm on the first 40 % (``_in_um``) and on the rest (``_out_um``), the out-of-sample ratio to the
time-only drift (``_vs_time``), the chosen τ (s) and sensor (tN); ``all`` pools the five channels.  A few CPU
seconds.  Run alone: ``python benchmarks/bench_real_thermal.py``."""
from __future__ import annotations

import json
import sys
from pathlib import Path

MODELS = ("time", "temp", "t5", "lag", "const")


def run() -> dict:
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import real_thermal as rt

    rows = rt.run()
    out: dict = {}
    for r in rows:
        key = f"real_thermal_{r['channel']}"
        for m in MODELS:
            out[f"{key}_{m}_in_um"], out[f"{key}_{m}_out_um"] = r[m].rms_in_um, r[m].rms_out_um
            if m != "time":
                out[f"{key}_{m}_vs_time"] = r[m].rms_out_um / r["time"].rms_out_um
        out.update({f"{key}_time_tau_s": r["tau_s"], f"{key}_temp_sensor": r["sensor"] + 1,
                    f"{key}_lag_sensor": r["lag_sensor"] + 1, f"{key}_lag_tau_s": r["lag_tau_s"]})
    for m in MODELS:
        for part in ("in", "out"):
            out[f"real_thermal_all_{m}_{part}_um"] = rt.pooled(rows, m, f"rms_{part}_um")
    out["real_thermal_all_temp_vs_time"] = out["real_thermal_all_temp_out_um"] / out["real_thermal_all_time_out_um"]
    return out


if __name__ == "__main__":
    print(json.dumps(run(), indent=1, sort_keys=True))
