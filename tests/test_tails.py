"""mtcal._tails against scipy.stats' own distributions (the reference implementation the diagnosis, the history's
comparisons, the plate's outlier test and identify's coverage factors used before): the same numbers at points
across each distribution, so a swapped argument (F's degrees of freedom, chi^2's k and x) fails here."""
from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from mtcal import _tails

X = np.array([1e-3, 0.3, 1.0, 2.7, 9.0, 40.0, 471.5])
DOF = [(1, 1300), (3, 50), (5, 7), (12, 2000)]


@pytest.mark.parametrize("k1,k2", DOF)
def test_f_tails_are_scipy_stats(k1, k2):
    np.testing.assert_allclose(_tails.f_sf(X, k1, k2), stats.f.sf(X, k1, k2), rtol=1e-12, atol=0)
    np.testing.assert_allclose(_tails.f_logsf(X, k1, k2), stats.f.logsf(X, k1, k2), rtol=1e-12, atol=1e-15)
    p = np.array([0.025, 0.5, 0.975])
    np.testing.assert_allclose(_tails.f_ppf(p, k1, k2), stats.f.ppf(p, k1, k2), rtol=1e-10)


@pytest.mark.parametrize("k", [1, 3, 4, 30, 3000])
def test_chi2_tails_are_scipy_stats(k):
    np.testing.assert_allclose(_tails.chi2_sf(X, k), stats.chi2.sf(X, k), rtol=1e-12, atol=0)
    np.testing.assert_allclose(_tails.chi2_ppf(0.95, k), stats.chi2.ppf(0.95, k), rtol=1e-12)


@pytest.mark.parametrize("nu", [1.0, 3.0, 7.0, 120.0, np.inf])
def test_t_tails_are_scipy_stats_and_the_normal_at_infinity(nu):
    np.testing.assert_allclose(_tails.t_sf(X, nu), stats.t.sf(X, nu), rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(_tails.t_ppf(0.975, nu), stats.t.ppf(0.975, nu), rtol=1e-12)
    # identify's coverage factors (GUM G.3.2): 3.18 for 3 degrees of freedom, 1.96 for the joint fit
    assert round(float(_tails.t_ppf(0.975, 3.0)), 2) == 3.18 and round(float(_tails.t_ppf(0.975, np.inf)), 2) == 1.96


def test_an_f_tail_beyond_the_float_range_is_minus_infinity_as_scipy_stats():
    assert _tails.f_logsf(1e5, 3, 1000) == stats.f.logsf(1e5, 3, 1000) == -np.inf


def test_the_runtime_does_not_import_scipy_stats():
    """scipy.stats' import is 0.4-1 s of every command's start (measured here); the tails need scipy.special only."""
    import subprocess
    import sys
    code = ("import sys, mtcal.cli._main, mtcal.diagnose, mtcal.identify, mtcal.history, mtcal.uncertainty; "
            "print('scipy.stats' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
