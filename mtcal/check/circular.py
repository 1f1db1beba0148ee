"""ISO 230-4 circular tests predicted from an error model (a double ballbar between a ball on the spindle and a
ball on the table, the two linear axes of a plane interpolating a circle).

Frame and signs: the circle is programmed in axis positions: the plane's first and second linear axis at
``centre + R (cos theta, sin theta)``, theta counter-clockwise from the first axis (deg), the other axes held
(linear axes at the centre, rotary axes at ``fixed``, default 0).  The table ball is set at the centre (where the
machine puts the tool there), so the ballbar reads the distance between the tool tip and that point, both in the
workpiece frame: deltaR(theta) = u . (dp(q(theta)) - dp(q_centre)) to first order, u the nominal radial unit
vector and dp the tool-tip deviation of the model's errors (Jacobian at zero error, generated from derive/), mm,
positive outward.  direction +1 counter-clockwise, -1 clockwise.

Figures (ISO 230-4:2005, clause 3; ``figures``): circular deviation G, the radial range of one path about its
least-squares circle centre (the linearised LSQ circle: deltaR ~ r0 + a cos theta + b sin theta, exact to first
order in the deviations); bidirectional circular deviation G(b), the same of both paths about their common LSQ
centre; circular hysteresis H, the largest radial difference of the two paths at one angle (common centre); radial
deviation F, the largest and smallest deltaR about the nominal centre (the ballbar's own set-up), F_max and F_min.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mtcal.errors import InputError
from mtcal.model.errormodel import ErrorEvaluator, ErrorModel

DIRECTIONS = {"ccw": (1,), "cw": (-1,), "both": (1, -1)}


@dataclass(frozen=True)
class CircleSetup:
    """An ISO 230-4 circular test (a ballbar circle) to predict: where, how large, which way.

    Parameters
    ----------
    plane : str
        Two linear axes, e.g. ``"XY"``: theta runs from the first towards the second.
    radius_mm : float
        The circle's radius, mm.
    centre_mm : tuple of float, optional
        The linear axes' positions at the centre, mm, in machine axis order (None: the middle of their ranges, or
        0).
    direction : {"both", "ccw", "cw"}, optional
        The paths (default both).
    arc_deg : float, optional
        The arc, deg (<= 360, default 360).
    start_deg : float, optional
        Where the arc starts, deg (default 0).
    points : int, optional
        Points per path (default 360).
    fixed : dict of str to float, optional
        The rotary axes' positions, deg (missing: 0).
    tool_length : float, optional
        The ball below the spindle gauge point, mm (default 0).

    Examples
    --------
    >>> import mtcal
    >>> mtcal.CircleSetup("XY", 150.0, fixed={"B": 0.0, "C": 0.0}).radius_mm
    150.0
    """

    plane: str
    radius_mm: float
    centre_mm: tuple[float, ...] | None = None
    direction: str = "both"
    arc_deg: float = 360.0
    start_deg: float = 0.0
    points: int = 360
    fixed: dict[str, float] = field(default_factory=dict)
    tool_length: float = 0.0


def parse_circular(text: str, machine) -> CircleSetup:
    """'PLANE,RADIUS[,X0,Y0,Z0]' (the CLI's ``--circular``; mm) -> CircleSetup; the centre names the machine's
    linear axes in order."""
    parts = [p.strip() for p in text.split(",")]
    lin = machine.linear_axes
    if len(parts) not in (2, 2 + len(lin)):
        raise InputError(f"circular test {text!r}: give PLANE,RADIUS or PLANE,RADIUS,{','.join(a + '0' for a in lin)} "
                         f"(mm)")
    try:
        nums = [float(p) for p in parts[1:]]
    except ValueError:
        raise InputError(f"circular test {text!r}: radius and centre must be numbers (mm)") from None
    return CircleSetup(parts[0].upper(), nums[0], tuple(nums[1:]) if len(nums) > 1 else None)


@dataclass
class CircleGeometry:
    """The nominal test: axis positions ``axes`` (n, n_axes) at angles ``theta_deg`` (n,), the radial unit
    vectors ``u`` (n, 3) in the workpiece frame and the centre's axis positions ``centre_axes`` (n_axes,)."""

    theta_deg: np.ndarray
    axes: np.ndarray
    u: np.ndarray
    centre_axes: np.ndarray


def geometry(machine, s: CircleSetup, theta_deg: np.ndarray | None = None) -> CircleGeometry:
    """The test's nominal axis positions and radial directions (see the module docstring); refuses a plane that
    is not two linear axes of the machine, a radius that is not positive, and positions outside the axes' limits."""
    lin = machine.linear_axes
    if len(s.plane) != 2 or s.plane[0] == s.plane[1] or any(a not in lin for a in s.plane):
        raise InputError(f"plane {s.plane!r}: two different linear axes of machine {machine.name} "
                         f"({''.join(lin)}), e.g. {lin[0]}{lin[1]}")
    if not (np.isfinite(s.radius_mm) and s.radius_mm > 0):
        raise InputError(f"radius must be a positive number of mm, got {s.radius_mm}")
    if not 0 < s.arc_deg <= 360:
        raise InputError(f"arc must be in (0, 360] deg, got {s.arc_deg}")
    centre = machine.axis_vector(s.fixed)
    cm = _centre(machine, s)
    for a, c in zip(lin, cm):
        centre[machine.index(a)] = c
    if theta_deg is None:
        n = int(s.points)
        end = s.arc_deg if s.arc_deg < 360 else 360.0 * (n - 1) / n
        theta_deg = s.start_deg + np.linspace(0.0, end, n)
    th = np.radians(np.asarray(theta_deg, dtype=float))
    axes = np.repeat(centre[None], len(th), axis=0)
    i, j = machine.index(s.plane[0]), machine.index(s.plane[1])
    axes[:, i] += s.radius_mm * np.cos(th)
    axes[:, j] += s.radius_mm * np.sin(th)
    machine.check_axes(axes)
    p = machine.forward(axes, tool_length=s.tool_length)[:, :3]
    p0 = machine.forward(centre, tool_length=s.tool_length)[:3]
    return CircleGeometry(np.asarray(theta_deg, dtype=float), axes, (p - p0) / s.radius_mm, centre)


def _centre(machine, s: CircleSetup) -> tuple[float, ...]:
    lin = machine.linear_axes
    if s.centre_mm is not None:
        if len(s.centre_mm) != len(lin):
            raise InputError(f"centre needs {len(lin)} numbers ({', '.join(lin)} in mm), got {len(s.centre_mm)}")
        return tuple(float(c) for c in s.centre_mm)
    out = []
    for a in lin:
        lim = machine.limits[machine.index(a)]
        out.append(0.0 if lim is None else 0.5 * (lim[0] + lim[1]))
    return tuple(out)


def radial_sensitivity(machine, g: CircleGeometry, tool_length: float = 0.0) -> np.ndarray:
    """d deltaR / d errors (n, n_errors) at every point: the radial component of the tool tip's first-order
    deviation minus that at the centre (mm per mm, mm per rad; errors evaluated at each point's own axes)."""
    J = machine.jacobian_errors(g.axes, tool_length)[:, :3, :]
    return np.einsum("nk,nke->ne", g.u, J)


def tip_deviation(machine, model: ErrorModel, g: CircleGeometry, tool_length: float = 0.0,
                  outside: dict[str, int] | None = None) -> np.ndarray:
    """(n, 3, n_errors) mm: each error's first-order share of the tool tip's deviation at every point, minus that
    at the centre, in the workpiece frame.  Positions outside an error function's measured range hold its end
    values (as ``compensate`` does by default); ``outside`` (a dict) is given the count per function."""
    ev = ErrorEvaluator(model, machine, "hold")
    e = ev(g.axes)
    e0 = ev(g.centre_axes[None])
    if outside is not None:
        outside.update(ev.outside_counts)
    J = machine.jacobian_errors(g.axes, tool_length)[:, :3, :]
    J0 = machine.jacobian_errors(g.centre_axes[None], tool_length)[0, :3, :]
    return np.einsum("nke,ne->nke", J, e) - (J0 * e0[0])[None]


def radial_deviation(machine, model: ErrorModel, g: CircleGeometry, tool_length: float = 0.0,
                     outside: dict[str, int] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(deltaR (n,) mm, contributions (n, n_errors) mm): the model's first-order radial deviation and each
    error's share (they sum to deltaR): ``tip_deviation`` along the nominal radial direction u."""
    contrib = np.einsum("nk,nke->ne", g.u, tip_deviation(machine, model, g, tool_length, outside))
    return contrib.sum(axis=1), contrib


def table_ball(g: CircleGeometry, c: np.ndarray) -> np.ndarray:
    """The table ball's offset (3,) mm in the workpiece frame from its offset ``c`` (2,) mm along the plane's two
    axes (their directions in that frame: u(theta) = cos theta e_a + sin theta e_b, fitted from ``g.u``)."""
    th = np.radians(g.theta_deg)
    e = np.linalg.lstsq(np.column_stack([np.cos(th), np.sin(th)]), g.u, rcond=None)[0]  # (2, 3): e_a, e_b
    return np.asarray(c, dtype=float) @ e


def offset_reading(g: CircleGeometry, dev: np.ndarray, radius_mm: float, c: np.ndarray) -> tuple[np.ndarray,
                                                                                                  np.ndarray]:
    """(deltaR (n,) mm, bar direction w (n, 3)) a ballbar reads whose table ball sits ``c`` (2,) mm off the
    centre, the tool tip deviating by ``dev`` (n, 3) mm: |R u + dev - c3| - R, exact in the offset (the bar's
    direction w = (R u - c3) / |R u - c3|, not u: at an offset e a deviation's tangential part reaches the reading
    by e / R of itself, which the first-order radial projection misses)."""
    c3 = table_ball(g, c)
    w = radius_mm * g.u - c3[None]
    w /= np.linalg.norm(w, axis=1)[:, None]
    return np.linalg.norm(radius_mm * g.u + dev - c3[None], axis=1) - radius_mm, w


# ----------------------------------------------------------------------------------------------- set-up
def setup_centre(theta_deg: np.ndarray, dr: np.ndarray, radius_mm: float,
                 iterations: int = 30) -> tuple[np.ndarray, float]:
    """The ballbar's set-up fitted exactly: (c (2,) mm, r0 mm), the table ball's offset from the circle's centre
    along the plane's two axes and the length beyond ``radius_mm``, such that the readings' lengths
    L = R + deltaR are |R u(theta) - c| + r0 in the least-squares sense (Gauss-Newton from the linearised
    centre).  A set-up offset e leaves, after its first-order term -e . u is removed, the oval e^2 sin^2 / 2R
    (ISO 230-4): only the exact centre takes it out."""
    th = np.radians(np.asarray(theta_deg, dtype=float))
    u = np.column_stack([np.cos(th), np.sin(th)])
    L = radius_mm + np.asarray(dr, dtype=float)
    r0, a, b = lsq_centre(theta_deg, dr)
    x = np.array([-a, -b, r0])
    for _ in range(iterations):
        v = radius_mm * u - x[:2]
        n = np.linalg.norm(v, axis=1)
        f = n + x[2] - L
        J = np.column_stack([-v / n[:, None], np.ones_like(n)])
        step = np.linalg.lstsq(J, -f, rcond=None)[0]
        x += step
        if np.abs(step).max() < 1e-13 * max(radius_mm, 1.0):
            break
    return x[:2], float(x[2])


def about_setup_centre(theta_deg: np.ndarray, dr: np.ndarray, radius_mm: float, c: np.ndarray) -> np.ndarray:
    """deltaR about the set-up centre ``c`` (mm along the plane's axes): the length read minus the distance of
    the nominal path from the table ball, L - |R u - c| (mm; the length r0 left in)."""
    th = np.radians(np.asarray(theta_deg, dtype=float))
    u = np.column_stack([np.cos(th), np.sin(th)])
    return radius_mm + np.asarray(dr, dtype=float) - np.linalg.norm(radius_mm * u - np.asarray(c)[None], axis=1)


MAX_GAP_DEG = 15.0  # a path covers the full circle with no gap wider (>= 24 readings): 20 signature columns


def check_minimum_data(theta_deg: np.ndarray, direction: np.ndarray, source: str,
                       lines: np.ndarray | None = None) -> None:
    """ISO 230-4's minimum data before any verdict: every path (direction) a full circle, no gap between
    neighbouring readings wider than MAX_GAP_DEG (an arc cannot tell the set-up centre from the ovals);
    InputError naming the file, the gap and its lines."""
    theta_deg, direction = np.asarray(theta_deg, dtype=float), np.asarray(direction)
    for d, key in ((1, "counter-clockwise"), (-1, "clockwise")):
        on = np.flatnonzero(direction == d)
        if not len(on):
            continue
        t = np.mod(theta_deg[on], 360.0)
        order = np.argsort(t, kind="stable")
        ts = t[order]
        gaps = np.diff(np.concatenate([ts, ts[:1] + 360.0]))
        k = int(np.argmax(gaps))
        if len(on) < 360.0 / MAX_GAP_DEG or gaps[k] > MAX_GAP_DEG + 1e-9:
            i, j = on[order[k]], on[order[(k + 1) % len(on)]]
            where = "" if lines is None else f" (lines {int(lines[i])} and {int(lines[j])})"
            raise InputError(f"{source}: the {key} path has {len(on)} readings and no reading between "
                             f"{ts[k]:g} and {np.mod(ts[k] + gaps[k], 360.0):g} deg{where}: ISO 230-4's circular "
                             f"test is a full circle (readings at most {MAX_GAP_DEG:g} deg apart, >= "
                             f"{int(360 / MAX_GAP_DEG)} a path); an arc cannot tell the ballbar's set-up from the "
                             f"machine's ovals")


# ----------------------------------------------------------------------------------------------- ISO 230-4
def lsq_centre(theta_deg: np.ndarray, dr: np.ndarray) -> np.ndarray:
    """Coefficients (r0, a, b) mm of the least-squares circle of a trace, linearised for small deviations:
    deltaR ~ r0 + a cos theta + b sin theta ((a, b) is the LSQ centre's offset along the plane's axes)."""
    th = np.radians(theta_deg)
    A = np.column_stack([np.ones_like(th), np.cos(th), np.sin(th)])
    return np.linalg.lstsq(A, dr, rcond=None)[0]


def about_lsq_centre(theta_deg: np.ndarray, dr: np.ndarray, coef: np.ndarray | None = None) -> np.ndarray:
    """deltaR about the LSQ circle's centre (its own, or ``coef``), mm (the radius change r0 left in)."""
    c = lsq_centre(theta_deg, dr) if coef is None else coef
    th = np.radians(theta_deg)
    return dr - c[1] * np.cos(th) - c[2] * np.sin(th)


def figures(theta_deg: np.ndarray, dr: np.ndarray, direction: np.ndarray) -> dict[str, float]:
    """ISO 230-4 figures (module docstring) of one or two paths (``direction`` +1 / -1 per point), mm:
    G (G(b) with both directions, else the one path's), G_ccw, G_cw, H (0 with one direction), F_max, F_min and F
    (the largest |deltaR| about the nominal centre)."""
    theta_deg, dr, direction = (np.asarray(v, dtype=float) for v in (theta_deg, dr, direction))
    out: dict[str, float] = {}
    paths = {}
    for d, key in ((1, "ccw"), (-1, "cw")):
        on = direction == d
        if on.sum() >= 3:
            c = about_lsq_centre(theta_deg[on], dr[on])
            out[f"G_{key}_mm"] = float(np.ptp(c))
            paths[key] = on
    if not paths:
        raise InputError("a circular test needs at least 3 points in one direction")
    common = about_lsq_centre(theta_deg, dr, lsq_centre(theta_deg, dr))
    out["G_mm"] = float(np.ptp(common)) if len(paths) == 2 else next(v for k, v in out.items() if k.startswith("G_"))
    out["H_mm"] = _hysteresis(theta_deg, common, paths) if len(paths) == 2 else 0.0
    out["F_max_mm"], out["F_min_mm"] = float(dr.max()), float(dr.min())
    out["F_mm"] = float(np.abs(dr).max())
    return out


def _hysteresis(theta_deg: np.ndarray, dr: np.ndarray, paths: dict[str, np.ndarray]) -> float:
    """Largest |deltaR_ccw - deltaR_cw| at one angle: the cw path interpolated at the ccw path's angles (periodic
    over 360 deg; arcs within their common range)."""
    a, b = paths["ccw"], paths["cw"]
    ta, tb = np.mod(theta_deg[a], 360.0), np.mod(theta_deg[b], 360.0)
    order = np.argsort(tb)
    tb, rb = tb[order], dr[b][order]
    full = np.ptp(tb) > 350
    if full:
        tb, rb = np.concatenate([tb - 360, tb, tb + 360]), np.tile(rb, 3)
    inside = (ta >= tb.min()) & (ta <= tb.max())
    return float(np.abs(dr[a][inside] - np.interp(ta[inside], tb, rb)).max()) if inside.any() else 0.0


# ----------------------------------------------------------------------------------------------- prediction
@dataclass
class CircularPrediction:
    """A predicted circular test: the trace, the ISO 230-4 figures and each error's share.

    Attributes
    ----------
    setup : CircleSetup
        The test.
    centre_mm : tuple of float
        The linear axes' positions at the centre, mm.
    theta_deg : numpy.ndarray, shape (n,)
        Angle of each point, deg, counter-clockwise from the plane's first axis.
    dr : numpy.ndarray, shape (n,)
        Radial deviation at each point, mm, positive outward.
    direction : numpy.ndarray, shape (n,)
        +1 counter-clockwise, -1 clockwise path.
    figures : dict of str to float
        ISO 230-4's G (per direction and both), H, F (min, max), mm.
    contributions : dict of str to float
        Each error's share of G: {ISO name: G of its part alone, mm}, largest first.
    outside : dict of str to int
        Error evaluations beyond an error function's measured range (end values held): {name: count}.
    """

    setup: CircleSetup
    centre_mm: tuple[float, ...]
    theta_deg: np.ndarray
    dr: np.ndarray
    direction: np.ndarray
    figures: dict[str, float]
    contributions: dict[str, float]
    outside: dict[str, int] = field(default_factory=dict)

    def to_dict(self) -> dict:
        s = self.setup
        return {"kind": "circular", "plane": s.plane, "radius_mm": s.radius_mm, "centre_mm": list(self.centre_mm),
                "direction": s.direction, "arc_deg": s.arc_deg, "fixed_deg": dict(s.fixed), **self.figures,
                "trace": [[round(float(t), 6), float(r), int(d)] for t, r, d in
                          zip(self.theta_deg, self.dr, self.direction)],
                "contributions": self.contributions, "outside_range": dict(self.outside)}


def _paths(theta_deg: np.ndarray, dr: np.ndarray, direction: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(theta, deltaR, direction) of the paths ``direction`` names, each in its order of travel (a quasi-static
    deviation depends on the position only: the clockwise path is the same trace, reversed)."""
    dirs = DIRECTIONS[direction]
    return (np.concatenate([theta_deg if d > 0 else theta_deg[::-1] for d in dirs]),
            np.concatenate([dr if d > 0 else dr[::-1] for d in dirs]),
            np.concatenate([np.full(len(dr), d) for d in dirs]))


def predict_circular(model: ErrorModel, setup: CircleSetup, machine=None) -> CircularPrediction:
    """The circular test ``setup`` as the model predicts it (first order, exact through the generated kinematics).

    Parameters
    ----------
    model : ErrorModel
        The error model (mm, rad); positions beyond its tables take the end values.
    setup : CircleSetup
        The test.
    machine : Machine, optional
        Default: the model's.

    Returns
    -------
    CircularPrediction
        The trace, G, H, F (mm) and each error's share of G.

    Raises
    ------
    mtcal.errors.InputError
        A plane that is not two linear axes of the machine, a circle beyond the travel, a bad direction.

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.data import path
    >>> model = mtcal.load_model(path("demo_truth.json"))
    >>> p = mtcal.predict_circular(model, mtcal.CircleSetup("XY", 150.0))
    >>> print(f"G {p.figures['G_mm'] * 1e3:.2f} um; largest shares: {', '.join(list(p.contributions)[:3])}")
    G 6.11 um; largest shares: E_XX, E_YY, E_C0Y
    """
    m = machine or model.kinematics
    if setup.direction not in DIRECTIONS:
        raise InputError(f"direction must be one of {', '.join(DIRECTIONS)}, got {setup.direction!r}")
    g = geometry(m, setup)
    outside: dict[str, int] = {}
    dr, contrib = radial_deviation(m, model, g, setup.tool_length, outside)
    theta, trace, direction = _paths(g.theta_deg, dr, setup.direction)
    parts = {}
    for k, name in enumerate(m.error_names):
        if np.any(contrib[:, k]):
            parts[name] = float(np.ptp(about_lsq_centre(g.theta_deg, contrib[:, k])))
    parts = dict(sorted(((n, v) for n, v in parts.items() if v > 0), key=lambda kv: -kv[1]))
    return CircularPrediction(setup, tuple(float(g.centre_axes[m.index(a)]) for a in m.linear_axes), theta, trace,
                              direction, figures(theta, trace, direction), parts, outside)


def predict_circular_compensated(model: ErrorModel, setup: CircleSetup, machine=None, iterations: int = 2,
                                 errors_of: ErrorModel | None = None) -> CircularPrediction:
    """The same test after the program is compensated with the model (mtcal.compensate, scope "position"): the
    circle's commands and the centre corrected, the ballbar read on the exact error-inclusive kinematics at the
    corrected axes of a machine with the model's errors (what is left: the compensation's own higher-order
    remainder) or, with ``errors_of``, another model's (e.g. the true machine's in a simulation); contributions:
    none."""
    from mtcal.compensate.solver import Compensator

    m = machine or model.kinematics
    g = geometry(m, setup)
    comp = Compensator(model, m, "position", setup.tool_length, iterations=iterations)
    q = comp.correct(g.axes)
    qc = comp.correct(g.centre_axes[None])
    real = comp if errors_of is None else Compensator(errors_of, m, "position", setup.tool_length)
    p = m.forward(q, real.errors(q), setup.tool_length, check=False)[:, :3]
    p0 = m.forward(qc, real.errors(qc), setup.tool_length, check=False)[0, :3]
    theta, trace, direction = _paths(g.theta_deg, np.linalg.norm(p - p0, axis=1) - setup.radius_mm, setup.direction)
    return CircularPrediction(setup, tuple(float(g.centre_axes[m.index(a)]) for a in m.linear_axes), theta, trace,
                              direction, figures(theta, trace, direction), {})
