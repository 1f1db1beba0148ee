"""Compensation of NC data from an error model: corrected axis commands that put the tool where it was meant to be.

Frames and units: axes X Y Z (mm) and B C (deg) as in the NC program (the positions the error model was measured
at); pose [x, y, z, i, j, k] of the tool tip and tool axis in the workpiece frame; errors in mm and rad.

Method (exact to first order, optionally iterated to the exact solution):
  target p* = forward(q_nom)  (nominal kinematics: what the program means);
  q_1 = q_0 - J^+ (p(q_0, e(q_0)) - p*),  e(q) = the model's errors at the commanded axes,
  first step from the generated first-order deviation and the nominal axis Jacobian, further steps
  (``iterations`` > 1) from the generated exact error-inclusive pose and Jacobian at the current command.
scope "position": X Y Z solve the 3x3 position block (the tool tip reaches p* under every modelled error,
ISO/TR 16907 L-VOL and R-VOL including R-ANG); scope "full": B and C first solve the orientation rows by least
squares (QR), then X Y Z the position (FOR added).  Near B = 0 the tool axis is parallel to C and the C column
of the orientation Jacobian vanishes (sin of the tilt): inside a cone of half-angle ``cone`` (deg, between tool
axis and C axis) only the position is corrected, between ``cone`` and 2 ``cone`` the B/C correction is blended in
with a smoothstep weight, so C never jumps; the orientation residual left there is reported as uncontrollable.
The same holds near B = 180 deg (tool axis at the edge of the reachable cone, k = 0), where the B, C Jacobian
also loses rank: the weight is computed from its smaller singular value (see ``Compensator.weight``).
"""
from __future__ import annotations

import io
import itertools
import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable

import numpy as np

from mtcal.errors import InputError
from mtcal.io import atomic_open, atomic_write_text
from mtcal.kinematics.machine import Machine, load_machine
from mtcal.model.errormodel import ErrorEvaluator, ErrorFunction, ErrorModel
from mtcal.nc import gcode

SCOPES = ("position", "full")
BLOCK = 4096  # rows per numeric block: keeps the generated functions' temporaries in cache
_P10 = 10.0 ** np.arange(23)
RESIDUAL_EVERY = 20  # default: the exact residual of every 20th move (and of every inserted point)
# plausibility bounds of a correction (see Guard): 1 mm is 20-50 times the largest volumetric error the thesis
# measured on the DMU 50 (43 um; positioning ~20 um), yet 1000 times below a model typed in um under "mm";
# 0.1 deg (1.7 mrad) is 10-50 times the largest angular errors of a rotary axis (thesis: tens of urad; ISO 230-1
# typical rotary positioning errors 10-30 arcsec = 50-150 urad)
MAX_CORRECTION_MM = 1.0
MAX_ROTARY_CORRECTION_DEG = 0.1
FEED_DECIMALS = 4  # inverse-time F (1/min) written on split G93 moves

# ISO/TR 16907 compensation types and the ISO 230-1 errors they act on (DMU 50: linear X Y Z, rotary B C)
ISO_TYPES: dict[str, tuple[str, ...]] = {
    "L-POS": ("E_XX", "E_YY", "E_ZZ"),
    "L-STR": ("E_YX", "E_ZX", "E_XY", "E_ZY", "E_XZ", "E_YZ"),
    "L-SQU": ("E_C0Y", "E_B0Z", "E_A0Z"),
    "L-ANG": ("E_AX", "E_BX", "E_CX", "E_AY", "E_BY", "E_CY", "E_AZ", "E_BZ", "E_CZ"),
    "R-POS": ("E_CB", "E_CC"),
    "R-RAX": ("E_XB", "E_YB", "E_ZB", "E_XC", "E_YC", "E_ZC"),
    "R-POR": ("E_X0B", "E_Y0B", "E_A0B", "E_B0B", "E_X0C", "E_Y0C", "E_A0C", "E_B0C"),
    "R-ANG": ("E_AB", "E_BB", "E_AC", "E_BC"),
}
ORIENTATION_ERRORS = ISO_TYPES["L-ANG"] + ISO_TYPES["R-ANG"] + ("E_CB", "E_CC", "E_A0B", "E_B0B", "E_A0C", "E_B0C")


def present_errors(model: ErrorModel) -> set[str]:
    """ISO names the model gives a non-zero value anywhere."""
    out = {n for n, v in model.constants.items() if v != 0}
    for n, f in model.functions.items():
        if np.any(f.values != 0) or (f.fit is not None and not f.fit.is_zero()):
            out.add(n)
    return out


def iso_types(model: ErrorModel, scope: str = "position") -> dict[str, list[str]]:
    """ISO/TR 16907 types covered by compensating ``model`` (composites L-VOL / R-VOL when all parts are there)."""
    names = present_errors(model)
    covered = [t for t, members in ISO_TYPES.items() if names & set(members)]
    if all(t in covered for t in ("L-POS", "L-STR", "L-SQU", "L-ANG")):
        covered.append("L-VOL")
    if all(t in covered for t in ("R-POS", "R-RAX", "R-POR", "R-ANG")):
        covered.append("R-VOL")
    if scope == "full" and names & set(ORIENTATION_ERRORS):
        covered.append("FOR")
    order = ["L-POS", "L-STR", "L-SQU", "L-ANG", "L-VOL", "R-POS", "R-RAX", "R-POR", "R-ANG", "R-VOL", "FOR"]
    partial = [t for t in ("L-VOL", "R-VOL") if t not in covered and any(p in covered for p in (
        ("L-POS", "L-STR", "L-SQU", "L-ANG") if t == "L-VOL" else ("R-POS", "R-RAX", "R-POR", "R-ANG")))]
    return {"covered": [t for t in order if t in covered], "partial": partial}


def _smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3 - 2 * x)


class Stats:
    """Running max / RMS of a non-negative quantity (streaming)."""

    def __init__(self) -> None:
        self.n, self.sq, self.max = 0, 0.0, 0.0

    def add(self, v: np.ndarray) -> None:
        if v.size:
            self.n += v.size
            self.sq += float(np.dot(v, v))
            self.max = max(self.max, float(v.max()))

    def as_dict(self, scale: float, digits: int = 4) -> dict:
        rms = (self.sq / self.n) ** 0.5 if self.n else 0.0
        return {"max": round(self.max * scale, digits), "rms": round(rms * scale, digits), "n": self.n}


