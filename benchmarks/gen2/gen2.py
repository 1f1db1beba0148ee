#!/usr/bin/env python3
"""gen2 -- an independent simulated laser-tracker campaign generator for the DMU 50 eVolution.

Written from /work/shared/design.md and derive/machines/dmu50.toml only (no mtcal imports).
Units inside: mm, rad, s.  CSV positions: mm (linear) / deg (rotary).  See README.md.
Usage: python gen2.py --out DIR --n 200 --seed 0 [--clean-fraction 0.4]
"""
import argparse, json, math, os
import numpy as np

D_B = 154.996                       # mm, B-axis intersection above the table reference (dmu50.toml)
TILT = math.radians(45.0)           # B axis inclined 45 deg to C
TRAVEL = {"X": (0.0, 500.0), "Y": (0.0, 450.0), "Z": (0.0, 400.0), "B": (0.0, 180.0), "C": (0.0, 360.0)}
LINEAR, ROTARY = "XYZ", "BC"
UNIT = {a: ("mm" if a in LINEAR else "rad") for a in "XYZBC"}
# 1-sigma noise laws (um, um/m): sigma = a + b*L.  AT960-like is the brief's MPE halved (MPE ~ 2 sigma).
INSTRUMENTS = {
    "at960_like": dict(a_r=0.2, b_r=0.15, a_t=7.5, b_t=3.0),    # radial:transverse ~ 1:25
    "ratio_1_4":  dict(a_r=1.5, b_r=0.5, a_t=6.0, b_t=2.0),
    "ratio_1_70": dict(a_r=0.1, b_r=0.05, a_t=7.0, b_t=3.5),
    "isotropic":  dict(a_r=1.0, b_r=0.5, a_t=1.0, b_t=0.5),
}
PHYSICS = ["backlash", "thermal_drift", "periodic", "scale", "growing_scale", "outlier",
           "knocked_nest", "reflector_creep", "tracker_knock"]
GROSS = ["label_swap", "duplicate_row", "mistyped_reading"]


# ---------------------------------------------------------------- small geometry helpers
def Rx(a):
    c, s = math.cos(a), math.sin(a); return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
def Ry(a):
    c, s = math.cos(a), math.sin(a); return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
def Rz(a):
    c, s = math.cos(a), math.sin(a); return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
def H(R=None, t=(0, 0, 0)):
    M = np.eye(4)
    if R is not None: M[:3, :3] = R
    M[:3, 3] = t; return M
def small_rot(w):
    """Exact rotation for the small rotation vector w (first order: I + [w]x)."""
    return Rx(w[0]) @ Ry(w[1]) @ Rz(w[2])
def unit(rng):
    v = rng.normal(size=3); return v / np.linalg.norm(v)


# ---------------------------------------------------------------- smooth random error functions
class LinFun:
    """Smooth random function of a linear-axis position s (mm), zero at s = 0, peak-to-peak `pp`.
    detrend=True removes the least-squares line over the full travel (straightness: ISO reference line)."""
    def __init__(self, rng, lo, hi, pp, trend=True, detrend=False):
        self.lo, self.hi = lo, hi
        k = np.arange(1, 5)
        self.c = rng.normal(size=4) / k ** 1.5; self.ph = rng.uniform(0, 2 * math.pi, 4)
        self.tr = rng.normal(0, 1.5) if trend else 0.0
        self.line = (0.0, 0.0); self.scale = 1.0; self.off = 0.0
        u = np.linspace(0, 1, 201); g = self._g(u)
        if detrend: self.line = tuple(np.polyfit(u, g, 1)); g = self._g(u)
        self.scale = pp / max(np.ptp(g), 1e-12); self.off = self._g(np.array([0.0]))[0]
    def _g(self, u):
        u = np.asarray(u, float); k = np.arange(1, 5)[:, None]
        g = (self.c[:, None] * np.sin(k * math.pi * u[None] + self.ph[:, None])).sum(0) + self.tr * u
        return (g - (self.line[0] * u + self.line[1])) * self.scale
    def __call__(self, s):
        return float(self._g(np.array([(s - self.lo) / (self.hi - self.lo)]))[0] - self.off)

class RotFun:
    """Smooth random function of a rotary position theta (rad): chosen harmonics, zero at 0, peak-to-peak pp."""
    def __init__(self, rng, harmonics, pp):
        self.k = np.array(harmonics, float)
        self.a = rng.normal(size=len(harmonics)) / self.k; self.b = rng.normal(size=len(harmonics)) / self.k
        th = np.linspace(0, 2 * math.pi, 361); self.scale = 1.0
        self.scale = pp / max(np.ptp(self._g(th)), 1e-12)
    def _g(self, th):
        th = np.asarray(th, float)[None]
        return ((self.a[:, None] * np.cos(self.k[:, None] * th) + self.b[:, None] * np.sin(self.k[:, None] * th)).sum(0)
                - self.a.sum()) * self.scale
    def __call__(self, th): return float(self._g([th])[0])


