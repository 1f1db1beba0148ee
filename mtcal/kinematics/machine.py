"""Runtime machine model: a thin layer over the generated kinematics of one chain spec.

Units: linear axes and positions in mm, rotary axes in degrees (as in NC programs), errors in mm and rad
with ISO 230-1 names.  Pose = [x, y, z, i, j, k]: tool tip and tool axis in the workpiece frame.
"""
from __future__ import annotations

import importlib
import json
import warnings
from functools import cached_property
from pathlib import Path
from typing import Mapping

import numpy as np

from mtcal.errors import InputError
from mtcal.kinematics.inverse import inverse_kinematics


class StaleGeneratedCodeWarning(UserWarning):
    """generated/ was produced from a different derive/ than the one beside it."""


def _check_stale(here: Path | None = None) -> None:
    """Warn when a source checkout's derive/ no longer has the bytes that ``here``/manifest.json (default: the
    generated/ in use) records for it: the runtime reads the manifest and never imports derive/."""
    import hashlib

    here = _generated_dir() if here is None else here
    try:
        recorded = json.loads((here / "manifest.json").read_text())["derive_files"]
    except (OSError, ValueError, KeyError):
        return
    root = here.parent
    if not (root / "derive").is_dir():  # installed without derive/: nothing to compare against
        return

    def now(rel: str) -> str | None:
        p = root / rel
        return hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else None
    if any(now(rel) != sha for rel, sha in recorded.items()):
        warnings.warn("generated/ is stale relative to derive/: run `python -m derive`",
                      StaleGeneratedCodeWarning, stacklevel=3)


