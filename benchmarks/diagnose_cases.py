"""Detection table of ``mtcal diagnose`` on the issue-13 cases (tests/campaigns.py, physical simulator), with and
without the tracker position, several seeds.  Run: python benchmarks/diagnose_cases.py [SEEDS] [CASE ...]."""
from __future__ import annotations

import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests"))

import campaigns as C  # noqa: E402
from diagnose_judge import judge  # noqa: E402

from mtcal.diagnose import diagnose  # noqa: E402


def main(seeds: int = 2, names=()) -> None:
    for name in names or sorted(C.CASES):
        for told in (True, False):
            right = 0
            for s in range(seeds):
                c = C.CASES[name](100 + s)
                if not told:
                    c = C.without_tracker(c)
                d = diagnose(c.recording, c.model, machine=c.design.machine, tracker=c.tracker)
                ok, msg = judge(d, c.expect)
                right += ok
                print(f"{name:<22} tracker {'told' if told else 'not told':<9} seed {100 + s}: {msg}", flush=True)
            print(f"== {name} tracker {'told' if told else 'not told'}: {right}/{seeds} right", flush=True)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 2, sys.argv[2:])
