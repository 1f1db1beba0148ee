#!/usr/bin/env python3
"""gen3 -- a third independent laser-tracker campaign generator for the DMU 50 eVolution (issue 52).

Written from docs/design.md, docs/guide/your-data.md, derive/machines/dmu50.toml and benchmarks/gen2/ only, by a
helper that has not read mtcal/diagnose/. It needs numpy and does not import mtcal. The campaign plan, the baseline
geometry, the tracker noise and every gen2 class come from gen2 itself (imported, called through its own functions);
gen3 adds thirteen classes of instrument, reflector, environment, structure and export physics (README.md).

Usage: python gen3.py --out DIR --n N --seed S [--start K] [--mix all|new|gen2] [--only NAME,...|none]
                      [--clean-fraction F]
Units inside: mm, rad, s (as gen2 and design.md). Truth displacements in um.
"""
import argparse
import contextlib
import importlib.util
import json
import math
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def _load_gen2():
    spec = importlib.util.spec_from_file_location("gen2", os.path.join(HERE, "..", "gen2", "gen2.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


gen2 = _load_gen2()
LINEAR, ROTARY = gen2.LINEAR, gen2.ROTARY
AXIS_DIR = {"X": np.array([1.0, 0, 0]), "Y": np.array([0, 1.0, 0]), "Z": np.array([0, 0, 1.0])}
DN_DT = -0.93e-6          # 1/K: refractive index of air against temperature (20 C, 1013 hPa, visible/NIR)
R_RIM = 220.0             # mm: the largest table-nest radius gen2 draws (its nests lie 60-220 mm from C)

# The new classes: category, whether the truth is a data problem, and what the campaign needs to carry it.
NEW = {
    "encoder_cyclic": ("instrument", False, "any"),
    "adm_cyclic": ("instrument", False, "any"),
    "smr_incidence": ("reflector", False, "linear"),
    "damaged_reflector": ("reflector", False, "any"),
    "floor_vibration": ("environment", False, "any"),
    "air_gradient": ("environment", False, "any"),
    "column_tilt": ("structure", False, "linear"),
    "table_sag": ("structure", False, "B"),
    "axis_settling": ("structure", False, "linear"),
    "coarse_rounding": ("export", True, "any"),
    "direction_inverted": ("export", True, "any"),
    "time_in_ms": ("export", True, "any"),
    "pass_time_restart": ("export", True, "any"),
}
NEW_NAMES = list(NEW)
GEN2_ALL = gen2.PHYSICS + gen2.GROSS + gen2.NEW
GEN2_DATA = set(gen2.GROSS + gen2.CARELESS)
RANDOM_CLASSES = {"damaged_reflector", "floor_vibration", "axis_scatter"}   # a variance, not a shape
EXPORT_TEXT = ("direction_inverted", "pass_time_restart", "time_in_ms", "coarse_rounding")   # in the order applied

# What the diagnosis' grammar calls each class (docs/design.md's member names), and names that describe part of
# it at first order (not false beside it, not enough alone). Out-of-grammar classes have no name of their own.
IN_GRAMMAR = {
    "backlash": ["backlash"], "thermal_drift": ["thermal_drift"], "periodic": ["periodic"], "scale": ["scale"],
    "outlier": ["outlier"], "knocked_nest": ["nest_knock", "offset"], "reflector_creep": ["nest_creep"],
    "tracker_knock": ["offset"], "table_warming": ["side_expansion"], "spindle_warming": ["side_expansion"],
    "axis_scatter": ["axis_scatter"], "graded_backlash": ["backlash_travel"], "air_temperature": ["air_index_drift"],
    "tracker_relevel": ["tracker_relevel", "offset"], "mistyped_reading": ["outlier"],
}
ACCEPTED = {
    "thermal_drift": ["side_expansion"], "table_warming": ["thermal_drift"], "spindle_warming": ["thermal_drift"],
    "graded_backlash": ["backlash"], "tracker_relevel": ["tracker_settling"], "tracker_knock": ["tracker_relevel"],
    "air_temperature": ["thermal_drift", "tracker_scale"],
    "column_tilt": ["thermal_drift"], "axis_settling": ["backlash"], "air_gradient": ["tracker_settling"],
}


class NotApplicable(Exception):
    """A class forced with --only that this campaign cannot carry."""


def applicable(c, P):
    if c in GEN2_ALL:
        return gen2.applicable(c, P)
    need = NEW[c][2]
    if need == "linear":
        return any(a in LINEAR for a in P["axes"])
    if need == "B":
        return "B" in P["axes"]
    return True


def _plan(seed, idx):
    """gen2's plan of (seed, idx): its first draws from default_rng([seed, idx]), as gen2.draw_campaign makes them."""
    rng = np.random.default_rng([seed, idx])
    gen2.Geometry(rng)
    return gen2.plan(rng)


def pick_classes(seed, idx, P, mix, clean_fraction, only):
    """The campaign's classes: `only` (every name, or [] for 'none'), else clean with probability clean_fraction,
    else exactly one class: mix new, one of gen3's; mix gen2, one of gen2's; mix all, gen3's or gen2's with
    probability 1/2 each, uniform among those that apply. Stream: default_rng([seed, idx, 30])."""
    if only is not None:
        names = [] if only == ["none"] else list(only)
        bad = [c for c in names if not applicable(c, P)]
        if bad:
            raise NotApplicable(f"class {bad[0]} does not apply to this campaign (axes {''.join(P['axes'])})")
        return names
    rng = np.random.default_rng([seed, idx, 30])
    if rng.random() < clean_fraction:
        return []
    pools = {"new": [NEW_NAMES], "gen2": [GEN2_ALL], "all": [NEW_NAMES, GEN2_ALL]}[mix]
    pool = pools[int(rng.integers(len(pools)))]
    return [str(rng.choice([c for c in pool if applicable(c, P)]))]


# ---------------------------------------------------------------- beam geometry of every reading
class Beams:
    """Per row: station position S (mm), beam vector v = p - S, length L (mm), unit u, and the two transverse
    unit vectors (a1 horizontal, a2 = u x a1), from the noise-free readings X0 (mm, machine frame)."""

    def __init__(self, P, X0):
        self.S = np.array([P["stations"][r["station"]]["position_mm"] for r in P["rows"]])
        self.v = X0 - self.S
        self.L = np.linalg.norm(self.v, axis=1)
        self.u = self.v / self.L[:, None]
        a1 = np.cross(self.u, [0.0, 0.0, 1.0])
        self.a1 = a1 / np.linalg.norm(a1, axis=1)[:, None]
        self.a2 = np.cross(self.u, self.a1)

    def law(self, noise):
        """1-sigma radial and transverse noise (mm) of every reading under gen2's law a + b*L (um, L in m)."""
        Lm = self.L / 1000.0
        return ((noise["a_r_um"] + noise["b_r_um_per_m"] * Lm) * 1e-3,
                (noise["a_t_um"] + noise["b_t_um_per_m"] * Lm) * 1e-3)


def _rows_of(P, pred):
    return np.array([i for i, r in enumerate(P["rows"]) if pred(r)], dtype=int)


def _frac(law, tau, t, t_end):
    return np.array([gen2.time_fraction(law, tau, float(x), t_end) for x in t])


def _law(rng, tau_h):
    law = "linear" if rng.random() < 0.5 else "first_order_lag"
    return law, (float(rng.uniform(*tau_h)) * 3600 if law == "first_order_lag" else None)


def _blocks(P):
    return [(b["axis"], b["round"]) for b in sorted(P["blocks"], key=lambda b: b["t0"])]


# ---------------------------------------------------------------- the new physics: parameters and displacement
# Each builder takes (P, beams, rng) and returns (entry, delta): entry = the truth record's physics part, delta the
# displacement (n_rows, 3) in mm it adds to the readings (machine frame, before the tracker noise is added).
def encoder_cyclic(P, B, rng):
    amp = float(rng.uniform(5e-6, 20e-6))
    k = int(rng.integers(8, 49))
    phase = {s["label"]: float(rng.uniform(0, 2 * math.pi)) for s in P["stations"]}
    ph = np.array([phase[P["stations"][r["station"]]["label"]] for r in P["rows"]])
    az = np.arctan2(B.v[:, 1], B.v[:, 0])
    dphi = amp * np.sin(k * az + ph)
    delta = dphi[:, None] * np.c_[-B.v[:, 1], B.v[:, 0], np.zeros(len(az))]
    return dict(
        place=dict(kind="tracker", station=[s["label"] for s in P["stations"]]),
        parameters=dict(amplitude_urad=amp * 1e6, cycles_per_turn=k, phase_rad_by_station=phase),
        describe=f"the tracker's horizontal angle encoder reads the azimuth off by {amp * 1e6:.1f} urad x "
                 f"sin({k} az + phase): a graduation error of {k} cycles per turn; every reading turns about the "
                 "tracker's vertical axis by it (up to " f"{amp * B.L.max() * 1e3:.0f} um across the beam)",
        model="reading = p + dphi * (z x (p - S)), dphi = A sin(k*az + phase_station), az = atan2(p_y - S_y, "
              "p_x - S_x): a function of the direction from the tracker, the same in every round"), delta


def adm_cyclic(P, B, rng):
    amp = float(rng.uniform(1e-3, 4e-3))
    lam = float(rng.uniform(20.0, 150.0))
    ph = float(rng.uniform(0, 2 * math.pi))
    delta = (amp * np.sin(2 * math.pi * B.L / lam + ph))[:, None] * B.u
    return dict(
        place=dict(kind="tracker", station=[s["label"] for s in P["stations"]]),
        parameters=dict(amplitude_um=amp * 1e3, period_mm=lam, phase_rad=ph),
        describe=f"the tracker's distance meter has a cyclic non-linearity of {amp * 1e3:.1f} um with a period of "
                 f"{lam:.0f} mm of distance: every reading moves along its beam by it",
        model="reading = p + A sin(2 pi L / period + phase) u, L = |p - S| (mm), u the beam's unit vector"), delta


def smr_incidence(P, B, rng):
    tool = sorted(lab for lab, (sd, _) in P["nests"].items() if sd == "tool")
    lab = str(rng.choice(tool))
    e30 = float(rng.uniform(5e-3, 20e-3))
    th0 = float(rng.uniform(10.0, 25.0))
    c = e30 / (math.pi / 6) ** 2
    q = P["nests"][lab][1]
    normals = {}
    for s in P["stations"]:
        u0 = (q - s["position_mm"]) / np.linalg.norm(q - s["position_mm"])
        w = np.cross(u0, gen2.unit(rng))
        w /= np.linalg.norm(w)
        normals[s["label"]] = (math.cos(math.radians(th0)) * -u0 + math.sin(math.radians(th0)) * w)
    rows = _rows_of(P, lambda r: r["point"] == lab)
    n = np.array([normals[P["stations"][P["rows"][i]["station"]]["label"]] for i in rows])
    theta = np.arccos(np.clip(np.sum(n * -B.u[rows], axis=1), -1, 1))
    delta = np.zeros((len(P["rows"]), 3))
    delta[rows] = (c * theta ** 2)[:, None] * B.u[rows]
    return dict(
        place=dict(kind="nest", point=lab, side="tool"),
        parameters=dict(point=lab, error_at_30deg_um=e30 * 1e3, coefficient_um_per_rad2=c * 1e3,
                        set_incidence_deg=th0, incidence_range_deg=[float(np.degrees(theta.min())),
                                                                    float(np.degrees(theta.max()))],
                        axis_of_smr_by_station={k: v.tolist() for k, v in normals.items()}),
        describe=f"the glass-prism reflector in spindle nest {lab} reads long by c*theta^2 along the beam "
                 f"({e30 * 1e3:.1f} um at 30 deg of incidence); set {th0:.0f} deg off its beam, the incidence swings "
                 f"{np.degrees(np.ptp(theta)):.1f} deg as the axes move it",
        model="reading += c theta^2 u, theta = angle between the SMR's axis (fixed in the nest, per station) and the "
              "beam back to the tracker, c = error_at_30deg / (pi/6)^2"), delta


def damaged_reflector(P, B, rng):
    lab = str(rng.choice(sorted(P["nests"])))
    sr = float(rng.uniform(1.5e-3, 6e-3))
    st = float(rng.uniform(3e-3, 10e-3))
    rows = _rows_of(P, lambda r: r["point"] == lab)
    z = rng.normal(size=(len(rows), 3))
    delta = np.zeros((len(P["rows"]), 3))
    delta[rows] = sr * z[:, :1] * B.u[rows] + st * (z[:, 1:2] * B.a1[rows] + z[:, 2:3] * B.a2[rows])
    return dict(
        place=dict(kind="nest", point=lab, side=P["nests"][lab][0]),
        parameters=dict(point=lab, extra_sigma_along_um=sr * 1e3, extra_sigma_across_um=st * 1e3),
        describe=f"the reflector in nest {lab} is dirty or chipped: its return is weak and every reading of it "
                 f"scatters by a further {sr * 1e3:.1f} um along the beam and {st * 1e3:.1f} um across it (1 sigma)",
        model="reading += N(0, s_along) u + N(0, s_across) (a1, a2), independent per reading of that nest"), delta


def floor_vibration(P, B, rng):
    t = np.array([r["time"] for r in P["rows"]])
    nwin = int(rng.integers(1, 4))
    wins = []
    for _ in range(nwin):
        c = float(t[int(rng.integers(len(t)))])
        d = float(rng.uniform(60.0, 240.0))
        wins.append([c - d / 2, c + d / 2])
    ang = float(rng.uniform(2e-6, 6e-6))
    sr = float(rng.uniform(0.5e-3, 2e-3))
    rows = np.array([i for i, x in enumerate(t) if any(a <= x <= b for a, b in wins)], dtype=int)
    z = rng.normal(size=(len(rows), 3))
    st = ang * B.L[rows]
    delta = np.zeros((len(P["rows"]), 3))
    delta[rows] = sr * z[:, :1] * B.u[rows] + st[:, None] * (z[:, 1:2] * B.a1[rows] + z[:, 2:3] * B.a2[rows])
    return dict(
        place=dict(kind="tracker", station=sorted({P["stations"][P["rows"][i]["station"]]["label"] for i in rows}),
                   windows_s=wins),
        parameters=dict(windows_s=wins, angular_sigma_urad=ang * 1e6, radial_sigma_um=sr * 1e3,
                        readings_in_windows=int(len(rows))),
        describe=f"the floor shook {nwin} time(s) (a forklift, a press nearby; {sum(b - a for a, b in wins):.0f} s in "
                 f"all): the tracker's stand vibrates and every reading then scatters by {ang * 1e6:.1f} urad "
                 f"(x distance) across the beam and {sr * 1e3:.1f} um along it",
        model="reading += N(0, s_r) u + N(0, ang*L) (a1, a2) for every reading inside a window"), delta


def air_gradient(P, B, rng):
    g = float(rng.uniform(1.0, 3.0))
    law, tau = _law(rng, (0.3, 2.0))
    t = np.array([r["time"] for r in P["rows"]])
    f = _frac(law, tau, t, P["t_end"])
    kappa = -DN_DT * g * f                                          # 1/m, curvature of the beam
    up = np.array([0.0, 0.0, 1.0]) - (B.u @ [0.0, 0.0, 1.0])[:, None] * B.u
    up /= np.linalg.norm(up, axis=1)[:, None]
    delta = (kappa * (B.L / 1000.0) ** 2 / 2 * 1000.0)[:, None] * up
    return dict(
        place=dict(kind="air", station=[s["label"] for s in P["stations"]]),
        parameters=dict(gradient_K_per_m_at_end=g, law=law, tau_s=tau, dn_dT_per_K=DN_DT),
        describe=f"a vertical air temperature gradient builds up to {g:.2f} K/m by the end ({law.replace('_', ' ')})"
                 f": the beam bends down and every point reads high by kappa L^2 / 2 across the beam (up to "
                 f"{np.abs(delta).max() * 1e3:.1f} um)",
        model="reading += (0.93e-6 g f(t)) L^2 / 2 e_up, L in m, e_up the upward unit vector across the beam; "
              "f = gen2's time fraction"), delta


def column_tilt(P, B, rng):
    th = float(rng.choice([-1, 1]) * rng.uniform(20e-6, 80e-6))
    beta = float(rng.uniform(0, 2 * math.pi))
    a = np.array([math.cos(beta), math.sin(beta), 0.0])
    c = np.array([rng.uniform(-200, 200), rng.uniform(-200, 200), -rng.uniform(600, 1200)])
    law, tau = _law(rng, (0.3, 2.0))
    rows = _rows_of(P, lambda r: r["axis"] in LINEAR)
    t = np.array([P["rows"][i]["time"] for i in rows])
    f = _frac(law, tau, t, P["t_end"])
    X0 = B.S[rows] + B.v[rows]
    delta = np.zeros((len(P["rows"]), 3))
    delta[rows] = (th * f)[:, None] * np.cross(a, X0 - c)
    return dict(
        place=dict(kind="side", side="tool"),
        parameters=dict(tilt_at_end_urad=th * 1e6, tilt_axis=a.tolist(), pivot_mm=c.tolist(), law=law, tau_s=tau),
        describe=f"the column warms unevenly and tilts {th * 1e6:+.0f} urad by the end ({law.replace('_', ' ')}) about "
                 f"a horizontal axis through its base {-c[2]:.0f} mm below the work zone: the spindle side turns "
                 "and shifts with time",
        model="tool-side reading += theta_end f(t) a x (p - pivot); f = gen2's time fraction"), delta


def table_sag(P, B, rng):
    w = float(rng.uniform(5e-3, 20e-3))
    tilt = gen2.TILT
    rows = _rows_of(P, lambda r: r["axis"] == "B")
    delta = np.zeros((len(P["rows"]), 3))
    for i in rows:
        r = P["rows"][i]
        q = P["nests"][r["point"]][1]
        n = gen2.Rx(tilt) @ gen2.Rz(math.radians(r["position"])) @ gen2.Rx(-tilt) @ np.array([0.0, 0.0, 1.0])
        delta[i] = w * (math.hypot(q[0], q[1]) / R_RIM) ** 2 * (1.0 - n[2]) * n
    return dict(
        place=dict(kind="side", side="table", axis="B"),
        parameters=dict(sag_at_rim_um=w * 1e3, rim_radius_mm=R_RIM),
        describe=f"the table sags under a heavy fixture, {w * 1e3:.1f} um at {R_RIM:.0f} mm from the C axis when it "
                 "faces up; as B swivels it, the load normal to the face falls and the sag springs back: the "
                 "table's face bends with B, the nests by the square of their radius",
        model="table reading += w (r / r_rim)^2 (1 - n_z(B)) n(B), n(B) = Rx(45) Rz(B) Rx(-45) z the table "
              "normal, r the nest's radius from the C axis"), delta


def axis_settling(P, B, rng):
    ax = str(rng.choice([a for a in P["axes"] if a in LINEAR]))
    e0 = float(rng.uniform(5e-3, 25e-3))
    tau = float(rng.uniform(1.5, 4.0))
    rows = _rows_of(P, lambda r: r["axis"] == ax)
    stops = {}
    for i in rows:
        r = P["rows"][i]
        stops.setdefault((r["round"], r["direction"], r["position"]), []).append(i)
    delta = np.zeros((len(P["rows"]), 3))
    ages = []
    for key in sorted(stops):
        idx = stops[key]
        t_arr = min(P["rows"][i]["time"] for i in idx) - float(rng.uniform(1.0, 3.0))
        for i in idx:
            age = P["rows"][i]["time"] - t_arr
            ages.append(age)
            delta[i] = -key[1] * e0 * math.exp(-age / tau) * AXIS_DIR[ax]
    return dict(
        place=dict(kind="axis", axis=ax),
        parameters=dict(axis=ax, error_on_arrival_um=e0 * 1e3, tau_s=tau,
                        age_of_readings_s=[float(min(ages)), float(max(ages))]),
        describe=f"{ax} is read before it settles: it arrives {e0 * 1e3:.1f} um short of its target in the approach "
                 f"direction and creeps in with tau {tau:.1f} s, so the first nests of every stop read it short",
        model="reading += -direction e0 exp(-(t - t_arrival)/tau) along the axis, t_arrival 1-3 s before the "
              "stop's first reading"), delta


def _export_block(P, rng, first_ok=True):
    bl = _blocks(P)
    return bl[int(rng.integers(0 if first_ok else 1, len(bl)))]


def coarse_rounding(P, B, rng):
    return dict(place=dict(kind="export", columns=["x", "y", "z"]), parameters=dict(decimals=2),
                describe="the export's number format was set to 2 decimals: every coordinate is written to 0.01 mm",
                model="written = round(reading, 2) in mm"), None


def direction_inverted(P, B, rng):
    ax, rd = _export_block(P, rng)
    return dict(place=dict(kind="export", axis=ax, round=int(rd), columns=["direction"]),
                parameters=dict(axis=ax, round=int(rd)),
                describe=f"the direction column of {ax} round {rd} is written with the wrong sign (the other "
                         "convention of one export)", model="written direction = -direction in that round"), None


def time_in_ms(P, B, rng):
    return dict(place=dict(kind="export", columns=["time_s"]), parameters=dict(factor=1000.0),
                describe="the time column is in milliseconds though it is called time_s",
                model="written time_s = 1000 t, 0 decimals"), None


def pass_time_restart(P, B, rng):
    ax, rd = _export_block(P, rng, first_ok=False)
    off = float(rng.uniform(0.5, 5.0))
    return dict(place=dict(kind="export", axis=ax, round=int(rd), columns=["time_s"]),
                parameters=dict(axis=ax, round=int(rd), first_time_written_s=off),
                describe=f"the time column of {ax} round {rd} restarts near 0 (that round was logged in a file "
                         "of its own and appended)",
                model="written t = t - t_first_of_round + first_time_written"), None


BUILDERS = {name: globals()[name] for name in NEW_NAMES}


# ---------------------------------------------------------------- what the data can see of a displacement
def beyond_stops(P, beams, noise, delta):
    """The part of `delta` (n, 3; mm) that neither a rigid motion of the nests per (station, axis, position) nor a
    constant offset of each nest in its side's frame takes (least squares, unweighted: in mm), and the chi^2 of the
    part the weighted fit leaves, whitened by the campaign's true noise law (what the data can see of it). The base's
    error motions free at every measured position are such a motion (the same in every round and direction); a
    nest's position in its side's frame is known only from the readings (no calibration is told where the
    reflectors sit), so a displacement constant in the side's frame -- a layout grown before its nests were first
    read -- is no more visible than a different layout. This is an upper bound on what the base can absorb of a
    pattern that is fixed in the machine's positions or the nests' frames, and nothing of one that changes with
    time or direction."""
    sr, st = beams.law(noise)
    u = beams.u
    W = (u[:, :, None] * u[:, None, :]) * (1 / sr - 1 / st)[:, None, None] + np.eye(3)[None] / st[:, None, None]
    A = _rigid_and_nests(P, beams)
    Aw = np.einsum("nij,njk->nik", W, A).reshape(-1, A.shape[2])
    bw = np.einsum("nij,nj->ni", W, delta).reshape(-1)
    res = bw - Aw @ np.linalg.lstsq(Aw, bw, rcond=None)[0]
    out = delta - np.einsum("nij,j->ni", A, np.linalg.lstsq(A.reshape(-1, A.shape[2]), delta.reshape(-1),
                                                           rcond=None)[0])
    return out, float(res @ res)


def _rigid_and_nests(P, beams):
    """(n, 3, m) columns: per (station, axis, position) cell a translation and a small rotation about the cell's
    centre; per nest a constant offset in its side's frame, carried into the machine frame by the cell's rotation of
    that side (Kabsch of the noise-free readings on the nests' nominal positions; the identity where a cell reads
    fewer than three nests of the side, which gen2's plans never do: every stop reads each nest of its side)."""
    rows, n = P["rows"], len(P["rows"])
    p = beams.S + beams.v
    cells, nests = {}, sorted({str(r["point"]) for r in rows})
    for i, r in enumerate(rows):
        cells.setdefault((r["station"], r["axis"], r["position"]), []).append(i)
    A = np.zeros((n, 3, 6 * len(cells) + 3 * len(nests)))
    for j, idx in enumerate(cells.values()):
        idx = np.array(idx)
        d = p[idx] - p[idx].mean(0)
        A[idx, :, 6 * j:6 * j + 3] = np.eye(3)
        A[idx, :, 6 * j + 3:6 * j + 6] = np.stack([np.cross(np.eye(3)[k], d) for k in range(3)], axis=2)
        for side in {P["nests"][str(rows[i]["point"])][0] for i in idx}:
            own = np.array([i for i in idx if P["nests"][str(rows[i]["point"])][0] == side])
            R = _kabsch(np.array([P["nests"][str(rows[i]["point"])][1] for i in own]), p[own])
            for i in own:
                k = 6 * len(cells) + 3 * nests.index(str(rows[i]["point"]))
                A[i, :, k:k + 3] = R
    return A


def _kabsch(q, p):
    """The rotation R (3, 3) taking the points q (side frame) onto p (machine frame) best, or the identity where
    fewer than three distinct points are given."""
    if len(np.unique(np.round(q, 6), axis=0)) < 3:
        return np.eye(3)
    H = (q - q.mean(0)).T @ (p - p.mean(0))
    U, _, Vt = np.linalg.svd(H)
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(Vt.T @ U.T))])
    return Vt.T @ D @ U.T


