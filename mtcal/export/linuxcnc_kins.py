"""A LinuxCNC kinematics component (KINEMATICS_BOTH) that applies an error model to every move, in real time.

World = the nominal axes the part program commands; joints = the compensated axis positions, what
``Compensator(model, scope=...)`` iterated to convergence gives for that pose (scope "position": the linear axes
corrected, the rotary axes as commanded; "full": the rotary axes correct the tool axis too, with Compensator's
blend near singular poses); forward = its exact inverse.  Under G43 LinuxCNC's world Z is the tool tip plus the
tool length L (pin ``tool-length``, fed from ``motion.tooloffset.z``), so joints = Compensator(tool_length=L)
.correct(world - L e_z) + L e_z.  The maths is generated/<machine>_kins.c (derive/kins_c.py: SymPy's C99 printer
over the cse of the generated functions, the error-function evaluator and the Newton solve); this module only
assembles the .comp from it and the model's data (ErrorEvaluator's plan: tables, harmonics, polynomials and
constants as static arrays, end values held beyond the measured range as compensate does).  Source of the
component's frame: LinuxCNC 2.9 src/hal/components/userkins.comp (the template of a halcompile'd kinematics
module) and src/emc/kinematics/kinematics.h.
"""
from __future__ import annotations

import keyword
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mtcal.errors import InputError
from mtcal.io import atomic_write_text, record_written, refuse_foreign
from mtcal.kinematics.machine import Machine, _generated_dir
from mtcal.model.errormodel import ErrorEvaluator, ErrorModel
from mtcal.model.plausibility import check_model

NAME = "linuxcnc-kins"
DEFAULT_NAME = "mtcalkins"
MAX_ITERATIONS = 10  # the default of pin max-iterations: the solve takes 2-4 steps
SCOPES = ("position", "full")  # as mtcal compensate --scope
CONE_DEG = 2.0  # scope "full": Compensator's default cone
# EmcPose fields of LinuxCNC's coordinate letters (src/emc/nml_intf/emcpos.h); linear and rotary letters
POSE_FIELDS = {"X": "tran.x", "Y": "tran.y", "Z": "tran.z", "A": "a", "B": "b", "C": "c", "U": "u", "V": "v",
               "W": "w"}
LINEAR_LETTERS, ROTARY_LETTERS = "XYZUVW", "ABC"
MODULE_DIR = Path("/usr/lib/linuxcnc/modules")  # where a loadable module is found (Makefile.modinc RTLIBDIR)
# kinematics and core modules of LinuxCNC 2.9 a component must not shadow (checked against MODULE_DIR too)
RESERVED = ("trivkins", "5axiskins", "xyzac_trt_kins", "xyzbc_trt_kins", "maxkins", "tripodkins", "genhexkins",
            "genserkins", "pumakins", "scarakins", "rotatekins", "corexykins", "userkins", "motmod", "homemod",
            "tpmod", "hal_lib", "rtapi", "kins", "switchkins", "mtcal")
C_IDENT = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,29}")  # HAL names hold 47 characters: NAME.max-iterations
C_KEYWORDS = {"auto", "break", "case", "char", "const", "continue", "default", "do", "double", "else", "enum",
              "extern", "float", "for", "goto", "if", "inline", "int", "long", "register", "restrict", "return",
              "short", "signed", "sizeof", "static", "struct", "switch", "typedef", "union", "unsigned", "void",
              "volatile", "while"}


@dataclass
class KinsExport:
    """What ``export_kins`` wrote and how to use it.

    Attributes
    ----------
    files : list of str
        The files written (NAME.comp, NAME.ini).
    name : str
        The component's (C) name: [KINS]KINEMATICS.
    hal_name : str
        Its HAL name (halcompile spells ``_`` as ``-``): the pins' prefix.
    lines : list of str
        The INI and HAL lines that use it.
    held : list of str
        The model's non-zero error names the module compensates.
    warnings : list of str
        What the user should know (a forced model).
    """

    files: list[str]
    name: str
    hal_name: str
    lines: list[str]
    held: list[str]
    warnings: list[str] = field(default_factory=list)


def check_name(name: str, module_dir: Path = MODULE_DIR) -> None:
    """A component name must be a C identifier that no LinuxCNC module has (InputError otherwise)."""
    if not (isinstance(name, str) and C_IDENT.fullmatch(name)) or name in C_KEYWORDS or keyword.iskeyword(name):
        raise InputError(f"--name {name!r} is not a C identifier (a letter, then letters, digits or _, at most 30)")
    clash = name in RESERVED or (module_dir / f"{name}.so").exists()
    if clash and not _ours(module_dir / f"{name}.so"):
        raise InputError(f"--name {name!r} is the name of a LinuxCNC module; choose another")


