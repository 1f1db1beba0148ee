"""Rates of `mtcal diagnose` on gen3's campaigns (benchmarks/gen3): right, partial, out of reach, missed, wrong per
class; false alarms on clean campaigns; the sizes of located entries against the planted displacement.

    python benchmarks/diagnose_gen3_rates.py --n 40 --seed 0 [--mix all|new|gen2] [--only A,B|none]
                                            [--clean-fraction 0.3] [--modes defaults,tracker] [--keep DIR]
                                            [--json OUT.json]
    python benchmarks/diagnose_gen3_rates.py --rejudge DIR [--json OUT.json]     # a kept run judged again

Each campaign is written by gen3 (its truth beside it) and diagnosed through the command line, `mtcal diagnose
REC.csv --json -q` (docs/design.md's CLI contract), two ways:
* **defaults**: the tracker columns removed (the station estimated from the data), single-station campaigns only;
* **tracker**: the tracker given, by the recording's tracker_x,y,z columns where gen2 wrote them, else
  `--tracker x,y,z` at the true station rounded to 1 mm.

What the diagnosis claims (docs/guide/diagnose.md, the JSON keys): a **name** is an entry of `effects` with
`significant` true, or `noise_model.axis_scatter.found` (an axis repeating worse); a **located** entry is one of
`unexplained` (where a mismatch is, no name); a **data problem** is `data_problems`, or a refusal (exit 2, one line).
Its place is its `axis` and the reflector labels (P1, P2, ...) its `where` names.

The judge, per run of a campaign carrying one class (the truth's `classes`):
* **right**: a data-problem class (an export's slip) reported as a data problem (listed or refused) with nothing
  named or located beside it; an in-grammar class named by one of its names (the truth's `in_grammar`) at an axis
  where it shows; an out-of-grammar class located (an `unexplained` entry at an axis where it shows and, where
  the entry names reflectors, one of those it moves) -- and in both cases nothing false beside it.
* **partial**: nothing false, and only a name that describes part of it (the truth's `accepted_names`, e.g. a
  drift of the spindle for a column tilting), or an in-grammar class located but not named.
* **wrong**: anything false: a name that is neither its own nor accepted, a name or a located entry at an axis (or
  reflector) it does not move, a data problem or refusal on a physics campaign, physics claimed for a data problem.
* **out of reach**: nothing claimed, and the planted displacement beyond the stops' rigid motions and the nests'
  unknown positions (truth: `displacement_um.chi2_beyond_stops`, whitened by the true noise law) below the
  criterion: chi2 < 40 for a shape
  (a free form of ~10 columns at p = 1e-5 has about 85 % power at a noncentrality of 50, 50 % near 34), or, for a
  variance (a noisier reflector, a shaking floor, gen2's axis scatter), chi2 < max(40, 5 sqrt(6 n)) over its n
  readings (5 standard deviations of the noise's own chi2 with 3n degrees of freedom). Data problems are always
  within reach.
* **missed**: nothing claimed although within reach.
A clean campaign is a **false alarm** when anything is claimed (a name, a located entry, a data problem, a refusal).
The **size check** counts located entries whose `size_mm` exceeds 1.5x the planted displacement's largest value at
a reading (truth `displacement_um.max_um`), and 1.5x the largest of its part beyond the stops' rigid motions and
the nests' positions (`beyond_stops_max_um`, nearer what issue 52 calls the displacement beyond the base); entries
without a size are not counted.
Bounds: one-sided 95 % Clopper-Pearson (upper for wrong and false alarms, lower for right).
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.stats import beta

sys.path.insert(0, str(Path(__file__).resolve().parent / "gen3"))
import gen3  # noqa: E402

OUTCOMES = ("right", "partial", "out_of_reach", "missed", "wrong", "error")
LABEL = re.compile(r"\bP\d+\b")


def upper95(k, n):
    return 1.0 if n == 0 or k == n else float(beta.ppf(0.95, k + 1, n - k))


def lower95(k, n):
    return 0.0 if n == 0 or k == 0 else float(beta.ppf(0.05, k, n - k + 1))


# ---------------------------------------------------------------- running the diagnosis
def _without_tracker(src, dst):
    with open(src) as f:
        rows = list(csv.reader(f))
    keep = [i for i, k in enumerate(rows[0]) if k not in ("tracker_x", "tracker_y", "tracker_z")]
    with open(dst, "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows([[r[i] for i in keep] for r in rows])


def diagnose(csv_path, extra=()):
    """(status, answer, seconds): status 'ok' (answer the JSON), 'refused' (exit 2: answer the message) or
    'error' (any other exit: answer stderr's last line)."""
    t0 = os.times()
    p = subprocess.run([sys.executable, "-m", "mtcal.cli", "diagnose", str(csv_path), "--json", "-q", *extra],
                       capture_output=True, text=True)
    t1 = os.times()
    cpu = t1.children_user + t1.children_system - t0.children_user - t0.children_system
    if p.returncode == 0:
        return "ok", json.loads(p.stdout), cpu
    last = (p.stderr.strip().splitlines() or [""])[-1]
    return ("refused" if p.returncode == 2 else "error"), last, cpu


def claims(status, out):
    """What a run claims: names [(name, axis, text)], located [(axis, text, size_mm)], data problems [text]."""
    if status == "refused":
        return [], [], [out]
    if status != "ok":
        return [], [], []
    names = [(e["name"], e.get("axis"), str(e.get("where", ""))) for e in out.get("effects", [])
             if e.get("significant")]
    found = ((out.get("noise_model") or {}).get("axis_scatter") or {}).get("found")
    for f in (found if isinstance(found, list) else [found] if found else []):
        names.append(("axis_scatter", f.get("axis"), str(f.get("says", ""))))
    located = [(u.get("axis"), f"{u.get('by')}: {u.get('where')}", u.get("size_mm"))
               for u in out.get("unexplained", [])]
    data = [str(d.get("text", d.get("kind"))) for d in (out.get("data_problems") or [])]
    return names, located, data


def _at(axis, text, shows):
    """A claim's place is among the places the class moves: its axis (when it has one) and, where it names
    reflectors, at least one of those the class moves."""
    if axis is not None and axis not in shows["axes"]:
        return False
    labels = set(LABEL.findall(text))
    return not labels or bool(labels & set(shows["points"]))


def within_reach(rec):
    if rec["data_problem"]:
        return True
    d = rec.get("displacement_um") or {}
    chi2 = d.get("chi2_beyond_stops", 0.0)
    if rec.get("random"):
        return bool(chi2 >= max(40.0, 5 * np.sqrt(6 * max(d.get("readings", 0), 1))))
    return bool(chi2 >= 40.0)


def judge(rec, status, out):
    """(outcome, reasons, sizes): sizes = [(size_um, planted max um)] of the located entries."""
    if status == "error":
        return "error", [out], []
    names, located, data = claims(status, out)
    shows = rec["shows_at"]
    why = []
    disp = rec.get("displacement_um") or {}
    planted, seen = disp.get("max_um"), disp.get("beyond_stops_max_um")
    sizes = [(s * 1e3, planted, seen) for _, _, s in located if s is not None and planted]
    if rec["data_problem"]:
        if [n for n in names if n[0] in rec["in_grammar"] and _at(n[1], n[2], shows)] == names and names \
                and not located and not data:
            return "right", [f"named {n} {a} (what the slip does to the readings)" for n, a, _ in names], sizes
        if data and not names and not located:
            return "right", ["data problem: " + data[0][:120]], sizes
        if names or located:
            why = [f"physics claimed: {n} {a}" for n, a, _ in names] + [f"located {a} {t[:80]}" for a, t, _ in located]
            return "wrong", why, sizes
        return "missed", ["no data problem reported"], sizes
    if data:
        return "wrong", ["data problem on physics: " + data[0][:120]], sizes
    own = [n for n in names if n[0] in rec["in_grammar"] and _at(n[1], n[2], shows)]
    part = [n for n in names if n[0] in rec["accepted_names"] and _at(n[1], n[2], shows)]
    false = [n for n in names if n not in own and n not in part]
    here = [loc for loc in located if _at(loc[0], loc[1], shows)]
    elsewhere = [loc for loc in located if loc not in here]
    if false or elsewhere:
        why = [f"false name: {n} {a} {t[:90]}" for n, a, t in false] + \
              [f"located elsewhere: {a} {t[:90]}" for a, t, _ in elsewhere]
        return "wrong", why, sizes
    said = [f"located {a} {t[:60]}" for a, t, _ in here]
    if own or (here and not rec["in_grammar"]):
        return "right", [f"named {n} {a}" for n, a, _ in own] + said, sizes
    if part or here:
        return "partial", [f"accepted {n} {a}" for n, a, _ in part] + said, sizes
    return ("missed" if within_reach(rec) else "out_of_reach"), [], sizes


def judge_clean(status, out):
    if status == "error":
        return "error", [out]
    names, located, data = claims(status, out)
    why = [f"name {n} {a}" for n, a, _ in names] + [f"located {a} {t[:80]}" for a, t, _ in located] + \
          [f"data problem {d[:80]}" for d in data]
    return ("false_alarm" if why else "quiet"), why


# ---------------------------------------------------------------- one campaign, both ways
def judge_run(truth, mode, status, out, cpu):
    run = dict(index=truth["index"], mode=mode, status=status, cpu_s=cpu, clean=truth["clean"])
    if truth["clean"]:
        run["outcome"], run["why"] = judge_clean(status, out)
    else:
        rec = truth["classes"][0]
        run.update(cls=rec["name"], source=rec["source"], data_problem=rec["data_problem"],
                   in_reach=within_reach(rec))
        run["outcome"], run["why"], run["sizes"] = judge(rec, status, out)
    return run


def run_campaign(seed, idx, work, args):
    """Write campaign idx, diagnose it each way, keep each answer beside it (campaign_NNNN.MODE.answer.json, which
    --rejudge reads) and judge it."""
    try:
        truth = gen3.write_campaign(seed, idx, work, args.clean_fraction, args.mix, args.only)
    except gen3.NotApplicable as err:
        return [dict(index=idx, skipped=str(err))]
    src = Path(work) / f"campaign_{idx:04d}.csv"
    stations = truth["tracker"]["stations"]
    runs = []
    for mode in args.modes:
        extra = []
        if mode == "defaults":
            if len(stations) > 1:
                continue
            path = Path(work) / f"campaign_{idx:04d}_defaults.csv"
            _without_tracker(src, path)
        else:
            path = src
            if not stations[0]["given_in_csv"]:
                extra = ["--tracker", ",".join(f"{v:.0f}" for v in stations[0]["position_mm"])]
        status, out, cpu = diagnose(path, extra)
        with open(Path(work) / f"campaign_{idx:04d}.{mode}.answer.json", "w") as f:
            json.dump(dict(status=status, answer=out, cpu_s=cpu, args=extra), f)
        runs.append(judge_run(truth, mode, status, out, cpu))
    return runs


def rejudge(folder, modes):
    """Judge the answers a kept run left in `folder` again (after a change of the judge), without diagnosing."""
    runs = []
    for tp in sorted(Path(folder).glob("campaign_*.truth.json")):
        truth = json.loads(tp.read_text())
        for mode in modes:
            ap = tp.with_name(tp.name.replace(".truth.json", f".{mode}.answer.json"))
            if ap.exists():
                a = json.loads(ap.read_text())
                runs.append(judge_run(truth, mode, a["status"], a["answer"], a["cpu_s"]))
    return runs


def summarise(runs, modes):
    out = {}
    for mode in modes:
        rr = [r for r in runs if r.get("mode") == mode]
        clean = [r for r in rr if r["clean"]]
        planted = [r for r in rr if not r["clean"]]
        per = {}
        for r in planted:
            c = per.setdefault(r["cls"], {k: 0 for k in OUTCOMES})
            c[r["outcome"]] += 1
        tot = {k: sum(c[k] for c in per.values()) for k in OUTCOMES}
        by_source = {src: {k: sum(r["outcome"] == k for r in planted if r["source"] == src) for k in OUTCOMES}
                     for src in ("gen3", "gen2")}
        n = len(planted)
        fa = sum(r["outcome"] == "false_alarm" for r in clean)
        reach_oog = [r for r in planted if r["in_reach"] and r["source"] == "gen3" and not r["data_problem"]
                     and r["outcome"] != "error"]
        big = [s for r in planted for s in r.get("sizes", []) if s[0] > 1.5 * s[1]]
        big_seen = [s for r in planted for s in r.get("sizes", []) if s[2] is not None and s[0] > 1.5 * s[2]]
        allsz = [s for r in planted for s in r.get("sizes", [])]
        out[mode] = dict(
            per_class=per, totals=tot, by_source=by_source, planted_runs=n, clean_runs=len(clean), false_alarms=fa,
            wrong_rate=tot["wrong"] / n if n else None, wrong_upper95=upper95(tot["wrong"], n),
            false_alarm_rate=fa / len(clean) if clean else None, false_alarm_upper95=upper95(fa, len(clean)),
            gen3_in_reach_runs=len(reach_oog), gen3_in_reach_right=sum(r["outcome"] == "right" for r in reach_oog),
            gen3_in_reach_right_lower95=lower95(sum(r["outcome"] == "right" for r in reach_oog), len(reach_oog)),
            sizes_checked=len(allsz), sizes_beyond_1_5x=len(big), sizes_beyond_1_5x_of_beyond_stops=len(big_seen),
            largest_size_ratio=max((s[0] / s[1] for s in allsz), default=None),
            cpu_s=sum(r["cpu_s"] for r in rr))
    return out


def print_table(summary):
    for mode, s in summary.items():
        print(f"\n== {mode}: {s['planted_runs']} planted runs, {s['clean_runs']} clean runs, "
              f"{s['cpu_s']:.0f} CPU-s of diagnosis")
        print(f"{'class':22s} " + " ".join(f"{k:>12s}" for k in OUTCOMES))
        for c in sorted(s["per_class"]):
            print(f"{c:22s} " + " ".join(f"{s['per_class'][c][k]:12d}" for k in OUTCOMES))
        for src, t in s["by_source"].items():
            print(f"{'  ' + src + ' classes':22s} " + " ".join(f"{t[k]:12d}" for k in OUTCOMES))
        print(f"{'total':22s} " + " ".join(f"{s['totals'][k]:12d}" for k in OUTCOMES))
        n = s["planted_runs"]
        if n:
            print(f"wrong {s['totals']['wrong']} of {n} ({100 * s['wrong_rate']:.1f} %, one-sided 95 % bound "
                  f"{100 * s['wrong_upper95']:.1f} %)")
        if s["clean_runs"]:
            print(f"false alarms {s['false_alarms']} of {s['clean_runs']} clean ({100 * s['false_alarm_rate']:.1f} %, "
                  f"bound {100 * s['false_alarm_upper95']:.1f} %)")
        k, m = s["gen3_in_reach_right"], s["gen3_in_reach_runs"]
        if m:
            print(f"gen3 physics within reach: right {k} of {m} ({100 * k / m:.0f} %, one-sided 95 % lower bound "
                  f"{100 * s['gen3_in_reach_right_lower95']:.0f} %)")
        print(f"located entries sized: {s['sizes_checked']}, beyond 1.5x the planted displacement's largest: "
              f"{s['sizes_beyond_1_5x']} (largest ratio {s['largest_size_ratio'] or 0:.1f}); beyond 1.5x its part "
              f"beyond the stops' rigid motions: {s['sizes_beyond_1_5x_of_beyond_stops']}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--start", type=int, default=0)
    ap.add_argument("--mix", choices=["all", "new", "gen2"], default="all")
    ap.add_argument("--only", default=None)
    ap.add_argument("--clean-fraction", type=float, default=0.3)
    ap.add_argument("--modes", default="defaults,tracker")
    ap.add_argument("--keep", default=None, help="write the campaigns into this folder (default: a temporary one)")
    ap.add_argument("--json", default=None, help="write the runs and the summary to this file")
    ap.add_argument("--rejudge", default=None, metavar="DIR",
                    help="judge the campaigns and answers a --keep run left in DIR again, diagnosing nothing")
    args = ap.parse_args(argv)
    args.only = None if args.only is None else [c.strip() for c in args.only.split(",") if c.strip()]
    args.modes = [m for m in args.modes.split(",") if m]
    t0 = time.time()
    if args.rejudge:
        runs = rejudge(args.rejudge, args.modes)
    else:
        runs = run_all(args)
    summary = summarise([r for r in runs if "skipped" not in r], args.modes)
    print_table(summary)
    if not args.rejudge:
        print(f"\n{args.n} campaigns (seed {args.seed}, mix {args.mix}) in {time.time() - t0:.0f} s of wall time")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(dict(seed=args.seed, n=args.n, start=args.start, mix=args.mix, only=args.only,
                           clean_fraction=args.clean_fraction, rejudged=args.rejudge, summary=summary, runs=runs),
                      f, indent=1)


def run_all(args):
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        work = args.keep or tmp
        os.makedirs(work, exist_ok=True)
        for i in range(args.start, args.start + args.n):
            for r in run_campaign(args.seed, i, work, args):
                runs.append(r)
                if "skipped" in r:
                    print(f"campaign {i}: skipped: {r['skipped']}", file=sys.stderr)
                    continue
                print(f"campaign {i} {r['mode']:8s} {r.get('cls', 'clean'):20s} {r['outcome']:12s} "
                      f"{r['cpu_s']:.1f} s  {'; '.join(r['why'])[:160]}", file=sys.stderr)
    return runs


if __name__ == "__main__":
    main()