def displacement_record(P, beams, noise, delta):
    """max and RMS (um) of the planted displacement over the readings it moves, and of its part beyond the stops'
    rigid motions, with that part's chi^2 (true noise law) and the count of readings moved."""
    if delta is None:
        return None
    mag = np.linalg.norm(delta, axis=1)
    moved = mag > 1e-9
    vis, chi2 = beyond_stops(P, beams, noise, delta)
    vm = np.linalg.norm(vis, axis=1)
    if not np.any(moved):
        return dict(max_um=0.0, rms_um=0.0, readings=0, beyond_stops_max_um=0.0, beyond_stops_rms_um=0.0,
                    chi2_beyond_stops=0.0)
    return dict(max_um=float(mag.max() * 1e3), rms_um=float(np.sqrt(np.mean(mag[moved] ** 2)) * 1e3),
                readings=int(np.sum(moved)), beyond_stops_max_um=float(vm.max() * 1e3),
                beyond_stops_rms_um=float(np.sqrt(np.mean(vm[moved] ** 2)) * 1e3), chi2_beyond_stops=chi2)


# ---------------------------------------------------------------- places and records of gen2's classes
def _gen2_place(c, e):
    """gen2's own truth entry -> the place a user would name (tracker / air / nest / side / axis / export)."""
    d = e.get("details") or {}
    if c in GEN2_DATA:
        return dict(kind="export", axis=e.get("axis") or (e.get("where") or {}).get("axis"),
                    round=e.get("round", (e.get("where") or {}).get("round")),
                    columns=(e.get("where") or {}).get("columns"))
    if "where" in e:
        w = e["where"]
        if c == "air_temperature":
            return dict(kind="air", station=w["station"])
        kind = {"table": "side", "tool": "side"}.get(w["place"], w["place"])
        return {k: v for k, v in dict(kind=kind, side=w.get("side"), axis=w.get("axis"), station=w.get("station"),
                                      round=w.get("round")).items() if v is not None}
    if c == "thermal_drift":
        return dict(kind="side", side="tool" if d["side"] == "spindle" else "table")
    if c == "outlier":
        return dict(kind="nest", point=d["row_key"]["point"], axis=e["axis"], reading=d["row_key"])
    if c in ("knocked_nest", "reflector_creep"):
        return dict(kind="nest", point=d["point"])
    if c == "tracker_knock":
        return dict(kind="tracker", station=d["station"])
    return dict(kind="axis", axis=e["axis"])