def _ours(so: Path) -> bool:
    """An installed module this export made (its name is not reserved and it says so): a re-install is fine."""
    try:
        return so.name[:-3] not in RESERVED and b"mtcal export" in so.read_bytes()
    except OSError:
        return False


def check_topology(machine: Machine) -> None:
    """LinuxCNC's joint layout: one joint per coordinate letter, linear axes X Y Z U V W and rotary A B C, each
    letter once, three linear axes (the C's position solve; derive/kins_c.py also needs one of them along z, the
    tool-length axis of G43)."""
    bad = [a for a, k in zip(machine.axes, machine.axis_kinds)
           if a not in (LINEAR_LETTERS if k == "linear" else ROTARY_LETTERS)]
    if bad or len(set(machine.axes)) != len(machine.axes) or len(machine.linear_axes) != 3:
        raise InputError(f"machine {machine.name} (axes {' '.join(machine.axes)}, "
                         f"{'/'.join(machine.axis_kinds)}) does not fit LinuxCNC's joint layout: each joint a "
                         f"coordinate letter, linear axes from {LINEAR_LETTERS}, rotary from {ROTARY_LETTERS}, three "
                         f"linear axes")


def generated_c(machine: Machine) -> str:
    """generated/<machine>_kins.c (derive/kins_c.py)."""
    p = _generated_dir() / f"{machine.name}_kins.c"
    if not p.is_file():
        raise InputError(f"machine {machine.name} has no generated C kinematics ({p.name}); run `python -m derive`")
    return p.read_text()


def _c_array(ctype: str, name: str, values) -> str:
    if not np.all(np.isfinite(np.asarray(values, dtype=float))):
        raise InputError(f"the model has a value that is not a finite number ({name}): a module cannot hold it")
    vals = [repr(int(v)) if ctype == "int" else repr(float(v)) for v in np.asarray(values).ravel()] or ["0"]
    body = ",\n    ".join(", ".join(vals[i: i + 6]) for i in range(0, len(vals), 6))
    return f"static const {ctype} {name}[{len(vals)}] = {{\n    {body}}};\n"


def model_data(model: ErrorModel, machine: Machine, scope: str = "position", cone: float = CONE_DEG) -> str:
    """The model as C data for ``struct mtk_model`` (generated/<machine>_kins.c): the scope, the cone (deg, scope
    "full") and ErrorEvaluator's plan, numbers written with 17 significant digits (each double exactly)."""
    ev = ErrorEvaluator(model, machine, "hold")
    out = [_c_array("double", "mtk_constants", ev.const)]
    tables, harmonics, polys = [], [], []
    for item in ev.plan:
        kind, ai, names = item[:3]
        k = len(tables) + len(harmonics) + len(polys)
        out.append(f"/* {kind} of {machine.axes[ai]}: {', '.join(names)} */\n")
        if kind == "table":
            cols, xp, step, coef = item[3:]
            out += [_c_array("int", f"mtk_c{k}", cols), _c_array("double", f"mtk_x{k}", xp),
                    _c_array("double", f"mtk_k{k}", coef)]
            tables.append(f"{{{ai}, {len(cols)}, {len(xp)}, {float(step)!r}, mtk_x{k}, mtk_c{k}, mtk_k{k}}}")
        elif kind == "harmonic":
            cols, period, a0, ca, sa = item[3:]
            out += [_c_array("int", f"mtk_c{k}", cols), _c_array("double", f"mtk_a{k}", a0),
                    _c_array("double", f"mtk_ca{k}", ca), _c_array("double", f"mtk_sa{k}", sa)]
            harmonics.append(f"{{{ai}, {len(cols)}, {ca.shape[1]}, {float(period)!r}, mtk_c{k}, mtk_a{k}, "
                             f"mtk_ca{k}, mtk_sa{k}}}")
        else:
            cols, f = item[3], item[4]
            lo, hi = float(f.positions.min()), float(f.positions.max())
            dom = f.fit.domain if f.fit.domain is not None else [lo, hi]
            off, scl = np.polynomial.polyutils.mapparms(dom, [-1, 1])
            out.append(_c_array("double", f"mtk_p{k}", f.fit.coefficients))
            polys.append(f"{{{ai}, {int(cols[0])}, {len(f.fit.coefficients)}, {lo!r}, {hi!r}, {float(off)!r}, "
                         f"{float(scl)!r}, mtk_p{k}}}")
    for ctype, name, rows in (("mtk_table", "mtk_tables", tables), ("mtk_harmonic", "mtk_harmonics", harmonics),
                              ("mtk_polynomial", "mtk_polynomials", polys)):
        body = ",\n    ".join(rows) if rows else "{0}"
        out.append(f"static const struct {ctype} {name}[] = {{\n    {body}}};\n")
    out.append(f"static const struct mtk_model mtk_model = {{{int(scope == 'full')}, {float(cone)!r}, mtk_constants, "
               f"{len(tables)}, {len(harmonics)}, {len(polys)}, mtk_tables, mtk_harmonics, mtk_polynomials}};\n")
    return "".join(out)