class MachineSpec:
    """The facts of one machine spec and the checks of its inputs: axes, their kinds, units, limits and sides, the
    ISO 230-1 error names (generated from derive/machines/<name>.toml).

    ``Machine`` adds the kinematics; use ``load_machine(name)``.  Axis vectors are (..., n_axes) in the spec's axis
    order, mm (linear) and deg (rotary); error vectors (..., n_errors) in the order of ``error_names``, mm and rad.

    Parameters
    ----------
    name : str
        The spec's name (``available_machines()``).

    Raises
    ------
    mtcal.errors.InputError
        An unknown machine name.
    """

    def __init__(self, name: str):
        if name not in available_machines():  # also the generated modules that are no machine (plate, ...)
            raise InputError(f"unknown machine {name!r}; available: {', '.join(available_machines())}")
        self._np = importlib.import_module(f"mtcal.generated.{name}_numpy")
        m = self._np
        self.name: str = m.MACHINE
        self.title: str = m.TITLE
        self.axes: tuple[str, ...] = m.AXES
        self.axis_kinds: tuple[str, ...] = m.AXIS_KINDS
        self.limits: tuple = m.AXIS_LIMITS
        self.error_names: tuple[str, ...] = m.ERRORS
        self.error_groups: dict[str, list[str]] = m.ERROR_GROUPS
        self.parameters: dict[str, str] = m.PARAMETERS
        self.ik_info: dict = m.IK
        self.sides: dict[str, str] = m.AXIS_SIDES  # axis -> "tool" (moves the spindle) or "table"
        self.positioning_errors: dict[str, str] = m.POSITIONING_ERRORS  # axis -> E_XX, E_CB, ...
        self.campaign: dict = m.CAMPAIGN  # default measurement campaign of the spec (positions, reflectors, ...)
        self._err_index = {n: i for i, n in enumerate(self.error_names)}
        self._ax_index = {a: i for i, a in enumerate(self.axes)}

    # ------------------------------------------------------------------ spec facts
    def index(self, axis: str) -> int:
        """Position of ``axis`` in the axis vector; an unknown axis is an InputError naming the machine's axes."""
        try:
            return self._ax_index[axis]
        except KeyError:
            raise InputError(f"{axis!r} is not an axis of machine {self.name} ({', '.join(self.axes)})") from None

    def kind(self, axis: str) -> str:
        """"linear" (mm) or "rotary" (deg)."""
        return self.axis_kinds[self.index(axis)]

    def unit(self, axis: str) -> str:
        return "mm" if self.kind(axis) == "linear" else "deg"

    def side(self, axis: str) -> str:
        """"tool" when the axis carries the spindle, "table" when it carries the workpiece."""
        self.index(axis)
        return self.sides[axis]

    @property
    def linear_axes(self) -> tuple[str, ...]:
        return tuple(a for a, k in zip(self.axes, self.axis_kinds) if k == "linear")

    @property
    def rotary_axes(self) -> tuple[str, ...]:
        return tuple(a for a, k in zip(self.axes, self.axis_kinds) if k == "rotary")

    def error_motions(self, axis: str) -> tuple[str, ...]:
        """ISO 230-1 names of the six error motions of an axis: E_X<axis> .. E_C<axis> (mm, then rad)."""
        self.index(axis)
        return tuple(f"E_{c}{axis}" for c in "XYZABC")

    def axis_vector(self, at: Mapping[str, float | np.ndarray] | None = None) -> np.ndarray:
        """Axis positions (..., n_axes) from {axis: position} (missing axes at zero)."""
        vals = {a: np.asarray(v, dtype=float) for a, v in (at or {}).items()}
        out = np.zeros(np.broadcast_shapes(*(v.shape for v in vals.values())) + (len(self.axes),))
        for a, v in vals.items():
            out[..., self.index(a)] = v
        return out

    # ------------------------------------------------------------------ input checks
    def check_axes(self, axes) -> np.ndarray:
        """(..., n_axes) float array; NaN, wrong shapes and positions outside the limits are errors."""
        a = np.asarray(axes, dtype=float)
        n = len(self.axes)
        if a.ndim == 0 or a.shape[-1] != n:
            raise InputError(f"axes must have shape (..., {n}) ordered {self.axes}, got shape {a.shape}")
        bad = ~np.isfinite(a)
        if bad.any():
            idx = tuple(int(i) for i in np.argwhere(bad)[0])
            raise InputError(f"axes contain NaN/inf at index {idx} (axis {self.axes[idx[-1]]})")
        for k, (name, lim) in enumerate(zip(self.axes, self.limits)):
            if lim is None:
                continue
            col = a[..., k]
            out = (col < lim[0]) | (col > lim[1])
            if out.any():
                idx = tuple(int(i) for i in np.argwhere(out)[0]) if col.ndim else ()
                val = float(col[idx]) if col.ndim else float(col)
                raise InputError(f"{name} = {val:.10g} {'deg' if self.axis_kinds[k] == 'rotary' else 'mm'} at index "
                                 f"{idx} is outside its range [{lim[0]:g}, {lim[1]:g}]")
        return a

    def error_vector(self, errors: Mapping[str, float | np.ndarray] | np.ndarray | None, lead=()) -> np.ndarray:
        """Errors by ISO name (missing names are zero) -> (..., n_errors) array; unknown names are errors."""
        n = len(self.error_names)
        if errors is None:
            return np.zeros(tuple(lead) + (n,))
        if isinstance(errors, Mapping):
            unknown = sorted(set(errors) - set(self._err_index))
            if unknown:
                raise InputError(f"unknown error names {unknown} for machine {self.name}; "
                                 f"known: {', '.join(self.error_names)}")
            vals = {k: np.asarray(v, dtype=float) for k, v in errors.items()}
            shape = np.broadcast_shapes(tuple(lead), *(v.shape for v in vals.values()))
            e = np.zeros(shape + (n,))
            for k, v in vals.items():
                e[..., self._err_index[k]] = v
        else:
            e = np.asarray(errors, dtype=float)
            if e.ndim == 0 or e.shape[-1] != n:
                raise InputError(f"error vector must have shape (..., {n}) ordered as Machine.error_names, "
                                 f"got {e.shape}")
        if not np.isfinite(e).all():
            raise InputError("error values contain NaN/inf")
        return e

    def __repr__(self) -> str:
        return f"Machine({self.name!r}: {self.title})"


