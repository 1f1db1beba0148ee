"""A real LinuxCNC for the tests (Debian packages linuxcnc-uspace, linuxcnc-uspace-dev): one headless simulator
runner, one file lock for every test that starts LinuxCNC, and the kinematics module's two builds (halcompile
--compile for the simulator, halcompile --preprocess + gcc for a userspace harness without one).

Why a lock: the `linuxcnc` script kills another instance by name when there is no tty, and HAL/NML shared
memory uses fixed keys, so two LinuxCNC runs (two pytest-xdist workers) would break each other; an flock on one
file serialises them across processes.
"""
from __future__ import annotations

import contextlib
import fcntl
import json
import os
import shutil
import subprocess
import tempfile
import uuid
from pathlib import Path

import pytest

LINUXCNC = shutil.which("linuxcnc")
HALCOMPILE = shutil.which("halcompile")
GCC = shutil.which("gcc")
LOCK = Path(tempfile.gettempdir()) / "mtcal-linuxcnc.lock"
MODULE_DIR = Path("/usr/lib/linuxcnc/modules")
# Makefile.modinc's EXTRA_CFLAGS of a uspace module (halcompile --print-modinc), warnings on
CFLAGS = ["-Os", "-I.", "-I/usr/include/linuxcnc", "-DUSPACE", "-fno-fast-math", "-mieee-fp",
          "-fno-unsafe-math-optimizations", "-DRTAPI", "-D_GNU_SOURCE", "-Drealtime", "-D__MODULE__",
          "-fno-builtin-sin", "-fno-builtin-cos", "-fno-builtin-sincos", "-Wframe-larger-than=2560", "-DSIM",
          "-fPIC", "-Wall", "-Wextra"]
HARNESS = r"""
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "MODULE.c"  /* the module exactly as halcompile --preprocess wrote it */

/* argv: inverse|forward, tool length (mm), max-iterations, input (rows of 9 or N doubles), output, repeats.
 * inverse: EmcPose x y z a b c u v w -> status, N joints; forward: N joints -> status, 9 pose fields.
 * The pins are the component's own struct, pointed at locals (as hal_pin_*_newf would point them at HAL). */
int main(int argc, char **argv)
{
    static hal_float_t tl;
    static hal_s32_t cap;
    struct __comp_state inst;
    KINEMATICS_FORWARD_FLAGS ff = 0;
    KINEMATICS_INVERSE_FLAGS fi = 0;
    FILE *f;
    double *in, *out, *pf;
    long n, i, r, reps, width, ow;
    struct timespec t0, t1;
    int inverse;
    if (argc != 7) return 2;
    inverse = !strcmp(argv[1], "inverse");
    tl = atof(argv[2]);
    cap = atoi(argv[3]);
    reps = atol(argv[6]);
    memset(&inst, 0, sizeof inst);
    inst.tool_length = &tl;
    inst.max_iterations = &cap;
    __comp_first_inst = &inst;
    width = inverse ? 9 : MTK_N_AXES;
    ow = 1 + (inverse ? MTK_N_AXES : 9);
    f = fopen(argv[4], "rb");
    fseek(f, 0, SEEK_END);
    n = ftell(f) / (long)(sizeof(double) * width);
    rewind(f);
    in = malloc(sizeof(double) * width * n);
    out = calloc(ow * n, sizeof(double));
    if (fread(in, sizeof(double) * width, n, f) != (size_t)n) return 3;
    fclose(f);
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t0);
    for (r = 0; r < reps; r++) {
        for (i = 0; i < n; i++) {
            double *o = out + ow * i;
            if (inverse) {
                EmcPose p;
                pf = in + 9 * i;
                p.tran.x = pf[0]; p.tran.y = pf[1]; p.tran.z = pf[2];
                p.a = pf[3]; p.b = pf[4]; p.c = pf[5]; p.u = pf[6]; p.v = pf[7]; p.w = pf[8];
                o[0] = kinematicsInverse(&p, o + 1, &fi, &ff);
            } else {
                EmcPose p;
                o[0] = kinematicsForward(in + MTK_N_AXES * i, &p, &ff, &fi);
                o[1] = p.tran.x; o[2] = p.tran.y; o[3] = p.tran.z;
                o[4] = p.a; o[5] = p.b; o[6] = p.c; o[7] = p.u; o[8] = p.v; o[9] = p.w;
            }
        }
    }
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t1);
    f = fopen(argv[5], "wb");
    fwrite(out, sizeof(double) * ow, n, f);
    fclose(f);
    printf("%.3f\n", ((t1.tv_sec - t0.tv_sec) * 1e9 + (t1.tv_nsec - t0.tv_nsec)) / ((double)n * reps));
    return 0;
}
"""