def _model_of(e):
    d = e.get("details")
    return d.get("model") if isinstance(d, dict) else d


def _shows_at(P, delta, place):
    """Where a class shows in the data: the axes, points and stations of the readings it moves (physics), or of
    the rows it writes wrong (an export: its axis, else every axis)."""
    if delta is not None:
        moved = np.linalg.norm(delta, axis=1) > 1e-9
        rows = [r for r, m in zip(P["rows"], moved) if m]
    else:
        ax = place.get("axis")
        rows = [r for r in P["rows"] if ax is None or r["axis"] == ax]
    return dict(axes=[a for a in P["axes"] if any(r["axis"] == a for r in rows)],
                points=sorted({str(r["point"]) for r in rows}),
                stations=sorted({P["stations"][r["station"]]["label"] for r in rows}))


def _record(c, source, category, place, parameters, describe, model, P, beams, noise, delta):
    rec = dict(name=c, source=source, category=category, data_problem=c in GEN2_DATA or (c in NEW and NEW[c][1]),
               random=c in RANDOM_CLASSES, in_grammar=IN_GRAMMAR.get(c, []), accepted_names=ACCEPTED.get(c, []),
               place=place, shows_at=_shows_at(P, delta, place), parameters=parameters, describe=describe,
               model=model, displacement_um=displacement_record(P, beams, noise, delta))
    return rec