class Compensator:
    """Corrected axis commands for nominal ones under an error model (see the module docstring)."""

    def __init__(self, model: ErrorModel, machine: Machine | None = None, scope: str = "position",
                 tool_length: float = 0.0, iterations: int = 1, cone: float = 2.0, outside: str = "hold"):
        if scope not in SCOPES:
            raise InputError(f"scope must be one of {SCOPES}, got {scope!r}")
        if iterations < 1:
            raise InputError(f"iterations must be >= 1, got {iterations}")
        if outside not in ("hold", "error"):
            raise InputError(f"outside must be 'hold' or 'error', got {outside!r}")
        for name, v in (("tool_length", tool_length), ("cone", cone)):
            if not np.isfinite(float(v)):
                raise InputError(f"{name} must be a finite number, got {v}")
        self.model = model
        self.machine = machine or load_machine(model.machine)
        self.scope, self.tool_length, self.iterations = scope, float(tool_length), int(iterations)
        self.cone, self.outside = float(cone), outside
        m = self.machine
        self._ev = ErrorEvaluator(model, m, outside)  # the one evaluator of error functions (mtcal.model.errormodel)
        self._lin = [i for i, k in enumerate(m.axis_kinds) if k == "linear"]
        # the orientation axes: the tilt and rotary axes of the inverse kinematics (spec [ik])
        self._rot = [m.index(m.ik_info["tilt_axis"]), m.index(m.ik_info["rotary_axis"])]
        self.zero = not present_errors(model)
        self.clipped_b = 0  # orientation steps clipped at the tilt axis' limits
        # scope position, first order: one generated pass gives the linear-axis step and both deviations
        self._fused = scope == "position" and self.iterations == 1
        if self._fused:  # |tool-tip deviation| = |J_lin step|: = |step| where the linear axes are orthonormal
            qs = np.random.default_rng(0).uniform(-300, 300, (16, len(m.axes)))
            for i, lim in enumerate(m.limits):
                if lim is not None:
                    qs[:, i] = np.random.default_rng(i).uniform(lim[0], lim[1], 16)
            jl = m.jacobian_axes(qs, None, self.tool_length, check=False)[:, :3, self._lin]
            self._lin_orthonormal = bool(np.abs(np.einsum("nki,nkj->nij", jl, jl) - np.eye(3)).max() < 1e-12)

    # ------------------------------------------------------------------ errors
    def errors(self, q: np.ndarray) -> np.ndarray:
        """Error vector (n, n_errors) at commanded axes (n, n_axes) by mtcal.model.errormodel.ErrorEvaluator
        (Fortran-ordered);
        outside a function's range: held (counted in ``outside_counts``) or an error."""
        return self._ev(q)

    @property
    def outside_counts(self) -> dict[str, int]:
        return self._ev.outside_counts

    # ------------------------------------------------------------------ correction
    def weight(self, q_nom: np.ndarray) -> np.ndarray:
        """Orientation-correction weight in [0, 1]: smoothstep of sigma_min / sin(cone) - 1, where sigma_min is the
        smaller singular value of d(tool axis)/d(B, C) per degree over pi/180.  Near B = 0 sigma_min is the sine of
        the angle between tool axis and C axis (the cone); near B = 180 (tool axis at the edge of the reachable
        cone, k = 0) it vanishes as well.  0: position only, 1: full correction."""
        if self.cone <= 0:
            return np.ones(len(q_nom))
        J = self.machine.jacobian_axes(q_nom, None, self.tool_length, check=False)[:, 3:, self._rot]
        smin = np.linalg.svd(J, compute_uv=False)[:, -1] / (np.pi / 180)
        sc = np.sin(np.radians(self.cone))
        return _smoothstep((smin - sc) / sc)

    def correct(self, q_nom, return_initial: bool = False):
        """Corrected commands (n, 5) for nominal axes (n, 5); with ``return_initial`` also the size of the
        uncorrected deviation (n, 2): |tool-tip deviation| (mm) and |tool-axis deviation| (rad), first order
        (exact when iterations > 1)."""
        q_nom = np.asarray(q_nom, dtype=float)
        single = q_nom.ndim == 1
        q_nom = np.atleast_2d(q_nom)
        out = np.empty_like(q_nom)
        dev0 = np.empty((len(q_nom), 2))
        e0 = None if self.zero else self.errors(q_nom)  # once for all blocks (fewer interpolation calls)
        if self._fused and not self.zero:
            qf = np.asfortranarray(q_nom)  # the generated code reads columns
            out[:] = q_nom
            for s in range(0, len(q_nom), BLOCK):
                qb = qf[s: s + BLOCK]
                r = self.machine.correction_first_order(qb, e0[s: s + BLOCK], self.tool_length, check=False)
                step = r[:, :3]
                out[s: s + BLOCK, self._lin] += step
                if not self._lin_orthonormal:
                    jq = self.machine.jacobian_axes(qb, None, self.tool_length, check=False)
                    step = np.einsum("nij,nj->ni", jq[:, :3, self._lin],
                                     step)
                dev0[s: s + BLOCK, 0] = np.sqrt(np.einsum("ij,ij->i", step, step))
                dev0[s: s + BLOCK, 1] = np.sqrt(np.einsum("ij,ij->i", r[:, 3:], r[:, 3:]))
        else:
            for s in range(0, len(q_nom), BLOCK):
                out[s: s + BLOCK], d = self._correct_block(
                    q_nom[s: s + BLOCK], None if e0 is None else e0[s: s + BLOCK])
                dev0[s: s + BLOCK, 0] = np.linalg.norm(d[:, :3], axis=1)
                dev0[s: s + BLOCK, 1] = np.linalg.norm(d[:, 3:], axis=1)
        if single:
            out, dev0 = out[0], dev0[0]
        return (out, dev0) if return_initial else out

    def _correct_block(self, q0: np.ndarray, e0: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
        tl = self.tool_length
        if self.zero:
            return q0.copy(), np.zeros((len(q0), 6))
        q = q0.copy()
        w = self.weight(q0) if self.scope == "full" else None
        target = None
        dev0 = None
        for it in range(self.iterations):
            if it == 0:  # first order: generated deviation and nominal Jacobian at the nominal command
                r = self.machine.deviation(q0, e0, 1, tl, check=False)
                J = self.machine.jacobian_axes(q0, None, tl, check=False)
                dev0 = r
            else:  # exact pose and Jacobian with the errors at the current command
                if target is None:
                    target = self.machine.forward(q0, None, tl, check=False)
                pose, J = self.machine.forward_with_jacobian(q, self.errors(q), tl, check=False)
                r = pose - target
            if self.scope == "full":
                # B, C first (first order; the blend weight on the first step, later steps only where w = 1);
                # then X, Y, Z from the exact pose at the new B, C: a C step of up to ~1e-3 rad swings a point
                # 300 mm off the C axis by ~0.1 um to second order
                q = q + self._step(q, J, r, w if it == 0 else (w >= 1).astype(float), position=False)
                r = self._exact(q, q0)
                J = self.machine.jacobian_axes(q, None, tl, check=False)
            q = q + self._step(q, J, r, None)
        return q, dev0

    def _exact(self, q: np.ndarray, q0: np.ndarray) -> np.ndarray:
        """Exact pose residual (n, 6) of commands q against the nominal pose of q0."""
        m, tl = self.machine, self.tool_length
        return m.forward(q, self.errors(q), tl, check=False) - m.forward(q0, None, tl, check=False)

    def _step(self, q: np.ndarray, J: np.ndarray, r: np.ndarray, w: np.ndarray | None,
              position: bool = True) -> np.ndarray:
        """Axis step that cancels the pose residual r (n, 6) to first order (J (n, 6, 5)): B, C from the
        orientation rows when w (orientation weights) is given, X, Y, Z from the position rows if ``position``
        (B, C: the machine's tilt and rotary axes; X, Y, Z its linear axes)."""
        d = np.zeros_like(q)
        rp = r[:, :3]
        ti, rot = self._rot[0], self._rot
        if w is not None:
            Jo = J[:, 3:][:, :, rot]  # d(i, j, k) / d(B, C): two columns, both orthogonal to the tool axis
            Q, R = np.linalg.qr(Jo)  # least squares: R dBC = Q^T (-r_o)
            rhs = -np.einsum("nij,ni->nj", Q, r[:, 3:])
            ok = w > 0
            dbc = np.zeros((len(q), 2))
            if ok.any():
                dbc[ok] = np.linalg.solve(R[ok], rhs[ok][..., None])[..., 0] * w[ok, None]
            lo, hi = self.machine.limits[ti] or (-np.inf, np.inf)
            nb = np.clip(q[:, ti] + dbc[:, 0], lo, hi)
            clipped = nb != q[:, ti] + dbc[:, 0]
            if clipped.any():
                self.clipped_b += int(clipped.sum())
                dbc[:, 0] = nb - q[:, ti]
            d[:, rot] = dbc
            rp = rp + np.einsum("nij,nj->ni", J[:, :3][:, :, rot], dbc)
        if not position:
            return d
        d[:, self._lin] = np.linalg.solve(J[:, :3][:, :, self._lin], -rp[..., None])[..., 0]  # a rotation: cond = 1
        return d

    def _slopes(self) -> np.ndarray:
        """Per axis (n_axes,): bound on d|correction|/d(axis) from the model's error slopes (mm per mm or per deg)."""
        if hasattr(self, "_slope_cache"):
            return self._slope_cache
        lever = 800.0 + abs(self.tool_length)  # mm: largest distance of the tool tip from an angular error's origin
        out = np.zeros(len(self.machine.axes))
        for name, ei, ai, f, lo, hi in self._ev.funcs:
            a, b = (0.0, 360.0) if not np.isfinite(lo) else (lo, hi)
            x = np.union1d(np.linspace(a, b, 4001), f.positions[(f.positions >= a) & (f.positions <= b)])
            s = np.abs(np.diff(f(x, "hold")) / np.diff(x)).max()
            out[ai] += s * (1.0 if name[2] in "XYZ" else lever)
        self._slope_cache = out
        return out

    def mid_bound(self, qa: np.ndarray, qb: np.ndarray) -> np.ndarray:
        """Upper bound (mm) of the mid-segment tool-tip error of a linearly interpolated move whose end points are
        corrected: 1/2 sum_a slope_a |dq_a| (Lipschitz bound of the error functions, kinks of tables included;
        angular errors times an 800 mm lever) plus |deviation| (1 - cos(dphi/2)) <= 0.2 mm dphi^2 / 8 for the
        deviation vector turned by the rotary step dphi (rad).  Moves under the tolerance by this bound skip
        the exact mid-segment evaluation."""
        dq = np.abs(qb - qa)
        rot = np.radians(dq[:, self._rot].sum(axis=1))
        return 0.5 * dq @ self._slopes() + 0.2 * rot * rot / 8

    def largest_errors(self, q: np.ndarray, k: int = 3) -> str:
        """The k largest model errors at axes q (n_axes,) (mm and rad; angles ranked at a 1 m lever), for messages."""
        e = self.errors(np.asarray(q, dtype=float)[None])[0]
        length = np.array([n[2] in "XYZ" for n in self.machine.error_names])
        size = np.abs(e) * np.where(length, 1.0, 1000.0)
        top = [i for i in np.argsort(-size, kind="stable")[:k].tolist() if size[i] > 0]
        return ", ".join(f"{self.machine.error_names[i]} = {e[i]:.6g} {'mm' if length[i] else 'rad'}" for i in top)

    def residual(self, q_cmd: np.ndarray, q_nom: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Exact error-inclusive residual of commands: tool-tip error (n, 3) mm and tool-axis angle (n,) rad."""
        q_cmd, q_nom = np.atleast_2d(q_cmd), np.atleast_2d(q_nom)
        dp = np.empty((len(q_cmd), 3))
        ang = np.empty(len(q_cmd))
        e = self.errors(q_cmd)
        for s in range(0, len(q_cmd), BLOCK):
            a, b = q_cmd[s: s + BLOCK], q_nom[s: s + BLOCK]
            p = self.machine.forward(a, e[s: s + BLOCK], self.tool_length, check=False)
            t = self.machine.forward(b, None, self.tool_length, check=False)
            dp[s: s + BLOCK] = p[:, :3] - t[:, :3]
            ang[s: s + BLOCK] = 2 * np.arcsin(np.clip(np.linalg.norm(p[:, 3:] - t[:, 3:], axis=1) / 2, 0, 1))
        return dp, ang


def thesis_model(model: ErrorModel) -> ErrorModel:
    """The thesis' compensation model (sec. 3.5): the angular errors of the linear axes neglected."""
    drop = set(ISO_TYPES["L-ANG"])
    return ErrorModel(model.machine, {k: v for k, v in model.constants.items() if k not in drop},
                      {k: f for k, f in model.functions.items() if k not in drop}, dict(model.meta))


def example_model(machine: Machine | None = None, seed: int = 6) -> ErrorModel:
    """A synthetic error model of the thesis' magnitudes (tens of um, tens of urad) for demos, tests, benchmarks.

    Linear axes: tables over [-400, 400] mm every 25 mm (smooth random curves, zero at 0); a rotary axis with
    limits: a table over its limits every 15 deg; one without: harmonic fits (periodic); the machine's
    squareness and location constants.  (DMU 50: B table over [0, 180], C harmonic.)
    """
    m = machine or load_machine()
    rng = np.random.default_rng(seed)
    funcs, consts = {}, {}
    parts = "XYZABC"  # ISO components of the six error motions

    def curve(x, amp, period):
        ph = rng.uniform(0, 2 * np.pi, 3)
        y = sum(a * np.sin(2 * np.pi * x / (period / (h + 1)) + p) for h, (a, p) in
                enumerate(zip(amp * rng.uniform(0.3, 1.0, 3) / np.arange(1, 4), ph)))
        y = y + amp * rng.uniform(-1, 1) * x / np.abs(x).max()
        return y - np.interp(0.0, x, y)

    xl = np.arange(-400.0, 400.0 + 1e-9, 25.0)
    for ax in m.linear_axes:
        own = m.positioning_errors[ax][2]
        for c in parts[:3]:
            funcs[f"E_{c}{ax}"] = ErrorFunction(ax, xl, curve(xl, 0.015 if c == own else 0.008, 900.0))
        for c in parts[3:]:
            funcs[f"E_{c}{ax}"] = ErrorFunction(ax, xl, curve(xl, 30e-6, 900.0))
    for ax in m.rotary_axes:
        lim = m.limits[m.index(ax)]
        if lim:
            xb = np.arange(lim[0], lim[1] + 1e-9, 15.0)
            for c, amp in zip(parts, (0.012, 0.012, 0.008, 30e-6, 30e-6, 40e-6)):
                funcs[f"E_{c}{ax}"] = ErrorFunction(ax, xb, curve(xb, amp, 360.0))
            continue
        xc = np.arange(0.0, 360.0 + 1e-9, 15.0)
        for c, amp in zip(parts, (0.010, 0.010, 0.006, 25e-6, 25e-6, 35e-6)):
            a0 = float(rng.normal(0, amp / 3))
            cos, sin = (amp * rng.uniform(-0.5, 0.5, 3)).tolist(), (amp * rng.uniform(-0.5, 0.5, 3)).tolist()
            fit = {"kind": "harmonic", "period": 360.0, "a0": a0, "cos": cos, "sin": sin}
            f = ErrorFunction(ax, xc, np.zeros_like(xc), fit)
            f.values = f(xc)
            funcs[f"E_{c}{ax}"] = f
    sizes = {"E_C0Y": 25e-6, "E_B0Z": -18e-6, "E_A0Z": 12e-6}  # the DMU 50's; others by their place in the group
    for i, n in enumerate(m.error_groups["squareness"]):
        consts[n] = sizes.get(n, (25e-6, -18e-6, 12e-6)[i % 3])
    for i, n in enumerate(m.error_groups["location"]):  # E_X0R, E_Y0R (mm), E_A0R, E_B0R (rad) per rotary axis
        k, r = i % 4, i // 4
        consts[n] = ((0.008, -0.006, 20e-6, -15e-6), (0.010, 0.007, -12e-6, 18e-6))[r % 2][k]
    return ErrorModel(m.name, consts, funcs, {"source": f"mtcal.compensate.core.example_model(seed={seed})"})


# ---------------------------------------------------------------------------------------------- NC programs
def _read_blocks(fin, size: int):
    """("text", block, lines, characters) for blocks of whole lines of about ``size`` characters."""
    while True:
        text = fin.read(size)
        if not text:
            return
        if text[-1] != "\n":  # complete the last line (also a CR LF cut after the CR)
            text += fin.readline()
        yield "text", text, gcode.count_lines(text), len(text)


@dataclass
class Guard:
    """Plausibility guard on what is written (nothing implausible reaches a machine): every written axis value is
    finite, every correction (written minus nominal command) is within ``max_mm`` on a linear axis (mm) and
    ``max_deg`` on a rotary axis (deg), and every evaluated predicted residual of the exact model (tool tip at the
    written points, mid-segment of feed moves after subdivision) is finite and within ``tolerance`` (mm).  A
    violation raises InputError naming the file, the line and the values; the caller raises it before the output
    is renamed into place, so no output file appears.  Defaults: ``MAX_CORRECTION_MM``,
    ``MAX_ROTARY_CORRECTION_DEG`` (justified there)."""

    max_mm: float
    max_deg: float
    tolerance: float

    def written(self, comp: Compensator, q_w: np.ndarray, q_nom: np.ndarray, src: str, lines: np.ndarray) -> None:
        """Refuse non-finite written axes or corrections beyond the bounds (q_w, q_nom (n, 5), mm and deg; ``lines``:
        the 1-based line of each row in ``src``)."""
        m = comp.machine
        linear = np.array([k == "linear" for k in m.axis_kinds])
        bound = np.where(linear, self.max_mm, self.max_deg)
        bad = ~(np.abs(q_w - q_nom) <= bound)  # NaN and inf included
        if not bad.any():
            return
        r, a = (int(v[0]) for v in np.nonzero(bad))
        ax, unit = m.axes[a], "mm" if linear[a] else "deg"
        if not np.isfinite(q_w[r, a]):
            msg = f"the corrected {ax} would be {q_w[r, a]} (not a finite number; tool length {comp.tool_length})"
        else:
            opt = "--max-correction" if linear[a] else "--max-rotary-correction"
            msg = (f"the correction of {ax} by {q_w[r, a] - q_nom[r, a]:+.4f} {unit} ({ax}{q_nom[r, a]:.4f} -> "
                   f"{ax}{q_w[r, a]:.4f}) exceeds the plausibility bound {bound[a]:g} {unit} ({opt})")
        errs = comp.largest_errors(q_nom[r]) if np.isfinite(q_nom[r]).all() else ""
        raise InputError(f"{src}, line {lines[r]}: {msg}; largest model errors there: {errs or 'none'} (are the "
                         "model's values in its stated units?); nothing written")

    def residual(self, err: np.ndarray, src: str, lines: np.ndarray, what: str) -> None:
        """Refuse a predicted residual (mm, (n,)) above the tolerance or not finite."""
        bad = ~(err <= self.tolerance)
        if not bad.any():
            return
        r = int(np.flatnonzero(bad)[0])
        raise InputError(f"{src}, line {lines[r]}: the predicted {what} error of the compensated program would be "
                         f"{err[r] * 1e3:.4g} um, above the tolerance {self.tolerance * 1e3:g} um (too few decimals "
                         "written (--precision), a tolerance below what they can hold, or an implausible model); "
                         "nothing written")


@dataclass
class Report:
    """What a compensation run did and the predicted (model) accuracy of the written commands."""

    lines: int = 0
    moves: int = 0
    lines_changed: int = 0
    lines_inserted: int = 0
    subdivided_moves: int = 0
    uncompensated_rapids: list[int] = field(default_factory=list)
    position: Stats = field(default_factory=Stats)       # |tool-tip residual|, mm (exact model, evaluated points)
    orientation: Stats = field(default_factory=Stats)    # tool-axis residual, rad (controllable points)
    orientation_all: Stats = field(default_factory=Stats)
    before_position: Stats = field(default_factory=Stats)     # first order, every move
    before_orientation: Stats = field(default_factory=Stats)
    mid_position: Stats = field(default_factory=Stats)   # mid-segment residual of feed moves (after subdivision)
    mid_bounded: int = 0  # feed moves whose mid-segment error is below the tolerance by the Lipschitz bound
    in_cone: int = 0
    blended: int = 0
    max_c_correction: float = 0.0
    residual_every: int = 1  # the exact residual is evaluated on every k-th move (and every inserted point)

    def residual_evaluated_on(self) -> str:
        if self.residual_every <= 1:
            return "all moves"
        return f"every {self.residual_every}th move (and every point of a subdivided move)"


class ProgramCompensator:
    """Streams an NC program (G-code or CL data) through a Compensator, block by block (memory stays flat).

    G-code blocks of whole lines take a vectorised byte-level path (``gcode.scan_block`` / ``render_block``) when
    their meaning is plain (absolute mm coordinates, G0/G1, comments, other words passed through), else the general
    line-piece path (``gcode.parse_chunk``); both write the same bytes.  The exact error-inclusive residual of what is
    written is evaluated on every ``residual_every``-th move (counted through the whole program, so the sample does
    not depend on the block size) and on every point of a subdivided move; the uncompensated deviation (first order)
    on every move."""

    def __init__(self, comp: Compensator, tolerance: float = 0.001, precision: int | None = None,
                 chunk_lines: int = 20000, max_subdivisions: int = 256,
                 progress: Callable[[int, int], None] | None = None, residual_every: int = RESIDUAL_EVERY,
                 max_correction: float = MAX_CORRECTION_MM, max_rotary_correction: float = MAX_ROTARY_CORRECTION_DEG,
                 allow_subprograms: bool = False):
        self.comp = comp
        self.tolerance = float(tolerance)
        p = 4 if precision is None else int(precision)
        for name, v in (("tolerance", self.tolerance), ("max_correction", max_correction),
                        ("max_rotary_correction", max_rotary_correction)):
            if not (np.isfinite(v) and v > 0):
                raise InputError(f"{name} must be a positive finite number, got {v}")
        if p < 0:
            raise InputError(f"precision must be >= 0 decimals, got {p}")
        self.guard = Guard(float(max_correction), float(max_rotary_correction), self.tolerance)
        self.min_decimals = (p, p + 1, p)  # mm, inch, deg
        self.chunk_lines = int(chunk_lines)
        self.chunk_chars = max(1024, 48 * self.chunk_lines)  # G-code blocks: about chunk_lines lines
        self.max_sub = int(max_subdivisions)
        self.progress = progress
        if int(residual_every) < 1:
            raise InputError(f"residual_every must be >= 1, got {residual_every}")
        self.report = Report(residual_every=int(residual_every))
        self.fast = True  # byte-level path for plain blocks (False: every block through parse_chunk)
        m = comp.machine
        self.words = replace(gcode.words(m), allow_subprograms=allow_subprograms)  # the machine's axis words
        self._ti, self._ri = m.index(m.ik_info["tilt_axis"]), m.index(m.ik_info["rotary_axis"])

    # ---------------------------------------------------------------- driver
    def run(self, src: str | os.PathLike, dst: str | os.PathLike, kind: str = "auto") -> Report:
        src, dst = Path(src), Path(dst)
        if kind == "auto":
            kind = "cl" if src.suffix.lower() in (".cl", ".cls", ".apt") else "gcode"
        if kind not in ("gcode", "cl"):
            raise InputError(f"input kind must be gcode or cl, got {kind!r}")
        total = src.stat().st_size
        enc = gcode.ENCODING
        with open(src, encoding=enc, newline="") as fin, atomic_open(dst, "wb") as fout:
            self._state = gcode.ModalState.for_words(self.words)
            self._prev: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # nominal, written mm, units
            self._prev_mm = self._state.position.copy()  # linear axes unknown, rotary at 0
            self._src, self._done, self._moves_seen = str(src), 0, 0
            self._cl_lines: np.ndarray | None = None  # CL data: the file line of each generated block
            first = 1
            if kind == "cl":
                fout.write(f"%\n(mtcal compensate: CL data {src.name}, scope {self.comp.scope})\nG90 G21\n"
                           .encode(enc))
                self._first_cl = True
                while True:
                    lines = list(itertools.islice(fin, self.chunk_lines))
                    if not lines:
                        break
                    self._refuse_binary("".join(lines), first)
                    fout.write(self._cl_chunk(lines, first).encode(enc))
                    first += len(lines)
                    self.report.lines += len(lines)
                    self._done += sum(map(len, lines))
                    if self.progress:
                        self.progress(self._done, total)
                fout.write(b"M30\n%\n")
            else:
                for _, text, n, size in _read_blocks(fin, self.chunk_chars):
                    self._refuse_binary(text, first)
                    fout.write(self._gcode_block(text, first))
                    first += n
                    self.report.lines += n
                    self._done += size
                    if self.progress:
                        self.progress(self._done, total)
            if self.report.moves == 0:  # raised before the output is renamed into place: no file appears
                what = "CL points (x y z i j k)" if kind == "cl" else "moves (G0/G1 blocks with axis words)"
                raise InputError(f"{src}: no {what} found{' (empty file)' if total == 0 else ''}; nothing to "
                                 "compensate, nothing written")
        return self.report

    def _refuse_binary(self, text: str, first: int) -> None:
        """A NUL byte: not a text program (a binary or corrupted file)."""
        k = text.find("\x00")
        if k >= 0:
            raise InputError(f"{self._src}, line {first + gcode.count_lines(text[:k + 1]) - 1}: NUL byte: not a text "
                             "NC program (binary or corrupted file)")

    # ---------------------------------------------------------------- G-code
    def _gcode_block(self, text: str, first: int) -> bytes:
        """Output bytes of a block of whole lines: the byte-level path when the block is plain, else by lines."""
        blk = gcode.scan_block(text, self._state, first, self.min_decimals, self.words) if self.fast else None
        if blk is None:
            return self._gcode_chunk(io.StringIO(text, newline="").readlines(), first).encode(gcode.ENCODING)
        out = self._compensate_rows(blk, first)
        if out is None:
            return blk.buf.tobytes()
        return self._render_fast(blk, *out)

    def _gcode_chunk(self, lines: list[str], first: int, exact: np.ndarray | None = None) -> str:
        ch = gcode.parse_chunk(lines, self._state, first, self._src, self.min_decimals, self.words)
        out = self._compensate_rows(ch, first, exact)
        if out is None:
            return "".join(lines)
        return self._render(ch, *out)

    def _compensate_rows(self, ch, first: int, exact: np.ndarray | None = None):
        """Corrected, rounded commands of the motion rows of a parsed chunk or block, the subdivisions and the
        report figures: (units, written mm, known, subdivisions, scale, 10**decimals), None without rows."""
        comp, rep = self.comp, self.report
        m = len(ch.rows)
        if m == 0:
            return None
        if exact is not None:  # CL data: the nominal axes from the inverse kinematics, unrounded
            ch.axes[:] = exact
        rep.moves += m
        q_nom = ch.axes
        lines = self._cl_lines if self._cl_lines is not None else first + ch.rows
        for i, lim in enumerate(comp.machine.limits):  # the spec's soft limits (the tilt axis on the shipped specs)
            if lim is None:
                continue
            bad = (q_nom[:, i] < lim[0]) | (q_nom[:, i] > lim[1])
            if bad.any():
                r = int(np.flatnonzero(bad)[0])
                raise InputError(f"{self._src}, line {lines[r]}: {comp.machine.axes[i]} = {q_nom[r, i]:.10g} "
                                 f"{comp.machine.unit(comp.machine.axes[i])} is outside its range "
                                 f"[{lim[0]:g}, {lim[1]:g}]")
        unknown = np.isnan(q_nom).any(axis=1)
        if unknown.any():
            feed = unknown & (ch.motion == 1)
            if feed.any():
                r = int(np.flatnonzero(feed)[0])
                miss = "".join(a for a, u in zip(self.words.letters, np.isnan(q_nom[r])) if u)
                after = ch.fresh is not None and bool(ch.fresh[r])
                raise InputError(f"{self._src}, line {lines[r]}: feed move while {miss} is not known yet "
                                 + ("(the machine-coordinate move before it, G28 / G30 / G53, left them in machine "
                                    "coordinates: program them again before the G1)" if after else
                                    "(program every linear axis before the first G1)"))
            rep.uncompensated_rapids.extend(lines[unknown].tolist())
        known = ~unknown
        all_known = bool(known.all())
        if ch.inch.any():
            scale = np.where(ch.inch[:, None] & self.words.linear, gcode.INCH, 1.0)
        else:
            scale = np.ones((m, 5))
        f = _P10[ch.decimals] if ch.decimals.max() < len(_P10) else 10.0 ** ch.decimals
        # corrected commands, rounded as written (program units), back in mm/deg
        if all_known:
            q_cmd, dev0 = comp.correct(q_nom, return_initial=True)
        else:
            q_cmd = q_nom.copy()
            dev0 = np.zeros((0, 2))
            if known.any():
                q_cmd[known], dev0 = comp.correct(q_nom[known], return_initial=True)
        rep.before_position.add(dev0[:, 0])
        rep.before_orientation.add(dev0[:, 1])
        mm = not ch.inch.any()  # scale 1: the same numbers without the divisions
        units = (np.round(q_cmd * f) if mm else np.round(q_cmd / scale * f)) / f + 0.0
        if not all_known:
            units[unknown] = q_nom[unknown] / scale[unknown]  # passed through as programmed
        q_w = units.copy() if mm else units * scale
        # a word missing from a block is only added when the correction moves that axis by half a digit or more
        # from what the machine holds; otherwise the held value stays (also across G20/G21 rounding)
        prev = np.vstack([self._prev_mm[None], q_w[:-1]])
        hold = ~ch.present & known[:, None] & (np.abs(q_cmd - prev) <= (0.5 / f if mm else 0.5 / f * scale))
        if hold.any():
            q_w[hold] = np.nan
            filled = np.vstack([self._prev_mm[None], q_w])
            ix = np.where(np.isnan(filled), 0, np.arange(m + 1)[:, None])
            np.maximum.accumulate(ix, axis=0, out=ix)
            q_w = np.where(hold, filled[ix, np.arange(5)][1:], q_w)
            units = np.where(hold, q_w / scale, units)
        self._hold = hold
        self.guard.written(comp, q_w[known], q_nom[known], self._src, lines[known])
        # subdivision of feed moves whose mid-segment error exceeds the tolerance
        subs = self._subdivide(ch, q_nom, q_w, known, scale, f, lines)
        # residual of what is written: every k-th move (global count) and every inserted point
        k = rep.residual_every
        kn = np.flatnonzero(known)
        ev = kn if k == 1 else kn[(self._moves_seen + np.arange(len(kn))) % k == 0]
        self._moves_seen += len(kn)
        qw = np.concatenate([q_w[ev]] + [s[1] for s in subs.values()])
        qn = np.concatenate([q_nom[ev]] + [s[0] for s in subs.values()])
        if len(qw):
            dp, ang = comp.residual(qw, qn)
            err = np.sqrt(np.einsum("ij,ij->i", dp, dp))
            self.guard.residual(err, self._src, np.concatenate([lines[ev]] + [np.full(len(s[1]), lines[r])
                                                                            for r, s in subs.items()]), "tool-tip")
            rep.position.add(err)
            rep.orientation_all.add(ang)
        if comp.scope == "full" and (len(kn) or subs):
            qw_all = np.concatenate([q_w[kn]] + [s[1] for s in subs.values()])
            qn_all = np.concatenate([q_nom[kn]] + [s[0] for s in subs.values()])
            w_all = comp.weight(qn_all)
            rep.in_cone += int((w_all <= 0).sum())
            rep.blended += int(((w_all > 0) & (w_all < 1)).sum())
            dc = np.abs(qw_all[:, self._ri] - qn_all[:, self._ri]).max()
            rep.max_c_correction = max(rep.max_c_correction, float(dc))
            if len(qw):
                w = w_all if k == 1 else comp.weight(qn)
                rep.orientation.add(ang[w >= 1])
        return units, q_w, known, subs, scale, f

    def _subdivide(self, ch, q_nom, q_w, known, scale, f, lines
                   ) -> dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """{row: (nominal (n, 5), written mm (n, 5), written units (n, 5))} for feed moves split into n pieces
        (the last piece ends at the row's own point).  Moves that start after a machine-coordinate line (G28, G53:
        start unknown) are not split."""
        comp, rep = self.comp, self.report
        prev_n = np.vstack([self._prev[0][None] if self._prev else np.full((1, 5), np.nan), q_nom[:-1]])
        prev_w = np.vstack([self._prev[1][None] if self._prev else np.full((1, 5), np.nan), q_w[:-1]])
        self._prev = (q_nom[-1].copy(), q_w[-1].copy(), None)
        cand = (ch.motion == 1) & known & ~np.isnan(prev_n).any(axis=1)
        if ch.fresh is not None:
            cand &= ~ch.fresh
        subs: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        if comp.zero or not cand.any():
            return subs
        idx = np.flatnonzero(cand)
        bound = comp.mid_bound(prev_n[idx], q_nom[idx])
        skip = bound <= self.tolerance
        rep.mid_bounded += int(skip.sum())
        idx = idx[~skip]
        if not len(idx):
            return subs
        dp, _ = comp.residual((prev_w[idx] + q_w[idx]) / 2, (prev_n[idx] + q_nom[idx]) / 2)
        err = np.linalg.norm(dp, axis=1)
        over = err > self.tolerance
        rep.mid_position.add(err[~over])
        # split moves: all moves of a round evaluated together; a move is done when its mid-segment errors are
        # within the tolerance, at max_subdivisions or after 6 rounds (then n doubles)
        rows = idx[over]
        ns = np.minimum(self.max_sub, np.maximum(2, np.ceil(np.sqrt(err[over] / self.tolerance)) + 1)).astype(np.int64)
        done: dict[int, tuple] = {}
        for round_ in range(6):
            if not len(rows):
                break
            mi = np.repeat(np.arange(len(rows)), ns)  # move of each piece
            first = np.cumsum(ns) - ns
            k = np.arange(len(mi)) - first[mi] + 1
            t = (k / ns[mi])[:, None]
            a, b = prev_n[rows][mi], q_nom[rows][mi]
            sn = a + t * (b - a)
            sc = comp.correct(sn)
            sc_scale, sc_f = scale[rows][mi], f[rows][mi]
            su = np.round(sc / sc_scale * sc_f) / sc_f + 0.0
            last = first + ns - 1
            su[last] = q_w[rows] / scale[rows]  # the row's own point, as already rounded
            sw = su * sc_scale
            an = np.empty_like(sn)
            aw = np.empty_like(sw)
            an[1:], aw[1:] = sn[:-1], sw[:-1]
            an[first], aw[first] = prev_n[rows], prev_w[rows]
            dpm, _ = comp.residual((aw + sw) / 2, (an + sn) / 2)
            em = np.sqrt(np.einsum("ij,ij->i", dpm, dpm))
            emax = np.maximum.reduceat(em, first)
            fin = (emax <= self.tolerance) | (ns >= self.max_sub) | (round_ == 5)
            for j in np.flatnonzero(fin).tolist():
                sl = slice(int(first[j]), int(first[j] + ns[j]))
                done[int(rows[j])] = (em[sl], sn[sl], sw[sl], su[sl])
            rows, ns = rows[~fin], np.minimum(self.max_sub, 2 * ns[~fin])
        for r in sorted(done):
            em, sn, sw, su = done[r]
            at = np.full(len(em), lines[r])
            self.guard.written(comp, sw, sn, self._src, at)
            self.guard.residual(em, self._src, at, f"mid-segment (move split into {len(em)} pieces)")
            rep.mid_position.add(em)
            rep.subdivided_moves += 1
            subs[r] = (sn[:-1], sw[:-1], su)
        return subs

    def _render(self, ch, units, q_w, known, subs, scale, f) -> str:
        """Output text of a chunk: changed numbers replaced, missing words added, continuation lines inserted."""
        rep = self.report
        prev_mm = np.vstack([self._prev_mm[None], q_w[:-1]])  # what the machine holds before each row, mm/deg
        given_r = np.round(ch.given * f) / f
        changed = ch.present & (units != given_r) & known[:, None]
        added = ~ch.present & known[:, None] & ~self._hold & ~np.isnan(q_w)
        need = changed.any(axis=1) | added.any(axis=1)
        slow = ~ch.absolute
        if subs:
            slow[list(subs)] = True
        pieces, numidx = ch.pieces, ch.numidx
        # common case (absolute, not subdivided): vectorised choice of cells, one format per changed number
        cells = changed & ~slow[:, None]
        if cells.any():
            r_, a_ = np.nonzero(cells)
            dec, val, idx = ch.decimals[r_, a_], units[r_, a_], numidx[r_, a_]
            for d in np.unique(dec).tolist():  # one %-format call per number of decimals (C loop)
                sel = dec == d
                strs = ((f"%.{d}f\n" * int(sel.sum())) % tuple(val[sel].tolist()))[:-1].split("\n")
                for j, s in zip(idx[sel].tolist(), strs):
                    pieces[j] = s
        rows_added = np.flatnonzero(added.any(axis=1) & ~slow).tolist()
        rows_slow = np.flatnonzero(slow).tolist()
        U = units.tolist() if rows_added or rows_slow else []
        D = ch.decimals.tolist() if rows_added or rows_slow else []
        for r in rows_added:
            d, u = D[r], U[r]
            line = ch.lines[int(ch.rows[r])]
            gcode.edit(ch, r, {}, [(a, "%.*f" % (d[a], u[a])) for a in np.flatnonzero(added[r]).tolist()],
                       " " if " " in line else "")
        rep.lines_changed += int((need & ~slow).sum())
        # incremental rows and subdivided moves: row by row
        Pm = prev_mm.tolist() if rows_slow else []
        HOLD = self._hold.tolist() if rows_slow else []
        for r in rows_slow:
            line = ch.lines[int(ch.rows[r])]
            new, add, cont, sep, feed = self._slow_row(ch, r, line, U, D, Pm, HOLD, scale, subs)
            if new or add or cont:
                gcode.edit(ch, r, new, add, sep, cont)
                if feed:
                    gcode.replace_feed(ch, r, feed)
                rep.lines_changed += 1
                rep.lines_inserted += len(cont)
        self._prev_mm = q_w[-1].copy()
        return "".join(pieces)

    def _slow_row(self, ch, r, line, U, D, Pm, HOLD, scale, subs):
        """Words of an incremental row or a subdivided move, row by row: (new numbers {axis: text}, added words,
        continuation lines, separator, new F of the row or None).  Inverse-time feed (G93, F = 1/minutes per
        block): the n pieces of a split move are equal fractions 1/n of it, so each block carries F * n (a piece
        merged into the next, having no word of its own, adds its fraction there)."""
        F = gcode.fmt
        sep = " " if " " in line else ""
        pts = [U[r]] if r not in subs else subs[r][2].tolist()
        dec, absolute = D[r], bool(ch.absolute[r])
        sc = scale[r].tolist()
        ref = [v / s for v, s in zip(Pm[r], sc)]  # previous written point in this row's units
        first_pt = pts[0]
        new, add = {}, []
        pres, g = ch.present[r].tolist(), ch.given[r].tolist()
        for a in range(5):
            v = first_pt[a] if absolute else first_pt[a] - ref[a]
            if v != v:  # NaN: axis not known (uncompensated rapid)
                continue
            v = round(v, dec[a]) + 0.0
            if pres[a]:
                if abs(v - round(g[a], dec[a])) > 0.5 * 10.0 ** -dec[a]:
                    new[a] = F(v, dec[a])
            elif r in subs:  # the first piece of a split move: add what differs from the held value
                if abs(first_pt[a] - ref[a]) > 0.5 * 10.0 ** -dec[a]:
                    add.append((a, F(v, dec[a])))
            elif not HOLD[r][a] and (absolute or v != 0):
                add.append((a, F(v, dec[a])))
        inv = ch.feed[r] if ch.feed is not None and r in subs and ch.feed[r] == ch.feed[r] else None
        cont, last, pieces = [], first_pt, 0
        for p in pts[1:]:
            words = []
            pieces += 1
            for a in range(5):
                if abs(p[a] - last[a]) > 0.5 * 10.0 ** -dec[a]:
                    v = p[a] if absolute else p[a] - last[a]
                    words.append(f"{self.words.letters[a]}{F(round(v, dec[a]) + 0.0, dec[a])}")
            last = p
            if words:
                if inv is not None:
                    words.append(f"F{F(inv * len(pts) / pieces, FEED_DECIMALS)}")
                    pieces = 0
                cont.append((sep or " ").join(words))
        return new, add, cont, sep, None if inv is None else F(inv * len(pts), FEED_DECIMALS)

    def _render_fast(self, blk, units, q_w, known, subs, scale, f) -> bytes:
        """Output bytes of a block (byte-level path): the same edits as ``_render``, changed numbers written from
        integer digits in one go, lines with added words or inserted pieces rewritten as text."""
        rep = self.report
        given_r = np.round(blk.given * f) / f
        kn = known[:, None]
        changed = blk.present & (units != given_r) & kn
        added = ~blk.present & kn & ~self._hold & ~np.isnan(q_w)
        add_rows = added.any(axis=1)
        need = changed.any(axis=1) | add_rows
        sub_rows = np.zeros(len(units), dtype=bool)
        if subs:
            sub_rows[list(subs)] = True
        special = add_rows | sub_rows
        rep.lines_changed += int((need & ~sub_rows).sum())
        num_text = []
        cells = changed
        if special.any():
            cells = changed & ~special[:, None]
        flat = np.flatnonzero(cells.ravel())
        if len(flat):
            dec, idx = blk.decimals.ravel()[flat], blk.numidx.ravel()[flat]
            kval = np.rint(units.ravel()[flat] * f.ravel()[flat]).astype(np.int64)  # the digits '%.{d}f' writes
            d0, d1 = int(dec.min()), int(dec.max())
            for d in range(d0, d1 + 1):
                sel = slice(None) if d0 == d1 else dec == d
                if d0 == d1 or sel.any():
                    txt, ln = gcode.format_fixed(kval[sel], d)
                    num_text.append((idx[sel], txt, ln))
        line_text: dict[int, str] = {}
        rows_special = np.flatnonzero(special).tolist()
        if rows_special:
            U, D = units.tolist(), blk.decimals.tolist()
            prev_mm = np.vstack([self._prev_mm[None], q_w[:-1]])
            Pm, HOLD = prev_mm.tolist(), self._hold.tolist()
            for r in rows_special:
                li = int(blk.rows[r])
                line = blk.line(li)
                if r in subs:
                    new, add, cont, sep, _ = self._slow_row(blk, r, line, U, D, Pm, HOLD, scale, subs)
                    if not (new or add or cont):
                        continue
                    rep.lines_changed += 1
                    rep.lines_inserted += len(cont)
                else:
                    d, u = D[r], U[r]
                    new = {a: "%.*f" % (d[a], u[a]) for a in np.flatnonzero(changed[r]).tolist()}
                    add = [(a, "%.*f" % (d[a], u[a])) for a in np.flatnonzero(added[r]).tolist()]
                    cont, sep = None, " " if " " in line else ""
                line_text[li] = gcode.edit_line(line, blk.code_line(li), new, add, sep, cont, self.words)
        self._prev_mm = q_w[-1].copy()
        return gcode.render_block(blk, num_text, line_text)

    # ---------------------------------------------------------------- CL data
    def _cl_chunk(self, lines: list[str], first: int) -> str:
        comp = self.comp
        poses, nos = gcode.parse_cl(lines, first, self._src)
        if len(poses) == 0:
            return ""
        m = comp.machine
        try:
            q0 = m.inverse(poses)
        except InputError as exc:  # name the first pose the machine cannot reach by its file line
            for r in range(len(poses)):
                try:
                    m.inverse(poses[r:r + 1])
                except InputError as one:
                    raise InputError(f"{self._src}:{int(nos[r])}: {str(one).replace(' at index (0,)', '')}") from None
            raise InputError(f"{self._src}: {exc}") from None
        # C continuity: at the singularity take the previous C, elsewhere the 360-deg multiple nearest the previous
        sing = np.hypot(poses[:, 3], poses[:, 4]) < 1e-9
        ri = self._ri
        c = q0[:, ri].copy()
        prev_c = self._prev[0][ri] if self._prev else 0.0
        seq = np.concatenate([[prev_c], c])
        for i in np.flatnonzero(sing):
            seq[i + 1] = seq[i]
        seq = np.unwrap(seq, period=360.0)
        hint = q0.copy()
        hint[:, ri] = seq[1:]
        q_nom = m.inverse(poses, hint=hint)
        # render as G-code, all five words a block, and compensate it with the unrounded nominal axes
        p = self.min_decimals[0]
        text = []
        for q in q_nom.tolist():
            words = " ".join(f"{a}{gcode.fmt(v, p)}" for a, v in zip(self.words.letters, q))
            text.append(("G1 " if self._first_cl else "") + words + "\n")
            self._first_cl = False
        self._cl_lines = nos
        try:
            return self._gcode_chunk(text, first, exact=q_nom)
        finally:
            self._cl_lines = None


# ---------------------------------------------------------------------------------------------- tables
def write_tables(model: ErrorModel, machine: Machine, folder: str | os.PathLike) -> list[str]:
    """Per-axis compensation tables for controllers that take them: the error tables with reversed sign.

    One CSV per axis, ``comp_<AXIS>.csv``: ``position`` (mm or deg) and one column per error function of that
    axis, ``comp_<NAME>_mm`` or ``comp_<NAME>_rad`` = -error, at the union of the functions' table positions
    (functions evaluated as stored, end values held); constants (squareness, axis location) in ``constants.csv``.
    """
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for ax in machine.axes:
        names = sorted(n for n, f in model.functions.items() if f.axis == ax)
        if not names:
            continue
        pos = np.unique(np.concatenate([model.functions[n].positions for n in names]))
        cols = [-model.functions[n](pos, "hold") for n in names]
        head = "position," + ",".join(f"comp_{n}_{'mm' if n[2] in 'XYZ' else 'rad'}" for n in names)
        rows = [",".join([f"{p:.6g}"] + [f"{c[i]:.9g}" for c in cols]) for i, p in enumerate(pos)]
        path = out / f"comp_{ax}.csv"
        atomic_write_text(path, "\n".join([head] + rows) + "\n")
        written.append(str(path))
    if model.constants:
        path = out / "constants.csv"
        atomic_write_text(path, "name,compensation,unit\n" + "".join(
            f"{n},{-v:.9g},{'mm' if n[2] in 'XYZ' else 'rad'}\n" for n, v in sorted(model.constants.items())))
        written.append(str(path))
    return written
