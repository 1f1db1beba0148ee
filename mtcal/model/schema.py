"""Small checks for JSON inputs (error model, plan): each names the file and the JSON path of a bad field.

JSON numbers only: booleans (``true`` is an int in Python), strings and null are refused, as are NaN and
infinities (Python's json reads ``NaN``/``Infinity``).  A dozen lines instead of a schema library: the
messages stay ours (file, path, expected, got) and nothing is added to the install.
"""
from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

from mtcal.errors import InputError


def _got(v: Any) -> str:
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "..."


def obj(v: Any, source: str, where: str) -> Mapping:
    """``v`` must be a JSON object."""
    if not isinstance(v, Mapping):
        raise InputError(f"{where} must be an object {{...}}, got {_got(v)}", source)
    return v


def number(v: Any, source: str, where: str, positive: bool = False) -> float:
    """A finite JSON number (not a boolean); ``positive``: > 0."""
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or (positive and v <= 0):
        raise InputError(f"{where} must be a {'positive' if positive else 'finite'} number, got {_got(v)}", source)
    return float(v)


def numbers(v: Any, source: str, where: str, min_len: int = 0) -> np.ndarray:
    """A JSON list of finite numbers (at least ``min_len``) as a float array."""
    if not isinstance(v, list) or len(v) < min_len:
        raise InputError(f"{where} must be a list of {'at least ' + str(min_len) + ' ' if min_len else ''}"
                         f"numbers, got {_got(v)}", source)
    return np.array([number(x, source, f"{where}[{i}]") for i, x in enumerate(v)], dtype=float)


def known_keys(v: Mapping, allowed, source: str, where: str) -> None:
    """No keys outside ``allowed``."""
    unknown = sorted(set(v) - set(allowed))
    if unknown:
        raise InputError(f"{where}: unknown key(s) {unknown}; allowed: {sorted(allowed)}", source)