# ---------------------------------------------------------------- the export's slips, on the written text
def _export(path, recs, P):
    """Apply gen3's export classes to the CSV gen2 wrote (in place); fill each record's csv_lines (1-based, the
    header line 1) and, for the rounding, its displacement."""
    with open(path) as f:
        text = f.read().splitlines()
    head = text[0].split(",")
    rows = [ln.split(",") for ln in text[1:]]
    col = {k: i for i, k in enumerate(head)}
    for rec in sorted(recs, key=lambda r: EXPORT_TEXT.index(r["name"])):
        c = rec["name"]
        pl = rec["place"]
        mine = [j for j, r in enumerate(rows) if "axis" not in pl or (r[col["axis"]] == pl["axis"]
                                                                      and int(r[col["round"]]) == pl["round"])]
        if c == "direction_inverted":
            for j in mine:
                rows[j][col["direction"]] = str(-int(rows[j][col["direction"]]))
        elif c == "pass_time_restart":
            t0 = min(float(rows[j][col["time_s"]]) for j in mine)
            for j in mine:
                t = float(rows[j][col["time_s"]]) - t0 + rec["parameters"]["first_time_written_s"]
                rows[j][col["time_s"]] = f"{t:.1f}"
        elif c == "time_in_ms":
            for r in rows:
                r[col["time_s"]] = f"{float(r[col['time_s']]) * 1000:.0f}"
        elif c == "coarse_rounding":
            old = np.array([[float(r[col[k]]) for k in "xyz"] for r in rows])
            for r in rows:
                for k in "xyz":
                    r[col[k]] = f"{float(r[col[k]]):.2f}"
            new = np.array([[float(r[col[k]]) for k in "xyz"] for r in rows])
            rec["_delta"] = new - old
        rec["csv_lines"] = [j + 2 for j in mine] if "axis" in pl else "all"
    with open(path, "w") as f:
        f.write("\n".join([",".join(head)] + [",".join(r) for r in rows]) + "\n")


