"""Real laser-tracker readings through mtcal's gross-error screen and noise-law estimate: the base reflectors of the
public repository icelinker/Robot-Calibration-LaserTracker (docs/guide/real-data-tracker.md).

    python benchmarks/real_icelinker.py FOLDER [--window 51] [--k 5] [--diagnose]

FOLDER holds ``measured_base_1.txt``, ``measured_base_2.txt``, ``measured_base_3.txt`` (mm, no header, one line
per robot pose).  Optional, from the same folder: ``measured_SMR_*.txt`` (the robot's reflectors: what a stray
reading locked onto) and ``measured_joints.txt`` (the robot's joint angles, deg: how much of the motion shared by
the three reflectors they explain).  The data carry no licence and are not shipped.  To get them, fetch the
repository (the search tool's ``fetch`` gives a bare git directory G: ``git --git-dir=G show
HEAD:4-DataProcess/Input/measured_base_1.txt > measured_base_1.txt``, and so on; or ``git clone
https://github.com/icelinker/Robot-Calibration-LaserTracker``) and pass its ``4-DataProcess/Input`` folder.

The layout as an mtcal Recording: one axis (X) held at position 0; pose i (file line i) is round i; points
base_1..3; time_s = the reading index 3 (i - 1) + k - 1 (the files hold no time).  Assumed: the readings are in the
tracker's frame, the FARO tracker at the origin (the files come straight from the tracker's API, and the mutual
distance that lies along the beams scatters 3x less than the two across them).  Prints JSON: the screen's flags,
an independent robust check, the drift, the motion shared by the three from pose to pose, the noise law (mtcal's
estimate, an independent one from the mutual distances, the AT960's); with ``--diagnose``, mtcal's diagnosis without
the tracker's position and with it at the origin (diagnosis_both).
"""
from __future__ import annotations

import argparse
import itertools
import json
import sys
from pathlib import Path

import numpy as np
from scipy.optimize import nnls

from mtcal.measurement.recordings import Recording, make_recording
from mtcal.measurement.screen import screen
from mtcal.measurement.tracker import AT960
from mtcal.measurement.tracker_position import estimate_position, estimate_shape, round_scatter, station_scatter

NAMES = ("base_1", "base_2", "base_3")
PAIRS = tuple(itertools.combinations(range(3), 2))
MAD = 1.4826  # robust sigma = MAD x this (normal noise)


def load(folder: Path) -> np.ndarray:
    """(n poses, 3 reflectors, 3) readings in mm from measured_base_{1,2,3}.txt."""
    files = [folder / f"measured_{n}.txt" for n in NAMES]
    missing = [str(f) for f in files if not f.is_file()]
    if missing:
        sys.exit(f"missing {missing}: fetch icelinker/Robot-Calibration-LaserTracker (see this script's docstring)")
    return np.stack([np.loadtxt(f, ndmin=2) for f in files], axis=1)


def load_smr(folder: Path, n: int) -> dict[str, np.ndarray]:
    """The robot's reflectors (mm, (n, 3) each) where their files are present, else {}."""
    out = {}
    for f in sorted(folder.glob("measured_SMR_*.txt")):
        a = np.loadtxt(f, ndmin=2)
        if a.shape == (n, 3):
            out[f.stem.removeprefix("measured_")] = a
    return out


def to_recording(xyz: np.ndarray) -> Recording:
    """One axis held at 0, pose i = round i, the reading index as time_s (see module docstring)."""
    n = len(xyz)
    pose = np.repeat(np.arange(1, n + 1), 3)
    rec = make_recording(np.full(3 * n, "X"), pose, np.zeros(3 * n), np.tile(NAMES, n), xyz.reshape(-1, 3),
                         time_s=np.arange(3 * n, dtype=float), source="measured_base_*.txt")
    rec.line = pose  # the screen's messages name the files' line (= the pose)
    return rec


def running_median(v: np.ndarray, window: int) -> np.ndarray:
    """Running median of v (n, ...) along axis 0 over ``window`` samples centred (fewer at the ends)."""
    h = window // 2
    pad = np.concatenate([np.full((h, *v.shape[1:]), np.nan), v, np.full((h, *v.shape[1:]), np.nan)])
    return np.nanmedian(np.lib.stride_tricks.sliding_window_view(pad, 2 * h + 1, axis=0), axis=-1)


