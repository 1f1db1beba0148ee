"""The generator itself: symbolic vs generated numeric, byte-identical regeneration, --check, machines as data."""
from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mtcal
from derive import codegen
from derive.kinematics import derive_machine
from derive.spec import load_spec

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module", params=sorted(p.stem for p in (ROOT / "derive" / "machines").glob("*.toml")))
def derived(request):
    return derive_machine(load_spec(request.param))


@pytest.mark.slow
def test_generated_numpy_equals_sympy_expressions(derived):
    """Each generated function against SymPy's own lambdify of the same expressions (independent printer, no cse)."""
    gen = mtcal.load_machine(derived.name)._np
    rng = np.random.default_rng(11)
    for f in derived.functions:
        syms = [s for a in f.args for s in a.symbols]
        ref = sp.lambdify(syms, f.outputs.tolist(), modules="math")
        for _ in range(3):
            vals = {}
            for a in f.args:
                for s in a.symbols:
                    name = str(s)
                    if name.startswith("E_"):
                        vals[s] = rng.normal() * (5e-5 if name[2] in "ABC" else 0.02)
                    elif name in ("B", "A"):
                        vals[s] = rng.uniform(5, 95)
                    elif name in ("i", "j"):
                        vals[s] = rng.uniform(-0.5, 0.5)
                    elif name == "k":
                        vals[s] = rng.uniform(0.3, 0.9)
                    else:
                        vals[s] = rng.uniform(-200, 200)
            if f.name == "ik_tilt":  # needs a unit vector
                i, j = vals[syms[0]], vals[syms[1]]
                vals[syms[2]] = np.sqrt(1 - i * i - j * j)
            expect = np.array(ref(*[vals[s] for s in syms]), dtype=float)
            args = [np.array([vals[s] for s in a.symbols]) if a.vector else vals[a.symbols[0]] for a in f.args]
            got = getattr(gen, f.name)(*args)
            atol = 1e-12 * max(1, np.abs(expect).max())
            assert np.allclose(got.reshape(expect.shape), expect, rtol=1e-12, atol=atol), f.name


