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

import numpy as np

from mtcal.errors import InputError
from mtcal.kinematics.machine import Machine
from mtcal.model.errormodel import ErrorEvaluator, ErrorModel
from mtcal.model.iso_types import present_errors

SCOPES = ("position", "full")
BLOCK = 4096  # rows per numeric block: keeps the generated functions' temporaries in cache
RESIDUAL_EVERY = 20  # default: the exact residual of every 20th move (and of every inserted point)
# plausibility bounds of a correction (see Guard): 1 mm is 20-50 times the largest volumetric error the thesis
# measured on the DMU 50 (43 um; positioning ~20 um), yet 1000 times below a model typed in um under "mm";
# 0.1 deg (1.7 mrad) is 10-50 times the largest angular errors of a rotary axis (thesis: tens of urad; ISO 230-1
# typical rotary positioning errors 10-30 arcsec = 50-150 urad)
MAX_CORRECTION_MM = 1.0
MAX_ROTARY_CORRECTION_DEG = 0.1

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
    """Corrected axis commands for nominal ones under an error model (the solver under ``compensate_program``).

    ``correct(q_nom)`` returns the commands that put the tool tip of the machine with the model's errors where the
    nominal machine puts it at ``q_nom`` (scope "position": the linear axes move; "full": the rotary axes also
    correct the tool axis outside the ``cone``): exactly to first order on the generated error-inclusive
    kinematics, or by fixed-point iterations on the exact model (see the module docstring).

    Parameters
    ----------
    model : ErrorModel
        The error model (mm, rad).
    machine : Machine, optional
        Its kinematics (default: the model's, ``model.kinematics``).
    scope : {"position", "full"}, optional
        ``"position"`` corrects the tool tip, ``"full"`` also the tool axis (default "position").
    tool_length : float, optional
        Tool length below the error reference point, mm (default 0).
    iterations : int, optional
        1: first order; more: fixed-point iterations on the exact model (default 1).
    cone : float, optional
        Scope "full": no orientation correction while the tool axis is within this angle of the rotary axis, deg,
        blended in up to twice it (default 2).
    outside : {"hold", "error"}, optional
        A position beyond an error table: its end value held and counted (``outside_counts``), or refused.

    Attributes
    ----------
    outside_counts : dict of str to int
        Evaluations held beyond each error's table so far.

    Raises
    ------
    mtcal.errors.InputError
        A bad scope, iterations, outside, tool_length or cone.

    Examples
    --------
    >>> import numpy as np
    >>> import mtcal
    >>> from mtcal.data import path
    >>> model = mtcal.load_model(path("demo_truth.json"))
    >>> m, comp = model.kinematics, mtcal.Compensator(model)
    >>> q_nom = np.array([[100.0, 20.0, 50.0, 10.0, 30.0]])  # X Y Z mm, B C deg
    >>> q = comp.correct(q_nom)
    >>> (q - q_nom).round(5)  # mm: the linear axes move
    array([[ 0.00831,  0.00183, -0.00202,  0.     ,  0.     ]])
    >>> before = m.forward(q_nom, model.errors_at(m, q_nom)) - m.forward(q_nom)
    >>> after = m.forward(q, model.errors_at(m, q)) - m.forward(q_nom)
    >>> print(f"{abs(before[0, :3]).max() * 1e3:.2f} um -> {abs(after[0, :3]).max() * 1e3:.4f} um")
    6.67 um -> 0.0003 um
    """

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
        self.machine = machine or model.kinematics
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
        """Corrected commands (n, n_axes) for nominal axes (n, n_axes); with ``return_initial`` also the size of the
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
        """Axis step that cancels the pose residual r (n, 6) to first order (J (n, 6, n_axes)): B, C from the
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
