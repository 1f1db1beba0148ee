"""Detection of ``mtcal diagnose`` against the size of a planted effect (tests/campaigns.py, physical simulator):
for each size, the share of diagnoses that are right, wrong (a confident wrong name) and missed, over seeds and
with the tracker told and not told.  Says where an effect comes out of the noise of a given campaign.
Run: python benchmarks/diagnose_sizes.py [SEEDS] (default 4)."""
from __future__ import annotations

import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests"))

import campaigns as C  # noqa: E402
from diagnose_judge import judge  # noqa: E402

from mtcal.diagnose import diagnose  # noqa: E402

# case -> (keyword, sizes, unit): the builder's size argument
SIZES = {"nest_creep": ("rate_um_h", (2.5, 5.0, 10.0, 20.0), "um/h"),
         "thermal_temperature": ("size", (0.5, 0.75, 1.0, 2.0), "x (8 ppm/K, 6 um/K)"),
         "lateral_play": ("play_mm", (0.00025, 0.0005, 0.001, 0.002), "mm"),
         "loose_nest": ("shift_mm", (0.001, 0.002, 0.004, 0.006), "mm")}


def main(seeds: int = 4) -> None:
    for name, (key, sizes, unit) in SIZES.items():
        for size in sizes:
            tally = {"right": 0, "WRONG": 0, "other": 0}
            for s in range(seeds):
                for told in (True, False):
                    c = C.CASES[name](700 + s, **{key: size})
                    c = c if told else C.without_tracker(c)
                    d = diagnose(c.recording, c.model, machine=c.design.machine, tracker=c.tracker)
                    ok, msg = judge(d, c.expect)
                    tally["right" if ok else "WRONG" if msg.startswith("WRONG") else "other"] += 1
            n = 2 * seeds
            print(f"{name:<20} {size:>8g} {unit:<22} right {tally['right']}/{n}  wrong {tally['WRONG']}/{n}  "
                  f"missed {tally['other']}/{n}", flush=True)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 4)
