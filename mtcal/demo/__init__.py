"""The main job on bundled data (``mtcal demo``), on the library."""
from mtcal.demo.run import run_demo

__all__ = ["run_demo"]