class Machine(MachineSpec):
    """Kinematics of one machine, on the code derive/ generated from its spec (derive/machines/<name>.toml).

    Use ``load_machine(name)`` (one instance per process).  Axis vectors are (..., n_axes) in the spec's axis order,
    mm (linear) and deg (rotary); error vectors (..., n_errors) in the order of ``error_names``, mm and rad; a pose
    is (..., 6) = [x, y, z (mm), i, j, k] of the tool tip in the workpiece frame.  ``forward``,
    ``forward_with_jacobian``, ``jacobian_axes``, ``jacobian_errors`` and ``inverse`` evaluate the kinematics.

    Parameters
    ----------
    name : str
        The spec's name (``available_machines()``: ``dmu50``, ``headbc``, ``xyzac``).

    Attributes
    ----------
    name : str
        The spec's name.
    title : str
        What the machine is.
    axes : tuple of str
        Axis names in axis-vector order.
    axis_kinds : tuple of str
        ``"linear"`` or ``"rotary"`` per axis.
    limits : tuple
        Per axis (low, high) in mm or deg, or None (unlimited).
    error_names : tuple of str
        ISO 230-1 names of the error vector, in order.
    sides : dict of str to str
        Per axis ``"tool"`` (it moves the spindle) or ``"table"`` (the workpiece).
    campaign : dict
        The spec's default measurement campaign (positions, reflectors, rounds, tracker stations).

    Raises
    ------
    mtcal.errors.InputError
        An unknown machine name.

    Examples
    --------
    >>> import mtcal
    >>> m = mtcal.load_machine("dmu50")
    >>> m.axes, len(m.error_names)
    (('X', 'Y', 'Z', 'B', 'C'), 41)
    >>> m.forward([[100.0, 20.0, 50.0, 0.0, 0.0]]).round(3)
    array([[100.,  20.,  50.,   0.,   0.,   1.]])
    """

    # ------------------------------------------------------------------ geometry of measured points
    def _side_of(self, axis_or_side: str) -> str:
        return axis_or_side if axis_or_side in ("tool", "table") else self.side(axis_or_side)

    def points(self, axis_or_side: str, axes, local, errors=None) -> np.ndarray:
        """Machine-frame positions (..., 3) mm of reflectors ``local`` (..., 3) fixed to the spindle ("tool":
        mm relative to the spindle gauge point) or the table ("table": workpiece coordinates), at axis positions
        (..., n_axes); exact error-inclusive with ``errors`` (..., n_errors), nominal without.  ``axis_or_side``:
        "tool", "table" or an axis (its side).  Positions are not limit-checked (campaigns stay inside)."""
        a, p = np.asarray(axes, dtype=float), np.asarray(local, dtype=float)
        e = np.zeros(len(self.error_names)) if errors is None else np.asarray(errors, dtype=float)
        side = self._side_of(axis_or_side)
        return (self._np.tool_point if side == "tool" else self._np.table_point)(a, e, p)

    def point_jacobian_errors(self, axis_or_side: str, axes, local) -> np.ndarray:
        """d points / d errors at zero error (..., 3, n_errors), mm per mm and mm per rad."""
        side = self._side_of(axis_or_side)
        fn = self._np.tool_point_jacobian_errors if side == "tool" else self._np.table_point_jacobian_errors
        return fn(np.asarray(axes, dtype=float), np.asarray(local, dtype=float))

    def rigid_motion(self, axis_or_side: str, axes) -> tuple[np.ndarray, np.ndarray]:
        """(b (..., 3), R (..., 3, 3)): the nominal map local -> machine frame x = b + R local of the spindle or
        table side at axis positions (..., n_axes), read off exactly from the images of 0 and the unit vectors."""
        a = np.asarray(axes, dtype=float)
        basis = self.points(axis_or_side, a[..., None, :], np.vstack([np.zeros(3), np.eye(3)]))  # (..., 4, 3)
        b = basis[..., 0, :]
        return b, np.swapaxes(basis[..., 1:, :] - b[..., None, :], -1, -2)

    def axis_frame(self, axis: str, axes) -> tuple[np.ndarray, np.ndarray]:
        """(R (..., 3, 3), o (..., 3) mm): the frame in which the error motion of ``axis`` acts, in the machine
        frame at axis positions (..., n_axes): a linear axis' frame after its nominal translation, a rotary
        axis' stator frame (z along its nominal rotation axis); generated by derive/threepoint.py."""
        from mtcal.generated import threepoint_numpy as tp
        key = f"{self.name}_{axis}"
        if key not in tp.FRAMES:
            raise InputError(f"no axis frame derived for axis {axis} of machine {self.name}: run `python -m derive`")
        f = getattr(tp, tp.FRAMES[key])(np.asarray(axes, dtype=float))
        return f[..., :3], f[..., 3]

    @cached_property
    def casadi(self):
        """The generated CasADi module (functions return casadi.Function objects)."""
        return importlib.import_module(f"mtcal.generated.{self.name}_casadi")

    # ------------------------------------------------------------------ kinematics
    # ``check=False`` skips the input checks (limits, NaN, error names) for batch code that checked its input
    # already (compensation of long programs): axes (..., n_axes) and errors (..., n_errors) arrays, as generated.
    def _in(self, axes, errors, check: bool, want_errors: bool = True):
        if not check:
            return axes, errors
        a = self.check_axes(axes)
        return a, (self.error_vector(errors, a.shape[:-1]) if want_errors else None)

    def forward(self, axes, errors=None, tool_length: float = 0.0, check: bool = True) -> np.ndarray:
        """Pose (..., 6) = [x, y, z (mm), i, j, k] in the workpiece frame; exact error-inclusive when ``errors``."""
        a, e = self._in(axes, errors, check, errors is not None)
        if errors is None:
            return self._np.forward(a, tool_length)
        return self._np.forward_errors(a, e, tool_length)

    def deviation(self, axes, errors, order: int | None = 1, tool_length: float = 0.0,
                  check: bool = True) -> np.ndarray:
        """Pose deviation (..., 6) caused by the errors: first order (order=1) or exact (order=None)."""
        a, e = self._in(axes, errors, check)
        if order == 1:
            return self._np.deviation_first_order(a, e, tool_length)
        if order is None:
            return self._np.forward_errors(a, e, tool_length) - self._np.forward(a, tool_length)
        raise InputError(f"order must be 1 (first order) or None (exact), got {order!r}")

    def correction_first_order(self, axes, errors, tool_length: float = 0.0, check: bool = True) -> np.ndarray:
        """(..., 6): the linear-axis step (mm) that cancels the first-order tool-tip deviation, and the tool-axis
        deviation in the machine frame (derive/kinematics.py, generated ``correction_first_order``)."""
        a, e = self._in(axes, errors, check)
        return self._np.correction_first_order(a, e, tool_length)

    def jacobian_axes(self, axes, errors=None, tool_length: float = 0.0, check: bool = True) -> np.ndarray:
        """d pose / d axes (..., 6, n_axes): per mm and per degree; at the given errors (held fixed) if any."""
        if errors is None:
            return self._np.jacobian_axes(self._in(axes, None, check, False)[0], tool_length)
        return self.forward_with_jacobian(axes, errors, tool_length, check)[1]

    def forward_with_jacobian(self, axes, errors=None, tool_length: float = 0.0,
                              check: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """The pose and its derivative by the axes, of the exact error-inclusive model, in one generated pass.

        Parameters
        ----------
        axes : array_like, shape (..., n_axes)
            Axis positions, mm (linear) and deg (rotary), in ``axes`` order.
        errors : array_like, shape (..., n_errors), optional
            Error vector in ``error_names`` order, mm and rad (e.g. ``model.errors_at(machine, axes)``); None: zero
            (the nominal machine).
        tool_length : float, optional
            Tool length below the spindle gauge point, mm (default 0).
        check : bool, optional
            Check shapes and finiteness (default True).

        Returns
        -------
        pose : numpy.ndarray, shape (..., 6)
            [x, y, z (mm), i, j, k] of the tool tip in the workpiece frame.
        jacobian : numpy.ndarray, shape (..., 6, n_axes)
            d pose / d axes, per mm and per deg, at the given errors (held fixed).

        Raises
        ------
        mtcal.errors.InputError
            Wrong shapes, NaN or inf.

        Examples
        --------
        >>> import mtcal
        >>> m = mtcal.load_machine("dmu50")
        >>> pose, J = m.forward_with_jacobian([[100.0, 20.0, 50.0, 10.0, 30.0]])
        >>> pose.shape, J.shape
        ((1, 6), (1, 6, 5))
        """
        a, e = self._in(axes, errors, check)
        out = self._np.forward_errors_with_jacobian(a, e, tool_length)
        return out[..., 0], out[..., 1:]

    def jacobian_errors(self, axes, tool_length: float = 0.0) -> np.ndarray:
        """d pose / d errors at zero error (..., 6, n_errors), columns ordered as ``error_names``."""
        return self._np.jacobian_errors(self.check_axes(axes), tool_length)

    # ------------------------------------------------------------------ inverse kinematics
    def inverse(self, pose, hint=None, singular_tol: float = 1e-9, tool_length: float = 0.0) -> np.ndarray:
        """Axes (..., n_axes) that reach pose (..., 6) = [x, y, z, i, j, k] nominally.

        Branches (``ik_info["branches"]``): the tilt angle inside its limits (the spec's preferred branch, else
        the other, else the one closer to ``hint``); the rotary angle is the 360-degree multiple closest to the
        hint's rotary angle (hint default: all zero); ``tool_length`` (mm) as in ``forward`` (it matters when the
        tilt axis is on the head).  At the singularity (tool axis parallel to the rotary axis, |u_xy| <
        ``singular_tol``) the rotary angle is taken from the hint.  The tool axis must be a unit vector within
        1e-3 (it is then normalised); k outside the reachable range is an error (``mtcal.kinematics.inverse``).
        """
        return inverse_kinematics(self, pose, hint, singular_tol, tool_length)


def _generated_dir() -> Path:
    import mtcal.generated as g
    return Path(g.__file__).parent


def available_machines() -> list[str]:
    """Machines whose kinematics are in generated/ (one per spec in derive/machines/)."""
    return sorted(p.name[: -len("_numpy.py")] for p in _generated_dir().glob("*_numpy.py")
                  if _is_machine(p.name[: -len("_numpy.py")]))


def _is_machine(name: str) -> bool:
    try:
        manifest = json.loads((_generated_dir() / "manifest.json").read_text())
        return "spec" in manifest["targets"].get(name, {})
    except (OSError, KeyError, ValueError):
        return False


_CACHE: dict[str, Machine] = {}
DEFAULT_MACHINE = "dmu50"  # the thesis' machine: what every command uses unless `machine` says otherwise


def load_machine(name: str = DEFAULT_MACHINE) -> Machine:
    """The kinematic model of a machine generated from derive/machines/<name>.toml (one instance per process).

    Parameters
    ----------
    name : str, optional
        The spec's name (default ``"dmu50"``; ``available_machines()`` lists them).

    Returns
    -------
    Machine
        Its kinematics (axes, error names, forward and inverse kinematics, Jacobians).

    Raises
    ------
    mtcal.errors.InputError
        An unknown machine name (the message lists the available ones).

    Examples
    --------
    >>> import mtcal
    >>> mtcal.load_machine("xyzac").axes
    ('X', 'Y', 'Z', 'A', 'C')
    """
    if name not in _CACHE:
        _check_stale()
        _CACHE[name] = Machine(name)
    return _CACHE[name]