@contextlib.contextmanager
def _readings_plus(delta):
    """gen2.write_campaign with `delta` (n_rows, 3; mm) added to the readings it draws: gen2 writes the CSV exactly
    as it would (its export, its gross errors, its careless slips) of readings that carry gen3's physics too."""
    orig = gen2.draw_campaign

    def patched(*a, **k):
        out = list(orig(*a, **k))
        out[6] = out[6] + delta
        return tuple(out)
    gen2.draw_campaign = patched
    try:
        yield
    finally:
        gen2.draw_campaign = orig


def draw(seed, idx, clean_fraction=0.3, mix="all", only=None):
    """One campaign's classes and gen3 physics: (names, P, noise, beams, X0, records, delta). P, the noise law and
    X0 (the noise-free readings with nothing planted) are gen2's `--only none` twin of (seed, idx); delta (mm) is
    what gen3's physics adds to the readings; records the truth of gen3's classes (gen2's are added on writing)."""
    names = pick_classes(seed, idx, _plan(seed, idx), mix, clean_fraction, only)
    _, P, noise, _, _, _, X0, _ = gen2.draw_campaign(seed, idx, 0.0, "v3", ["none"], noise_free=True)
    beams = Beams(P, X0)
    delta = np.zeros_like(X0)
    recs = []
    for c in [c for c in names if c in NEW]:
        entry, d = BUILDERS[c](P, beams, np.random.default_rng([seed, idx, 31, NEW_NAMES.index(c)]))
        if d is not None:
            delta = delta + d
        recs.append(_record(c, "gen3", NEW[c][0], entry["place"], entry["parameters"], entry["describe"],
                            entry["model"], P, beams, noise, d))
    return names, P, noise, beams, X0, recs, delta