def need(*progs: str) -> None:
    """Skip, naming the Debian package, when a program is absent."""
    for name, path in (("linuxcnc", LINUXCNC), ("halcompile", HALCOMPILE), ("gcc", GCC)):
        if name in progs and path is None:
            pkg = {"linuxcnc": "linuxcnc-uspace", "halcompile": "linuxcnc-uspace-dev", "gcc": "gcc"}[name]
            pytest.skip(f"{name} is not installed (Debian package {pkg})")


@contextlib.contextmanager
def linuxcnc_lock():
    """Hold the one lock of every LinuxCNC run (module docstring), across pytest-xdist workers."""
    with open(LOCK, "a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def run_linuxcnc(folder: Path, ini: str = "comp.ini", timeout: float = 180) -> dict:
    """Run the configuration ``folder/ini`` (its display, a probe script, writes probe_out.json) under the lock;
    HOME points there (the linuxcnc script copies its logs to $HOME).  Skips, with the log's tail, when LinuxCNC
    does not start headless here."""
    env = dict(os.environ, HOME=str(folder))
    with linuxcnc_lock(), tempfile.TemporaryDirectory(prefix="mtcal-rtapi-") as fifo:
        if os.geteuid() == 0:  # rtapi_app refuses root without a fallback user, who must reach the FIFO
            os.chmod(fifo, 0o777)
            env.update(RTAPI_UID="65534", RTAPI_FIFO_PATH=str(Path(fifo) / "rtapi_fifo"))
        r = subprocess.run([LINUXCNC, str(folder / ini)], cwd=folder, env=env, stdin=subprocess.DEVNULL,
                           capture_output=True, text=True, timeout=timeout)
    out = folder / "probe_out.json"
    if not out.exists():
        log = folder / "linuxcnc_debug.txt"
        tail = [ln for ln in (log.read_text().splitlines() if log.exists() else []) if not ln.startswith("+")]
        pytest.skip(f"LinuxCNC did not start headless here (exit {r.returncode}): {' | '.join(tail[-4:])}")
    return json.loads(out.read_text())


def _no_warning(r: subprocess.CompletedProcess) -> None:
    assert r.returncode == 0, r.stdout + r.stderr
    assert "warning" not in (r.stdout + r.stderr).lower(), r.stdout + r.stderr


@contextlib.contextmanager
def installed(comp: Path):
    """``halcompile --install COMP`` (the docs' step: builds NAME.so into LinuxCNC's module folder, where a module
    must be to load; no warning allowed), removed afterwards; the name must be unique (``unique_name``).  Skips
    when the folder is not writable."""
    dest = MODULE_DIR / f"{comp.stem}.so"
    if not os.access(MODULE_DIR, os.W_OK):
        pytest.skip(f"{MODULE_DIR} is not writable here (the module must be installed there to load)")
    assert not dest.exists(), f"{dest} exists: not a unique name"
    try:
        _no_warning(subprocess.run([HALCOMPILE, "--install", comp.name], cwd=comp.parent, capture_output=True,
                                   text=True, timeout=300))
        assert dest.is_file()
        yield dest
    finally:
        dest.unlink(missing_ok=True)


def unique_name(stem: str = "mtcaltest") -> str:
    """A component name no other run uses (a C identifier)."""
    return f"{stem}_{uuid.uuid4().hex[:10]}"


def build_harness(comp: Path) -> Path:
    """halcompile --preprocess COMP, then gcc the harness that includes that C (module flags, -Wall -Wextra; linked
    with LinuxCNC's HAL library for halcompile's frame, which the harness never calls) -> the executable."""
    r = subprocess.run([HALCOMPILE, "--preprocess", comp.name], cwd=comp.parent, capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    src = comp.parent / "harness.c"
    src.write_text(HARNESS.replace("MODULE", comp.stem))
    exe = comp.parent / "harness"
    r = subprocess.run([GCC, *CFLAGS, "-o", str(exe), str(src), "-lm", "-llinuxcnchal"],
                       cwd=comp.parent, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    # silent under -Wall -Wextra, but for halcompile's own frame (its export() never uses extra_arg)
    loud = [ln for ln in r.stderr.splitlines() if "warning" in ln and "extra_arg" not in ln]
    assert not loud, "\n".join(loud)
    return exe
