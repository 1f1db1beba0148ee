"""Bundled data: the demo campaign of a DMU 50 and its truth, the NBS plate tables (NBSIR 79-1752), a five-axis
sample program.  ``path(name)`` gives a file's path."""
from __future__ import annotations

from importlib import resources
from pathlib import Path


def path(name: str) -> Path:
    """Path of a bundled file, e.g. path("demo_campaign.csv")."""
    return Path(str(resources.files("mtcal.data").joinpath(name)))
