"""Packages named like the user's verbs (``mtcal.identify``, ``mtcal.diagnose``) are also those verbs.

Importing a package binds its name on ``mtcal`` to the module (Python's import system sets the parent's attribute
after the package has run), which would hide the lazy ``mtcal.identify()`` of ``mtcal/__init__`` behind the
package as soon as anything imported ``mtcal.identify.run``.  Such a package is therefore made callable as its
function: ``mtcal.identify(rec, ...)`` works whatever was imported first."""
from __future__ import annotations

import sys
import types
from typing import Callable


def callable_package(name: str, function: Callable) -> None:
    """Make package ``name`` (already in sys.modules) call ``function`` when called."""

    class VerbPackage(types.ModuleType):
        def __call__(self, *args, **kwargs):
            return function(*args, **kwargs)

    VerbPackage.__call__.__doc__ = function.__doc__
    sys.modules[name].__class__ = VerbPackage