def write_campaign(seed, idx, outdir, clean_fraction=0.3, mix="all", only=None):
    names, P, noise, beams, X0, recs, delta = draw(seed, idx, clean_fraction, mix, only)
    os.makedirs(outdir, exist_ok=True)
    g2 = [c for c in names if c in GEN2_ALL]
    with _readings_plus(delta):
        t2 = gen2.write_campaign(seed, idx, outdir, 0.0, "v3", g2 or ["none"])
    base = os.path.join(outdir, f"campaign_{idx:04d}")
    exports = [r for r in recs if r["name"] in EXPORT_TEXT]
    if exports:
        _export(base + ".csv", exports, P)
        for r in exports:
            if "_delta" in r:
                d = r.pop("_delta")
                r["displacement_um"] = (displacement_record(P, beams, noise, d) if len(d) == len(P["rows"]) else
                                        dict(max_um=float(np.abs(d).max() * 1e3),
                                             rms_um=float(np.sqrt(np.mean(np.sum(d ** 2, 1))) * 1e3)))
    phys2 = [c for c in g2 if c not in GEN2_DATA]
    d2 = gen2.planted_displacement(seed, idx, 0.0, "v3", phys2)[1] if phys2 else None
    entries = {e["name"]: e for e in t2["effects"] + t2["gross_errors"]}
    for c in g2:
        e = entries[c]
        pl = _gen2_place(c, e)
        dd = None if c in GEN2_DATA else d2
        rec = _record(c, "gen2", "gen2:" + e.get("kind", "gross" if c in GEN2_DATA else "listed"), pl,
                      dict(size=e.get("size"), unit=e.get("unit"), details=e.get("details")),
                      e.get("describe", f"gen2's {c} (benchmarks/gen2/README.md)"), _model_of(e),
                      P, beams, noise, dd)
        if len(phys2) > 1 and dd is not None:
            rec["displacement_um"]["note"] = "the displacement of gen2's classes " + ", ".join(phys2) + " together"
        recs.append(rec)
    truth = dict(seed=seed, index=idx, generator="gen3", mix=mix if only is None else "only:" + ",".join(only),
                 clean=not names, classes=recs, tracker=t2["tracker"], campaign=t2["campaign"],
                 gen2=dict(effects=t2["effects"], gross_errors=t2["gross_errors"]), geometry=t2["geometry"],
                 units=dict(csv="mm, deg, s (design.md)", parameters="as each key's suffix",
                            displacement_um="um: max and RMS over the readings moved; beyond_stops: the part no rigid "
                                            "motion of the nests per (station, axis, position) takes; its chi2 "
                                            "under the true noise law"))
    with open(base + ".truth.json", "w") as f:
        json.dump(truth, f, indent=1, default=lambda o: o.tolist() if hasattr(o, "tolist") else float(o))
    return truth


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--start", type=int, default=0)
    ap.add_argument("--clean-fraction", type=float, default=0.3)
    ap.add_argument("--mix", choices=["all", "new", "gen2"], default="all",
                    help="all: one class of gen3's or of gen2's (1/2 each); new: one of gen3's; gen2: one of gen2's")
    ap.add_argument("--only", default=None, help="comma-separated classes planted in every campaign, or 'none'")
    a = ap.parse_args(argv)
    only = None if a.only is None else [c.strip() for c in a.only.split(",") if c.strip()]
    unknown = [c for c in (only or []) if c not in NEW_NAMES + GEN2_ALL + ["none"]]
    if unknown:
        ap.error(f"--only: unknown class {unknown[0]} (known: {', '.join(NEW_NAMES + GEN2_ALL)}, none)")
    os.makedirs(a.out, exist_ok=True)
    for i in range(a.start, a.start + a.n):
        try:
            t = write_campaign(a.seed, i, a.out, a.clean_fraction, a.mix, only)
        except NotApplicable as err:
            print(f"campaign_{i:04d}: skipped: {err}")
            continue
        print(f"campaign_{i:04d}: clean={t['clean']} classes="
              f"{[c['name'] + '@' + c['place']['kind'] for c in t['classes']]}")


if __name__ == "__main__":
    main()
