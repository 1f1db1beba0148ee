"""The Monte Carlo of `mtcal uncertainty` (mtcal.uncertainty): speed against workers and coverage of its intervals.

`python benchmarks/uncertainty_mc.py speed [--trials 8] [--fast-trials 20000]`: trials per second of the full path
(identify per trial, `--exact`) and of the batched path (mtcal.uncertainty.fast) on the bundled campaign (all five
axes, the joint fit), on one core (a process of its own with BLAS limited to one thread: `one-core`), and with 1
and 2 local Dask workers, and the projected hours of 10^5 and 10^6 trials on two workers.

`python benchmarks/uncertainty_mc.py coverage [--n 240] [--trials 200] [--refs 6] [--direct 6] [--stations 1|4]`:
how often the 95 % intervals hold the truth, over n simulated campaigns of the demo's true machine (all five
axes; the demo plan from one station, 4 rounds, tracker given; or from four stations, 1 round each), AT960 noise
only (the campaigns carry no scale or centring error, so the Monte Carlo draws noise only).  The truth in
identify's gauge is the noise-free campaign's identification (its functions reproduce the true tables to < 1e-6
mm).  A Monte Carlo of every campaign is out of reach here (240 x 200 trials x 0.25 s), so ``refs`` further
campaigns get one, and their intervals' offsets about their own estimates, averaged, are applied to the n
campaigns' estimates: the estimator's real scatter over campaigns judged against the Monte Carlo's width
(``width_spread_between_refs`` says how much that width varies between campaigns; ``coverage_95_direct`` judges
the ``direct`` reference campaigns by their own intervals).  Reported per kind (errors at their table positions,
table values and fitted functions; constants; the tool tip at 100 poses of the work volume and at 100 moves of
the sample program): coverage of the intervals as reduced (``percentile``, the product's) and, for the analysis,
re-centred on the estimate and reflected (``basic`` bootstrap); the estimator's scatter and bias in units of the
Monte Carlo's standard uncertainty.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import mtcal  # noqa: E402
from mtcal.campaign.stations import simulate_stations  # noqa: E402
from mtcal.data import path  # noqa: E402
from mtcal.data.make_demo_data import DEMO_PLAN  # noqa: E402
from mtcal.uncertainty import Inputs, monte_carlo  # noqa: E402
from mtcal.uncertainty.run import default_poses, program_poses  # noqa: E402
from mtcal.uncertainty.trials import Outputs, trial_block  # noqa: E402

ONE_THREAD = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def _demo():
    """(recording, identify options, base result, inputs, outputs) of the bundled campaign as `mtcal uncertainty`
    runs it."""
    from mtcal.uncertainty import run as mc

    rec = mtcal.read_recording(path("demo_campaign.csv"))
    opt = {"tracker": DEMO_PLAN["tracker"]}
    base = mtcal.identify(rec, worth=False, **opt)
    inputs = mc.drawn_law(Inputs(), base)
    outputs = Outputs.of(base.model, default_poses(base.model.kinematics, base.model), False)
    return rec, opt, base, inputs, outputs


def one_core(trials: int, blocks: int = 10) -> dict:
    """In this process (started by ``speed`` with BLAS limited to one thread, ``ONE_THREAD``): trials per second
    (wall) and per CPU-second of the batched path (``blocks`` blocks of mtcal.uncertainty.fast.BLOCK trials after
    the set-up, the screen and shape test on every SAMPLE-th as in a run) and of the full path (``trials`` trials
    of identify), their ratio, and where a block's time goes (cProfile, the five largest by own time)."""
    import cProfile
    import pstats

    from mtcal.uncertainty import fast as fp
    from mtcal.uncertainty.trials import trackers_of

    rec, opt, base, inputs, outputs = _demo()
    options = {**opt, "method": base.method}
    out = {"blas_threads_env": {k: os.environ.get(k) for k in ONE_THREAD}, "readings": len(rec),
           "load_average_1min_before": os.getloadavg()[0]}
    t, c = time.perf_counter(), time.process_time()
    b, why = fp.prepare(rec, options, outputs)
    out["batched_setup_s"], out["batched_setup_cpu_s"] = time.perf_counter() - t, time.process_time() - c
    trk = trackers_of(rec, opt["tracker"])
    fp.fast_block(b, rec, trk, inputs, options, outputs, 0, list(range(1, 11)))  # the per-worker set-up
    t, c = time.perf_counter(), time.process_time()
    for i in range(blocks):
        b.merge(fp.fast_block(b, rec, trk, inputs, options, outputs, 0,
                              list(range(1 + i * fp.BLOCK, 1 + (i + 1) * fp.BLOCK)))[2])
    dt, dc = time.perf_counter() - t, time.process_time() - c
    n = blocks * fp.BLOCK
    out.update(batched_trials=n, batched_trials_per_s=n / dt, batched_trials_per_cpu_s=n / dc,
               counts=dict(b.counts))
    t, c = time.perf_counter(), time.process_time()
    trial_block(rec, trk, inputs, options, outputs, 0, list(range(trials)))
    out.update(full_trials=trials, full_trials_per_s=trials / (time.perf_counter() - t),
               full_trials_per_cpu_s=trials / (time.process_time() - c))
    out["ratio_cpu"] = out["batched_trials_per_cpu_s"] / out["full_trials_per_cpu_s"]
    prof = cProfile.Profile()
    prof.enable()
    fp.fast_block(b, rec, trk, inputs, options, outputs, 0, list(range(1, 1 + fp.BLOCK)))
    prof.disable()
    st = pstats.Stats(prof)
    top = sorted(st.stats.items(), key=lambda kv: -kv[1][2])[:5]
    out["block_profile_own_s"] = {f"{Path(k[0]).name}:{k[2]}": round(v[2], 4) for k, v in top}
    out["load_average_1min_after"] = os.getloadavg()[0]
    return out