class Geometry:
    """First-order geometric errors of the DMU 50 (ISO 230-1 names, design.md conventions)."""
    def __init__(self, rng):
        U = rng.uniform; self.f = {}; self.const = {}
        for J in LINEAR:
            lo, hi = TRAVEL[J]
            for c in "XYZ":
                self.f[f"E_{c}{J}"] = (LinFun(rng, lo, hi, U(10e-3, 20e-3), trend=True) if c == J else
                                       LinFun(rng, lo, hi, U(2e-3, 6e-3), detrend=True))
            for c in "ABC":
                self.f[f"E_{c}{J}"] = LinFun(rng, lo, hi, U(10e-6, 30e-6), trend=True)
        for n in ("E_C0Y", "E_B0Z", "E_A0Z"):
            self.const[n] = float(rng.choice([-1, 1]) * U(5e-6, 20e-6))
        for R in ROTARY:   # error motions in the stator frame (z = rotation axis); 1st radial harmonic = location
            self.f[f"E_X{R}"] = RotFun(rng, (2, 3, 4), U(1e-3, 4e-3))
            self.f[f"E_Y{R}"] = RotFun(rng, (2, 3, 4), U(1e-3, 4e-3))
            self.f[f"E_Z{R}"] = RotFun(rng, (1, 2, 3), U(1e-3, 3e-3))
            self.f[f"E_A{R}"] = RotFun(rng, (2, 3), U(3e-6, 15e-6))
            self.f[f"E_B{R}"] = RotFun(rng, (2, 3), U(3e-6, 15e-6))
            self.f[f"E_C{R}"] = RotFun(rng, (1, 2), U(10e-6, 40e-6))   # angular positioning about the own axis
            for n in (f"E_X0{R}", f"E_Y0{R}"): self.const[n] = float(U(-30e-3, 30e-3))
            for n in (f"E_A0{R}", f"E_B0{R}"): self.const[n] = float(U(-40e-6, 40e-6))

    def tool_point(self, J, s, r, extra_pos=0.0):
        """Machine-frame position of spindle nest r (mm, rel. to gauge point) with axis J at s, others at 0.
        Delta = E + w x r (r in the moving axis frame, which coincides with the machine frame at s = 0)."""
        E = np.array([self.f[f"E_{c}{J}"](s) for c in "XYZ"])
        w = np.array([self.f[f"E_{c}{J}"](s) for c in "ABC"])
        k = self.const
        d = {"X": np.array([1.0, 0, 0]), "Y": np.array([-k["E_C0Y"], 1.0, 0]),
             "Z": np.array([k["E_B0Z"], -k["E_A0Z"], 1.0])}[J]
        return r + (s + extra_pos) * d + E + np.cross(w, r)

    def _rot(self, R, ang, sign, extra_ang=0.0):
        th = math.radians(ang)
        E = [self.f[f"E_{c}{R}"](th) for c in "XYZ"]
        w = [self.f[f"E_{c}{R}"](th) for c in "ABC"]; w[2] += extra_ang
        k = self.const
        Dl = H(Rx(k[f"E_A0{R}"]) @ Ry(k[f"E_B0{R}"]), (k[f"E_X0{R}"], k[f"E_Y0{R}"], 0.0))
        return H(small_rot(w), E) @ Dl @ H(Rz(sign * th)) @ np.linalg.inv(Dl)

    def table_T(self, B, C, extra_B=0.0, extra_C=0.0):
        """T_0^w = Tz(d) Rx(45) [B] Rx(-45) Tz(-d) [C]  (B, C in degrees; extra_* angular positioning, rad)."""
        return (H(t=(0, 0, D_B)) @ H(Rx(TILT)) @ self._rot("B", B, +1, extra_B) @ H(Rx(-TILT))
                @ H(t=(0, 0, -D_B)) @ self._rot("C", C, -1, extra_C))

    def to_json(self, grids):
        funcs = {}
        for n, f in self.f.items():
            ax = n[-1]
            if ax not in grids: continue
            pos = [float(p) for p in grids[ax]]
            vals = [f(p) if ax in LINEAR else f(math.radians(p)) for p in pos]
            funcs[n] = {"axis": ax, "positions": pos, "values": vals}
        return {"machine": "dmu50", "units": {"length": "mm", "angle": "rad"},
                "constants": dict(self.const), "functions": funcs}


# ---------------------------------------------------------------- campaign plan
def spread_points(rng, n, kind):
    while True:
        if kind == "tool":   # spindle nests (mm, relative to the spindle gauge point)
            P = np.c_[rng.uniform(-90, 90, n), rng.uniform(-90, 90, n), rng.uniform(0, 150, n)]
        else:                # table nests (mm, workpiece coordinates = machine frame at B = C = 0)
            a = rng.uniform(0, 2 * math.pi, n); rr = rng.uniform(60, 220, n)
            P = np.c_[rr * np.cos(a), rr * np.sin(a), rng.uniform(20, 150, n)]
        d = P - P.mean(0)
        if np.linalg.svd(d, compute_uv=False)[1] > 30 and min(np.linalg.norm(P[i] - P[j]) for i in range(n)
                                                              for j in range(i)) > 40:
            return P