def robust_sigma(e: np.ndarray) -> np.ndarray:
    """MAD-based standard deviation along axis 0 (same units as e)."""
    return MAD * np.median(np.abs(e - np.median(e, axis=0)), axis=0)


def what_it_read(p: np.ndarray, pose: int, median: np.ndarray, smr: dict[str, np.ndarray]) -> str:
    """Words for a stray reading p (mm) of pose ``pose`` (0-based): no target, or which robot reflector."""
    if np.allclose(p, 0.0):
        return "no target: the tracker returned (0, 0, 0)"
    text = f"another target, {np.linalg.norm(p - median):.1f} mm from the reflector"
    near = {k: float(np.linalg.norm(p - a[pose])) for k, a in smr.items()}
    if near and min(near.values()) < 0.1:
        k = min(near, key=near.get)
        text += f": the robot's {k} of the same pose ({near[k] * 1e3:.0f} um away)"
    return text


def screen_report(rec: Recording, xyz: np.ndarray, smr: dict[str, np.ndarray]) -> tuple[dict, np.ndarray]:
    """mtcal's gross-error screen: every flagged reading (file line = pose) and why; (report, kept (n, 3))."""
    s = screen(rec)
    med = np.median(xyz, axis=0)
    rows = []
    for p in s.problems:
        for pt in p.points:
            k, i = NAMES.index(pt), p.round - 1
            rows.append({"file": f"measured_{pt}.txt", "line": p.round, "reading_mm": xyz[i, k].round(4).tolist(),
                         "kind": p.kind, "size_mm": round(p.size_mm, 3),
                         "looks_like": what_it_read(xyz[i, k], i, med[k], smr), "screen_says": p.text})
    kinds = {}
    for r in rows:
        key = r["looks_like"].split(":")[0].split(",")[0]
        kinds[key] = kinds.get(key, 0) + 1
    keep = s.keep.reshape(-1, 3)
    return {"flagged_readings": len(rows), "by_class": kinds, "poses_left_out": int((~keep.all(axis=1)).sum()),
            "rows_left_out": int((~s.keep).sum()), "notes": s.notes, "flagged": rows}, keep


def independent_check(xyz: np.ndarray, good: np.ndarray, window: int, k: float) -> list[dict]:
    """Kept readings a robust check finds suspicious: a coordinate > k robust sigmas from the reflector's running
    median, or a mutual distance > k robust sigmas from its running median (immune to motions shared by all
    three).  Sizes in um."""
    idx = np.flatnonzero(good)
    x = xyz[idx]
    res = x - running_median(x, window)
    z_pt = np.abs(res) / robust_sigma(res)
    d = np.stack([np.linalg.norm(x[:, a] - x[:, b], axis=1) for a, b in PAIRS], axis=1)
    e = d - running_median(d, window)
    z_d = np.abs(e) / robust_sigma(e)
    out = []
    for j in np.flatnonzero((z_pt.max(axis=2) > k).any(axis=1) | (z_d > k).any(axis=1)):
        out.append({"line": int(idx[j]) + 1,
                    "from_running_median_um": {n: (res[j, m] * 1e3).round(1).tolist() for m, n in enumerate(NAMES)
                                               if z_pt[j, m].max() > k},
                    "robust_sigmas": round(float(max(z_pt[j].max(), z_d[j].max())), 1),
                    "mutual_distances_off_um": {f"{NAMES[a]}-{NAMES[b]}": round(float(e[j, m]) * 1e3, 1)
                                                for m, (a, b) in enumerate(PAIRS) if z_d[j, m] > k}})
    return out