COMP = '''\
component {name} "mtcal volumetric compensation of {machine} (model {model}): a KINEMATICS_BOTH module";
description """
Written by mtcal export {model} --format linuxcnc-kins (model sha256 {digest}).
World: the nominal axes {axes} the part program commands.  Joints: the axis positions that put the tool tip there on
the machine with the model's errors, scope "{scope}" (position: the linear axes corrected, the rotary axes as
commanded; full: the rotary axes correct the tool axis too, as mtcal compensate --scope full).
The error functions are compiled in; beyond their measured range their end values are held.
Pin tool-length: the tool length L (mm) of G43, from motion.tooloffset.z (world {tool} = tool tip + L).
Pin max-iterations: the cap of the inverse's Newton steps; a move that does not converge within it is refused.
""";
pin in float tool_length = 0 "tool length L, mm: net it to motion.tooloffset.z (G43)";
pin in s32 max_iterations = {max_iterations} "cap of the inverse's Newton steps; not converged: the move is refused";
option singleton yes;
license "GPL";
author "mtcal export (generated)";
;;
#include "rtapi_math.h"
#include "kinematics.h"
#undef tool_length    /* halcompile's pin macros: the generated C has a parameter of that name */
#undef max_iterations

{generated}
/* ----------------------------------------------------------------- the model (mtcal export: data only) */
{data}
/* ----------------------------------------------------------------- LinuxCNC's entry points */
static int mtk_pins(double *tool_length_mm, int *cap)
{{
    const struct __comp_state *inst = __comp_first_inst;
    if (!inst) return -1;
    *tool_length_mm = *inst->tool_length;
    *cap = *inst->max_iterations;
    return 0;
}}

int kinematicsForward(const double *joint, EmcPose *pos, const KINEMATICS_FORWARD_FLAGS *fflags,
                      KINEMATICS_INVERSE_FLAGS *iflags)
{{
    double world[MTK_N_AXES], tl;
    int cap;
    (void)fflags;
    (void)iflags;
    if (mtk_pins(&tl, &cap) || mtk_forward_kins(&mtk_model, joint, tl, cap, world)) return -1;
{to_pose}
    return 0;
}}

int kinematicsInverse(const EmcPose *pos, double *joint, const KINEMATICS_INVERSE_FLAGS *iflags,
                      KINEMATICS_FORWARD_FLAGS *fflags)
{{
    double world[MTK_N_AXES], tl;
    int cap;
    (void)iflags;
    (void)fflags;
    if (mtk_pins(&tl, &cap)) return -1;
{from_pose}
    return mtk_inverse(&mtk_model, world, tl, cap, joint) < 0 ? -1 : 0;
}}

KINEMATICS_TYPE kinematicsType(void) {{ return KINEMATICS_BOTH; }}

int kinematicsSwitchable(void) {{ return 0; }}  /* kinematics.h's KINS_NOT_SWITCHABLE, without its unused parameter */
int kinematicsSwitch(int switchkins_type) {{ (void)switchkins_type; return 0; }}
EXPORT_SYMBOL(kinematicsSwitchable);
EXPORT_SYMBOL(kinematicsSwitch);
EXPORT_SYMBOL(kinematicsType);
EXPORT_SYMBOL(kinematicsForward);
EXPORT_SYMBOL(kinematicsInverse);
'''


def render_comp(model: ErrorModel, machine: Machine, name: str, model_path: str, scope: str = "position",
                cone: float = CONE_DEG) -> str:
    """The .comp text: halcompile's header, generated/<machine>_kins.c, the model's data and the entry points
    (each coordinate letter's EmcPose field <-> the joint of the same index)."""
    fields = [POSE_FIELDS[a] for a in machine.axes]
    unused = [f for f in POSE_FIELDS.values() if f not in fields]
    to_pose = "".join(f"    pos->{f} = world[{i}];\n" for i, f in enumerate(fields)) + "".join(
        f"    pos->{f} = 0;\n" for f in unused)
    from_pose = "".join(f"    world[{i}] = pos->{f};\n" for i, f in enumerate(fields))
    tool = machine.axes[int(re.search(r"#define MTK_TOOL_AXIS (\d+)", generated_c(machine))[1])]
    return COMP.format(name=name, machine=machine.name, model=Path(model_path).name, digest=model.digest(),
                       axes=" ".join(machine.axes), tool=tool, max_iterations=MAX_ITERATIONS,
                       generated=generated_c(machine), data=model_data(model, machine, scope, cone), scope=scope,
                       to_pose=to_pose.rstrip("\n"),
                       from_pose=from_pose.rstrip("\n"))


