"""The diagnosis engine's separability and overlap against plain least squares written here (the F test against
a plain least-squares F test: tests/test_diagnose.py)."""
from __future__ import annotations

import numpy as np

from mtcal.diagnose import Engine


def test_engine_refuses_a_column_inside_the_base():
    rng = np.random.default_rng(1)
    X = rng.normal(size=(30, 3))
    eng = Engine([(np.arange(30), X)], rng.normal(size=30))
    s = eng.score(X @ np.array([[1.0], [2.0], [-1.0]]))
    assert not s.separable and s.sep < 1e-6
    # overlap after the base: |cos| between the two columns with the base projected out (written here)
    a, b = rng.normal(size=(30, 1)), rng.normal(size=(30, 1))
    b = b + 2.0 * a
    ra, rb = (v[:, 0] - X @ np.linalg.lstsq(X, v[:, 0], rcond=None)[0] for v in (a, b))
    cos = abs(ra @ rb) / (np.linalg.norm(ra) * np.linalg.norm(rb))
    assert abs(eng.overlap(a, b) - cos) < 1e-9 and 0.5 < cos < 1.0