def drift(xyz: np.ndarray, good: np.ndarray, window: int) -> dict:
    """The slow drift (um): each reflector's running median (``window`` poses) against its value at the start, the
    shared part (mean of the three), the range from the tracker, and the mutual distances (the part no rigid
    motion explains)."""
    x = xyz[good]
    rm = running_median(x, window)
    dev = (rm - rm[0]) * 1e3
    d = running_median(np.stack([np.linalg.norm(x[:, a] - x[:, b], axis=1) for a, b in PAIRS], axis=1), window)
    dist = running_median(np.linalg.norm(x, axis=2), window)  # range from the tracker (origin)
    shared = dev.mean(axis=1)
    return {"window_poses": window,
            "per_reflector_largest_um": {n: round(float(np.linalg.norm(dev[:, m], axis=1).max()), 1)
                                         for m, n in enumerate(NAMES)},
            "per_reflector_first_to_last_um": {n: dev[-1, m].round(1).tolist() for m, n in enumerate(NAMES)},
            "shared_first_to_last_um": shared[-1].round(1).tolist(),
            "shared_largest_um": round(float(np.linalg.norm(shared, axis=1).max()), 1),
            "range_first_to_last_um": {n: round(float(dist[-1, m] - dist[0, m]) * 1e3, 1) for m, n in enumerate(NAMES)},
            "mutual_distance_first_to_last_um": {f"{NAMES[a]}-{NAMES[b]}": round(float(d[-1, m] - d[0, m]) * 1e3, 1)
                                                 for m, (a, b) in enumerate(PAIRS)},
            "mutual_distance_range_um": {f"{NAMES[a]}-{NAMES[b]}": round(float(np.ptp(d[:, m])) * 1e3, 1)
                                         for m, (a, b) in enumerate(PAIRS)}}


def shared_motion(xyz: np.ndarray, good: np.ndarray, window: int, joints: np.ndarray | None) -> dict:
    """Pose-to-pose scatter about the running median (um), its correlation between the reflectors, and the share
    of the shared part (mean of the three) the robot's joint angles explain (``joints`` (n, 6) deg, or None)."""
    x = xyz[good]
    res = (x - running_median(x, window)) * 1e3
    corr = [[round(float(np.corrcoef(res[:, a, c], res[:, b, c])[0, 1]), 2) for a, b in PAIRS] for c in range(3)]
    centre = res.mean(axis=1)
    out = {"scatter_sd_um_xyz": {n: res[:, m].std(axis=0).round(2).tolist() for m, n in enumerate(NAMES)},
           "correlation_between_reflectors_xyz": dict(zip("xyz", corr)),
           "shared_sd_um_xyz": centre.std(axis=0).round(2).tolist(),
           "lag1_autocorrelation_xyz": [round(float(np.corrcoef(c[1:], c[:-1])[0, 1]), 2) for c in centre.T]}
    if joints is not None:
        q = np.radians(joints[good])
        F = np.column_stack([np.ones(len(q)), np.sin(q), np.cos(q)])
        fit = F @ np.linalg.lstsq(F, centre, rcond=None)[0]
        out["r2_on_robot_joints_xyz"] = (1 - (centre - fit).var(axis=0) / centre.var(axis=0)).round(2).tolist()
    return out


def load_joints(folder: Path, n: int) -> np.ndarray | None:
    """measured_joints.txt ((n, 6) deg) where present, else None."""
    f = folder / "measured_joints.txt"
    a = np.loadtxt(f, ndmin=2) if f.is_file() else None
    return a if a is not None and a.shape == (n, 6) else None


