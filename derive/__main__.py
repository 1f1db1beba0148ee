"""python -m derive [--check] [--jobs N] [--out DIR]: regenerate generated/ or check that it is current."""
from __future__ import annotations

import argparse
import difflib
import json
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from . import codegen
from .provenance import ROOT, derive_files, derive_hash, sha256
from .targets import TARGETS

OUT = ROOT / "generated"
INIT = '"""Generated code (do not edit): see manifest.json and derive/ for how it was made."""\n'


def _build(name: str) -> tuple[str, dict[str, str], dict, float]:
    t0 = time.perf_counter()

    def progress(msg: str) -> None:
        print(f"  [{name}] {msg} ({time.perf_counter() - t0:5.1f} s)", file=sys.stderr, flush=True)

    mod = TARGETS[name](progress)
    files = {f"{mod.name}_numpy.py": codegen.emit_numpy(mod, name),
             f"{mod.name}_casadi.py": codegen.emit_casadi(mod, name)}
    info = {"source": f"derive/{mod.source}", "functions": [f.name for f in mod.functions]}
    spec = mod.metadata.get("MACHINE")
    if spec:  # a machine: also the C of its controller kinematics module
        from .kins_c import emit
        from .spec import load_spec
        files[f"{mod.name}_kins.c"] = emit(mod, name, load_spec(spec))
        info["spec"] = f"derive/machines/{spec}.toml"
        info["spec_sha256"] = sha256((ROOT / info["spec"]).read_bytes())
    return name, files, info, time.perf_counter() - t0


def generate(names: list[str], jobs: int) -> dict[str, str]:
    import casadi
    import sympy
    files: dict[str, str] = {"__init__.py": INIT}
    manifest = {"generator": "python -m derive", "sympy": sympy.__version__, "casadi": casadi.__version__,
                "derive_sha256": derive_hash(), "derive_files": derive_files(), "targets": {}}
    with ProcessPoolExecutor(max_workers=jobs) as pool:
        for name, fs, info, secs in pool.map(_build, names):
            print(f"derived {name} in {secs:.1f} s", file=sys.stderr, flush=True)
            files.update(fs)
            info["files"] = {k: sha256(v) for k, v in sorted(fs.items())}
            manifest["targets"][name] = info
    files["manifest.json"] = json.dumps(manifest, indent=2, sort_keys=True) + "\n"
    return files


def stale(files: dict[str, str], out: Path) -> list[str]:
    """Lines naming every file of ``out`` that differs from the derivation ``files`` (with the first changed
    lines), or that the derivation does not produce; empty when ``out`` is current."""
    lines = []
    for fname, text in sorted(files.items()):
        p = out / fname
        old = p.read_text() if p.exists() else ""
        if old != text:
            diff = list(difflib.unified_diff(old.splitlines(), text.splitlines(), f"generated/{fname}",
                                             f"derived/{fname}", lineterm="", n=0))
            lines.append(f"STALE {fname}: {sum(1 for d in diff if d[:1] in '+-') - 2} changed lines")
            lines += ["    " + line[:160] for line in diff[2:14]]
    for e in sorted(p.name for p in out.glob("*") if p.is_file() and p.name not in files):
        lines.append(f"STALE {e}: in generated/ but not produced by the derivation")
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m derive", description=__doc__)
    ap.add_argument("--check", action="store_true", help="compare with generated/ instead of writing; exit 1 if stale")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="parallel derivations")
    ap.add_argument("--out", type=Path, default=OUT, help="output folder (default: generated/)")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    files = generate(sorted(TARGETS), max(1, args.jobs))
    if args.check:
        problems = stale(files, args.out)
        for line in problems:
            print(line, file=sys.stderr)
        if problems:
            n = sum(1 for line in problems if line.startswith("STALE"))
            print(f"generated/ is stale ({n} files); run `python -m derive`", file=sys.stderr)
            return 1
        print(f"generated/ is current ({len(files)} files, {time.perf_counter() - t0:.1f} s)")
        return 0
    args.out.mkdir(parents=True, exist_ok=True)
    for fname, text in files.items():
        p = args.out / fname
        if not p.exists() or p.read_text() != text:
            tmp = p.with_suffix(p.suffix + ".tmp")
            tmp.write_text(text)
            os.replace(tmp, p)
    print(f"wrote {len(files)} files to {args.out} in {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
