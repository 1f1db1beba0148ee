"""mtcal: machine-tool calibration toolkit (derived kinematics, identification, compensation, diagnosis)."""
from __future__ import annotations

__version__ = "0.1.0"

from mtcal.kinematics.machine import Machine, load_machine  # noqa: E402

__all__ = ["Machine", "load_machine", "__version__"]