def beams(ref: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Unit beam directions (3, 3) from the tracker t (mm) to the reflectors ref (3, 3) mm."""
    u = ref - t
    return u / np.linalg.norm(u, axis=1)[:, None]


def pair_law(xyz: np.ndarray, good: np.ndarray, window: int, t: np.ndarray) -> dict:
    """Noise law from the mutual distances (invariant to any rigid motion: drift, shared motion): var(d_ab) =
    s_r^2 (ca^2 + cb^2) + s_t^2 (2 - ca^2 - cb^2), c the cosine between the pair and each beam; one-sigma s_r, s_t
    (um) at the reflectors' distance by non-negative least squares over the three pairs (robust variances); each
    pair alone bounds each sigma from above."""
    x = xyz[good]
    ref = np.median(x, axis=0)
    u = beams(ref, t)
    rows, var, per = [], [], {}
    for a, b in PAIRS:
        d = np.linalg.norm(x[:, a] - x[:, b], axis=1)
        s = float(robust_sigma(d - running_median(d, window))) * 1e3
        w = (ref[a] - ref[b]) / np.linalg.norm(ref[a] - ref[b])
        ca, cb = float(w @ u[a]), float(w @ u[b])
        rows.append([ca**2 + cb**2, 2 - ca**2 - cb**2])
        var.append(s**2)
        per[f"{NAMES[a]}-{NAMES[b]}"] = {"sd_um": round(s, 2), "cos_to_beams": [round(ca, 2), round(cb, 2)]}
    G, v = np.array(rows), np.array(var)
    sol = nnls(G, v)[0]  # variances >= 0
    s_r, s_t = np.sqrt(sol)
    dist_m = float(np.linalg.norm(ref - t, axis=1).mean()) / 1e3
    return {"pairs": per, "at_distance_m": round(dist_m, 3),
            "radial_sigma_um": round(float(s_r), 2), "transverse_sigma_um": round(float(s_t), 2),
            "pairs_sd_fitted_um": np.sqrt(G @ sol).round(2).tolist(),
            "upper_bounds_um": {"radial": round(float(np.sqrt(v / G[:, 0]).min()), 2),
                                "transverse": round(float(np.sqrt(v / G[:, 1]).min()), 2)},
            "law_1sigma_at960_a_to_b": _as_law(float(s_r), float(s_t), dist_m)}


def _as_law(s_r: float, s_t: float, dist_m: float) -> dict:
    """One-sigma s_r, s_t (um) at dist_m (m) as a + b L with the AT960's a : b in each direction (um, um/m): one
    layout's distances (2.6-3.1 m here) cannot separate a from b."""
    r0, t0 = (float(v) * 1e3 for v in AT960.sigmas(dist_m * 1e3))
    cr, ct = s_r / r0, s_t / t0
    k = AT960.k
    return {"radial_um": round(AT960.radial_um / k * cr, 3),
            "radial_um_per_m": round(AT960.radial_um_per_m / k * cr, 3),
            "transverse_um": round(AT960.transverse_um / k * ct, 3),
            "transverse_um_per_m": round(AT960.transverse_um_per_m / k * ct, 3)}


def at960_law(distance_m: float) -> dict:
    """The AT960's MPE law and its one sigma (MPE/2) at ``distance_m`` (um)."""
    s_r, s_t = AT960.sigmas(distance_m * 1e3)
    return {"mpe": {"radial_um": AT960.radial_um, "radial_um_per_m": AT960.radial_um_per_m,
                    "transverse_um": AT960.transverse_um, "transverse_um_per_m": AT960.transverse_um_per_m},
            "sigma_at_distance_um": {"radial": round(float(s_r) * 1e3, 2), "transverse": round(float(s_t) * 1e3, 2)}}


def mtcal_law(rec: Recording, t: np.ndarray, distance_m: float) -> dict:
    """mtcal's shape estimate about t (mm) and its station estimate from the round scatter less each round's mean
    (station_scatter, as identify and the diagnosis place it) (um, mm)."""
    sh = estimate_shape(rec, t)
    law = sh.law()
    at = {"radial": law["radial_um"] + law["radial_um_per_m"] * distance_m,
          "transverse": law["transverse_um"] + law["transverse_um_per_m"] * distance_m}
    r, s = round_scatter(rec), station_scatter(rec)  # the station is placed from s, as identify does
    pos = estimate_position(rec.xyz, s, [rec.point == n for n in NAMES])
    return {"estimate_shape": sh.to_dict(), "law_text": sh.law_text(),
            "sigma_at_distance_um": {k: round(v, 2) for k, v in at.items()},
            "round_scatter_sd_um": (r.std(axis=0) * 1e3).round(2).tolist(),
            "station_scatter_sd_um": (s.std(axis=0) * 1e3).round(2).tolist(),
            "estimate_position": {"position_mm": pos.position.round(0).tolist(), "accepted": pos.accepted,
                                  "p_isotropic": round(pos.p_isotropic, 4), "scale_vs_at960": round(pos.scale, 2),
                                  "shape_vs_at960": round(pos.shape, 2)}}


def findings(d) -> list[str]:
    """The significant findings of a diagnosis ``d`` in words: the effect, its variant, where."""
    return [" ".join(str(v) for v in (f.name, f.get("variant"), f.get("where")) if v) for f in d.effects
            if f.significant]


def same_as(f) -> str:
    """What makes two runs' findings the same finding: the effect, its variant, its side and reflector, and the
    round (pose) it starts in -- not its estimate, its time constant or t0 within the pose."""
    d = f.to_dict()
    return " ".join(f"{k}={d[k]}" for k in ("name", "variant", "side", "point", "round") if d.get(k) is not None)


def predicted_pair_sd(W: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """The sd (um) of the three mutual distances that the whitening ``W`` ((3 n, 3, 3), 1/mm, the kept poses'
    readings in file order) predicts: var(d_ab) = u^T (C_a + C_b) u, C = (W^T W)^-1, u the pair's direction
    (``ref`` (3, 3) mm), averaged over the poses.  Station-free: it holds the weights to what is rigid whatever
    station they were built about."""
    C = np.linalg.inv(np.einsum("nji,njk->nik", W, W)).reshape(-1, 3, 3, 3)
    out = []
    for a, b in PAIRS:
        u = (ref[b] - ref[a]) / np.linalg.norm(ref[b] - ref[a])
        out.append(np.sqrt(np.mean(u @ (C[:, a] + C[:, b]) @ u)) * 1e3)
    return np.array(out)


def diagnosis_both(xyz: np.ndarray, good: np.ndarray, measured_sd: np.ndarray) -> dict:
    """mtcal's diagnosis of the recording without the tracker's position and with it at the files' origin: the
    findings of each (and the mismatches each located without a name), those of one only, the station's status,
    and the mutual distances' sd (um) that each run's weights predict against ``measured_sd`` (the pairs' robust
    sd: the law within 2x of what is rigid)."""
    from mtcal.diagnose import diagnose

    rec, ref = to_recording(xyz), np.median(xyz[good], axis=0)
    out = {}
    for label, t in (("without_tracker", None), ("tracker_at_origin", np.zeros(3))):
        d = diagnose(rec, tracker=t)
        sd = predicted_pair_sd(d.noise.W, ref) if len(d.noise.W) == 3 * good.sum() else None
        station = d.noise.details.get("station_interval")
        out[label] = {"findings": findings(d), "same_as": [same_as(f) for f in d.effects if f.significant],
                      "located": [f"{u.by}: {u.where}"[:160] for u in d.unexplained],
                      "noise_model": d.noise.kind,
                      "station": None if station is None else {k: station[k] for k in ("distance_mm",
                                                                                         "interval_95_mm",
                                                                                         "determined")},
                      "pairs_sd_predicted_um": None if sd is None else sd.round(2).tolist(),
                      "predicted_over_measured": None if sd is None else (sd / measured_sd).round(2).tolist()}
    a, b = (set(out[k]["same_as"]) for k in out)
    out["in_both"] = sorted(a & b)
    out["only_without_tracker"], out["only_with_tracker"] = sorted(a - b), sorted(b - a)
    return out


def run(folder: Path, window: int = 51, k: float = 5.0, with_diagnosis: bool = False) -> dict:
    """Everything the script prints (see module docstring); ``with_diagnosis``: also diagnosis_both."""
    xyz = load(folder)
    rec = to_recording(xyz)
    scr, keep = screen_report(rec, xyz, load_smr(folder, len(xyz)))
    good = keep.all(axis=1)
    t = np.zeros(3)  # assumed: the tracker's frame
    law = pair_law(xyz, good, window, t)
    out = {"poses": len(xyz), "readings": int(xyz.size // 3), "tracker_assumed_at_mm": t.tolist(),
            "screen": scr, "independent_check": {"k_sigmas": k, "window_poses": window,
                                                 "kept_but_suspicious": independent_check(xyz, good, window, k)},
            "drift": drift(xyz, good, window),
            "shared_motion": shared_motion(xyz, good, window, load_joints(folder, len(xyz))),
            "noise_law": {"mtcal": mtcal_law(rec.select(keep.ravel()), t, law["at_distance_m"]),
                          "mutual_distances": law, "at960": at960_law(law["at_distance_m"])}}
    if with_diagnosis:
        out["diagnosis"] = diagnosis_both(xyz, good, np.array([v["sd_um"] for v in law["pairs"].values()]))
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folder", type=Path, help="folder with measured_base_{1,2,3}.txt (4-DataProcess/Input)")
    ap.add_argument("--window", type=int, default=51, help="running-median window, poses (default 51)")
    ap.add_argument("--k", type=float, default=5.0, help="robust sigmas of the independent check (default 5)")
    ap.add_argument("--diagnose", action="store_true",
                    help="also diagnose the recording without and with the tracker's position (about 30 s)")
    a = ap.parse_args(argv)
    print(json.dumps(run(a.folder, a.window, a.k, a.diagnose), indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
