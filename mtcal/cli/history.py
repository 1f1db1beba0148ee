"""`mtcal history add|list|show|compare|trend`: a machine's calibration history in a database (mtcal.history; this
module parses arguments and formats)."""
from __future__ import annotations

import argparse
import datetime as dt

from mtcal.cli._options import finite
from mtcal.io import dumps

NAME = "history"
HELP = ("a machine's calibration history: add a result (model, uncertainty, ISO 230-2, check, verify, diagnose), "
        "list the machines, show one's results, compare calibrations against their uncertainty, an error's trend "
        "(SQLite ./mtcal-history.db, $MTCAL_HISTORY_DB or --db URL)")


def date(text: str) -> dt.date:
    """YYYY-MM-DD (``--date``, ``--from``, ``--to``)."""
    try:
        return dt.date.fromisoformat(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a date YYYY-MM-DD, got {text!r}") from None


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--db", metavar="URL", help="the history database: a SQLite file or postgresql://... (default: "
                                               "$MTCAL_HISTORY_DB, else ./mtcal-history.db)")
    p.add_argument("--json", action="store_true", default=argparse.SUPPRESS,
                   help="print a machine-readable JSON answer on stdout")
    p.add_argument("-q", "--quiet", action="store_true", default=argparse.SUPPRESS, help="warnings and errors only")


def _parser_class(p: argparse.ArgumentParser) -> type:
    """The actions' parsers: a bad option is one line under the command's name, ``mtcal history: error: ...``, as
    every refusal of the command (mtcal.cli._main)."""
    class ActionParser(type(p)):
        def error(self, message: str):
            self.exit(2, f"{p.prog}: error: {message} (see {self.prog} --help)\n")
    return ActionParser


def add_arguments(p: argparse.ArgumentParser) -> None:
    sub = p.add_subparsers(dest="action", required=True, metavar="ACTION", parser_class=_parser_class(p))
    a = sub.add_parser("add", help="add a result file to a machine's history")
    a.add_argument("result", metavar="RESULT.json", help="an error model (identify -o) or the --json answer of "
                                                          "uncertainty, iso230-2, check evaluate, verify, diagnose")
    a.add_argument("--machine", required=True, metavar="ID", help="the machine's ID (letters, digits, . _ -)")
    a.add_argument("--date", type=date, metavar="YYYY-MM-DD", help="the calibration's date (default today)")
    lst = sub.add_parser("list", help="the machines of the history: spec, results, first and last date")
    s = sub.add_parser("show", help="a machine's results, one line each")
    s.add_argument("machine", metavar="ID")
    c = sub.add_parser("compare", help="changes between consecutive calibrations (or two dates) beyond their "
                                       "uncertainty")
    c.add_argument("machine", metavar="ID")
    c.add_argument("--from", dest="date_from", type=date, metavar="YYYY-MM-DD")
    c.add_argument("--to", dest="date_to", type=date, metavar="YYYY-MM-DD")
    t = sub.add_parser("trend", help="an error's values over time with their 95 %% intervals")
    t.add_argument("machine", metavar="ID")
    t.add_argument("--error", required=True, metavar="NAME", help="an ISO 230-1 error name, e.g. E_C0Y")
    t.add_argument("--position", type=finite, metavar="P", help="an error function's position (mm or deg; default: "
                                                               "where its latest value is largest in size)")
    t.add_argument("--plot", metavar="FILE.png", help="write the trend as a picture")
    for q in (a, lst, s, c, t):
        _common(q)


def run(args: argparse.Namespace) -> int:
    return {"add": _add, "list": _list, "show": _show, "compare": _compare, "trend": _trend}[args.action](args)


def _add(args: argparse.Namespace) -> int:
    from mtcal.history import add
    r = add(args.result, args.machine, args.date, args.db)
    if args.json:
        print(dumps(r.to_dict()))
    else:
        print(f"{r.machine}: added the {r.kind} {r.source} of {r.date.isoformat()} ({len(r.quantities)} values)")
    return 0


def _list(args: argparse.Namespace) -> int:
    from mtcal.history import machines
    ms = machines(args.db)
    if args.json:
        print(dumps({"machines": ms}))
        return 0
    wid, wspec = (max([len(str(m[k] or "-")) for m in ms] + [1]) for k in ("machine", "spec"))
    for m in ms:
        n = m["results"]
        kinds = ", ".join(f"{k} {v}" for k, v in m["kinds"].items())
        print(f"{m['machine']:<{wid}}  {m['spec'] or '-':<{wspec}}  {n} result{'s' if n != 1 else ' '}  "
              + (f"{m['first']} .. {m['last']}  ({kinds})" if n else "no results"))
    return 0


def _show(args: argparse.Namespace) -> int:
    from mtcal.history import show
    recs = show(args.machine, args.db)
    if args.json:
        print(dumps({"machine": args.machine, "results": [r.to_dict() for r in recs]}))
        return 0
    for r in recs:
        print(f"{r.date.isoformat()}  {r.kind:11s} {r.source}  {r.instrument or ''}  mtcal {r.tool_version}  "
              f"sha256 {r.file_sha256[:12]}")
    return 0


def _compare(args: argparse.Namespace) -> int:
    from mtcal.history import compare_history
    c = compare_history(args.machine, args.date_from, args.date_to, args.db)
    if args.json:
        print(dumps(c.to_dict()))
        return 0
    print(f"{c.machine}: changes beyond their uncertainty (family-wise level {c.level:g}, Holm)")
    for s in c.steps:
        print(f"{s.date_from.isoformat()} -> {s.date_to.isoformat()}: {len(s.changed)} changed, {s.unchanged} "
              "unchanged" + (f", not compared: {', '.join(s.not_compared)}" if s.not_compared else ""))
        for ch in s.changed:
            print(f"  {ch.text}")
    return 0


def _trend(args: argparse.Namespace) -> int:
    from mtcal.history import trend_of
    from mtcal.history.store import refuse_database_output
    from mtcal.io import refuse_overwrite
    if args.plot:
        refuse_database_output([args.plot], args.db)
        refuse_overwrite(args.plot)
    t = trend_of(args.machine, args.error, args.position, args.db)
    out = t.to_dict()
    if args.plot:
        from mtcal.report.pictures import save_trend
        save_trend(t, args.plot)
        out["plot"] = args.plot
    if args.json:
        print(dumps(out))
        return 0
    print(f"{t.machine} {t.name} ({t.unit}{', ' + t.note if t.note else ''})")
    for p in t.points:
        u = "" if p["u95"] is None else f" ± {p['u95']:.2f}"
        print(f"  {p['date']}  {p['value']:+.2f}{u}")
    return 0