def speed(trials: int, fast_trials: int = 20000) -> dict:
    """Trials per second of the full path (`--exact`: identify per trial) and of the batched path
    (mtcal.uncertainty.fast): on one core in a process of its own with BLAS limited to one thread (``one_core``),
    and end to end with 1 and 2 local Dask workers (set-up included; ``trials_phase``: from the first block's
    arrival to the last, the set-up of the base fit, the linearisation, the check and the cluster excluded), the
    speed-ups, and the projected hours of 10^5 and 10^6 trials on two workers (batched: the 2-worker run's set-up
    plus the trials at its steady rate; full: two cores at the one-core CPU rate)."""
    import subprocess

    env = {**os.environ, **ONE_THREAD}
    p = subprocess.run([sys.executable, __file__, "one-core", "--trials", str(trials)], env=env, check=True,
                       capture_output=True, text=True)
    out = {"trials_full": trials, "trials_batched": fast_trials, "cores": os.cpu_count(),
           "load_average_1min_before": os.getloadavg()[0], "one_core": json.loads(p.stdout)}
    rec, opt, *_ = _demo()
    for w in (1, 2):
        for name, n, exact in (("full", trials, True), ("batched", fast_trials, False)):
            arrivals = []
            t = time.perf_counter()
            r = monte_carlo(rec, trials=n, seed=0, workers=w, exact=exact, progress=lambda k, a=arrivals: a.append(
                (time.perf_counter(), k)), **opt)
            dt = time.perf_counter() - t
            first, last = arrivals[0][0], arrivals[-1][0]
            done = sum(k for _, k in arrivals[1:])
            out[f"{name}_workers_{w}"] = {"seconds": dt, "trials_per_s": n / dt, "setup_s": first - t,
                                          "trials_phase_per_s": done / max(last - first, 1e-9),
                                          "load_average_1min_after": os.getloadavg()[0], "path": r.path}
    for name in ("full", "batched"):
        one, two = out[f"{name}_workers_1"], out[f"{name}_workers_2"]
        out[f"{name}_speedup_2_over_1"] = two["trials_per_s"] / one["trials_per_s"]
        out[f"{name}_speedup_2_over_1_trials_phase"] = two["trials_phase_per_s"] / one["trials_phase_per_s"]
    # projected: batched, the 2-worker run's set-up and its rate once the trials ran; full, two cores at the
    # one-core CPU rate (its few trials make no steady rate of their own)
    b2, full = out["batched_workers_2"], out["one_core"]["full_trials_per_cpu_s"]
    out["projected_hours"] = {f"{p}_{n:.0e}".replace("+0", ""): h for n in (1e5, 1e6) for p, h in
                              (("batched_2_workers", (b2["setup_s"] + n / b2["trials_phase_per_s"]) / 3600),
                               ("full_2_workers", n / (2 * full) / 3600))}
    out["load_average_1min_after"] = os.getloadavg()[0]
    return out


FOUR = {"S1": (250.0, -1500.0, 150.0), "S2": (-1500.0, 250.0, 150.0), "S3": (1500.0, 300.0, 150.0),
        "S4": (-300.0, 1500.0, 150.0)}


def _campaign(truth, stations: int, seed: int, noise: bool = True):
    """(recording, identify options) of one campaign of the demo's true machine: the demo plan from its one
    station (4 rounds, tracker given), or from the four stations FOUR (1 round each, tracker columns)."""
    if stations == 1:
        rec, _ = mtcal.simulate(truth, plan=DEMO_PLAN, rounds=None, seed=seed, noise=noise)
        return rec, {"tracker": DEMO_PLAN["tracker"]}
    al = {} if noise else {"alignment_um": 0.0, "alignment_urad": 0.0}
    rec, _ = simulate_stations(truth, list(FOUR.items()), rounds=1, seed=seed, plan=DEMO_PLAN, noise=noise, **al)
    return rec, {}


