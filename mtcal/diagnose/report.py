"""The result of a diagnosis (``Diagnosis``) and its residual plots."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mtcal.diagnose.prepare import Prepared
from mtcal.io import save_figure


# ---------------------------------------------------------------------------------------------- diagnosis
@dataclass
class Diagnosis:
    base_sigma: float
    base_sigma_ratio: float
    sigma_after: float
    sigma_ratio_after: float
    effects: list[dict]
    located: list[dict]
    base: dict
    notes: list[str] = field(default_factory=list)
    residuals_before: np.ndarray | None = None
    residuals_after: np.ndarray | None = None
    prep: Prepared | None = None

    def to_dict(self) -> dict:
        return {"base_sigma": self.base_sigma, "base_sigma_ratio": self.base_sigma_ratio,
                "sigma_after": self.sigma_after, "sigma_ratio_after": self.sigma_ratio_after,
                "effects": self.effects, "located": self.located, "base_model": self.base,
                "units": {"length": "mm", "angle": "rad", "position": "mm (linear axes) or deg (rotary axes)",
                          "sigma_ratio": "1 = the tracker's specification (AT960) when --tracker is given"},
                "notes": self.notes}


# ---------------------------------------------------------------------------------------------- plots
def plot_residuals(diag: Diagnosis, directory) -> list[str]:
    """PNG of the raw residuals (um) of every axis before and after the selected effects."""
    import os

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    prep = diag.prep
    os.makedirs(directory, exist_ok=True)
    n = len(prep.rec)
    paths = []
    for tag, rw in (("before", diag.residuals_before), ("after", diag.residuals_after)):
        if prep.weighted:  # whitened: every component has unit variance at the tracker's specification
            raw, ylab, labels = rw.reshape(n, 3), "whitened", ("w1", "w2", "w3")
        else:
            raw, ylab, labels = rw.reshape(n, 3) * 1e3, "residual, um", ("x", "y", "z")
        fig, axs = plt.subplots(len(prep.axes), 1, figsize=(9, 2.2 * len(prep.axes)), squeeze=False)
        for ax, a in zip(axs[:, 0], prep.axes):
            idx = np.flatnonzero(prep.rec.axis == a)
            idx = idx[np.argsort(prep.order[idx])]
            for k, c in enumerate(labels):
                ax.plot(np.arange(len(idx)), raw[idx, k], ".", ms=2, label=c)
            ax.set_ylabel(f"{a} {ylab}")
            ax.legend(loc="upper right", fontsize=7, ncol=3)
        axs[-1, 0].set_xlabel("reading (time order within the axis)")
        fig.suptitle(f"residuals {tag} the diagnosed effects ({prep.rec.source})")
        fig.tight_layout()
        p = os.path.join(str(directory), f"residuals_{tag}.png")
        save_figure(fig, p, dpi=110)
        plt.close(fig)
        paths.append(p)
    return paths