def usage_lines(machine: Machine, name: str) -> list[str]:
    """The INI and HAL lines that load the component (HAL names spell ``_`` as ``-``, as halcompile does)."""
    hal = name.replace("_", "-")
    return [f"# build and install: halcompile --install {name}.comp  (or copy the built {name}.so to {MODULE_DIR})",
            "[KINS]", f"KINEMATICS = {name}", f"JOINTS = {len(machine.axes)}",
            "[TRAJ]", f"COORDINATES = {''.join(machine.axes)}",
            "# HAL (after motmod is loaded, e.g. in a [HAL]HALFILE of its own):",
            f"net mtcal-tool-length motion.tooloffset.z => {hal}.tool-length",
            f"setp {hal}.max-iterations {MAX_ITERATIONS}"]


def export_kins(model: ErrorModel, machine: Machine, out: str | Path, name: str = DEFAULT_NAME,
                model_path: str = "MODEL.json", force: bool = False, protect: tuple = (), scope: str = "position",
                cone: float = CONE_DEG) -> KinsExport:
    """Write the kinematics component NAME.comp (and NAME.ini, the lines to use it) into the folder ``out``.

    Parameters
    ----------
    model : ErrorModel
        The error model (mm, rad); it passes the plausibility guard (mtcal.model.plausibility) unless ``force``.
    machine : Machine
        The machine the module is for; refused when the model is of another, or when its axes do not fit
        LinuxCNC's joint layout (``check_topology``).
    out : str or pathlib.Path
        The output folder; refused when it holds a file mtcal did not write.
    name : str, optional
        The component's name: a C identifier that no LinuxCNC module has (default ``mtcalkins``).
    model_path : str, optional
        The model's name in messages and in the component's description.
    force : bool, optional
        Write a model that fails the plausibility guard, with a loud warning.
    protect : tuple, optional
        Paths that must not be written over (the inputs).
    scope : {"position", "full"}, optional
        As ``Compensator``'s: "position" corrects the linear axes, "full" the rotary axes too (default "position").
    cone : float, optional
        Scope "full": no orientation correction within this angle (deg) of a singular pose, blended in up to twice
        it (``Compensator``'s, default 2).

    Returns
    -------
    KinsExport
        The files, the component's C and HAL names, the INI/HAL lines, the errors held.

    Raises
    ------
    mtcal.errors.InputError
        Any of the refusals above; nothing is written then.

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.data import path
    >>> from mtcal.export.linuxcnc_kins import export_kins
    >>> model = mtcal.load_model(path("demo_truth.json"))
    >>> res = export_kins(model, model.kinematics, "kins", name="dmu_kins")
    >>> res.files, res.hal_name
    (['kins/dmu_kins.comp', 'kins/dmu_kins.ini'], 'dmu-kins')
    """
    if model.machine != machine.name:
        raise InputError(f"{model_path}: the model is of machine {model.machine}, not {machine.name} (`machine`)")
    if scope not in SCOPES or not (cone == cone and abs(cone) < 90):
        raise InputError(f"scope must be one of {SCOPES} and cone a finite angle below 90 deg, got {scope!r}, {cone!r}")
    check_name(name)
    check_topology(machine)
    warnings = check_model(model, machine, force, model_path, fit_against_table=True)
    held = [n for n in model.names() if n in model.constants and model.constants[n] != 0
            or n in model.functions and not _zero(model.functions[n])]
    if not held:
        raise InputError(f"{model_path}: the model has no non-zero error; nothing was written")
    files = {f"{name}.comp": render_comp(model, machine, name, model_path, scope, cone),
             f"{name}.ini": "".join(f"{ln}\n" for ln in
                                    [f"# mtcal export {Path(model_path).name} --format linuxcnc-kins --name {name} "
                                     f"--scope {scope}"]
                                    + usage_lines(machine, name))}
    out = Path(out)
    _refuse_folder(out, files, protect)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for fname, text in files.items():
        atomic_write_text(out / fname, text)
        record_written(out / fname)
        paths.append(str(out / fname))
    return KinsExport(paths, name, name.replace("_", "-"), usage_lines(machine, name), held, warnings)


def _zero(f) -> bool:
    return not np.any(f.values) and (f.fit is None or f.fit.is_zero())


def _refuse_folder(out: Path, files: dict, protect: tuple) -> None:
    """The output folder: a folder (or new), holding only files mtcal wrote, none of them an input."""
    if out.exists() and not out.is_dir():
        raise InputError("exists and is not a folder; format linuxcnc-kins writes a folder", out)
    if out.is_dir():
        for p in sorted(out.iterdir()):
            if p.is_file():
                refuse_foreign(p)
    for p in protect:
        if p and any(os.path.exists(out / f) and os.path.samefile(out / f, p) for f in files):
            raise InputError(f"output {out} would overwrite the input {p}; choose another folder")
