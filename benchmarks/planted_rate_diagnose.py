"""Rates of ``mtcal diagnose`` on random planted campaigns (tests/campaigns.py ``planted``: a varied design --
station front / side / far, 3-6 rounds, five axes or three, tracker told or not -- with one or two effects drawn
from the generator's pool at sizes above the noise, through the physical simulator).  Each diagnosis is judged by
tests/diagnose_judge.py: right, out of reach (stated: the answer says this campaign cannot show it), missed
(nothing named, nothing said) or WRONG (a confident wrong name).
Run: python benchmarks/planted_rate_diagnose.py [N] [FIRST_SEED] (default 60, 0)."""
from __future__ import annotations

import collections
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests"))

import campaigns as C  # noqa: E402
from diagnose_judge import judge  # noqa: E402

from mtcal.diagnose import diagnose  # noqa: E402


def verdict(msg: str) -> str:
    return msg.split(":", 1)[0]


def main(n: int = 60, first: int = 0) -> collections.Counter:
    tally: collections.Counter = collections.Counter()
    for s in range(first, first + n):
        c = C.planted(s)
        d = diagnose(c.recording, c.model, machine=c.design.machine, tracker=c.tracker)
        _, msg = judge(d, c.expect)
        tally[verdict(msg)] += 1
        print(f"{s:4d} {c.name:<34} {c.design.station:<5} {c.design.rounds} rounds {''.join(c.design.axes):<5} "
              f"tracker {'told' if c.tracker else 'not told':<8} | {msg}", flush=True)
    print("; ".join(f"{k}: {v} of {n}" for k, v in sorted(tally.items())))
    return tally


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 60, int(sys.argv[2]) if len(sys.argv) > 2 else 0)