def make_grid(rng, ax):
    lo, hi = TRAVEL[ax]
    if ax in LINEAR:
        n = int(rng.integers(6, 13)); s0 = 0.0 if rng.random() < 0.8 else round(float(rng.uniform(5, 50)), 1)
        s1 = round(float(rng.uniform(0.6, 1.0) * hi), 1)
        return np.round(np.linspace(s0, s1, n), 3)
    if ax == "B":
        n = int(rng.integers(6, 14)); s1 = float(rng.choice([90.0, 120.0, 150.0, 180.0]))
        return np.round(np.linspace(0.0, s1, n), 3)
    n = int(rng.integers(8, 25)); step = 360.0 / n
    m = n if rng.random() < 0.7 else int(rng.integers(max(6, n // 2), n))
    return np.round(np.arange(m) * step, 3)

def make_noise(rng):
    name = str(rng.choice(list(INSTRUMENTS)))
    p = {k: v * float(np.exp(rng.uniform(math.log(0.6), math.log(1.6)))) for k, v in INSTRUMENTS[name].items()}
    u = rng.random()   # random shape: sometimes pure constant or pure distance-proportional (same sigma at 3 m)
    for s in ("r", "t"):
        if u < 0.15: p["a_" + s] += 3 * p["b_" + s]; p["b_" + s] = 0.0
        elif u < 0.3: p["b_" + s] += p["a_" + s] / 3; p["a_" + s] = 0.0
    if name == "isotropic": p["a_t"], p["b_t"] = p["a_r"], p["b_r"]
    shape = "constant" if u < 0.15 else "proportional" if u < 0.3 else "affine"
    return {"instrument": name, "shape": shape, "law": "1-sigma [um] = a + b*L, L = tracker-to-point [m]",
            "a_r_um": p["a_r"], "b_r_um_per_m": p["b_r"], "a_t_um": p["a_t"], "b_t_um_per_m": p["b_t"]}


def plan(rng):
    if rng.random() < 0.5: axes = list("XYZBC")
    else:
        k = int(rng.integers(2, 5)); sub = {str(a) for a in rng.choice(list("XYZBC"), k, replace=False)}
        axes = [a for a in "XYZBC" if a in sub]
    grids = {a: make_grid(rng, a) for a in axes}
    rounds = int(rng.integers(2, 9))
    nst = int(rng.choice([1, 2, 3], p=[0.7, 0.2, 0.1])); nst = min(nst, rounds)
    ntool, ntab = int(rng.integers(3, 6)), int(rng.integers(3, 6))
    tool = spread_points(rng, ntool, "tool"); tab = spread_points(rng, ntab, "table")
    labels_tool = [f"P{i + 1}" for i in range(ntool)]; labels_tab = [f"P{ntool + i + 1}" for i in range(ntab)]
    nests = {l: ("tool", tool[i]) for i, l in enumerate(labels_tool)}
    nests.update({l: ("table", tab[i]) for i, l in enumerate(labels_tab)})
    centre = np.array([150.0, 120.0, 150.0])
    stations = []
    for s in range(nst):
        L = rng.uniform(1500, 4000); az = rng.uniform(0, 2 * math.pi); el = math.radians(rng.uniform(-5, 35))
        pos = centre + L * np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
        pos[2] = max(pos[2], -600.0)
        stations.append({"label": f"S{s + 1}", "position_mm": pos,
                         "t": rng.normal(0, 0.02, 3) if nst > 1 else np.zeros(3),     # mm
                         "w": rng.normal(0, 20e-6, 3) if nst > 1 else np.zeros(3)})   # rad
    if nst > 1:   # gauge: translations sum to zero; rotations also taken zero-mean (our choice)
        mt = np.mean([s["t"] for s in stations], 0); mw = np.mean([s["w"] for s in stations], 0)
        for s in stations: s["t"] = s["t"] - mt; s["w"] = s["w"] - mw
    # rounds of each axis split between stations in contiguous blocks
    split = np.array_split(np.arange(1, rounds + 1), nst)
    rows, blocks, t = [], [], 0.0
    order_tool = list(rng.permutation(labels_tool)); order_tab = list(rng.permutation(labels_tab))
    for si, st in enumerate(stations):
        if si: t += rng.uniform(1200, 2700)
        for ax in axes:
            labels = order_tool if ax in LINEAR else order_tab
            b0 = t
            for rd in split[si]:
                r_rows = []
                for dirn, seq in ((1, grids[ax]), (-1, grids[ax][::-1])):
                    for pos in seq:
                        t += rng.uniform(3, 8)
                        for lab in labels:
                            t += rng.uniform(1.5, 4.0)
                            r_rows.append(dict(station=si, axis=ax, round=int(rd), position=float(pos), point=lab,
                                               direction=dirn, time=t))
                    t += rng.uniform(5, 15)
                rows += r_rows; blocks.append(dict(station=si, axis=ax, round=int(rd), t0=r_rows[0]["time"],
                                                   t1=r_rows[-1]["time"], start=b0))
                t += rng.uniform(60, 300)
            for b in blocks:
                if b["axis"] == ax and b["station"] == si: b["block_end"] = t
            t += rng.uniform(300, 1200)
    return dict(axes=axes, grids=grids, rounds=rounds, stations=stations, nests=nests, rows=rows, blocks=blocks,
                t_end=rows[-1]["time"])


# ---------------------------------------------------------------- planted effects
def side_of(ax): return "tool" if ax in LINEAR else "table"

def choose_effects(rng, P, n, forced=None):
    axes = P["axes"]; lin = [a for a in axes if a in LINEAR]; rot = [a for a in axes if a in ROTARY]
    pool = [c for c in PHYSICS + GROSS if not ((c in ("scale", "growing_scale") and not lin)
                                               or (c == "periodic" and not rot))]
    classes = [str(c) for c in rng.choice(pool, n, replace=False)] if n else []
    if forced is not None: classes = list(forced)   # v3 mixes: the classes were drawn elsewhere
    eff, gross = [], []
    U = rng.uniform
    def pick_round(axset):
        bl = [b for b in P["blocks"] if b["axis"] in axset]; return bl[int(rng.integers(len(bl)))]
    def axes_after(t0, side):
        return [a for a in axes if side_of(a) == side and any(b["axis"] == a and b["t1"] > t0 for b in P["blocks"])]
    for c in classes:
        if c == "backlash":
            ax = str(rng.choice(axes)); b = U(5e-3, 30e-3) if ax in LINEAR else U(20e-6, 80e-6)
            eff.append(dict(name=c, axis=ax, size=b, unit=UNIT[ax], details=dict(
                model="effective position = nominal + direction*size/2 (reversal value = size)")))
        elif c == "thermal_drift":
            side = str(rng.choice([s for s in ("tool", "table") if any(side_of(a) == s for a in axes)]))
            sb = [b for b in P["blocks"] if side_of(b["axis"]) == side]
            onset = 0.0 if rng.random() < 0.5 else U(0.0, 0.8) * sb[-1]["t1"]
            kind = str(rng.choice(["linear", "exponential"]))
            v = unit(rng)
            if side == "tool": v = v + np.array([0, 0, -2.0]); v /= np.linalg.norm(v)   # spindle growth mostly -z
            if kind == "linear": size = U(10e-3, 50e-3); rate = size / (P["t_end"] - onset); tau = None
            else: size = U(10e-3, 50e-3); tau = U(0.2, 1.5) * 3600; rate = None
            eff.append(dict(name=c, axis=axes_after(onset, side)[0], size=size, unit="mm", details=dict(
                side="spindle" if side == "tool" else "table", kind=kind, onset_s=onset,
                rate_mm_per_s=rate, tau_s=tau, direction=v.tolist(), axes=axes_after(onset, side),
                model="linear: rate*(t-onset); exponential: size*(1-exp(-(t-onset)/tau)); size for linear = "
                      "drift reached at the end of the campaign; added to every reading of that side")))
        elif c == "periodic":
            ax = str(rng.choice(rot)); g = P["grids"][ax]; step = float(np.min(np.diff(g)))
            kmax = max(3, int(360.0 / (3 * step)))
            k = int(rng.integers(3, kmax + 1)); amp = U(10e-6, 40e-6)
            eff.append(dict(name=c, axis=ax, size=amp, unit="rad", details=dict(
                cycles_per_rev=k, period_deg=360.0 / k, phase_rad=U(0, 2 * math.pi), component=f"E_C{ax}",
                model="extra angular positioning about the axis' own line: size*(sin(k*theta+phase)-sin(phase))")))
        elif c == "scale":
            ax = str(rng.choice(lin)); s = float(rng.choice([-1, 1]) * U(30e-6, 100e-6))
            eff.append(dict(name=c, axis=ax, size=s, unit="ratio", details=dict(ppm=s * 1e6,
                        model="extra positioning error size*position along the axis")))
        elif c == "growing_scale":
            ax = str(rng.choice(lin)); s = U(20e-6, 80e-6)
            bl = [b for b in P["blocks"] if b["axis"] == ax]
            eff.append(dict(name=c, axis=ax, size=s, unit="ratio", details=dict(ppm_at_block_end=s * 1e6,
                        blocks=sorted({(b["start"], b["block_end"]) for b in bl}),
                        model="positioning error size*position*(t-block_start)/(block_end-block_start), "
                              "ramping within each measurement block of the axis (heating while moving)")))
        elif c == "outlier":
            i = int(rng.integers(len(P["rows"]))); r = P["rows"][i]; s = U(20e-3, 100e-3); v = unit(rng)
            ref = r["direction"] == 1 and r["position"] == float(P["grids"][r["axis"]][0])
            eff.append(dict(name=c, axis=r["axis"], size=s, unit="mm", details=dict(
                row_key=key(r), vector_mm=(s * v).tolist(), is_round_reference=bool(ref))))
            r["outlier"] = s * v
        elif c == "knocked_nest":
            b = pick_round(axes); r_rows = [r for r in P["rows"] if r["axis"] == b["axis"] and r["round"] == b["round"]]
            t0 = U(r_rows[len(r_rows) // 10]["time"], r_rows[-2]["time"])
            lab = str(rng.choice(sorted({r["point"] for r in r_rows}))); s = U(10e-3, 50e-3); v = unit(rng)
            eff.append(dict(name=c, axis=b["axis"], size=s, unit="mm", details=dict(
                point=lab, t0_s=t0, round=b["round"], vector_mm=(s * v).tolist(),
                frame="moving part (spindle nest: machine axes; table nest: workpiece frame)",
                model="nest displaced from t0 to the end of the campaign")))
        elif c == "reflector_creep":
            lab = str(rng.choice(sorted({r["point"] for r in P["rows"]}))); rate = U(2e-3, 10e-3) / 3600
            sd = P["nests"][lab][0]; rel = [b for b in P["blocks"] if side_of(b["axis"]) == sd]
            onset = 0.0 if rng.random() < 0.5 else U(0, 0.6) * rel[-1]["t1"]
            eff.append(dict(name=c, axis=axes_after(onset, sd)[0], size=rate * 3600, unit="mm/h", details=dict(
                point=lab, onset_s=onset, direction=unit(rng).tolist(), axes=axes_after(onset, sd),
                model="nest moves by rate*(t-onset) along direction (moving-part frame)")))
        elif c == "tracker_knock":
            b = pick_round(axes); r_rows = [r for r in P["rows"] if r["station"] == b["station"]
                                            and r["axis"] == b["axis"] and r["round"] == b["round"]]
            t0 = U(r_rows[len(r_rows) // 10]["time"], r_rows[-2]["time"]); s = U(10e-3, 50e-3); v = unit(rng)
            eff.append(dict(name=c, axis=b["axis"], size=s, unit="mm", details=dict(
                station=P["stations"][b["station"]]["label"], t0_s=t0, round=b["round"], vector_mm=(s * v).tolist(),
                model="every reading of that station from t0 on is translated by vector_mm")))
        else:
            gross.append(dict(name=str(c)))
    return eff, gross

def key(r):
    return dict(axis=r["axis"], round=r["round"], position=r["position"], point=r["point"],
                direction=r["direction"], time_s=round(r["time"], 1))


# ---------------------------------------------------------------- v3: physics outside the list, careless slips
# Drawn only in the v3 mixes (--mix v3 / outside, or --only), from their own random streams, so that the v2 mix
# (the default) writes exactly what it wrote before these classes existed.
OUTSIDE = ["table_warming", "spindle_warming", "axis_scatter", "graded_backlash", "thermal_straightness",
           "air_temperature", "tracker_relevel"]
CARELESS = ["rotary_radians", "inch_positions", "columns_swapped"]
NEW = OUTSIDE + CARELESS
ALPHA = 11.5e-6                      # 1/K, linear expansion of steel / cast iron
AXIS_DIR = {"X": np.array([1.0, 0, 0]), "Y": np.array([0, 1.0, 0]), "Z": np.array([0, 0, 1.0])}
ZONE = np.array([150.0, 120.0, 150.0])   # mm, the work-zone centre the stations look at (plan)
WHERE_KEYS = ("place", "side", "axis", "station", "round", "point", "columns")


class NotApplicable(Exception):
    """A class forced with --only that this campaign cannot carry (e.g. a rotary class without B or C)."""


def applicable(c, P):
    axes = P["axes"]; lin = [a for a in axes if a in LINEAR]; rot = [a for a in axes if a in ROTARY]
    if c in ("scale", "growing_scale", "spindle_warming", "axis_scatter", "graded_backlash", "thermal_straightness",
             "inch_positions"): return bool(lin)
    if c in ("periodic", "table_warming", "rotary_radians"): return bool(rot)
    if c == "tracker_relevel": return bool(relevel_boundaries(P))
    return True


def relevel_boundaries(P):
    """(previous block, next block) pairs at one station, consecutive in time: a pause in which the tracker can be
    re-levelled. Pairs of two rounds of the same axis come first (the issue's case)."""
    out = []
    for si in range(len(P["stations"])):
        bl = sorted([b for b in P["blocks"] if b["station"] == si], key=lambda b: b["t0"])
        out += [(a, b) for a, b in zip(bl, bl[1:])]
    same = [ab for ab in out if ab[0]["axis"] == ab[1]["axis"]]
    return same or out


def time_fraction(law, tau, t, t_end):
    """Fraction of the end-of-campaign value reached at t (s): 0 at t = 0, 1 at t_end.
    linear: t/t_end; first_order_lag: (1 - exp(-t/tau)) / (1 - exp(-t_end/tau))."""
    if t <= 0: return 0.0
    if law == "linear": return t / t_end
    return (1 - math.exp(-t / tau)) / (1 - math.exp(-t_end / tau))


def draw_law(rng, tau_h):
    law = "linear" if rng.random() < 0.5 else "first_order_lag"
    return law, (float(rng.uniform(*tau_h)) * 3600 if law == "first_order_lag" else None)


def where(**kw):
    return {k: kw.get(k) for k in WHERE_KEYS}


def pick_classes_v3(rng3, P, mix, clean_fraction, only):
    """The campaign's classes in the v3 mixes: (old-list classes, new classes)."""
    if only is not None:
        names = [] if only == ["none"] else list(only)
        bad = [c for c in names if not applicable(c, P)]
        if bad: raise NotApplicable(f"class {bad[0]} does not apply to this campaign (axes {''.join(P['axes'])})")
    elif rng3.random() < clean_fraction:
        names = []
    elif mix == "outside":
        names = [str(rng3.choice([c for c in NEW if applicable(c, P)]))]
    else:
        pool = [c for c in PHYSICS + GROSS + NEW if applicable(c, P)]
        names = [str(c) for c in rng3.choice(pool, int(rng3.choice([1, 2], p=[0.6, 0.4])), replace=False)]
    return [c for c in names if c not in NEW], [c for c in names if c in NEW]


def choose_new(rng, P, classes):
    """Draw the v3 classes' parameters. Each entry: name, kind (outside_list | careless), judge_as, axis, size, unit,
    where, what, along, grows_with, describe, details (see README)."""
    axes = P["axes"]; lin = [a for a in axes if a in LINEAR]; rot = [a for a in axes if a in ROTARY]
    t_end = P["t_end"]; hours = t_end / 3600; U = rng.uniform; out = []
    for c in classes:
        e = dict(name=c, kind="careless" if c in CARELESS or c == "tracker_relevel" else "outside_list",
                 judge_as="data_problem" if c in CARELESS else "located_unexplained")
        if c in ("table_warming", "spindle_warming"):
            tbl = c == "table_warming"
            dT = float(U(1.0, 4.0) if tbl else U(2.0, 6.0)); law, tau = draw_law(rng, (0.3, 2.0) if tbl else (0.2, 1.0))
            eps = ALPHA * dT; side = "table" if tbl else "tool"
            sax = rot if tbl else lin
            e.update(axis=sax[0], size=eps, unit="ratio", where=where(place=side, side=side),
                     what="expansion",
                     along="radial from centre_mm: the " + ("table-side reflector layout (workpiece frame)" if tbl
                                                            else "spindle-side reflector layout (spindle frame)")
                           + " grows about that point",
                     grows_with="time",
                     describe=f"the {'table' if tbl else 'spindle'}-side reflectors move apart: {eps * 1e6:.1f} ppm "
                              f"at the end of the campaign ({dT:.2f} K at 11.5 ppm/K, {law.replace('_', ' ')}"
                              + (f", tau {tau / 3600:.2f} h" if tau else "") + f"), {eps * 1e6 / hours:.1f} ppm/h "
                              "on average: a warming " + ("table" if tbl else "spindle head"),
                     details=dict(ppm_at_end=eps * 1e6, delta_T_end_K=dT, alpha_per_K=ALPHA, law=law, tau_s=tau,
                                  mean_ppm_per_h=eps * 1e6 / hours, centre_mm=[0.0, 0.0, 0.0],
                                  frame="workpiece (C-axis centre at the table top)" if tbl else
                                        "spindle (the gauge point, tool length 0)", axes=sax,
                                  points=sorted(l for l, (sd, _) in P["nests"].items() if sd == side),
                                  model="nest q(t) = c + (1 + alpha*dT_end*f(t))*(q - c), f = time_fraction "
                                        "(linear t/t_end, or (1-exp(-t/tau))/(1-exp(-t_end/tau)))"))
        elif c == "axis_scatter":
            ax = str(rng.choice(lin)); sig = float(U(1.5e-3, 5e-3))
            stops = sorted({(r["round"], r["direction"], r["position"]) for r in P["rows"] if r["axis"] == ax})
            delta = {k: float(rng.normal(0, sig)) for k in stops}
            e.update(axis=ax, size=sig, unit="mm", where=where(place="axis", axis=ax), what="scatter",
                     along=f"the {ax} axis direction", grows_with="nothing (one independent draw per stop)",
                     describe=f"{ax} repeats worse than the other axes: {sig * 1e3:.1f} um (1 sigma) of extra "
                              f"positioning scatter along {ax}",
                     details=dict(sigma_um=sig * 1e3, n_stops=len(stops),
                                  realised_rms_um=float(np.sqrt(np.mean(np.square(list(delta.values()))))) * 1e3,
                                  model="each stop (round, direction, position) of the axis lands N(0, sigma) off "
                                        "along the axis; all reflectors read at that stop share the draw"),
                     _delta=delta)
        elif c == "graded_backlash":
            ax = str(rng.choice(lin)); hi = TRAVEL[ax][1]
            while True:
                b0, b1 = float(U(0, 12e-3)), float(U(0, 12e-3))
                if abs(b1 - b0) >= 4e-3: break
            e.update(axis=ax, size=b1 - b0, unit="mm", where=where(place="axis", axis=ax), what="lost_motion",
                     along=f"the {ax} axis direction", grows_with="position",
                     describe=f"the lost motion of {ax} grows along the travel: {b0 * 1e3:.1f} um at 0 mm to "
                              f"{b1 * 1e3:.1f} um at {hi:.0f} mm (a worn screw)",
                     details=dict(lost_motion_at_0_um=b0 * 1e3, lost_motion_at_end_um=b1 * 1e3, travel_end_mm=hi,
                                  model="effective position = nominal + direction*b(s)/2, b(s) = b0 + (b1-b0)*s/"
                                        "travel_end; reversal value at s = b(s); size = b1 - b0"))
        elif c == "thermal_straightness":
            ax = str(rng.choice(lin)); comp = str(rng.choice([k for k in "XYZ" if k != ax]))
            amp = float(rng.choice([-1, 1]) * U(3e-3, 10e-3)); law, tau = draw_law(rng, (0.3, 2.0))
            e.update(axis=ax, size=amp, unit="mm", where=where(place="axis", axis=ax),
                     what="straightness", along=f"{comp} (E_{comp}{ax})", grows_with="position x time",
                     describe=f"the straightness of {ax} in {comp} bows with time: {amp * 1e3:+.1f} um at mid-travel "
                              f"by the end of the campaign ({law.replace('_', ' ')}): a guideway warming unevenly",
                     details=dict(component=f"E_{comp}{ax}", direction=AXIS_DIR[comp].tolist(),
                                  bow_at_mid_travel_end_um=amp * 1e3, travel_end_mm=TRAVEL[ax][1], law=law, tau_s=tau,
                                  model="reading += size*4u(1-u)*f(t)*direction, u = s/travel_end, f = time_fraction"))
        elif c == "air_temperature":
            k = float(rng.choice([-1, 1]) * U(1.5e-6, 5e-6)); law, tau = draw_law(rng, (0.3, 2.0))
            e.update(axis=axes[0], size=k, unit="ratio",
                     where=where(place="tracker", station=[s["label"] for s in P["stations"]]),
                     what="scale", along="the beam (radial from each station)", grows_with="time x distance",
                     describe=f"the tracker's length scale drifts {k * 1e6:+.2f} ppm over the campaign "
                              f"({law.replace('_', ' ')}): the air changed and its weather compensation did not follow",
                     details=dict(ppm_at_end=k * 1e6, law=law, tau_s=tau, axes=list(axes),
                                  model="reading = S + (1 + size*f(t))*(p - S), S the station, f = time_fraction; "
                                        "0 at t = 0 (compensated at the start)"))
        elif c == "tracker_relevel":
            bnd = relevel_boundaries(P); a, b = bnd[int(rng.integers(len(bnd)))]
            st = P["stations"][b["station"]]; t0 = float(U(a["t1"] + 1.0, b["t0"] - 1.0))
            u = rng.random(); rot_on, tr_on = u < 0.8, u >= 0.4
            ang = float(U(10e-6, 100e-6)) if rot_on else 0.0; az = float(U(0, 2 * math.pi))
            hax = np.array([math.cos(az), math.sin(az), 0.0])
            tv = unit(rng) * float(U(5e-3, 50e-3)) if tr_on else np.zeros(3)
            R = rodrigues(hax * ang); S = st["position_mm"]
            step = R @ (ZONE - S) - (ZONE - S) + tv
            e.update(axis=b["axis"], size=float(np.linalg.norm(step)), unit="mm",
                     where=where(place="tracker", station=st["label"], round=b["round"]),
                     what="rotation+translation" if rot_on and tr_on else "rotation" if rot_on else "translation",
                     along="a rigid motion of the tracker frame about the tracker", grows_with="step at t0",
                     describe=f"the tracker {st['label']} was re-levelled before {b['axis']} round {b['round']}: "
                              f"{ang * 1e6:.0f} urad about a horizontal axis through it and {np.linalg.norm(tv) * 1e3:.0f}"
                              f" um of translation; the work zone steps {np.linalg.norm(step) * 1e3:.0f} um",
                     details=dict(station=st["label"], t0_s=t0, last_block_before=dict(axis=a["axis"], round=a["round"]),
                                  first_block_after=dict(axis=b["axis"], round=b["round"]),
                                  rotation_angle_rad=ang, rotation_axis=hax.tolist(), rotation_vector_rad=(hax * ang).tolist(),
                                  centre_mm=S.tolist(), translation_mm=tv.tolist(),
                                  step_at_zone_mm=step.tolist(), zone_mm=ZONE.tolist(),
                                  model="every reading of that station from t0 on: S + R(p - S) + translation, "
                                        "R = exp([rotation_vector]x); size = the step at zone_mm"))
        else:   # careless campaigns: the export's slips
            if c == "columns_swapped":
                bl = P["blocks"][int(rng.integers(len(P["blocks"])))]
                cols = [str(x) for x in sorted(rng.choice(list("xyz"), 2, replace=False))]
            else:
                bl = [b for b in P["blocks"] if b["axis"] in (rot if c == "rotary_radians" else lin)]
                bl = bl[int(rng.integers(len(bl)))]; cols = ["position"]
            ax, rd = bl["axis"], bl["round"]
            e.update(axis=ax, size=None, unit=None, where=where(place="axis", axis=ax, round=rd, columns=cols),
                     what="units" if c != "columns_swapped" else "columns", along="the written columns",
                     grows_with="round", details=dict(csv_lines=None))
            if c == "rotary_radians":
                e.update(size=math.pi / 180, unit="ratio", describe=f"the {ax} positions of round {rd} are written in "
                         f"rad while the table moved in degrees (written = nominal_deg*pi/180)")
            elif c == "inch_positions":
                e.update(size=1 / 25.4, unit="ratio", describe=f"the {ax} positions of round {rd} are written in "
                         f"inch while the machine moved in mm (written = nominal_mm/25.4, 4 decimals)")
            else:
                e.update(describe=f"columns {cols[0]} and {cols[1]} are exchanged in every row of {ax} round {rd}")
        e["_t_end"] = t_end; out.append(e)
    return out


def rodrigues(w):
    th = float(np.linalg.norm(w))
    if th == 0: return np.eye(3)
    k = w / th; K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(th) * K + (1 - math.cos(th)) * K @ K


def _frac(e, t): return time_fraction(e["details"]["law"], e["details"]["tau_s"], t, e["_t_end"])

def v3_nest(new, side, q, t):
    e = new.get("table_warming" if side == "table" else "spindle_warming")
    if not e: return q
    c = np.array(e["details"]["centre_mm"])
    return c + (1 + e["size"] * _frac(e, t)) * (q - c)

def v3_lost_motion(new, r):
    e = new.get("graded_backlash")
    if not e or e["axis"] != r["axis"]: return 0.0
    d = e["details"]; b0, b1 = d["lost_motion_at_0_um"] * 1e-3, d["lost_motion_at_end_um"] * 1e-3
    return r["direction"] * (b0 + (b1 - b0) * r["position"] / d["travel_end_mm"]) / 2

def v3_scatter(new, r):
    e = new.get("axis_scatter")
    if not e or e["axis"] != r["axis"]: return 0.0
    return e["_delta"][(r["round"], r["direction"], r["position"])]

def v3_straightness(new, r):
    e = new.get("thermal_straightness")
    if not e or e["axis"] != r["axis"]: return np.zeros(3)
    u = r["position"] / e["details"]["travel_end_mm"]
    return e["size"] * 4 * u * (1 - u) * _frac(e, r["time"]) * np.array(e["details"]["direction"])

def v3_air(new, st, p, t):
    e = new.get("air_temperature")
    if not e: return p
    S = st["position_mm"]; return S + (1 + e["size"] * _frac(e, t)) * (p - S)

def v3_relevel(new, st, p, t):
    e = new.get("tracker_relevel")
    if not e or e["details"]["station"] != st["label"] or t < e["details"]["t0_s"]: return p
    S = np.array(e["details"]["centre_mm"])
    return S + rodrigues(np.array(e["details"]["rotation_vector_rad"])) @ (p - S) + np.array(e["details"]["translation_mm"])


def careless_export(new, P, lines):
    """Apply the careless classes to the written lines; return {name: list of line objects} to number later."""
    marked = {}
    for e in new:
        if e["kind"] != "careless" or e["name"] == "tracker_relevel": continue
        ax, rd = e["where"]["axis"], e["where"]["round"]
        idx = [i for i, r in enumerate(P["rows"]) if r["axis"] == ax and r["round"] == rd]
        for i in idx:
            pos = P["rows"][i]["position"]
            if e["name"] == "rotary_radians": lines[i][2] = fmt_num(math.radians(pos), 6)
            elif e["name"] == "inch_positions": lines[i][2] = fmt_num(pos / 25.4, 4)
            else:
                a, b = (4 + "xyz".index(k) for k in e["where"]["columns"]); lines[i][a], lines[i][b] = lines[i][b], lines[i][a]
        marked[e["name"]] = [lines[i] for i in idx]
    return marked

def fmt_num(v, nd): s = f"{v:.{nd}f}".rstrip("0").rstrip("."); return s if s not in ("-0", "") else "0"


# ---------------------------------------------------------------- the virtual tracker
def simulate(rng, geo, P, eff, noise, new=None):
    """new: {name: effect} of the v3 classes (None for the v2 mixes: then nothing below changes)."""
    E = {e["name"]: e for e in eff}
    rows = P["rows"]; out = []
    for r in rows:
        ax, pos, t, d, lab = r["axis"], r["position"], r["time"], r["direction"], r["point"]
        side, q = P["nests"][lab]; q = q.copy()
        e = E.get("knocked_nest")
        if e and e["details"]["point"] == lab and t >= e["details"]["t0_s"]: q += e["details"]["vector_mm"]
        e = E.get("reflector_creep")
        if e and e["details"]["point"] == lab and t > e["details"]["onset_s"]:
            q += np.array(e["details"]["direction"]) * e["size"] / 3600 * (t - e["details"]["onset_s"])
        if new: q = v3_nest(new, side, q, t)
        bl = E.get("backlash"); blk = d * bl["size"] / 2 if bl and bl["axis"] == ax else 0.0
        if new: blk = blk + v3_lost_motion(new, r)
        if ax in LINEAR:
            extra = 0.0
            e = E.get("scale")
            if e and e["axis"] == ax: extra += e["size"] * pos
            e = E.get("growing_scale")
            if e and e["axis"] == ax:
                for a, b in e["details"]["blocks"]:
                    if a <= t <= b: extra += e["size"] * pos * (t - a) / (b - a)
            if new: extra = extra + v3_scatter(new, r)
            p = geo.tool_point(ax, pos + blk, q, extra)
            if new: p = p + v3_straightness(new, r)
        else:
            ang = pos + (math.degrees(blk) if blk else 0.0); xa = 0.0
            e = E.get("periodic")
            if e and e["axis"] == ax:
                k, ph = e["details"]["cycles_per_rev"], e["details"]["phase_rad"]
                xa = e["size"] * (math.sin(k * math.radians(ang) + ph) - math.sin(ph))
            T = geo.table_T(ang, 0.0, extra_B=xa) if ax == "B" else geo.table_T(0.0, ang, extra_C=xa)
            p = (T @ np.r_[q, 1.0])[:3]
        e = E.get("thermal_drift")
        if e and e["details"]["side"] == ("spindle" if side == "tool" else "table") and t > e["details"]["onset_s"]:
            dt = t - e["details"]["onset_s"]
            m = e["details"]["rate_mm_per_s"] * dt if e["details"]["kind"] == "linear" else \
                e["size"] * (1 - math.exp(-dt / e["details"]["tau_s"]))
            p = p + m * np.array(e["details"]["direction"])
        # tracker noise in the beam frame of this station
        st = P["stations"][r["station"]]
        if new: p = v3_air(new, st, p, t)
        v = p - st["position_mm"]; L = np.linalg.norm(v) / 1000.0
        u = v / np.linalg.norm(v); a1 = np.cross(u, [0, 0, 1.0])
        if np.linalg.norm(a1) < 1e-6: a1 = np.cross(u, [1.0, 0, 0])
        a1 /= np.linalg.norm(a1); a2 = np.cross(u, a1)
        sr = (noise["a_r_um"] + noise["b_r_um_per_m"] * L) * 1e-3
        stt = (noise["a_t_um"] + noise["b_t_um_per_m"] * L) * 1e-3
        p = p + u * rng.normal(0, sr) + (a1 * rng.normal() + a2 * rng.normal()) * stt
        p = small_rot(st["w"]) @ p + st["t"]          # that station's alignment error
        e = E.get("tracker_knock")
        if e and e["details"]["station"] == st["label"] and t >= e["details"]["t0_s"]:
            p = p + np.array(e["details"]["vector_mm"])
        if "outlier" in r: p = p + r["outlier"]
        if new: p = v3_relevel(new, st, p, t)
        out.append(p)
    return np.array(out)


def fmt_pos(p): s = f"{p:.3f}".rstrip("0").rstrip("."); return s if s not in ("-0", "") else "0"

def draw_campaign(seed, idx, clean_fraction, mix="v2", only=None, noise_free=False):
    """(geo, P, noise, eff, gross, v3eff, XYZ, rng): one campaign's draws as write_campaign makes them (its docstring),
    rng the stream the export draws from next. noise_free: XYZ without the tracker's noise (the same draws else)."""
    rng = np.random.default_rng([seed, idx])
    geo = Geometry(rng); P = plan(rng); noise = make_noise(rng)
    law = dict(noise, a_r_um=0.0, b_r_um_per_m=0.0, a_t_um=0.0, b_t_um_per_m=0.0) if noise_free else noise
    if mix == "v2" and only is None:
        clean = rng.random() < clean_fraction
        n = 0 if clean else int(rng.choice([1, 2], p=[0.6, 0.4]))
        eff, gross = choose_effects(rng, P, n)
        v3eff = []
        XYZ = simulate(rng, geo, P, eff, law)
    else:
        rng3 = np.random.default_rng([seed, idx, 3])
        old, new_cls = pick_classes_v3(rng3, P, mix, clean_fraction, only)
        eff, gross = choose_effects(rng, P, len(old), forced=old)
        v3eff = choose_new(rng3, P, new_cls)
        XYZ = simulate(np.random.default_rng([seed, idx, 1]), geo, P, eff, law, {e["name"]: e for e in v3eff})
        rng = np.random.default_rng([seed, idx, 2])
    return geo, P, noise, eff, gross, v3eff, XYZ, rng


def planted_displacement(seed, idx, clean_fraction, mix="v2", only=None):
    """(keys, delta): what the planted physics moves every reading by, without the tracker's noise -- the campaign's
    readings with its effects less the same campaign's without them (mm, machine frame, (n, 3)); keys: key(row) of
    each (the rows as simulated: before the export's gross errors and careless slips)."""
    geo, P, _, eff, _, v3eff, XYZ, _ = draw_campaign(seed, idx, clean_fraction, mix, only, noise_free=True)
    still = dict(a_r_um=0.0, b_r_um_per_m=0.0, a_t_um=0.0, b_t_um_per_m=0.0)
    rows = [{k: v for k, v in r.items() if k != "outlier"} for r in P["rows"]]
    bare = simulate(np.random.default_rng(0), geo, dict(P, rows=rows), [], still, None)
    return [key(r) for r in P["rows"]], XYZ - bare


def write_campaign(seed, idx, outdir, clean_fraction, mix="v2", only=None):
    """mix v2 (the default) is the original generator, byte for byte. mix v3 / outside, or `only` (a list of class
    names, or ["none"] for a forced clean campaign), draw the classes from their own stream [seed, idx, 3], the
    tracker noise from [seed, idx, 1] and the export's draws from [seed, idx, 2]: for one (seed, idx) the
    geometry, plan, noise law and noise samples are the same whatever classes are planted."""
    geo, P, noise, eff, gross, v3eff, XYZ, rng = draw_campaign(seed, idx, clean_fraction, mix, only)
    nst = len(P["stations"]); give_tracker = nst > 1 or rng.random() < 0.6
    given = [np.round(s["position_mm"] + rng.normal(0, 10, 3)) for s in P["stations"]]
    cols = ["axis", "round", "position", "point", "x", "y", "z", "time_s", "direction"]
    if nst > 1: cols.append("station")
    if give_tracker: cols += ["tracker_x", "tracker_y", "tracker_z"]
    lines = []
    for r, p in zip(P["rows"], XYZ):
        row = [r["axis"], str(r["round"]), fmt_pos(r["position"]), r["point"], f"{p[0]:.4f}", f"{p[1]:.4f}",
               f"{p[2]:.4f}", f"{r['time']:.1f}", str(r["direction"])]
        if nst > 1: row.append(P["stations"][r["station"]]["label"])
        if give_tracker: row += [f"{v:.0f}" for v in given[r["station"]]]
        lines.append(row)
    marked = careless_export(v3eff, P, lines) if v3eff else {}
    # gross errors of the export
    for g in gross:
        if g["name"] == "label_swap":
            b = P["blocks"][int(rng.integers(len(P["blocks"])))]
            idxs = [i for i, r in enumerate(P["rows"]) if r["axis"] == b["axis"] and r["round"] == b["round"]]
            a, c = rng.choice(sorted({P["rows"][i]["point"] for i in idxs}), 2, replace=False)
            for i in idxs:
                if lines[i][3] == a: lines[i][3] = str(c)
                elif lines[i][3] == c: lines[i][3] = str(a)
            g.update(axis=b["axis"], round=b["round"], points=[str(a), str(c)],
                     details="labels exchanged in every row of that round (all positions, both directions)")
        elif g["name"] == "mistyped_reading":
            i = int(rng.integers(len(lines))); ci = int(rng.integers(3)); s = lines[i][4 + ci]
            place = float(rng.choice([1.0, 0.1, 0.01], p=[0.2, 0.4, 0.4])); dot = s.index(".")
            j = dot - 1 if place == 1.0 else dot + (1 if place == 0.1 else 2)
            old = int(s[j]); new = int(rng.choice([k for k in range(10) if k != old]))
            s2 = s[:j] + str(new) + s[j + 1:]; lines[i][4 + ci] = s2
            g.update(axis=P["rows"][i]["axis"], row_key=key(P["rows"][i]), coordinate="xyz"[ci], original=s,
                     written=s2, error_mm=float(s2) - float(s))
    for g in gross:   # duplicate last, so that row indices above stay valid
        if g["name"] == "duplicate_row":
            i = int(rng.integers(len(lines))); lines.insert(i + 1, list(lines[i]))
            g.update(axis=P["rows"][i]["axis"], row_key=key(P["rows"][i]), csv_line=i + 3,
                     details="exact copy written on the line after the original (1-based line incl. header)")
    base = os.path.join(outdir, f"campaign_{idx:04d}")
    with open(base + ".csv", "w") as f:
        f.write(",".join(cols) + "\n")
        for row in lines: f.write(",".join(row) + "\n")
    stations = [dict(label=s["label"], position_mm=s["position_mm"].tolist(), given_in_csv=bool(give_tracker),
                     given_position_mm=given[k].tolist() if give_tracker else None,
                     alignment=dict(translation_mm=s["t"].tolist(), rotation_rad=s["w"].tolist(),
                                    model="reported = Rx(w0)Ry(w1)Rz(w2) @ measured + translation")) for k, s in
                enumerate(P["stations"])]
    for e in v3eff:
        if e["name"] in marked:
            ids = {id(x) for x in marked[e["name"]]}
            e["details"]["csv_lines"] = [k + 2 for k, x in enumerate(lines) if id(x) in ids]
        for k in [k for k in e if k.startswith("_")]: del e[k]
    truth = {"seed": seed, "index": idx, "generator": "gen2", "clean": not eff and not gross,
             "tracker": {"noise": noise, "stations": stations},
             "effects": eff, "gross_errors": gross,
             "campaign": {"axes": P["axes"], "rounds": P["rounds"], "grids": {a: g.tolist() for a, g in P["grids"].items()},
                          "nests": {l: {"side": "spindle" if s == "tool" else "table", "nominal_mm": q.tolist()}
                                    for l, (s, q) in P["nests"].items()},
                          "n_rows": len(lines), "duration_s": P["t_end"], "columns": cols},
             "geometry": geo.to_json(P["grids"])}
    if not (mix == "v2" and only is None):
        for e in eff: e["kind"] = "listed"
        for g in gross: g["kind"] = "gross"
        truth.update(generator="gen2/v3", mix=mix if only is None else "only:" + ",".join(only),
                     clean=not eff and not gross and not v3eff)
        truth["effects"] = eff + v3eff
    with open(base + ".truth.json", "w") as f:
        json.dump(truth, f, indent=1, default=lambda o: o.tolist() if hasattr(o, "tolist") else float(o))
    return truth


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True); ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--seed", type=int, default=0); ap.add_argument("--start", type=int, default=0)
    ap.add_argument("--clean-fraction", type=float, default=0.4)
    ap.add_argument("--mix", choices=["v2", "v3", "outside"], default="v2",
                    help="v2: the original classes (default, old seeds reproduce byte for byte); v3: the original "
                         "and the new classes; outside: each planted campaign carries exactly one new class")
    ap.add_argument("--only", default=None,
                    help="comma-separated class names planted in every campaign (any mix), or 'none' for clean")
    a = ap.parse_args(argv)
    only = None if a.only is None else [c.strip() for c in a.only.split(",") if c.strip()]
    unknown = [c for c in (only or []) if c not in PHYSICS + GROSS + NEW + ["none"]]
    if unknown: ap.error(f"--only: unknown class {unknown[0]} (known: {', '.join(PHYSICS + GROSS + NEW)}, none)")
    os.makedirs(a.out, exist_ok=True)
    for i in range(a.start, a.start + a.n):
        try:
            t = write_campaign(a.seed, i, a.out, a.clean_fraction, a.mix, only)
        except NotApplicable as err:
            print(f"campaign_{i:04d}: skipped: {err}"); continue
        print(f"campaign_{i:04d}: clean={t['clean']} effects={[e['name'] + ':' + e['axis'] for e in t['effects']]}"
              f" gross={[g['name'] for g in t['gross_errors']]}")

if __name__ == "__main__":
    main()
