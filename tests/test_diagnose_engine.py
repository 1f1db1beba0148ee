"""The diagnosis engine's F test against a plain least-squares F test written here (textbook nested-model F:
F = ((RSS0 - RSS1) / k) / (RSS1 / (N - p - k)), p value from the F(k, N - p - k) distribution)."""
from __future__ import annotations

import numpy as np
from scipy import stats

from mtcal.diagnose import Engine


def plain_f(X: np.ndarray, G: np.ndarray, y: np.ndarray) -> tuple[float, float, int]:
    def rss(A):
        beta = np.linalg.lstsq(A, y, rcond=None)[0]
        return float(np.sum((y - A @ beta) ** 2))
    rss0, rss1 = rss(X), rss(np.hstack([X, G]))
    k, dof = G.shape[1], len(y) - X.shape[1] - G.shape[1]
    F = ((rss0 - rss1) / k) / (rss1 / dof)
    return F, float(stats.f.sf(F, k, dof)), dof


def test_engine_f_test_equals_plain_least_squares():
    rng = np.random.default_rng(7)
    N = 90
    X1, X2 = rng.normal(size=(40, 3)), rng.normal(size=(50, 4))  # two blocks of rows (two axes)
    X = np.zeros((N, 7))
    X[:40, :3], X[40:, 3:] = X1, X2
    G = rng.normal(size=(N, 2)) + 0.5 * X[:, :2]                 # overlaps the base, still separable
    y = X @ rng.normal(size=7) + 0.3 * G[:, 0] + rng.normal(scale=0.5, size=N)
    eng = Engine([(np.arange(40), X1), (np.arange(40, 90), X2)], y)
    s = eng.score(G)
    F, p, dof = plain_f(X, G, y)
    assert s.separable and s.k == 2 and s.dof == dof
    assert abs(s.F - F) < 1e-9 * F and abs(np.exp(s.logp) - p) < 1e-9 * max(p, 1e-300) + 1e-15
    # after adding G, a further column is tested against base + G
    H = rng.normal(size=(N, 1))
    eng.add(G)
    F2, p2, _ = plain_f(np.hstack([X, G]), H, y)
    assert abs(eng.score(H).F - F2) < 1e-9 * F2


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