@pytest.mark.slow
def test_regeneration_is_byte_identical():
    """`python -m derive --check` with another hash seed: a fresh derivation equals generated/ byte for byte (the
    one derivation of the suite; CI relies on it instead of a separate step)."""
    env = dict(os.environ, PYTHONHASHSEED="12345")
    r = subprocess.run([sys.executable, "-m", "derive", "--check"], cwd=ROOT, env=env,
                       capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stderr
    assert "generated/ is current" in r.stdout


def test_check_names_an_edited_a_missing_and_an_extra_file(tmp_path):
    """--check's comparison (derive.__main__.stale) on a copy of generated/: an edit, a removal and a foreign file
    are each reported; the copy itself is current."""
    from derive.__main__ import stale
    gen = ROOT / "generated"
    files = {p.name: p.read_text() for p in gen.iterdir() if p.is_file()}
    out = tmp_path / "gen"
    shutil.copytree(gen, out, ignore=shutil.ignore_patterns("__pycache__"))
    assert stale(files, out) == []
    target = out / "dmu50_numpy.py"
    target.write_text(target.read_text().replace("import numpy", "import numpy  # edited", 1))
    (out / "plate_numpy.py").unlink()
    (out / "notes.txt").write_text("x")
    lines = "\n".join(stale(files, out))
    assert "STALE dmu50_numpy.py: 2 changed lines" in lines and "edited" in lines
    assert "STALE plate_numpy.py" in lines
    assert "STALE notes.txt: in generated/ but not produced by the derivation" in lines


def test_the_runtime_warns_on_a_stale_derive_without_importing_it(tmp_path):
    """The manifest records derive/'s files; a changed byte warns (StaleGeneratedCodeWarning), the same bytes do
    not, and loading a machine imports no module of derive/."""
    from mtcal.kinematics.machine import StaleGeneratedCodeWarning, _check_stale
    (tmp_path / "derive").mkdir()
    (tmp_path / "generated").mkdir()
    src = tmp_path / "derive" / "kinematics.py"
    src.write_text("x = 1\n")
    import hashlib
    import json
    manifest = {"derive_files": {"derive/kinematics.py": hashlib.sha256(b"x = 1\n").hexdigest()}}
    (tmp_path / "generated" / "manifest.json").write_text(json.dumps(manifest))
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _check_stale(tmp_path / "generated")
    src.write_text("x = 2\n")
    with pytest.warns(StaleGeneratedCodeWarning):
        _check_stale(tmp_path / "generated")
    code = ("import sys, mtcal; mtcal.load_machine('dmu50'); "
            "print(sorted(m for m in sys.modules if m.startswith('derive')))")
    r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "[]"


def test_every_generated_file_has_provenance_header():
    for p in (ROOT / "generated").glob("*.py"):
        if p.name == "__init__.py":
            continue
        head = p.read_text().splitlines()[:4]
        assert "GENERATED FILE - DO NOT EDIT." in head[1] and "python -m derive" in head[2], p.name


def _chain_reference(ax: np.ndarray, d: float, tilt_deg: float) -> np.ndarray:
    """Straight HTM product of docs/design.md's chain with other d and tilt (independent of derive/)."""
    def rx(a):
        c, s = np.cos(a), np.sin(a)
        return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])

    def rz(a):
        c, s = np.cos(a), np.sin(a)
        return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])

    def tz(v):
        t = np.eye(4)
        t[2, 3] = v
        return t
    out = []
    for X, Y, Z, B, C in ax:
        tilt = np.radians(tilt_deg)
        t0w = tz(d) @ rx(tilt) @ rz(np.radians(B)) @ rx(-tilt) @ tz(-d) @ rz(-np.radians(C))
        t0t = np.eye(4)
        t0t[:3, 3] = X, Y, Z
        t = np.linalg.solve(t0w, t0t)
        out.append(np.r_[t[:3, 3], t[:3, 2]])
    return np.array(out)


@pytest.mark.slow
def test_changing_d_and_tilt_in_the_spec_needs_no_other_edit(tmp_path):
    text = (ROOT / "derive/machines/dmu50.toml").read_text()
    text = text.replace('d = "154.996"', 'd = "200.5"').replace('tilt = "45"', 'tilt = "30"')
    text = text.replace('name = "dmu50"', 'name = "dmu50mod"')
    spec_path = tmp_path / "dmu50mod.toml"
    spec_path.write_text(text)
    mod = derive_machine(load_spec(spec_path))
    src = tmp_path / "dmu50mod_numpy.py"
    src.write_text(codegen.emit_numpy(mod, "dmu50mod"))
    spec = importlib.util.spec_from_file_location("dmu50mod_numpy", src)
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    rng = np.random.default_rng(12)
    ax = np.column_stack([rng.uniform(-200, 200, (50, 3)), rng.uniform(0, 180, 50), rng.uniform(-360, 360, 50)])
    assert np.abs(gen.forward(ax, 0.0) - _chain_reference(ax, 200.5, 30.0)).max() < 1e-9
    assert gen.PARAMETERS == {"d": "401/2", "tilt": "30"}
    assert gen.IK["k_range"][0] == pytest.approx(np.cos(np.radians(60)))  # k = cos^2 + sin^2 cos B reaches cos(2 tilt)


def test_spec_errors_name_the_file(tmp_path):
    bad = tmp_path / "bad.toml"
    shutil.copy(ROOT / "derive/machines/dmu50.toml", bad)
    bad.write_text(bad.read_text().replace('joint = "C"', 'joint = "W"'))
    with pytest.raises(ValueError, match=r"bad.toml: table_chain\[5\] names unknown axis 'W'"):
        load_spec(bad)
