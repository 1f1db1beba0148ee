"""LinuxCNC joint compensation files (`[JOINT_n]COMP_FILE`, `COMP_FILE_TYPE` 0 or 1) and the INI snippet.

Source: LinuxCNC 2.9 sources, src/emc/motion/usrmotintf.cc `usrmotLoadComp` (reads "%lf %lf %lf" per line and
stops silently at the first line that is not three numbers; type 0: trim = nominal - forward, nominal - reverse;
type 1: the columns are the trims), src/emc/motion/command.c `EMCMOT_SET_JOINT_COMP` (nominals must increase
strictly, at most EMCMOT_COMP_SIZE = 256 entries), src/emc/motion/control.c `compute_screw_comp` (trim linearly
interpolated at the commanded joint position, forward trim while the joint moves up, reverse trim while it moves
down, held while it stands; motor command = joint command + trim) and motion.c (sentinel entries at -/+DBL_MAX
with zero slope: the end trims are held outside the table).
Units and spacing: machine units (mm for linear joints, deg for rotary joints), nominal positions on a regular
grid of ``step``, no header line (a comment line would end the file for the loader).
Sign: type 1 holds the trim added to the commanded joint position (= minus the joint-equivalent error), type 0 the
position the joint actually reaches when commanded to the nominal position (= nominal + error).
"""
from __future__ import annotations

from mtcal.errors import InputError
from mtcal.export.sampling import AxisTable

NAME = "linuxcnc"
MAX_POINTS = 256
HARD_LIMIT = True   # the controller cannot take more points
CROSS = False  # a joint table holds the joint's own positioning only
FILES = "joint*.comp"  # the tables this format writes (a re-export removes stale ones)
BACKLASH_NOTE = ("the table's forward/reverse trims hold the reversal; LinuxCNC ignores [JOINT_n]BACKLASH while a "
                 "COMP_FILE is loaded (control.c), set it to 0 anyway so that removing the table does not bring "
                 "back a second backlash compensation")
SIGN = {1: "type 1: forward/reverse trim added to the commanded joint position (= -error); source: LinuxCNC "
           "usrmotintf.cc usrmotLoadComp and control.c compute_screw_comp",
        0: "type 0: actual position reached when moving forward/reverse (= nominal + error; the loader takes "
           "trim = nominal - actual); source: LinuxCNC usrmotintf.cc usrmotLoadComp"}


LINEAR_UNITS = {"mm": 1.0, "inch": 1.0 / 25.4}  # the INI's [TRAJ]LINEAR_UNITS -> factor from mm


def comp_file(t: AxisTable, file_type: int, scale: float = 1.0) -> str:
    """The three-column text of one joint (machine units: ``scale`` converts a linear joint's mm, no header)."""
    k = scale if t.unit == "mm" else 1.0
    pos, fwd, rev = t.positions * k, t.directional(+1) * k, t.directional(-1) * k
    if file_type == 0:
        fwd, rev = pos - fwd, pos - rev
    return "".join(f"{p:.6f} {f:.9f} {r:.9f}\n" for p, f, r in zip(pos, fwd, rev))


def render(tables: list[AxisTable], machine, file_type: int, model_path: str,
           linear_units: str = "mm") -> dict[str, str]:
    """{file name: text}: one comp file per joint and linuxcnc_comp.ini (the [JOINT_n] lines to merge);
    ``linear_units``: the machine's [TRAJ]LINEAR_UNITS (mm or inch): linear joints' tables in that unit."""
    if linear_units not in LINEAR_UNITS:
        raise InputError(f"`linear_units` must be mm or inch (the INI's [TRAJ]LINEAR_UNITS), got {linear_units!r}")
    scale = LINEAR_UNITS[linear_units]
    files, ini = {}, [f"# mtcal export {model_path} --format linuxcnc: merge into the machine's INI file.",
                      f"# {SIGN[file_type]}.",
                      f"# units: linear joints in {linear_units} (this must be the INI's [TRAJ]LINEAR_UNITS; "
                      f"converted from mm), rotary joints in deg.",
                      "# Joint numbers follow the machine's axis order (trivkins); change n if your joints differ.",
                      "# With a COMP_FILE loaded, control.c uses its trims and ignores [JOINT_n]BACKLASH.",
                      "# Outside a table the end trims are held: a rotary joint beyond its table range (e.g. C past "
                      "360 deg) gets the end value, not a wrapped one.", ""]
    for t in tables:
        n = machine.axes.index(t.axis)
        name = f"joint{n}_{t.axis}.comp"
        files[name] = comp_file(t, file_type, scale)
        unit, k = (linear_units, scale) if t.unit == "mm" else (t.unit, 1.0)
        ini += [f"[JOINT_{n}]", f"# axis {t.axis}: {len(t.positions)} points, step {t.step * k:g} {unit}, "
                f"from {', '.join(t.sources[t.axis])}; reversal {t.reversal * k:.6g} {unit}",
                f"COMP_FILE = {name}", f"COMP_FILE_TYPE = {file_type}", ""]
    files["linuxcnc_comp.ini"] = "\n".join(ini)
    return files