def _groups(outputs: Outputs, n_volume: int) -> dict[str, np.ndarray]:
    """Output indices by kind: errors, constants, the tool tip over the work volume and over the program."""
    err = np.concatenate([np.arange(s.start, s.stop) for _, _, s in outputs.functions.values()])
    vol = np.arange(outputs.volumetric.start, outputs.volumetric.stop)
    return {"errors": err, "constants": np.array(sorted(outputs.constants.values()), dtype=int),
            "volume": vol[:3 * n_volume], "program": vol[3 * n_volume:]}


def coverage(n: int, trials: int, stations: int, refs: int, direct: int, workers: int = 2) -> dict:
    """Coverage of the 95 % intervals (module docstring): the truth in identify's gauge is the noise-free
    campaign's identification (its functions reproduce the true tables to < 1e-6 mm); ``refs`` campaigns get a
    Monte Carlo of ``trials`` trials, whose interval offsets about their estimate are applied to the estimates of
    ``n`` further campaigns (the estimator's own scatter over campaigns against the Monte Carlo's width);
    ``direct`` of the ``refs`` are also judged by their own interval."""
    truth = mtcal.load_model(path("demo_truth.json"))
    rec0, opt = _campaign(truth, stations, 0, noise=False)
    gauge = mtcal.identify(rec0, worth=False, **opt).model
    m = gauge.kinematics
    poses = np.vstack([default_poses(m, gauge, 100), program_poses(path("sample_5axis.nc"), m, 100)])
    out = {"campaigns": n, "stations": stations, "trials": trials, "reference_campaigns": refs}
    models = [mtcal.identify(_campaign(truth, stations, 5000 + c)[0], worth=False, **opt).model for c in range(n)]
    for mode in ("tables", "fits"):
        o = Outputs.of(gauge, poses, mode == "tables")
        true = o.vector(gauge)
        lo, hi, mid, u, hits = [], [], [], [], []
        for k in range(refs):
            rec, _ = _campaign(truth, stations, 9000 + k)
            r = monte_carlo(rec, trials=trials, seed=k, workers=workers, inputs=Inputs().only("noise"), poses=poses,
                            tables=mode == "tables", **opt)
            est = o.vector(mtcal.identify(rec, worth=False, **opt).model)
            lo.append(r.stats["lo"] - est)
            hi.append(r.stats["hi"] - est)
            mid.append(r.stats["mean"] - est)
            u.append(r.stats["u"])
            hits.append((r.stats["lo"] <= true + 1e-12) & (true - 1e-12 <= r.stats["hi"]))
        dlo, dhi, dmid, u = np.mean(lo, axis=0), np.mean(hi, axis=0), np.mean(mid, axis=0), np.mean(u, axis=0)
        est = np.array([o.vector(mdl) for mdl in models])
        variants = {"percentile": (dlo, dhi), "centred_on_estimate": (dlo - dmid, dhi - dmid),
                    "basic": (-dhi, -dlo)}
        res = {}
        for g, idx in _groups(o, 100).items():
            if mode == "tables" and g in ("volume", "program"):
                continue  # the tool tip is the fitted functions' in both
            idx = idx[u[idx] > 1e-9]  # outputs the gauge holds (an error at its reference position) have no spread
            if not len(idx):
                continue
            z = (est[:, idx] - true[idx]) / u[idx]
            res[g] = {"outputs": int(len(idx)),
                      **{f"coverage_95_{v}": float(((est[:, idx] + a[idx] <= true[idx] + 1e-12)
                                                    & (true[idx] - 1e-12 <= est[:, idx] + b[idx])).mean())
                         for v, (a, b) in variants.items()},
                      "coverage_95_direct": float(np.mean([h[idx].mean() for h in hits[:direct]])) if direct else None,
                      "scatter_over_mc_u": float(np.sqrt(np.mean(z.std(axis=0, ddof=1) ** 2))),
                      "bias_over_mc_u_rms": float(np.sqrt(np.mean(z.mean(axis=0) ** 2))),
                      "trial_mean_shift_over_u_rms": float(np.sqrt(np.mean((dmid[idx] / u[idx]) ** 2))),
                      "width_spread_between_refs": float(np.median(np.std(np.array(hi) - np.array(lo), axis=0)[idx]
                                                                   / (dhi - dlo)[idx]))}
        out[mode] = res
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("what", choices=("speed", "coverage", "one-core"))
    ap.add_argument("--trials", type=int, default=None)
    ap.add_argument("--fast-trials", type=int, default=20000, help="speed: trials of the batched path")
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--stations", type=int, choices=(1, 4), default=1)
    ap.add_argument("--refs", type=int, default=6)
    ap.add_argument("--direct", type=int, default=6)
    ap.add_argument("--workers", type=int, default=2, help="coverage: the reference campaigns' Monte Carlo workers "
                                                           "(0: in this process)")
    a = ap.parse_args()
    res = (speed(a.trials or 8, a.fast_trials) if a.what == "speed" else one_core(a.trials or 8)
           if a.what == "one-core" else coverage(a.n, a.trials or 200, a.stations, a.refs, min(a.direct, a.refs),
                                                           a.workers))
    print(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
