"""Tail probabilities and quantiles of the chi^2, F, Student-t and normal distributions, one place for the tests'
statistics (F tests of the diagnosis, likelihood ratios, intervals).

scipy.special's cdflib and Boost functions directly: the same numbers as scipy.stats' distributions (``stats.f.sf``
is ``special.fdtrc``, ``stats.chi2.sf`` is ``special.chdtrc``, ...), without their argument checking (about 0.1 ms a
call: the diagnosis calls them thousands of times) and without importing scipy.stats (0.4-1 s of every command's
start)."""
from __future__ import annotations

import numpy as np
from scipy import special

# each takes numbers or arrays (numpy broadcasting) and returns what scipy.special returns (a numpy float or array)


def chi2_sf(x, k):
    """P(X > x) for X ~ chi^2 with k degrees of freedom."""
    return special.chdtrc(k, x)


def chi2_ppf(p, k):
    """The p-quantile of chi^2 with k degrees of freedom."""
    return special.chdtri(k, 1.0 - np.asarray(p, float))


def chi2_isf(q, k):
    """The chi^2 value with k degrees of freedom exceeded with probability q (exact for tiny q)."""
    return special.chdtri(k, q)


def f_sf(x, k1, k2):
    """P(X > x) for X ~ F(k1, k2)."""
    return special.fdtrc(k1, k2, x)


def f_logsf(x, k1, k2):
    """log P(X > x) for X ~ F(k1, k2) (-inf beyond the float range, as scipy.stats' own)."""
    with np.errstate(divide="ignore"):
        return np.log(special.fdtrc(k1, k2, x))


def f_ppf(p, k1, k2):
    """The p-quantile of F(k1, k2)."""
    return special.fdtri(k1, k2, p)


def t_sf(x, nu):
    """P(X > x) for X ~ Student-t with nu degrees of freedom (the normal's for infinite nu)."""
    return special.stdtr(nu, -np.asarray(x, float))


def t_ppf(p, nu):
    """The p-quantile of Student-t with nu degrees of freedom (the normal's for infinite nu)."""
    return special.stdtrit(nu, p)
