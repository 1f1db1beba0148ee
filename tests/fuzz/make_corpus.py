"""Generate the fuzz corpus of issue 11: bad and hostile inputs for every mtcal command, with expected outcomes.

    python tests/fuzz/make_corpus.py OUT_DIR        # writes OUT_DIR/<case>/... and OUT_DIR/cases.json

Deterministic (seeded).  Written from the issue text and the docs (the CLI contract), not from the
implementation: this is the independent oracle.  Each case is a folder holding its input files, plus an entry in
cases.json:

    {"id", "command", "kind" (input kind under test), "argv" (relative to the case folder),
     "setup": [argv, ...],                     # optional: mtcal commands run first (must exit 0)
     "rewrites": [prefix, ...],                # optional: earlier outputs the command may rewrite
     "expect": [alternative, ...],            # the case passes when one alternative holds
     "signal": {...}}                          # optional: run as a subprocess and send a signal

An alternative is {"exit": 0 | 2 | "bug" | 130 | "signal", "error": {"file", "line", "problem": [words],
"also": [words] (a second group, one of which must be said too), "forbid": [words]},
"option": bool (argparse-style usage block + one error line allowed), "checks": [...], "say": [words]}.
Error expectations follow issue 11: one line naming the file, the line where there is one and the problem,
exit 2, no traceback.  Valid inputs get output checks (tests/fuzz/oracle.py, run by tests/test_fuzz.py).
Input file lines are physical lines, 1-based (the CSV header is line 1).
"""
from __future__ import annotations

import csv
import io
import json
import math
import random
import sys
from pathlib import Path

DATA = Path(__file__).resolve().parents[2] / "mtcal" / "data"
SEED = 20261123


# --------------------------------------------------------------------------- helpers

def err(file=None, line=None, *problem, option=False):
    """Alternative: exit 2 with one error line naming file, line and one of the problem words."""
    alt = {"exit": 2, "error": {"file": file, "line": line, "problem": list(problem)}}
    if option:
        alt["option"] = True
    return alt


def err_also(alt, *words):
    """The same error, whose message must also say one of `words` (e.g. the option and what is wrong with it)."""
    alt["error"]["also"] = list(words)
    return alt


def ok(*checks, say=None):
    alt = {"exit": 0, "checks": list(checks)}
    if say:
        alt["say"] = list(say)
    return alt


class Corpus:
    def __init__(self, root: Path):
        self.root = root
        self.cases: list[dict] = []

    def add(self, cid, command, kind, argv, files=None, expect=(), dirs=(), signal=None, note="", links=None,
            setup=(), rewrites=()):
        if any(c["id"] == cid for c in self.cases):
            raise SystemExit(f"duplicate case id {cid}")
        d = self.root / cid
        d.mkdir(parents=True)
        for sub in dirs:
            (d / sub).mkdir(parents=True, exist_ok=True)
        for name, content in (files or {}).items():
            p = d / name
            p.parent.mkdir(parents=True, exist_ok=True)
            p.write_bytes(content if isinstance(content, bytes) else content.encode("utf-8"))
        for name, target in (links or {}).items():
            (d / name).symlink_to(target)
        case = {"id": cid, "command": command, "kind": kind, "argv": [command, *argv] if command else list(argv),
                "expect": list(expect)}
        if signal:
            case["signal"] = signal
        if setup:
            case["setup"] = [list(a) for a in setup]
        if rewrites:
            case["rewrites"] = list(rewrites)
        if note:
            case["note"] = note
        self.cases.append(case)

    def write(self):
        (self.root / "cases.json").write_text(json.dumps(self.cases, indent=1))


def rows_to_csv(header, rows, sep=",", eol="\n"):
    out = io.StringIO()
    w = csv.writer(out, delimiter=sep, lineterminator=eol)
    w.writerow(header)
    w.writerows(rows)
    return out.getvalue()


# --------------------------------------------------------------------------- base inputs

def base_recording():
    """Rounds 1-2 of axes X and C of the bundled demo campaign (small, real shape): header + rows."""
    with open(DATA / "demo_campaign.csv", newline="") as f:
        r = list(csv.reader(f))
    header, rows = r[0], [x for x in r[1:] if x[0] in ("X", "C") and x[1] in ("1", "2")]
    return header, rows


def recording_x_only():
    header, rows = base_recording()
    return header, [r for r in rows if r[0] == "X"]


# Hand model: E_XX linear in X (10 um per 500 mm) and squareness E_C0Y = 20 urad.  First-order oracle at B = C = 0,
# tool length 0 (docs/design.md: actual Y direction (-E_C0Y, 1, 0)):  X' = X - E_XX(X) + Y * E_C0Y,  Y' = Y,  Z' = Z.
EXX = {"axis": "X", "positions": [-500.0, 500.0], "values": [-0.01, 0.01]}
C0Y = 2e-5
HAND_MODEL = {"machine": "dmu50", "units": {"length": "mm", "angle": "rad"},
              "constants": {"E_C0Y": C0Y}, "functions": {"E_XX": EXX}}
ORACLE = {"exx": [EXX["positions"], EXX["values"]], "c0y": C0Y, "scale": 1.0}
# V-shaped E_XX (piecewise linear): a straight feed move across X = 0 has a mid-segment error -> subdivided.
V_MODEL = {"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": {},
           "functions": {"E_XX": {"axis": "X", "positions": [-500.0, 0.0, 500.0], "values": [0.02, 0.0, 0.02]}}}


def jdump(obj):
    return json.dumps(obj, indent=2)


def program(eol="\n", comments=True):
    """A 3-axis program (B = C = 0) with comments of both kinds before and after moves."""
    lines = ["%", "O1000 (FUZZ BASE)", "N10 G90 G21 G17 (ABSOLUTE, MM)",
             "N20 G0 X0 Y0 Z50 ; rapid to clearance", "N30 G1 X50 Y20 Z10 F800",
             "(a comment line between moves)", "N40 X100 ; semicolon comment", "N50 Y-40",
             "; full-line semicolon comment", "N60 X-80 Y60 Z5", "N70 G0 Z50", "M30", "%"]
    if not comments:
        lines = [ln.split(";")[0].rstrip() for ln in lines if not ln.startswith(("(", ";"))]
    return eol.join(lines) + eol


def gcode_check(inp="prog.nc", out="out.nc", oracle=ORACLE, bound=0.05, **kw):
    return {"kind": "gcode", "input": inp, "output": out, "oracle": oracle, "bound": bound, **kw}


# --------------------------------------------------------------------------- plate data

def plate_points():
    """A 4 x 4 grid plate, 100 mm pitch, with one point off-grid (labels 1..16), mm."""
    pts = [(100.0 * i, 100.0 * j) for j in range(4) for i in range(4)]
    pts[5] = (130.0, 110.0)
    return pts


def plate_csv(turn_deg=90.0, alpha=0.0, header="point,x1,y1,x2,y2", sep=",", dec=".", eol="\n", pre=""):
    """Noise-free measurements of plate_points() on a machine whose y axis leans by alpha (rad, shear
    x' = x + alpha y), position 2 turned by turn_deg clockwise about the plate origin and shifted."""
    def machine(x, y):
        return x + alpha * y, y

    rows = []
    c, s = math.cos(math.radians(-turn_deg)), math.sin(math.radians(-turn_deg))
    for k, (x, y) in enumerate(plate_points(), start=1):
        x1, y1 = machine(x + 5.0, y + 7.0)
        xr, yr = c * x - s * y, s * x + c * y
        x2, y2 = machine(xr + 3.0, yr + 400.0)
        vals = [f"{v:.9f}".replace(".", dec) for v in (x1, y1, x2, y2)]
        rows.append(sep.join([str(k), *vals]))
    return pre + eol.join([header.replace(",", sep), *rows]) + eol


# --------------------------------------------------------------------------- the cases

def cases_identify(C: Corpus, rnd: random.Random):
    header, rows = base_recording()
    rec = rows_to_csv(header, rows)
    model_check = {"kind": "model_json", "path": "model.json", "axes": ["X", "C"]}
    C.add("identify_valid", "identify", "recording CSV", ["rec.csv", "-o", "model.json", "--json"],
          {"rec.csv": rec}, [ok(model_check, {"kind": "stdout_json", "keys": ["axes", "squareness"]})])
    C.add("identify_valid_crlf", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
          {"rec.csv": rows_to_csv(header, rows, eol="\r\n")}, [ok(model_check)])
    C.add("identify_bom", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
          {"rec.csv": b"\xef\xbb\xbf" + rec.encode()}, [ok(model_check)])
    german = rows_to_csv(header, [[c.replace(".", ",") for c in r] for r in rows], sep=";")
    C.add("identify_german_semicolon", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
          {"rec.csv": german}, [ok(model_check, say=[";", "semicolon", "decimal comma"])])
    C.add("identify_german_semicolon_bom_crlf", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
          {"rec.csv": b"\xef\xbb\xbf" + rows_to_csv(header, [[c.replace(".", ",") for c in r] for r in rows],
                                                    sep=";", eol="\r\n").encode()},
          [ok(model_check, say=[";", "semicolon", "decimal comma"])])
    C.add("identify_cp1252_comment", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
          {"rec.csv": "# tracker AT960, 20.1\xb0C, noise 15 \xb5m\n".encode("cp1252") + rec.encode()},
          [ok(model_check)])
    C.add("identify_utf8_comment", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
          {"rec.csv": "# tracker AT960, 20.1°C, noise 15 µm — Ω\n" + rec}, [ok(model_check)])
    cols = header[:]
    perm = [cols.index(c) for c in ["z", "x", "point", "y", "axis", "position", "round", "time_s", "direction",
                                    "temperature_c"]]
    C.add("identify_columns_reordered", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
          {"rec.csv": rows_to_csv([cols[i] for i in perm], [[r[i] for i in perm] for r in rows])}, [ok(model_check)])
    uni = [[*r[:3], {"P": "Pμ", "Q": "Q点", "K": "K✓"}[r[3]], *r[4:]] for r in rows]
    C.add("identify_unicode_labels", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
          {"rec.csv": rows_to_csv(header, uni)}, [ok(model_check)])
    # tracker option
    C.add("identify_tracker_negative_sep", "identify", "option", ["rec.csv", "-o", "model.json", "--tracker",
                                                                   "-2000,0,300"],
          {"rec.csv": rec}, [ok(model_check)])
    C.add("identify_tracker_negative_eq", "identify", "option", ["rec.csv", "-o", "model.json",
                                                                  "--tracker=-2000,0,300"],
          {"rec.csv": rec}, [ok(model_check)])
    for cid, val, words in [("two", "1,2", ["3", "three", "x,y,z"]), ("four", "1,2,3,4", ["3", "three", "x,y,z"]),
                            ("nan", "nan,0,0", ["finite", "nan"]), ("inf", "0,inf,0", ["finite", "inf"]),
                            ("text", "a,b,c", ["number", "x,y,z", "float", "invalid"])]:
        C.add(f"identify_tracker_{cid}", "identify", "option", ["rec.csv", "-o", "model.json", "--tracker", val],
              {"rec.csv": rec}, [err_also(err(None, None, "--tracker", option=True), *words)])
    for cid, argv, word in [("max_degree_neg", ["--max-degree", "-1"], "--max-degree"),
                            ("outlier_k_nan", ["--outlier-k", "nan"], "--outlier-k"),
                            ("outlier_k_neg", ["--outlier-k", "-3"], "--outlier-k")]:
        C.add(f"identify_{cid}", "identify", "option", ["rec.csv", "-o", "model.json", *argv], {"rec.csv": rec},
              [err(None, None, word, option=True)])
    # recording mutations with known lines (line = index in rows + 2)
    def mutate(cid, fn, expect, kind="recording CSV", extra=()):
        rs = [r[:] for r in rows]
        hdr = header[:]
        content = fn(hdr, rs)
        if content is None:
            content = rows_to_csv(hdr, rs)
        C.add(f"identify_{cid}", "identify", kind, ["rec.csv", "-o", "model.json", *extra],
              {"rec.csv": content}, expect)

    i = 40
    def setcell(col, val, at=i):
        def fn(h, rs):
            rs[at][h.index(col)] = val
        return fn
    for col, val, words in [("x", "nan", ["nan", "finite"]), ("y", "inf", ["inf", "finite"]),
                            ("z", "-inf", ["inf", "finite"]), ("x", "", ["empty", "missing", "number", "x"]),
                            ("x", "abc", ["abc", "number"]), ("position", "nan", ["nan", "finite", "position"]),
                            ("z", "1e400", ["inf", "finite", "1e400"]), ("round", "abc", ["round"]),
                            ("axis", "Q", ["axis", "Q"]), ("axis", "Ｘ", ["axis"]),
                            ("direction", "0", ["direction"]), ("point", "", ["point", "empty", "missing"])]:
        safe = "".join(ch if ch.isalnum() else "_" for ch in val.encode("ascii", "replace").decode())
        mutate(f"cell_{col}_{safe or 'empty'}", setcell(col, val), [err("rec.csv", i + 2, *words)])
    mutate("row_short", lambda h, rs: rs.__setitem__(i, rs[i][:4]) or None,
           [err("rec.csv", i + 2, "column", "field", "missing", "expected", "value")])
    mutate("row_long", lambda h, rs: rs.__setitem__(i, rs[i] + ["9", "9"]) or None,
           [err("rec.csv", i + 2, "column", "field", "extra", "expected", "value")])
    # an exact copy of a line is an export slip: named (the line and the one it repeats) and left out (issue 24)
    mutate("duplicate_row", lambda h, rs: rs.insert(i + 1, rs[i][:]) or None,
           [ok({"kind": "model_json", "path": "model.json", "axes": ["X", "C"]}, say=[f"line {i + 3} repeats"])])
    def long_line(h, rs):
        rs[i][h.index("point")] = "P" * 200_000
    C.add("identify_very_long_field", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
          {"rec.csv": rows_to_csv(header, [r if k != i else [*r[:3], "P" * 200_000, *r[4:]]
                                           for k, r in enumerate(rows)])},
          [{**err("rec.csv", None, "point", "label", "long", "field"), "max_stderr": 1000},
           {**err("rec.csv", i + 2, "point", "label", "long", "field"), "max_stderr": 1000}])
    mutate("missing_column_z", lambda h, rs: rows_to_csv([c for c in h if c != "z"],
                                                         [[v for c, v in zip(h, r) if c != "z"] for r in rs]),
           [err("rec.csv", 1, "z", "column")])
    mutate("no_header", lambda h, rs: rows_to_csv(rs[0], rs[1:]), [err("rec.csv", None, "column", "header")])
    mutate("header_only", lambda h, rs: rows_to_csv(h, []), [err("rec.csv", None, "no data", "empty", "no rows",
                                                                 "no readings")])
    mutate("empty", lambda h, rs: "", [err("rec.csv", None, "empty", "no data", "header")])
    mutate("nul_bytes", lambda h, rs: b"\x00" * 64 + rows_to_csv(h, rs).encode(),
           [err("rec.csv", None, "binary", "nul", "NUL", "decode", "header")])
    mutate("binary", lambda h, rs: bytes(rnd.randrange(256) for _ in range(3000)),
           [err("rec.csv", None, "binary", "nul", "NUL", "decode", "encoding", "header", "column")])
    cut = rows_to_csv(header, rows)
    mid = cut.index("\n", len(cut) // 2) + 1
    tline = cut[:mid].count("\n") + 1
    trunc = cut[:mid] + ",".join(rows[tline - 2][:5])
    mutate("truncated_mid_row", lambda h, rs: trunc,
           [err("rec.csv", tline, "column", "field", "missing", "expected", "value", "truncated")])
    mutate("two_points", lambda h, rs: rows_to_csv(h, [r for r in rs if r[3] != "K"]),
           [err("rec.csv", None, "point", "3", "three")])
    def collinear(h, rs):
        out = []
        for r in rs:
            r = r[:]
            if r[0] == "X":   # make Q and K lie on the line through P along x (same y, z)
                p0 = [x for x in rs if x[0] == "X" and x[1] == r[1] and x[2] == r[2] and x[3] == "P"
                      and x[8] == r[8]][0]
                if r[3] != "P":
                    r[5], r[6] = p0[5], p0[6]
            out.append(r)
        return rows_to_csv(h, out)
    mutate("collinear_points", collinear, [err("rec.csv", None, "collinear")])
    mutate("positions_in_metres", lambda h, rs: rows_to_csv(h, [[*r[:2], f"{float(r[2]) / 1000:g}", *r[3:]]
                                                                if r[0] == "X" else r for r in rs]),
           [err("rec.csv", None, "metre", "unit", "position")])
    # generated random cell mutations (seeded)
    bad_values = ["nan", "NaN", "inf", "-Infinity", "", "--1", "1.2.3", "0x1p3", "1e999", "one", "1,5", "∞"]
    num_cols = ["x", "y", "z", "position", "round"]
    for k in range(12):
        at = rnd.randrange(len(rows))
        col = rnd.choice(num_cols)
        val = bad_values[k % len(bad_values)]
        mutate(f"gen_cell_{k:02d}", setcell(col, val, at), [err("rec.csv", at + 2, col, "number", "finite", "nan",
                                                                 "inf", "invalid", "empty", "missing", val or "x")])
    # paths
    C.add("identify_input_is_directory", "identify", "path", ["recdir", "-o", "model.json"], dirs=["recdir"],
          expect=[err("recdir", None, "directory")])
    C.add("identify_input_missing", "identify", "path", ["nope.csv", "-o", "model.json"],
          expect=[err("nope.csv", None, "no such", "not found", "does not exist", "missing")])
    C.add("identify_output_is_directory", "identify", "path", ["rec.csv", "-o", "outdir"], {"rec.csv": rec},
          dirs=["outdir"], expect=[err("outdir", None, "directory")])
    C.add("identify_output_parent_is_file", "identify", "path", ["rec.csv", "-o", "afile/model.json"],
          {"rec.csv": rec, "afile": "x"}, expect=[err("afile", None, "not a directory", "directory")])
    C.add("identify_output_parent_missing", "identify", "path", ["rec.csv", "-o", "no/such/dir/model.json"],
          {"rec.csv": rec}, expect=[err("model.json", None, "no such", "not exist", "directory", "missing"),
                                    ok({"kind": "model_json", "path": "no/such/dir/model.json", "axes": ["X", "C"]})])
    C.add("identify_output_name_too_long", "identify", "path", ["rec.csv", "-o", "m" * 300 + ".json"],
          {"rec.csv": rec}, expect=[err("mmmm", None, "too long", "name")])
    C.add("identify_output_equals_input", "identify", "overwrite", ["rec.csv", "-o", "rec.csv"], {"rec.csv": rec},
          expect=[err("rec.csv", None, "input", "overwrite", "same")])
    C.add("identify_output_equals_input_respelled", "identify", "overwrite",
          ["sub/rec.csv", "-o", "sub/../sub/./rec.csv"], {"sub/rec.csv": rec},
          expect=[err("rec.csv", None, "input", "overwrite", "same")])
    C.add("identify_plots_onto_file", "identify", "path", ["rec.csv", "-o", "model.json", "--plots", "plots"],
          {"rec.csv": rec, "plots": "I am a file"}, expect=[err("plots", None, "directory", "exists", "file")])
    C.add("identify_plots_parent_is_file", "identify", "path", ["rec.csv", "-o", "model.json", "--plots", "f/plots"],
          {"rec.csv": rec, "f": "I am a file"}, expect=[err("f", None, "directory", "exists", "file")])
    C.add("identify_plots_overwrite_input", "identify", "overwrite",
          ["plots/identify_X.png", "-o", "model.json", "--plots", "plots"],
          {"plots/identify_X.png": rec}, expect=[err("identify_X.png", None, "input", "overwrite", "same")])
    C.add("identify_inspire_with_tidy_file", "identify", "recording CSV",
          ["rec.csv", "-o", "model.json", "--layout", "inspire", "--axis", "X"], {"rec.csv": rec},
          expect=[err("rec.csv", None, "inspire", "layout", "format", "block", "row", "column", "expected")])


def cases_compensate(C: Corpus, rnd: random.Random):
    hand = jdump(HAND_MODEL)
    base = {"prog.nc": program(), "model.json": hand}
    argv = ["prog.nc", "--model", "model.json", "-o", "out.nc"]

    def add(cid, kind, files, expect, extra=(), args=None):
        C.add(f"compensate_{cid}", "compensate", kind, (args or argv) + list(extra), {**base, **files}, expect)

    for eol, name in [("\n", "lf"), ("\r\n", "crlf"), ("\r", "cr")]:
        add(f"eol_{name}", "NC program", {"prog.nc": program(eol)}, [ok(gcode_check(eol=eol))])
        add(f"eol_{name}_nocomments", "NC program", {"prog.nc": program(eol, comments=False)},
            [ok(gcode_check(eol=eol))])
    add("valid_json", "NC program", {}, [ok(gcode_check(), {"kind": "stdout_json", "keys": []})], ["--json"])
    # lone CR: a G2 after a ';' comment must still be seen (and refused), at its own line
    cr_arc = "\r".join(["G90 G21", "; comment", "G1 X10 Y0 Z0 F100", "G2 X20 Y0 I5 J0", "G1 X30", "M30"]) + "\r"
    add("cr_arc_after_comment", "NC program", {"prog.nc": cr_arc}, [err("prog.nc", 4, "arc", "G2")])
    crlf_arc = "\r\n".join(["G90 G21", "(c)", "G1 X10 Y0 Z0 F100", "G3 X20 Y0 R5", "M30"]) + "\r\n"
    add("crlf_arc_r", "NC program", {"prog.nc": crlf_arc}, [err("prog.nc", 4, "arc", "G3")])
    add("ijk_without_g2", "NC program", {"prog.nc": "G90 G21\nG1 X10 Y0 Z0 F100\nX20 I5\nM30\n"},
        [err("prog.nc", 3, "I", "arc")])
    # words with stray text
    def word_case(cid, word, words):
        p = f"G90 G21\nG1 X0 Y0 Z0 F100\nG1 {word} Y10\nG1 X5\nM30\n"
        add(f"word_{cid}", "NC program", {"prog.nc": p}, [err("prog.nc", 3, *words)])
    word_case("x1_2_3", "X1.2.3", ["X1.2.3", "number", "word"])
    word_case("x1e2", "X1e2", ["X1e2", "X1E2", "number", "word", "exponent"])
    word_case("x_double_minus", "X--1", ["X--1", "number", "word"])
    word_case("x_alone", "X", ["X", "number", "word", "value"])
    word_case("x_plus_minus", "X+-3", ["X+-3", "number", "word"])
    word_case("unknown_axis_a", "A10", ["A", "axis", "word"])
    word_case("unknown_axis_u", "U5", ["U", "axis", "word"])
    word_case("parameter", "X#1", ["#", "parameter", "variable"])
    word_case("x_nan", "Xnan", ["nan", "number", "word"])
    # Fanuc ignores blanks inside words: X1 0.5 is X10.5; accepting it as such, or refusing clearly, are both fine
    blank = "G90 G21\nG1 X0 Y0 Z0 F100\nG1 X1 0.5 Y10\nM30\n"
    blank_as_fanuc = "G90 G21\nG1 X0 Y0 Z0 F100\nG1 X10.5 Y10\nM30\n"
    add("word_blank_inside_number", "NC program", {"prog.nc": blank, "fanuc.nc": blank_as_fanuc},
        [ok(gcode_check(same_as="fanuc.nc")), err("prog.nc", 3, "blank", "space", "number", "word", "0.5")])
    # refused modes with their own message
    for cid, line, words in [("m128", "M128", ["M128", "TCPM", "tool centre", "tool center"]),
                             ("g43_4", "G43.4 H1", ["G43.4", "TCPM", "tool centre", "tool center"]),
                             ("traori", "TRAORI", ["TRAORI", "TCPM", "transformation"]),
                             ("g68", "G68 X0 Y0 R30", ["G68", "rotation", "rotate"]),
                             ("g68_2", "G68.2 X0 Y0 Z0 I0 J45 K0", ["G68.2", "rotation", "tilted", "frame"]),
                             ("g81", "G81 X10 Y10 Z-5 R2 F100", ["G81", "cycle"]),
                             ("g83", "G83 X10 Y10 Z-5 R2 Q1 F100", ["G83", "cycle"]),
                             ("cycl_def", "CYCL DEF 200 DRILLING", ["CYCL", "cycle", "Heidenhain", "word"]),
                             ("g52", "G52 X10", ["G52", "frame", "offset", "local"]),
                             ("g92", "G92 X0 Y0", ["G92", "frame", "offset", "preset"])]:
        p = f"%\nG90 G21\nG1 X0 Y0 Z20 F500\n{line}\nG1 X20 Y10\nM30\n%\n"
        add(f"refuse_{cid}", "NC program", {"prog.nc": p}, [err("prog.nc", 4, *words)])
        if cid in ("g68", "g81"):   # the message must not be about arcs
            C.cases[-1]["expect"][0]["error"]["forbid"] = ["arc"]
    # safe headers: machine-coordinate moves passed through unchanged, the rest compensated
    hdr = "%\nO2000\nG90 G21 G17\nG91 G28 Z0\nG90\nG0 X10 Y10 Z50\nG1 Z5 F300\nX60 Y-20\nG53 G0 Z0\nM30\n%\n"
    add("safe_headers_g28_g53", "NC program", {"prog.nc": hdr}, [ok(gcode_check(passthrough=[4, 9]))])
    hdr2 = "G21 G90\nG53 G0 Z0\nG0 X0 Y0 Z30\nG1 X40 Y40 Z2 F300\nG91 G28 Z0\nM30\n"
    add("safe_headers_g53_first", "NC program", {"prog.nc": hdr2}, [ok(gcode_check(passthrough=[2, 5]))])
    # empty / binary programs and other degenerate inputs
    for cid, content, words in [("empty", b"", ["empty", "no move"]),
                                ("only_comments", b"%\n(NOTHING HERE)\n; nothing\n%\n", ["empty", "no move"]),
                                ("whitespace", b"\n\n   \r\n\t\n", ["empty", "no move"]),
                                ("nul_bytes", b"\x00" * 512, ["binary", "NUL", "nul"]),
                                ("nul_inside", b"G90 G21\nG1 X1 Y1 Z1 F100\n\x00\x00\x00\nX5\n",
                                 ["binary", "NUL", "nul"]),
                                ("binary_random", bytes(rnd.randrange(256) for _ in range(4000)),
                                 ["binary", "NUL", "nul", "decode", "encoding"])]:
        add(f"program_{cid}", "NC program", {"prog.nc": content}, [err("prog.nc", None, *words)])
    # cp1252 comment bytes: preserved byte for byte, or refused clearly
    p1252 = "G90 G21\n(SPINDEL 20\xb0C, TOLERANZ 5 \xb5m)\nG1 X10 Y5 Z0 F500\nX50\nM30\n".encode("cp1252")
    add("cp1252_comment", "NC program", {"prog.nc": p1252},
        [ok(gcode_check()), err("prog.nc", 2, "decode", "encoding", "UTF-8", "utf-8")])
    add("utf8_comment", "NC program", {"prog.nc": "G90 G21\n(20°C, 5 µm, Ω)\nG1 X10 Y5 Z0 F500\nX50\nM30\n"},
        [ok(gcode_check())])
    add("b_out_of_range", "NC program", {"prog.nc": "G90 G21\nG1 X0 Y0 Z0 F100\nG1 B190\nM30\n"},
        [err("prog.nc", 3, "B", "range", "190")])
    add("inch", "NC program", {"prog.nc": "G20 G90\nG1 X1 Y0.5 Z0 F10\nX3 Y-1\nM30\n"},
        [ok(gcode_check(units="inch"))])
    add("incremental", "NC program", {"prog.nc": "G21 G90\nG1 X0 Y0 Z10 F100\nG91\nX20 Y5\nX20\nY-10 Z-5\nG90\nM30\n"},
        [ok(gcode_check())])
    # G93 inverse time: a subdivided move's pieces all carry F and take the original move's time together
    g93 = "G21 G90 G94\nG0 X-100 Y0 Z10\nG93 G1 X100 F2\nG1 X-100 F4\nG94 G0 Z50\nM30\n"
    C.add("compensate_g93_subdivided", "compensate", "NC program",
          ["prog.nc", "--model", "v.json", "-o", "out.nc", "--tolerance", "0.001"],
          {"prog.nc": g93, "v.json": jdump(V_MODEL)},
          [ok(gcode_check(oracle={"exx": [[-500, 0, 500], [0.02, 0, 0.02]], "c0y": 0.0, "scale": 1.0},
                          g93=True, min_inserted=2))])
    g94 = "G21 G90 G94\nG0 X-100 Y0 Z10\nG1 X100 F500\nM30\n"
    C.add("compensate_g94_subdivided", "compensate", "NC program",
          ["prog.nc", "--model", "v.json", "-o", "out.nc", "--tolerance", "0.001"],
          {"prog.nc": g94, "v.json": jdump(V_MODEL)},
          [ok(gcode_check(oracle={"exx": [[-500, 0, 500], [0.02, 0, 0.02]], "c0y": 0.0, "scale": 1.0},
                          min_inserted=2))])
    # generated G-code mutations: a bad word inserted on a random move line
    bad_words = ["X1.2.3", "Y1e3", "Z--2", "X1.2e", "U7", "Y1..5", "X1-2", "Z+", "X0x10", "B1.5.5"]
    base_lines = program().split("\n")
    movable = [k for k, ln in enumerate(base_lines) if ln.startswith("N") and ("X" in ln or "Y" in ln)]
    for k, w in enumerate(bad_words):
        at = rnd.choice(movable)
        ls = base_lines[:]
        code, sep, com = ls[at].partition(";")
        ls[at] = code.rstrip() + " " + w + (" ;" + com if sep else "")
        add(f"gen_badword_{k:02d}", "NC program", {"prog.nc": "\n".join(ls)},
            [err("prog.nc", at + 1, w[0], "word", "number", "axis", w)])
    # options
    for cid, opt, val in [("tool_length_nan", "--tool-length", "nan"), ("tool_length_inf", "--tool-length", "inf"),
                          ("precision_neg", "--precision", "-1"), ("tolerance_nan", "--tolerance", "nan"),
                          ("tolerance_neg", "--tolerance", "-0.001"),
                          ("cone_nan", "--cone", "nan"), ("cone_neg", "--cone", "-2"),
                          ("iterations_zero", "--iterations", "0"), ("iterations_neg", "--iterations", "-1"),
                          ("residual_every_zero", "--residual-every", "0"),
                          ("max_correction_nan", "--max-correction", "nan"),
                          ("max_correction_neg", "--max-correction", "-1")]:
        add(f"opt_{cid}", "option", {}, [err(None, None, opt, option=True)], [opt, val])
    # --tolerance 0 cannot be met by subdividing: refuse it, or stop subdividing somewhere and still be right
    add("opt_tolerance_zero", "option", {}, [err(None, None, "--tolerance", option=True), ok(gcode_check())],
        ["--tolerance", "0"])
    # models
    def model_case(cid, model_text, expect, prog=None):
        add(f"model_{cid}", "model JSON", {"model.json": model_text, **({"prog.nc": prog} if prog else {})}, expect)
    um = {"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": {"E_C0Y": 18},
          "functions": {"E_XX": {"axis": "X", "positions": [-500, 500], "values": [12.5, 12.5]}}}
    um_prog = "G90 G21\nG0 X0 Y0 Z50\nG1 X50 Y10 Z10 F500\nM30\n"
    model_case("um_under_mm_guard", jdump(um), [err("model.json", None, "plausibility bound"),
                                                err("prog.nc", 2, "correction", "implausible", "max-correction",
                                                    "residual")], um_prog)
    big = {"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": {},
           "functions": {"E_XX": {"axis": "X", "positions": [-500, 500], "values": [2.0, 2.0]}}}
    model_case("correction_2mm_guard", jdump(big), [err("model.json", None, "plausibility bound"),
                                                    err("prog.nc", 2, "correction", "implausible",
                                                        "max-correction")], um_prog)
    C.add("compensate_model_correction_2mm_allowed", "compensate", "option",
          argv + ["--max-correction", "5", "--force"], {"prog.nc": um_prog, "model.json": jdump(big)},
          [ok(gcode_check(oracle={"exx": [[-500, 500], [2.0, 2.0]], "c0y": 0.0, "scale": 1.0}, bound=2.1))])
    # a model saved by a Windows editor in cp1252: refused, or read as such and said (it is then a zero model)
    model_case("latin1_bytes", '{"machine": "dmu50", "note": "20\xb0C"}'.encode("latin-1"),
               [err("model.json", None, "decode", "encoding", "UTF-8", "utf-8", "JSON", "json"),
                ok(gcode_check(oracle={"exx": [[-500, 500], [0.0, 0.0]], "c0y": 0.0}),
                   say=["cp1252", "latin", "1252", "encoding"])])
    um_ok = {"machine": "dmu50", "units": {"length": "um", "angle": "urad"}, "constants": {"E_C0Y": 20.0},
             "functions": {"E_XX": {"axis": "X", "positions": [-500, 500], "values": [-10.0, 10.0]}}}
    model_case("stated_um_urad", jdump(um_ok), [ok(gcode_check()), err("model.json", None, "unit", "um")])
    shapes = shape_models()
    for cid, text, words in shapes:
        model_case(cid, text, [err("model.json", None, *words)])
    # tool length nan via model path etc.
    add("tool_length_valid", "option", {}, [ok(gcode_check(oracle=None, bound=0.05))], ["--tool-length", "150"])
    # outputs onto inputs
    C.add("compensate_output_equals_input", "compensate", "overwrite",
          ["prog.nc", "--model", "model.json", "-o", "prog.nc"], base, [err("prog.nc", None, "input", "overwrite",
                                                                          "same")])
    C.add("compensate_output_equals_model", "compensate", "overwrite",
          ["prog.nc", "--model", "model.json", "-o", "./model.json"], base,
          [err("model.json", None, "input", "overwrite", "same")])
    C.add("compensate_tables_dir_holds_model", "compensate", "overwrite",
          ["prog.nc", "--model", "tables/constants.csv", "-o", "out.nc", "--tables", "tables"],
          {"prog.nc": program(), "tables/constants.csv": hand},
          [err("constants.csv", None, "input", "overwrite", "same")])
    C.add("compensate_tables_dir_holds_program", "compensate", "overwrite",
          ["tables/comp_X.csv", "--input", "gcode", "--model", "model.json", "-o", "out.nc", "--tables", "tables"],
          {"tables/comp_X.csv": program(), "model.json": hand},
          [err("comp_X.csv", None, "input", "overwrite", "same")])
    C.add("compensate_tables_onto_file", "compensate", "path",
          ["prog.nc", "--model", "model.json", "-o", "out.nc", "--tables", "tables"],
          {**base, "tables": "a file"}, [err("tables", None, "directory", "exists", "file")])
    C.add("compensate_output_is_directory", "compensate", "path", argv, base, dirs=["out.nc"],
          expect=[err("out.nc", None, "directory")])
    C.add("compensate_output_parent_is_file", "compensate", "path",
          ["prog.nc", "--model", "model.json", "-o", "f/out.nc"], {**base, "f": "file"},
          [err("f", None, "not a directory", "directory")])
    C.add("compensate_output_readonly_fs", "compensate", "path",
          ["prog.nc", "--model", "model.json", "-o", "/proc/mtcal_fuzz_out.nc"], base,
          [err("mtcal_fuzz_out.nc", None, "permission", "read-only", "no such", "denied", "not permitted",
               "directory")],
          note="root ignores permission bits: /proc stands in for a directory nobody may create files in")
    C.add("compensate_program_is_directory", "compensate", "path", argv, {"model.json": hand}, dirs=["prog.nc"],
          expect=[err("prog.nc", None, "directory")])
    C.add("compensate_model_is_directory", "compensate", "path", argv, {"prog.nc": program()}, dirs=["model.json"],
          expect=[err("model.json", None, "directory")])
    C.add("compensate_model_missing", "compensate", "path", argv, {"prog.nc": program()},
          expect=[err("model.json", None, "no such", "not found", "does not exist", "missing")])
    # CL data
    cl = "\n".join(["0 0 50 0 0 1", "10 5 20 0 0 1", "40 -10 15 0.342020143 0 0.939692621",
                    "60 -10 15 0 0.5 0.866025404", "80 0 10 0 0 1"]) + "\n"
    C.add("compensate_cl_valid", "compensate", "CL data", ["path.cl", "--model", "model.json", "-o", "out.nc"],
          {"path.cl": cl, "model.json": hand}, [ok({"kind": "cl_output", "output": "out.nc", "moves": 5})])
    for cid, text, line, words in [("empty", "", None, ["empty", "no "]),
                                   ("comments_only", "# nothing\n\n", None, ["empty", "no "]),
                                   ("five_numbers", cl.replace("10 5 20 0 0 1", "10 5 20 0 1"), 2,
                                    ["6", "six", "number", "column", "field", "x y z i j k"]),
                                   ("nan", cl.replace("10 5 20", "10 nan 20"), 2, ["nan", "finite"]),
                                   ("text", cl.replace("40 -10", "forty -10"), 3, ["forty", "number"]),
                                   ("zero_axis", cl.replace("0 0 1\n10", "0 0 0\n10", 1), 1,
                                    ["axis", "zero", "unit", "length", "vector", "ijk", "i j k"]),
                                   ("unreachable", cl.replace("80 0 10 0 0 1", "80 0 10 0 0 -1"), 5,
                                    ["reach", "range", "k", "B", "orientation"]),
                                   ("binary", "\x00\x01\x02" * 50, None, ["binary", "NUL", "nul", "number"])]:
        C.add(f"compensate_cl_{cid}", "compensate", "CL data", ["path.cl", "--model", "model.json", "-o", "out.nc"],
              {"path.cl": text, "model.json": hand}, [err("path.cl", line, *words)])


def shape_models():
    """Model JSON of the wrong shape or with bad fields: (case id, text, problem words)."""
    u = {"length": "mm", "angle": "rad"}
    def m(**kw):
        return jdump({"machine": "dmu50", "units": u, **kw})
    return [
        ("shape_list", "[1, 2]", ["object", "dict", "mapping", "list", "JSON object"]),
        ("shape_constants_list", m(constants=[1e-5, 2e-5]), ["constants"]),
        ("shape_functions_string", m(functions="E_XX"), ["functions"]),
        ("shape_poly_no_coefficients", m(functions={"E_XX": {**EXX, "fit": {"kind": "polynomial",
                                                                             "domain": [-500, 500]}}}),
         ["coefficients", "E_XX"]),
        ("shape_harmonic_no_cos_sin", m(functions={"E_XC": {"axis": "C", "positions": [0, 90, 180, 270],
                                                             "values": [0, 1e-3, 0, -1e-3],
                                                             "fit": {"kind": "harmonic", "period": 360,
                                                                     "a0": 0.0}}}),
         ["cos", "sin", "E_XC"]),
        ("field_true", m(constants={"E_XX": True}), ["E_XX", "number", "bool"]),
        ("field_string", m(constants={"E_C0Y": "1e-5"}), ["E_C0Y", "number"]),
        ("field_nan", '{"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": {"E_C0Y": NaN}}',
         ["E_C0Y", "finite", "nan", "NaN"]),
        ("field_infinity", '{"machine": "dmu50", "constants": {"E_B0Z": Infinity}}', ["E_B0Z", "finite", "inf"]),
        ("function_over_wrong_axis", m(functions={"E_XX": {"axis": "Y", "positions": [-500, 500],
                                                            "values": [0, 1e-3]}}), ["E_XX", "axis", "Y"]),
        ("unknown_error_name", m(constants={"E_QQ": 1e-5}), ["E_QQ", "unknown"]),
        ("function_as_constant_name", m(functions={"E_C0Y": {"axis": "Y", "positions": [0, 1],
                                                              "values": [0, 1e-5]}}), ["E_C0Y"]),
        ("length_mismatch", m(functions={"E_XX": {"axis": "X", "positions": [-500, 0, 500], "values": [0, 1e-3]}}),
         ["E_XX", "length", "positions", "values"]),
        ("empty_table", m(functions={"E_XX": {"axis": "X", "positions": [], "values": []}}),
         ["E_XX", "empty", "positions"]),
        ("values_nan_string", m(functions={"E_XX": {"axis": "X", "positions": [-500, 500], "values": [0, "x"]}}),
         ["E_XX", "values", "number"]),
        ("units_unknown", jdump({"machine": "dmu50", "units": {"length": "furlong", "angle": "rad"},
                                 "constants": {"E_C0Y": 1e-5}}), ["furlong", "unit", "length"]),
        ("machine_unknown", jdump({"machine": "nosuchmachine", "units": u, "constants": {}}),
         ["nosuchmachine", "machine"]),
        ("truncated_json", m(constants={"E_C0Y": 1e-5, "E_B0Z": 2e-5})[:-25], ["JSON", "json", "expect", "parse"]),
        ("empty_file", "", ["JSON", "json", "empty"]),
    ]


def cases_model_shapes_elsewhere(C: Corpus):
    """The issue names compensate, diagnose and simulate for the wrong-shape models."""
    header, rows = recording_x_only()
    rec = rows_to_csv(header, rows)
    wanted = {"shape_list", "shape_constants_list", "shape_functions_string", "shape_poly_no_coefficients",
              "shape_harmonic_no_cos_sin", "field_true", "function_over_wrong_axis", "field_nan",
              "truncated_json"}
    for cid, text, words in shape_models():
        if cid not in wanted:
            continue
        C.add(f"diagnose_model_{cid}", "diagnose", "model JSON", ["rec.csv", "--model", "model.json"],
              {"rec.csv": rec, "model.json": text}, [err("model.json", None, *words)])
        C.add(f"simulate_model_{cid}", "simulate", "model JSON",
              ["--model", "model.json", "--plan", "plan.json", "-o", "sim.csv"],
              {"model.json": text, "plan.json": jdump(SMALL_PLAN)}, [err("model.json", None, *words)])


SMALL_PLAN = {"rounds": 2, "axes": {"X": {"start": 0, "stop": 200, "count": 5},
                                    "C": {"start": 0, "stop": 90, "count": 4}}}


def cases_simulate(C: Corpus):
    plan = jdump(SMALL_PLAN)
    n_rows = 2 * (5 + 4) * 3 * 2
    csv_check = {"kind": "recording_csv", "path": "sim.csv", "rows": n_rows}
    base = ["--plan", "plan.json", "-o", "sim.csv"]
    C.add("simulate_valid", "simulate", "plan JSON", base + ["--json"], {"plan.json": plan},
          [ok(csv_check, {"kind": "stdout_json", "keys": []})])
    C.add("simulate_exx_no_noise", "simulate", "model JSON", base + ["--model", "model.json", "--no-noise"],
          {"plan.json": plan, "model.json": jdump(HAND_MODEL)},
          [ok(csv_check, {"kind": "sim_exx", "path": "sim.csv", "exx": ORACLE["exx"]})])
    C.add("simulate_tracker_negative_sep", "simulate", "option", base + ["--tracker", "-1500,225,150"],
          {"plan.json": plan}, [ok(csv_check)])
    for cid, eff, words in [("periodic_pitch0", "periodic:axis=X,pitch=0", ["pitch"]),
                            ("periodic_amp_1e300", "periodic:axis=X,amplitude=1e300", ["amplitude", "periodic"]),
                            ("backlash_nan", "backlash:axis=X,amount=nan", ["amount", "finite", "nan"]),
                            ("backlash_text", "backlash:axis=X,amount=abc", ["amount", "abc", "number"]),
                            ("backlash_axis_q", "backlash:axis=Q,amount=0.004", ["axis", "Q"]),
                            ("unknown_effect", "wobble:axis=X", ["wobble", "effect"]),
                            ("unknown_key", "backlash:axis=X,amuont=0.004", ["amuont", "key"]),
                            ("no_equals", "backlash:axis", ["backlash", "key=value", "="]),
                            ("thermal_inf", "thermal_drift:amplitude=inf", ["amplitude", "finite", "inf"])]:
        C.add(f"simulate_effect_{cid}", "simulate", "option", base + ["--effect", eff], {"plan.json": plan},
              [err(None, None, *words, option=True)])
    for cid, argv, words in [("rounds_zero", ["--rounds", "0"], ["--rounds"]),
                             ("rounds_neg", ["--rounds", "-2"], ["--rounds"]),
                             ("tracker_two", ["--tracker", "1,2"], ["--tracker"]),
                             ("tracker_nan", ["--tracker", "nan,0,150"], ["--tracker"])]:
        C.add(f"simulate_opt_{cid}", "simulate", "option", base + argv, {"plan.json": plan},
              [err(None, None, *words, option=True)])
    C.add("simulate_seed_negative", "simulate", "option", base + ["--seed", "-1"], {"plan.json": plan},
          [ok(csv_check), err(None, None, "--seed", option=True)])
    # plans
    def plan_case(cid, text, words, cmd="simulate"):
        argv = base if cmd == "simulate" else ["--plan", "plan.json", "--json"]
        C.add(f"{cmd}_plan_{cid}", cmd, "plan JSON", argv, {"plan.json": text}, [err("plan.json", None, *words)])
    bad_plans = [
        ("b_270", jdump({"rounds": 1, "axes": {"B": {"positions": [0, 90, 270]}}}), ["B", "270", "range", "limit"]),
        ("b_270_at", jdump({"rounds": 1, "axes": {"X": {"positions": [0, 100], "at": {"B": 270}}}}),
         ["B", "270", "range", "limit"]),
        ("list", "[1, 2]", ["object", "dict", "mapping", "list"]),
        ("axes_string", jdump({"axes": "X"}), ["axes"]),
        ("unknown_key", jdump({"roudns": 2}), ["roudns", "unknown"]),
        ("rounds_zero", jdump({"rounds": 0}), ["rounds"]),
        ("rounds_text", jdump({"rounds": "two"}), ["rounds"]),
        ("rounds_true", jdump({"rounds": True}), ["rounds"]),
        ("tracker_two", jdump({"tracker": [1, 2]}), ["tracker"]),
        ("tracker_nan", '{"tracker": [NaN, 0, 150]}', ["tracker", "finite", "nan", "NaN"]),
        ("positions_nan", '{"rounds": 1, "axes": {"X": {"positions": [0, NaN, 100]}}}', ["X", "positions", "finite",
                                                                                        "nan", "NaN"]),
        ("count_zero", jdump({"axes": {"X": {"start": 0, "stop": 100, "count": 0}}}), ["count", "X"]),
        ("unknown_axis", jdump({"axes": {"Q": {"positions": [0, 1]}}}), ["Q", "axis"]),
        ("two_points", jdump({"points": {"tool": {"P": [0, 0, 0], "Q": [100, 0, 0]}}}), ["point", "3", "three"]),
        ("collinear_points", jdump({"points": {"tool": {"P": [0, 0, 0], "Q": [100, 0, 0], "K": [200, 0, 0]}}}),
         ["collinear"]),
        ("feed_negative", jdump({"feed_mm_s": -50}), ["feed_mm_s"]),
        ("truncated", plan[:-10], ["JSON", "json", "expect", "parse"]),
    ]
    for cid, text, words in bad_plans:
        plan_case(cid, text, words)
    for cid in ("b_270", "list", "tracker_nan", "unknown_axis"):
        text, words = next((t, w) for c, t, w in bad_plans if c == cid)
        plan_case(cid, text, words, cmd="plan")
    # paths and overwrites
    C.add("simulate_output_is_directory", "simulate", "path", base, {"plan.json": plan}, dirs=["sim.csv"],
          expect=[err("sim.csv", None, "directory")])
    C.add("simulate_output_parent_is_file", "simulate", "path", ["--plan", "plan.json", "-o", "f/sim.csv"],
          {"plan.json": plan, "f": "file"}, [err("f", None, "not a directory", "directory")])
    C.add("simulate_output_equals_model", "simulate", "overwrite",
          ["--plan", "plan.json", "--model", "model.json", "-o", "model.json"],
          {"plan.json": plan, "model.json": jdump(HAND_MODEL)}, [err("model.json", None, "input", "overwrite",
                                                                      "same")])
    C.add("simulate_truth_equals_model", "simulate", "overwrite",
          ["--plan", "plan.json", "--model", "sim.truth.json", "-o", "sim.csv"],
          {"plan.json": plan, "sim.truth.json": jdump(HAND_MODEL)},
          [err("sim.truth.json", None, "input", "overwrite", "same")])
    C.add("simulate_output_equals_plan", "simulate", "overwrite", ["--plan", "plan.json", "-o", "plan.json"],
          {"plan.json": plan}, [err("plan.json", None, "input", "overwrite", "same")])
    C.add("simulate_plan_is_directory", "simulate", "path", base, dirs=["plan.json"],
          expect=[err("plan.json", None, "directory")])


def cases_plan(C: Corpus):
    C.add("plan_valid_pos2", "plan", "option", ["--tracker=-1500,225,150", "--axes", "X", "--estimator", "three-point",
                                                 "--json"], {},
          [ok({"kind": "plan_sigma", "axis": "X", "name": "E_XX", "value": 0.0019, "rtol": 0.15})])
    C.add("plan_tracker_negative_sep", "plan", "option", ["--tracker", "-1500,225,150", "--axes", "X", "--estimator",
                                                           "three-point", "--json"], {},
          [ok({"kind": "plan_sigma", "axis": "X", "name": "E_XX", "value": 0.0019, "rtol": 0.15})])
    for cid, argv, words in [("tracker_two", ["--tracker", "1,2"], ["--tracker"]),
                             ("tracker_text", ["--tracker", "a,b,c"], ["--tracker"]),
                             ("tracker_nan", ["--tracker", "nan,0,0"], ["--tracker"]),
                             ("monte_carlo_neg", ["--monte-carlo", "-5"], ["--monte-carlo"]),
                             ("axes_unknown", ["--axes", "Q"], ["Q", "--axes", "axis"])]:
        C.add(f"plan_opt_{cid}", "plan", "option", argv + ["--axes", "X"] * (cid.startswith("tracker")), {},
              [err(None, None, *words, option=True)])
    C.add("plan_plot_onto_directory", "plan", "path", ["--axes", "X", "--plot", "map.png"], dirs=["map.png"],
          expect=[err("map.png", None, "directory")])
    C.add("plan_plot_parent_is_file", "plan", "path", ["--axes", "X", "--plot", "f/map.png"], {"f": "file"},
          [err("f", None, "not a directory", "directory")])
    C.add("plan_plot_equals_plan", "plan", "overwrite", ["--plan", "plan.json", "--plot", "plan.json"],
          {"plan.json": jdump(SMALL_PLAN)}, [err("plan.json", None, "input", "overwrite", "same")])
    C.add("plan_plan_missing", "plan", "path", ["--plan", "nope.json"], {},
          [err("nope.json", None, "no such", "not found", "does not exist", "missing")])


def cases_diagnose(C: Corpus, rnd: random.Random):
    header, rows = recording_x_only()
    rec = rows_to_csv(header, rows)
    dj = {"kind": "stdout_json", "keys": ["base_sigma", "effects", "located"]}
    C.add("diagnose_valid", "diagnose", "recording CSV", ["rec.csv", "--json"], {"rec.csv": rec}, [ok(dj)])
    C.add("diagnose_bom", "diagnose", "recording CSV", ["rec.csv", "--json"],
          {"rec.csv": b"\xef\xbb\xbf" + rec.encode()}, [ok(dj)])
    C.add("diagnose_german_semicolon", "diagnose", "recording CSV", ["rec.csv", "--json"],
          {"rec.csv": rows_to_csv(header, [[c.replace(".", ",") for c in r] for r in rows], sep=";")},
          [ok(dj, say=[";", "semicolon", "decimal comma"])])
    C.add("diagnose_with_model", "diagnose", "model JSON", ["rec.csv", "--model", "model.json", "--json"],
          {"rec.csv": rec, "model.json": jdump(HAND_MODEL)}, [ok(dj)])
    for cid, val in [("nan", "nan"), ("zero", "0"), ("one_and_half", "1.5"), ("neg", "-0.01")]:
        C.add(f"diagnose_level_{cid}", "diagnose", "option", ["rec.csv", "--level", val], {"rec.csv": rec},
              [err(None, None, "--level", option=True)])
    C.add("diagnose_tracker_two", "diagnose", "option", ["rec.csv", "--tracker", "1,2"], {"rec.csv": rec},
          [err(None, None, "--tracker", option=True)])
    C.add("diagnose_tracker_negative", "diagnose", "option", ["rec.csv", "--tracker", "-1500,225,150", "--json"],
          {"rec.csv": rec}, [ok(dj)])
    for k in range(6):
        at = rnd.randrange(len(rows))
        col = rnd.choice(["x", "y", "z", "position", "time_s"])
        val = ["nan", "inf", "", "abc", "1e999", "-nan"][k]
        rs = [r[:] for r in rows]
        rs[at][header.index(col)] = val
        C.add(f"diagnose_gen_cell_{k:02d}", "diagnose", "recording CSV", ["rec.csv"],
              {"rec.csv": rows_to_csv(header, rs)},
              [err("rec.csv", at + 2, col, "number", "finite", "nan", "inf", "invalid", "empty", "missing")])
    C.add("diagnose_empty", "diagnose", "recording CSV", ["rec.csv"], {"rec.csv": ""},
          [err("rec.csv", None, "empty", "no data", "header")])
    C.add("diagnose_input_is_directory", "diagnose", "path", ["rec.csv"], dirs=["rec.csv"],
          expect=[err("rec.csv", None, "directory")])
    C.add("diagnose_plots_onto_file", "diagnose", "path", ["rec.csv", "--plots", "plots"],
          {"rec.csv": rec, "plots": "a file"}, [err("plots", None, "directory", "exists", "file")])
    C.add("diagnose_plots_overwrite_input", "diagnose", "overwrite",
          ["plots/residuals_before.png", "--plots", "plots"], {"plots/residuals_before.png": rec},
          [err("residuals_before.png", None, "input", "overwrite", "same")])


def cases_plate(C: Corpus, rnd: random.Random):
    nbs = (DATA / "nbs_table1_corrected.csv").read_text()
    nbs_check = {"kind": "plate", "alpha": 4.81e-6, "alpha_tol": 0.01e-6, "gamma": 13.69e-6, "gamma_tol": 0.01e-6}
    C.add("plate_nbs_table1", "plate", "plate CSV", ["pos.csv", "--json"], {"pos.csv": nbs}, [ok(nbs_check)])
    C.add("plate_nbs_bom_crlf", "plate", "plate CSV", ["pos.csv", "--json"],
          {"pos.csv": b"\xef\xbb\xbf" + nbs.replace("\n", "\r\n").encode()}, [ok(nbs_check)])
    body = [ln for ln in nbs.splitlines() if not ln.startswith("#")]
    german = "\n".join(ln.replace(",", ";").replace(".", ",") for ln in body) + "\n"
    C.add("plate_nbs_german", "plate", "plate CSV", ["pos.csv", "--json"], {"pos.csv": german},
          [ok(nbs_check, say=[";", "semicolon", "decimal comma"])])
    C.add("plate_nbs_cp1252_comment", "plate", "plate CSV", ["pos.csv", "--json"],
          {"pos.csv": "# Messung bei 20\xb0C, Unsicherheit 0,5 \xb5in\n".encode("cp1252") + nbs.encode()},
          [ok(nbs_check)])
    for turn in (60.0, 100.0, 90.0, 135.0):
        t = f"{turn:g}"
        C.add(f"plate_turn_{t}", "plate", "plate CSV", ["pos.csv", "--json"],
              {"pos.csv": plate_csv(turn, alpha=1e-4)},
              [ok({"kind": "plate", "alpha_abs": 1e-4, "alpha_tol": 2e-6, "sigma_max": 1e-6})])
    C.add("plate_turn_60_perfect", "plate", "plate CSV", ["pos.csv", "--json"], {"pos.csv": plate_csv(60.0)},
          [ok({"kind": "plate", "alpha_abs": 0.0, "alpha_tol": 1e-9, "gamma_abs_max": 1e-9, "sigma_max": 1e-7})])
    for cid, val in [("nan", "nan"), ("zero", "0"), ("two", "2")]:
        C.add(f"plate_level_{cid}", "plate", "option", ["pos.csv", "--level", val], {"pos.csv": nbs},
              [err(None, None, "--level", option=True)])
    C.add("plate_origin_unknown", "plate", "option", ["pos.csv", "--origin", "99"], {"pos.csv": nbs},
          [err(None, None, "99", "--origin", "point", option=True)])
    C.add("plate_align_bad_axis", "plate", "option", ["pos.csv", "--align", "5:z"], {"pos.csv": nbs},
          [err(None, None, "--align", "5:z", "z", option=True)])
    lines = nbs.splitlines()
    first = next(k for k, ln in enumerate(lines) if ln.startswith("point"))

    def mut(cid, new_lines, line, words):
        C.add(f"plate_{cid}", "plate", "plate CSV", ["pos.csv"], {"pos.csv": "\n".join(new_lines) + "\n"},
              [err("pos.csv", line, *words)])
    for k, (val, words) in enumerate([("nan", ["nan", "finite"]), ("inf", ["inf", "finite"]), ("", ["empty", "missing",
                                                                                                   "number"]),
                                      ("abc", ["abc", "number"]), ("1e999", ["finite", "inf", "1e999"]),
                                      ("1.2.3", ["1.2.3", "number"])]):
        at = first + 1 + rnd.randrange(9)
        ls = lines[:]
        cells = ls[at].split(",")
        col = 1 + rnd.randrange(4)
        cells[col] = val
        ls[at] = ",".join(cells)
        mut(f"gen_cell_{k:02d}", ls, at + 1, words + ["x1", "y1", "x2", "y2"][col - 1:col])
    ls = lines[:]
    ls[first + 3] = ls[first + 3].rsplit(",", 1)[0]
    mut("row_short", ls, first + 4, ["column", "field", "missing", "expected", "value"])
    ls = lines[:]
    ls.insert(first + 3, ls[first + 2])
    mut("duplicate_point", ls, None, ["duplicate", "point", "3"])
    mut("missing_column", [ln.rsplit(",", 1)[0] for ln in lines], first + 1, ["y2", "column"])
    mut("header_only", lines[:first + 1], None, ["no data", "empty", "point", "no rows"])
    mut("two_points", lines[:first + 3], None, ["point", "few", "enough", "3"])
    mut("x3_without_y3", lines[:first] + [lines[first] + ",x3"] + [ln + ",1.0" for ln in lines[first + 1:]],
        first + 1, ["x3", "y3", "column", "pair"])
    C.add("plate_empty", "plate", "plate CSV", ["pos.csv"], {"pos.csv": ""}, [err("pos.csv", None, "empty", "no data",
                                                                                  "header")])
    C.add("plate_binary", "plate", "plate CSV", ["pos.csv"], {"pos.csv": bytes(range(256)) * 4},
          [err("pos.csv", None, "binary", "decode", "encoding", "header", "column", "NUL")])
    C.add("plate_input_is_directory", "plate", "path", ["pos.csv"], dirs=["pos.csv"],
          expect=[err("pos.csv", None, "directory")])
    C.add("plate_input_missing", "plate", "path", ["pos.csv"], {},
          [err("pos.csv", None, "no such", "not found", "does not exist", "missing")])
    C.add("plate_plot_equals_input", "plate", "overwrite", ["pos.csv", "--plot", "pos.csv"], {"pos.csv": nbs},
          [err("pos.csv", None, "input", "overwrite", "same")])
    C.add("plate_plot_onto_directory", "plate", "path", ["pos.csv", "--plot", "p.png"], {"pos.csv": nbs},
          dirs=["p.png"], expect=[err("p.png", None, "directory")])
    C.add("plate_plot_parent_is_file", "plate", "path", ["pos.csv", "--plot", "f/p.png"], {"pos.csv": nbs, "f": "x"},
          [err("f", None, "not a directory", "directory")])


def cases_demo_and_cli(C: Corpus):
    C.add("demo_out_onto_file", "demo", "path", ["--out", "d", "--quiet"], {"d": "a file"},
          [err("d", None, "directory", "exists", "file")])
    C.add("demo_out_parent_is_file", "demo", "path", ["--out", "f/d", "--quiet"], {"f": "a file"},
          [err("f", None, "directory", "exists", "file")])
    C.add("cli_no_command", "", "option", [], {}, [err(None, None, "command", "COMMAND", "required", option=True)])
    C.add("cli_unknown_command", "frobnicate", "option", [], {},
          [err(None, None, "frobnicate", "invalid choice", option=True)])
    C.add("cli_unknown_option", "compensate", "option", ["prog.nc", "--model", "m.json", "-o", "o.nc", "--frobnicate"],
          {}, [err(None, None, "--frobnicate", "unrecognized", option=True)])



def cases_real_data(C: Corpus):
    """Valid runs on the bundled data and on simulate's output, chained through the commands a user types."""
    sample = (DATA / "sample_5axis.nc").read_bytes()
    truth = (DATA / "demo_truth.json").read_bytes()
    files = {"prog.nc": sample, "truth.json": truth}
    argv = ["prog.nc", "--model", "truth.json", "-o", "out.nc"]
    # demo_truth: volumetric error up to ~43 um, angular ~25 urad: corrections stay well under 0.2 mm / 0.2 deg
    chk = gcode_check(oracle=None, bound=0.2)
    C.add("compensate_sample_5axis", "compensate", "NC program", argv + ["--json"], files,
          [ok(chk, {"kind": "stdout_json", "keys": []})])
    C.add("compensate_sample_5axis_full", "compensate", "NC program", argv + ["--scope", "full"], files, [ok(chk)])
    for eol, name in [(b"\r\n", "crlf"), (b"\r", "cr")]:
        # the same program with other line ends must give the same numbers, with its own line ends
        C.add(f"compensate_sample_5axis_{name}", "compensate", "NC program", argv,
              {**files, "prog.nc": sample.replace(b"\n", eol), "lf.nc": sample},
              [ok(chk, {"kind": "same_as", "path": "out.nc", "ref": "ref.nc", "eol": eol.decode()})],
              setup=[["compensate", "lf.nc", "--model", "truth.json", "-o", "ref.nc"]])
    # simulate (no noise) -> identify -> compensate: the identified model must compensate like the planted one
    plan = {"rounds": 2, "axes": {"X": {"start": 0, "stop": 200, "count": 5},
                                  "Y": {"start": 0, "stop": 200, "count": 5}}}
    prog = "G90 G21\nG0 X0 Y0 Z20\nG1 X150 Y20 Z5 F500\nX180 Y190\nX30\nY60 Z0\nG0 Z20\nM30\n"
    C.add("chain_simulate_identify_compensate", "compensate", "model JSON",
          ["prog.nc", "--model", "ident.json", "-o", "out.nc"],
          {"plan.json": jdump(plan), "truth.json": jdump(HAND_MODEL), "prog.nc": prog},
          [ok(gcode_check())],
          setup=[["simulate", "--plan", "plan.json", "--model", "truth.json", "--no-noise", "-o", "rec.csv"],
                 ["identify", "rec.csv", "-o", "ident.json"]])
    C.add("chain_identify_model_values", "identify", "recording CSV", ["rec.csv", "-o", "ident.json", "--json"],
          {"plan.json": jdump(plan), "truth.json": jdump(HAND_MODEL)},
          [ok({"kind": "model_json", "path": "ident.json", "axes": ["X", "Y"]},
              {"kind": "model_exx", "path": "ident.json", "exx": ORACLE["exx"], "c0y": C0Y})],
          setup=[["simulate", "--plan", "plan.json", "--model", "truth.json", "--no-noise", "-o", "rec.csv"]])
    header, rows = base_recording()
    C.add("identify_plots_valid", "identify", "recording CSV", ["rec.csv", "-o", "model.json", "--plots", "plots"],
          {"rec.csv": rows_to_csv(header, rows)},
          [ok({"kind": "model_json", "path": "model.json", "axes": ["X", "C"]},
              {"kind": "png", "dir": "plots", "min": 2})])
    C.add("diagnose_plots_valid", "diagnose", "recording CSV", ["rec.csv", "--plots", "plots"],
          {"rec.csv": rows_to_csv(*recording_x_only())},
          [ok({"kind": "png", "dir": "plots", "min": 2})])
    C.add("plate_plot_valid", "plate", "plate CSV", ["pos.csv", "--plot", "p.png", "--json"],
          {"pos.csv": (DATA / "nbs_table2_corrected.csv").read_bytes()},
          [ok({"kind": "plate", "alpha": -0.67e-6, "alpha_tol": 0.01e-6, "gamma": 2.82e-6, "gamma_tol": 0.01e-6},
              {"kind": "png", "file": "p.png"})])
    # a valid `mtcal demo` run (~30 s on a loaded machine) is left to tests/test_demo.py


def cases_more_paths(C: Corpus):
    hand = jdump(HAND_MODEL)
    base = {"prog.nc": program(), "model.json": hand}
    C.add("compensate_output_symlink_to_input", "compensate", "overwrite",
          ["prog.nc", "--model", "model.json", "-o", "link.nc"], base, links={"link.nc": "prog.nc"},
          expect=[err("link.nc", None, "input", "overwrite", "same"),
                  err("prog.nc", None, "input", "overwrite", "same")])
    C.add("compensate_output_equals_input_respelled", "compensate", "overwrite",
          ["prog.nc", "--model", "model.json", "-o", "sub/../prog.nc"], base, dirs=["sub"],
          expect=[err("prog.nc", None, "input", "overwrite", "same")])
    C.add("compensate_program_symlink_loop", "compensate", "path", ["loop.nc", "--model", "model.json", "-o", "o.nc"],
          {"model.json": hand}, links={"loop.nc": "loop.nc"},
          expect=[err("loop.nc", None, "symbolic", "link", "loop")])
    C.add("compensate_output_empty_name", "compensate", "path", ["prog.nc", "--model", "model.json", "-o", ""], base,
          [err(None, None, "-o", "--output", "output", "empty", "path", option=True)])
    C.add("identify_output_empty_name", "identify", "path", ["rec.csv", "-o", ""],
          {"rec.csv": rows_to_csv(*recording_x_only())},
          [err(None, None, "-o", "--output", "output", "empty", "path", option=True)])
    utf16 = rows_to_csv(*recording_x_only(), sep="\t").encode("utf-16")
    # Excel's "Unicode Text" (UTF-16, tab-separated): read and said (issue 20; it was called "a binary file")
    C.add("identify_utf16_export", "identify", "recording CSV", ["rec.csv", "-o", "model.json"], {"rec.csv": utf16},
          [ok(say=["UTF-16"])])
    C.add("plate_utf16_export", "plate", "plate CSV", ["pos.csv"],
          {"pos.csv": (DATA / "nbs_table1_corrected.csv").read_text().encode("utf-16")}, [ok(say=["UTF-16"])])
    C.add("compensate_model_bom", "compensate", "model JSON", ["prog.nc", "--model", "model.json", "-o", "out.nc"],
          {**base, "model.json": b"\xef\xbb\xbf" + hand.encode()},
          [ok(gcode_check()), err("model.json", None, "BOM", "byte-order", "byte order", "JSON", "decode")])
    C.add("identify_semicolon_dot_decimals", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
          {"rec.csv": rows_to_csv(*recording_x_only(), sep=";")},
          [ok({"kind": "model_json", "path": "model.json", "axes": ["X"]}, say=[";", "semicolon"])])


def cases_generated(C: Corpus, rnd: random.Random):
    """Generated mutations: truncated JSON, swapped columns, odd characters, very long lines, option values."""
    hand = jdump(HAND_MODEL)
    for k in range(5):   # model JSON cut at a random byte: the JSON decoder's line is the line to name
        cut = rnd.randrange(5, len(hand) - 2)
        text = hand[:cut]
        try:
            json.loads(text)
            continue
        except json.JSONDecodeError as exc:
            line = exc.lineno
        C.add(f"compensate_gen_model_truncated_{k:02d}", "compensate", "model JSON",
              ["prog.nc", "--model", "model.json", "-o", "out.nc"], {"prog.nc": program(), "model.json": text},
              [err("model.json", line, "JSON", "json", "expect", "parse", "truncated", "end")])
    plan = jdump({"rounds": 2, "axes": {"X": {"start": 0, "stop": 200, "count": 5}}, "tracker": [250, -1500, 150]})
    for k in range(3):
        cut = rnd.randrange(5, len(plan) - 2)
        try:
            json.loads(plan[:cut])
            continue
        except json.JSONDecodeError as exc:
            line = exc.lineno
        C.add(f"simulate_gen_plan_truncated_{k:02d}", "simulate", "plan JSON", ["--plan", "plan.json", "-o", "s.csv"],
              {"plan.json": plan[:cut]}, [err("plan.json", line, "JSON", "json", "expect", "parse", "truncated",
                                              "end")])
    header, rows = recording_x_only()
    def swapped(a, b):
        ia, ib = header.index(a), header.index(b)
        out = []
        for r in rows:
            r = r[:]
            r[ia], r[ib] = r[ib], r[ia]
            out.append(r)
        return rows_to_csv(header, out)
    for a, b, words in [("axis", "point", ["axis", "P"]), ("x", "point", ["x", "number", "P"]),
                        ("round", "point", ["round", "P"])]:
        C.add(f"identify_swapped_{a}_{b}", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
              {"rec.csv": swapped(a, b)}, [err("rec.csv", 2, *words)])
    # old Mac line ends (lone CR) in a CSV: read as lines; an error names the right line
    C.add("identify_lone_cr_csv", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
          {"rec.csv": rows_to_csv(header, rows, eol="\r")}, [ok({"kind": "model_json", "path": "model.json",
                                                                "axes": ["X"]})])
    bad = [r[:] for r in rows]
    bad[30][header.index("y")] = "nan"
    C.add("identify_lone_cr_csv_nan", "identify", "recording CSV", ["rec.csv", "-o", "model.json"],
          {"rec.csv": rows_to_csv(header, bad, eol="\r")}, [err("rec.csv", 32, "nan", "finite", "y")])
    # G-code: characters a controller would not read as numbers, and a very long comment line (passed through)
    for cid, word in [("fullwidth_digits", "X１０"), ("unicode_minus", "X−5"), ("arabic_digits", "Y٣")]:
        p = f"G90 G21\nG1 X0 Y0 Z0 F100\nG1 {word} Y10\nM30\n"
        C.add(f"compensate_word_{cid}", "compensate", "NC program",
              ["prog.nc", "--model", "model.json", "-o", "out.nc"], {"prog.nc": p, "model.json": hand},
              [err("prog.nc", 3, "number", "word", word[0], "character")])
    longp = program().replace("(a comment line between moves)", "(" + "LONG COMMENT " * 20000 + ")")
    C.add("compensate_very_long_comment", "compensate", "NC program", ["prog.nc", "--model", "model.json", "-o",
                                                                       "out.nc"],
          {"prog.nc": longp, "model.json": hand}, [ok(gcode_check())])
    nbs = (DATA / "nbs_table1_corrected.csv").read_text()
    huge = "\n".join(ln if not ln.startswith("3,") else "3,1e300,2.674304,2.674759,-3.141279"
                     for ln in nbs.splitlines()) + "\n"
    C.add("plate_huge_number", "plate", "plate CSV", ["pos.csv", "--json"], {"pos.csv": huge},
          [err("pos.csv", None), ok({"kind": "stdout_json", "keys": ["alpha", "beta", "gamma"]})])
    # option values: every numeric option refuses non-numbers and empty strings; nonsense infinities
    numeric = {"compensate": ["--tolerance", "--tool-length", "--precision", "--cone", "--iterations",
                              "--residual-every", "--max-correction"],
               "identify": ["--max-degree", "--outlier-k"], "simulate": ["--rounds", "--seed"],
               "plan": ["--monte-carlo", "--seed"], "diagnose": ["--level"], "plate": ["--level"]}
    inf_ok = {"--tolerance", "--max-correction", "--outlier-k"}   # infinity may mean "off" there
    files = {"prog.nc": program(), "model.json": hand, "rec.csv": rows_to_csv(header, rows),
             "pos.csv": nbs, "plan.json": jdump(SMALL_PLAN)}
    lead = {"compensate": ["prog.nc", "--model", "model.json", "-o", "out.nc"],
            "identify": ["rec.csv", "-o", "model.json"], "simulate": ["--plan", "plan.json", "-o", "s.csv"],
            "plan": ["--axes", "X"], "diagnose": ["rec.csv"], "plate": ["pos.csv"]}
    for cmd, opts in numeric.items():
        for opt in opts:
            for val in ["abc", "", "inf", "1e999"]:
                if val in ("inf", "1e999") and opt in inf_ok:
                    continue
                tag = {"abc": "text", "": "empty", "inf": "inf", "1e999": "overflow"}[val]
                need = {"compensate": ["prog.nc", "model.json"], "identify": ["rec.csv"], "simulate": ["plan.json"],
                        "plan": [], "diagnose": ["rec.csv"], "plate": ["pos.csv"]}[cmd]
                C.add(f"{cmd}_gen_opt_{opt[2:].replace('-', '_')}_{tag}", cmd, "option", lead[cmd] + [opt, val],
                      {f: files[f] for f in need}, [err(None, None, opt, option=True)])


def sa_export(rows, header, eol="\n", scale=1.0, bad=None):
    """A SpatialAnalyzer ASCII export (docs: Collection Group Target x y z) of recording rows; names encode
    axis, round, position, point and direction.  bad = (index, text) replaces one line's coordinates."""
    ix = {c: header.index(c) for c in ("axis", "round", "position", "point", "x", "y", "z", "direction")}
    out = ["// SA Version 2021.01.08", "// Working Frame: Machine::Machine Frame"]
    for k, r in enumerate(rows):
        d = "up" if r[ix["direction"]] == "1" else "dn"
        name = f"{r[ix['axis']]}_r{r[ix['round']]}_{r[ix['position']]}_{r[ix['point']]}_{d}_{k}"
        xyz = " ".join(f"{float(r[ix[c]]) / scale:.9f}" for c in "xyz")
        if bad and bad[0] == k:
            xyz = bad[1]
        out.append(f"DMU50 Run{r[ix['round']]} {name} {xyz}")
    return eol.join(out) + eol


def sa_mapping(rows, header, bad_round_at=None):
    """Mapping CSV target,axis,round,position,point,direction for sa_export's names; one round spelled 'one'."""
    ix = {c: header.index(c) for c in ("axis", "round", "position", "point", "direction")}
    out = ["target,axis,round,position,point,direction"]
    for k, r in enumerate(rows):
        d = "up" if r[ix["direction"]] == "1" else "dn"
        name = f"{r[ix['axis']]}_r{r[ix['round']]}_{r[ix['position']]}_{r[ix['point']]}_{d}_{k}"
        rnd = "one" if k == bad_round_at else r[ix["round"]]
        out.append(",".join([name, r[ix["axis"]], rnd, r[ix["position"]], r[ix["point"]], r[ix["direction"]]]))
    return "\n".join(out) + "\n"


SA_PATTERN = r"(?P<axis>[A-Z])_r(?P<round>\d+)_(?P<position>-?[\d.]+)_(?P<point>[A-Z]+)_(?P<direction>up|dn)_\d+"


def cases_iso230_and_import(C: Corpus):
    header, rows = recording_x_only()
    rec = rows_to_csv(header, rows)
    plan = jdump({"rounds": 2, "axes": {"X": {"start": 0, "stop": 200, "count": 5}}})
    sim = ["simulate", "--plan", "plan.json", "--model", "truth.json", "--no-noise", "-o", "rec.csv"]
    # noise-free X with E_XX = 2e-5 * X: the mean positional deviation at each target is E_XX(P) (um)
    C.add("iso230_2_planted_exx", "iso230-2", "recording CSV", ["rec.csv", "--axis", "X", "--json"],
          {"plan.json": plan, "truth.json": jdump(HAND_MODEL)},
          [ok({"kind": "iso_mean", "axis": "X", "exx": ORACLE["exx"]})], setup=[sim])
    C.add("iso230_2_report_dir", "iso230-2", "recording CSV", ["rec.csv", "-o", "rep"], {"rec.csv": rec},
          [ok({"kind": "png", "dir": "rep", "min": 1}, {"kind": "exists", "paths": ["rep/iso230-2_X.csv"]})])
    C.add("iso230_2_bom_german", "iso230-2", "recording CSV", ["rec.csv", "--json"],
          {"rec.csv": b"\xef\xbb\xbf" + rows_to_csv(header, [[c.replace(".", ",") for c in r] for r in rows],
                                                      sep=";").encode()},
          [ok({"kind": "stdout_json", "keys": ["axes"]}, say=[";", "semicolon", "decimal comma"])])
    bad = [r[:] for r in rows]
    bad[20][header.index("x")] = "nan"
    C.add("iso230_2_cell_nan", "iso230-2", "recording CSV", ["rec.csv"], {"rec.csv": rows_to_csv(header, bad)},
          [err("rec.csv", 22, "nan", "finite", "x")])
    for cid, argv, words in [("axis_unknown", ["--axis", "Q"], ["Q", "axis"]),
                             ("target_points_text", ["--target-points", "a,b"], ["--target-points", "number"]),
                             ("alpha_nan", ["--alpha", "nan", "--temperature-normalise"], ["--alpha", "finite"]),
                             ("normalise_without_alpha", ["--temperature-normalise"], ["--alpha"]),
                             ("point_unknown", ["--point", "ZZ"], ["ZZ", "point", "--point"]),
                             ("angle_unit_bad", ["--angle-unit", "grad"], ["--angle-unit", "grad"])]:
        C.add(f"iso230_2_opt_{cid}", "iso230-2", "option", ["rec.csv", *argv], {"rec.csv": rec},
              [err(None, None, *words, option=True), err("rec.csv", None, *words)])
    C.add("iso230_2_empty", "iso230-2", "recording CSV", ["rec.csv"], {"rec.csv": ""},
          [err("rec.csv", None, "empty", "no data", "header")])
    C.add("iso230_2_input_is_directory", "iso230-2", "path", ["rec.csv"], dirs=["rec.csv"],
          expect=[err("rec.csv", None, "directory")])
    C.add("iso230_2_output_onto_file", "iso230-2", "path", ["rec.csv", "-o", "rep"], {"rec.csv": rec, "rep": "x"},
          [err("rep", None, "directory", "exists", "file")])
    C.add("iso230_2_output_overwrites_input", "iso230-2", "overwrite", ["rep/iso230-2_X.csv", "-o", "rep"],
          {"rep/iso230-2_X.csv": rec}, [err("iso230-2_X.csv", None, "input", "overwrite", "same")])
    # import-sa: the export of a recording imports back to the same readings
    exp = sa_export(rows, header)
    rt = {"kind": "recording_equal", "path": "out.csv", "ref": "orig.csv"}
    base = ["export.txt", "--pattern", SA_PATTERN, "-o", "out.csv"]
    C.add("import_sa_round_trip", "import-sa", "SA export", base + ["--json"], {"export.txt": exp, "orig.csv": rec},
          [ok(rt, {"kind": "stdout_json", "keys": []})])
    C.add("import_sa_crlf_inches", "import-sa", "SA export", base + ["--units", "in"],
          {"export.txt": sa_export(rows, header, eol="\r\n", scale=25.4), "orig.csv": rec}, [ok(rt)])
    C.add("import_sa_bom_cp1252_comment", "import-sa", "SA export", base,
          {"export.txt": b"\xef\xbb\xbf// Messung 20\xb0C\n".replace(b"\xb0", "°".encode("cp1252"))
           + exp.encode(), "orig.csv": rec}, [ok(rt), err("export.txt", 1, "decode", "encoding", "BOM")])
    for cid, badline, words in [("text", "1.0 abc 3.0", ["number", "abc"]), ("nan", "1.0 nan 3.0", ["finite", "nan"]),
                                ("two_numbers", "1.0 2.0", ["x y z", "number", "field", "column"])]:
        C.add(f"import_sa_line_{cid}", "import-sa", "SA export", base,
              {"export.txt": sa_export(rows, header, bad=(7, badline))}, [err("export.txt", 10, *words)])
    C.add("import_sa_unmatched", "import-sa", "SA export", base,
          {"export.txt": exp + "DMU50 Run1 Nest_check 0 0 0\n"},
          [err("export.txt", len(rows) + 3, "match", "Nest_check")])
    C.add("import_sa_pattern_invalid", "import-sa", "option", ["export.txt", "--pattern", "(?P<axis", "-o", "o.csv"],
          {"export.txt": exp}, [err(None, None, "--pattern", "regular expression", "regex", option=True)])
    C.add("import_sa_pattern_no_groups", "import-sa", "option", ["export.txt", "--pattern", "X_.*", "-o", "o.csv"],
          {"export.txt": exp}, [err(None, None, "--pattern", "group", "axis", option=True)])
    C.add("import_sa_mapping_missing", "import-sa", "path", ["export.txt", "--mapping", "map.csv", "-o", "o.csv"],
          {"export.txt": exp}, [err("map.csv", None, "no such", "not found", "does not exist", "missing")])
    C.add("import_sa_mapping_bad_row", "import-sa", "recording CSV",
          ["export.txt", "--mapping", "map.csv", "-o", "o.csv"],
          {"export.txt": exp, "map.csv": sa_mapping(rows, header, bad_round_at=3)},
          [err("map.csv", 5, "round", "one", "number", "integer")])
    C.add("import_sa_mapping_valid", "import-sa", "SA export", ["export.txt", "--mapping", "map.csv", "-o", "out.csv"],
          {"export.txt": exp, "map.csv": sa_mapping(rows, header), "orig.csv": rec}, [ok(rt)])
    C.add("import_sa_empty", "import-sa", "SA export", base, {"export.txt": ""},
          [err("export.txt", None, "empty", "no ")])
    C.add("import_sa_binary", "import-sa", "SA export", base, {"export.txt": bytes(range(256)) * 8},
          [err("export.txt", None, "binary", "decode", "encoding", "NUL", "number")])
    C.add("import_sa_output_equals_input", "import-sa", "overwrite",
          ["export.txt", "--pattern", SA_PATTERN, "-o", "export.txt"], {"export.txt": exp},
          [err("export.txt", None, "input", "overwrite", "same")])
    C.add("import_sa_output_is_directory", "import-sa", "path", base, {"export.txt": exp}, dirs=["out.csv"],
          expect=[err("out.csv", None, "directory")])


def cases_export(C: Corpus):
    """mtcal export: the hand model's E_XX in LinuxCNC tables (docs: type 1 trims = -error, type 0 = nominal +
    error), the other formats written and finite; bad models, options and paths refused."""
    hand = jdump(HAND_MODEL)
    for t in ("0", "1"):
        C.add(f"export_linuxcnc_type{t}", "export", "model JSON",
              ["model.json", "--format", "linuxcnc", "-o", "lc", "--comp-file-type", t, "--json"], {"model.json": hand},
              [ok({"kind": "linuxcnc_comp", "dir": "lc", "axis": "X", "type": int(t), "exx": ORACLE["exx"]},
                  {"kind": "stdout_json", "keys": []})])
    # exporting again into the folder a previous export wrote (the usual re-run) works and rewrites the tables
    C.add("export_linuxcnc_rerun_same_folder", "export", "path",
          ["model.json", "--format", "linuxcnc", "-o", "lc", "--comp-file-type", "1"], {"model.json": hand},
          [ok({"kind": "linuxcnc_comp", "dir": "lc", "axis": "X", "type": 1, "exx": ORACLE["exx"]})],
          setup=[["export", "model.json", "--format", "linuxcnc", "-o", "lc", "--comp-file-type", "0"]],
          rewrites=["lc/"])
    for fmt, out in [("siemens", "COMP.MPF"), ("heidenhain", "tnc"), ("tf5280", "vol.csv"), ("etalon", "etalon.txt")]:
        C.add(f"export_{fmt}_valid", "export", "model JSON", ["model.json", "--format", fmt, "-o", out],
              {"model.json": hand}, [ok({"kind": "finite_text", "path": out})])
    C.add("export_demo_truth_siemens", "export", "model JSON", ["truth.json", "--format", "siemens", "-o", "C.MPF"],
          {"truth.json": (DATA / "demo_truth.json").read_bytes()}, [ok({"kind": "finite_text", "path": "C.MPF"})])
    lc = ["model.json", "--format", "linuxcnc", "-o", "lc"]
    wanted = {"shape_list", "shape_constants_list", "shape_functions_string", "field_true", "function_over_wrong_axis",
              "field_nan", "truncated_json", "shape_poly_no_coefficients"}
    for cid, text, words in shape_models():
        if cid in wanted:
            C.add(f"export_model_{cid}", "export", "model JSON", lc, {"model.json": text},
                  [err("model.json", None, *words)])
    for cid, argv, words in [("step_nan", ["--step", "nan"], ["--step"]), ("step_zero", ["--step", "0"], ["--step"]),
                             ("step_neg", ["--step", "-5"], ["--step"]),
                             ("max_points_zero", ["--max-points", "0"], ["--max-points"]),
                             ("max_points_one", ["--max-points", "1"], ["--max-points", "point"]),
                             ("format_bogus", ["--format", "fanuc"], ["--format", "fanuc"]),
                             ("comp_file_type_2", ["--comp-file-type", "2"], ["--comp-file-type"]),
                             ("require_unknown", ["--require", "E_QQ"], ["E_QQ", "--require", "unknown"])]:
        C.add(f"export_opt_{cid}", "export", "option", ["model.json", "-o", "lc", *argv]
              + (["--format", "linuxcnc"] if cid != "format_bogus" else []), {"model.json": hand},
              [err(None, None, *words, option=True)])
    C.add("export_require_not_held", "export", "option", lc + ["--require", "E_C0Y"], {"model.json": hand},
          [{**err(None, None, "E_C0Y", "not held", "cannot", option=True),
            "checks": [{"kind": "absent", "path": "lc"}]}])
    for cid, text, words in [("missing", None, ["no such", "not found", "does not exist", "missing"]),
                             ("list", "[1, 2]", ["object", "dict", "mapping", "list", "effects", "diagnos"]),
                             ("truncated", '{"effects": [', ["JSON", "json", "expect", "parse"])]:
        files = {"model.json": hand, **({"diag.json": text} if text is not None else {})}
        C.add(f"export_diagnosis_{cid}", "export", "model JSON", lc + ["--diagnosis", "diag.json"], files,
              [err("diag.json", None, *words)])
    C.add("export_output_equals_model", "export", "overwrite",
          ["model.json", "--format", "siemens", "-o", "model.json"], {"model.json": hand},
          [err("model.json", None, "input", "overwrite", "same")])
    C.add("export_output_dir_holds_model", "export", "overwrite",
          ["lc/joint0_X.comp", "--format", "linuxcnc", "-o", "lc"], {"lc/joint0_X.comp": hand},
          [err("joint0_X.comp", None, "input", "overwrite", "same")])
    C.add("export_output_equals_diagnosis", "export", "overwrite",
          ["model.json", "--format", "tf5280", "-o", "diag.json", "--diagnosis", "diag.json"],
          {"model.json": hand, "diag.json": jdump({"effects": []})},
          [err("diag.json", None, "input", "overwrite", "same")])
    C.add("export_file_format_onto_directory", "export", "path", ["model.json", "--format", "siemens", "-o", "d"],
          {"model.json": hand}, dirs=["d"], expect=[err("d", None, "directory")])
    C.add("export_folder_format_onto_file", "export", "path", lc, {"model.json": hand, "lc": "a file"},
          [err("lc", None, "directory", "exists", "file")])
    C.add("export_output_parent_is_file", "export", "path", ["model.json", "--format", "tf5280", "-o", "f/v.csv"],
          {"model.json": hand, "f": "a file"}, [err("f", None, "not a directory", "directory")])
    C.add("export_model_is_directory", "export", "path", lc, dirs=["model.json"],
          expect=[err("model.json", None, "directory")])

def cases_export_guard(C: Corpus):
    """Issue 21: what reaches a controller passes the plausibility guard; each refusal says what the file is, which
    value and which limit, and writes nothing (the harness checks every refused case for new files)."""
    hand = HAND_MODEL
    formats = [("linuxcnc", "lc"), ("siemens", "C.INI"), ("heidenhain", "tnc"), ("tf5280", "v.csv"),
               ("etalon", "e.txt")]

    def variant(**kw):
        m = json.loads(jdump(hand))
        m.update(kw)
        return jdump(m)
    exx = hand["functions"]["E_XX"]
    um = variant(functions={"E_XX": {**exx, "values": [v * 1000 for v in exx["values"]]}})
    big = variant(constants={"E_C0Y": 1e300})
    for fmt, out in formats:  # a model in um read as mm, and 1e300: refused in every format
        C.add(f"export_guard_um_as_mm_{fmt}", "export", "model JSON", ["model.json", "--format", fmt, "-o", out],
              {"model.json": um}, [err("model.json", None, "plausibility bound")])
        C.add(f"export_guard_1e300_{fmt}", "export", "model JSON", ["model.json", "--format", fmt, "-o", out],
              {"model.json": big}, [err("model.json", None, "plausibility bound")])
    C.add("export_guard_um_as_mm_forced", "export", "option",
          ["model.json", "--format", "linuxcnc", "-o", "lc", "--force"], {"model.json": um}, [ok(say=["FORCED"])])
    b270 = variant(functions={"E_CB": {"axis": "B", "positions": [0, 90, 180, 270], "values": [0, 1e-5, 2e-5, 3e-5]}})
    c400 = variant(functions={"E_CC": {"axis": "C", "positions": [0, 200, 400], "values": [0, 1e-5, 2e-5]}})
    for cid, text, words in [("b_over_travel", b270, ["travel", "[0, 180]"]), ("c_over_a_turn", c400, ["turn"]),
                             ("constants_only", jdump({"machine": "dmu50", "constants": {"E_C0Y": 1e-5}}),
                              ["nothing format"]),
                             ("empty_model", jdump({"machine": "dmu50"}), ["empty model", "nothing format"])]:
        C.add(f"export_guard_{cid}", "export", "model JSON", ["model.json", "--format", "siemens", "-o", "C.INI"],
              {"model.json": text}, [err("model.json", None, *words)])
    answers = [("diagnose", {"base_sigma": 0.01, "effects": [], "located": []}),
               ("plate", {"alpha": 1e-6, "beta": 0.0, "gamma": 0.0}),
               ("identify", {"axes": {}, "squareness": {}, "weighted": False}),
               ("compensate", {"program": "p.nc", "residual": {}})]
    for cmd, answer in answers:  # another command's JSON given as the model: named as such
        for fmt, out in (("siemens", "C.INI"), ("linuxcnc", "lc")):
            C.add(f"export_guard_{cmd}_answer_{fmt}", "export", "model JSON",
                  ["model.json", "--format", fmt, "-o", out], {"model.json": jdump(answer)},
                  [err("model.json", None, f"answer of `mtcal {cmd}")])
    diag = {"machine": "dmu50", "recording": "other.csv", "base_sigma": 0.01,
            "effects": [{"name": "backlash", "axis": "X", "significant": True, "estimate": 0.004, "unit": "mm"}]}
    ident = variant(identified_from="campaign.csv")
    C.add("export_guard_diagnosis_of_another_recording", "export", "model JSON",
          ["model.json", "--format", "linuxcnc", "-o", "lc", "--diagnosis", "diag.json"],
          {"model.json": ident, "diag.json": jdump(diag)}, [err("diag.json", None, "other.csv")])
    C.add("export_guard_diagnosis_of_another_machine", "export", "model JSON",
          ["model.json", "--format", "linuxcnc", "-o", "lc", "--diagnosis", "diag.json"],
          {"model.json": jdump(hand), "diag.json": jdump({**diag, "machine": "xyzac", "recording": "x"})},
          [err("diag.json", None, "machine xyzac")])
    C.add("export_guard_backlash_unit_bogus", "export", "model JSON",
          ["model.json", "--format", "linuxcnc", "-o", "lc", "--diagnosis", "diag.json"],
          {"model.json": jdump(hand), "diag.json": jdump({**diag, "recording": "x", "effects": [
              {**diag["effects"][0], "unit": "furlong"}]})}, [err("diag.json", None, "furlong")])
    for cid, argv, words in [("machine_other", ["--machine", "xyzac"], ["machine dmu50, not xyzac"]),
                             ("machine_not_a_machine", ["--machine", "plate"], ["unknown machine"]),
                             ("control_on_linuxcnc", ["--control", "828d"], ["siemens option"]),
                             ("linear_units_on_siemens", ["--linear-units", "inch", "--format", "siemens"],
                              ["linuxcnc option"])]:
        fmt = [] if "--format" in argv else ["--format", "linuxcnc"]
        C.add(f"export_guard_{cid}", "export", "option", ["model.json", "-o", "out", *fmt, *argv],
              {"model.json": jdump(hand)}, [err(None, None, *words, option=True), err("model.json", None, *words)])
    C.add("export_guard_828d_points", "export", "option",
          ["model.json", "--format", "siemens", "-o", "C.INI", "--control", "828d", "--max-points", "256"],
          {"model.json": jdump(hand)}, [err(None, None, "200 interpolation points", option=True)])
    C.add("export_guard_heidenhain_too_wide", "export", "model JSON",
          ["model.json", "--format", "heidenhain", "-o", "tnc", "--force"],
          {"model.json": variant(functions={"E_XX": {**exx, "values": [123456789.0] * len(exx["values"])}})},
          [err("model.json", None, "TNC column")])
    C.add("export_guard_reexport_removes_stale", "export", "path",
          ["x.json", "--format", "linuxcnc", "-o", "lc"],
          {"model.json": variant(functions={"E_XX": exx, "E_YY": {**exx, "axis": "Y"}}),
           "x.json": variant(constants={})},
          [ok({"kind": "absent", "path": "lc/joint1_Y.comp"}, say=["earlier export"])],
          setup=[["export", "model.json", "--format", "linuxcnc", "-o", "lc"]], rewrites=["lc/"])


def cases_signals(C: Corpus):
    big = ["%", "G90 G21", "G0 X0 Y0 Z50", "G1 Z5 F1000"]
    for k in range(150_000):
        big.append(f"X{(k % 400) - 200:.3f} Y{((k * 7) % 300) - 150:.3f}")
    big += ["M30", "%"]
    files = {"prog.nc": "\n".join(big) + "\n", "model.json": jdump(HAND_MODEL)}
    argv = ["prog.nc", "--model", "model.json", "-o", "out.nc"]
    C.add("signal_sigint_compensate", "compensate", "signal", argv, files,
          [{"exit": 130, "quiet": True, "checks": [{"kind": "absent", "path": "out.nc"}]}],
          signal={"sig": "SIGINT", "when": "temp"})
    C.add("signal_sigterm_compensate", "compensate", "signal", argv, files,
          [{"exit": "signal", "quiet": True, "checks": [{"kind": "absent", "path": "out.nc"}]}],
          signal={"sig": "SIGTERM", "when": "temp"})
    C.add("signal_stdout_closed", "plan", "signal", ["--axes", "X", "--json"], {},
          [{"exit": "any", "quiet": True, "checks": []}], signal={"sig": "EPIPE", "when": "epipe"},
          note="stdout is a pipe whose reader has gone (mtcal ... | head): no traceback")
    C.add("signal_sigint_plan", "plan", "signal", ["--monte-carlo", "2000000", "--axes", "C"], {},
          [{"exit": 130, "quiet": True, "checks": []}], signal={"sig": "SIGINT", "when": "delay", "delay": 2.0})


def b02_readings(header="target_mm,run,direction,measured_mm", scale=1.0, sep=",", extra=None):
    """The public b02 axis' readings (tests/data/iso230_2_b02_x.csv) in another spelling: header, length scale,
    separator; ``extra`` (column name, value) appended to every row."""
    src = Path(__file__).resolve().parents[1] / "data" / "iso230_2_b02_x.csv"
    rows = [ln.split(",") for ln in src.read_text().splitlines() if ln and not ln.startswith("#")][1:]
    out = [(header + (f",{extra[0]}" if extra else "")).replace(",", sep)]
    for t, r, d, m in rows:
        vals = [f"{float(t) * scale:.9g}", r, d, f"{float(m) * scale:.12g}"] + ([str(extra[1])] if extra else [])
        out.append(sep.join(vals))
    return "\n".join(out) + "\n"


def cases_issue20(C: Corpus):
    """Issue 20: ISO 230-2 readings, careless SpatialAnalyzer exports, plates, subprogram calls, names that are
    no machine: each refusal names file, line and problem and writes nothing; each valid input is read and said."""
    ok_json = ok({"kind": "stdout_json", "keys": ["axes"]})
    iso = [
        ("readings_b02", b02_readings(), [], [ok_json]),
        ("readings_inch", b02_readings("target_in,run,direction,measured_in", 1 / 25.4), [], [ok_json]),
        ("readings_unit_option", b02_readings("target,run,direction,measured"), ["--unit", "mm"], [ok_json]),
        ("readings_unit_undeclared", b02_readings("target,run,direction,measured"), [],
         [err("r.csv", 1, "not declared")]),
        ("readings_semicolon", b02_readings(sep=";"), [], [ok({"kind": "stdout_json", "keys": ["axes"]}, say=[";"])]),
        ("readings_tab", b02_readings(sep="\t"), [], [ok({"kind": "stdout_json", "keys": ["axes"]}, say=["tab"])]),
        ("readings_utf16", b02_readings().encode("utf-16"), [], [ok(say=["UTF-16"])]),
        ("readings_temperature_2000", b02_readings(extra=("material_temperature_c", 2000)), [],
         [err("r.csv", 2, "degC", "outside")]),
        ("readings_duplicate_column", b02_readings("target_mm,run,direction,measured_mm,measured_mm"), [],
         [err("r.csv", 1, "twice")]),
        ("readings_measured_and_deviation", b02_readings(extra=("deviation_um", 1)), [],
         [err("r.csv", 2, "disagree")]),  # issue 54: both read and cross-checked (1 um against -49.2 um)
        ("readings_mixed_units", b02_readings("target_mm,run,direction,measured_deg"), [], [err("r.csv", 1, "mix")]),
        ("readings_inf", b02_readings().replace("-20,1,up,-20.0492258741", "-20,1,up,inf", 1), [],
         [err("r.csv", 2, "finite")]),
        ("readings_bad_direction", b02_readings().replace(",up,", ",sideways,", 1), [], [err("r.csv", 2, "up/down")]),
        ("readings_run_not_whole", b02_readings().replace("-20,1,up", "-20,1.5,up", 1), [], [err("r.csv", 2, "whole")]),
        ("readings_read_twice", b02_readings() + b02_readings().splitlines()[1] + "\n", [],
         [err("r.csv", 92, "twice")]),
        ("readings_alpha_without_temperature", b02_readings(), ["--alpha", "11.5e-6", "--temperature-normalise"],
         [err("r.csv", None, "material_temperature_c")]),
        ("readings_negative_target_points", b02_readings(), ["--target-points", "-10,0,10"], [ok_json]),
    ]
    for cid, text, argv, expect in iso:
        C.add(f"iso230_2_{cid}", "iso230-2", "ISO 230-2 readings", ["r.csv", "--json", *argv], {"r.csv": text}, expect)
    C.add("iso230_2_later_output_is_a_folder", "iso230-2", "path", ["r.csv", "--axis", "X", "-o", "rep"],
          {"r.csv": b02_readings()}, [err("iso230-2_X.png", None, "directory")], dirs=["rep/iso230-2_X.png"])
    header, rows = recording_x_only()
    C.add("iso230_2_unit_on_a_recording", "iso230-2", "option", ["rec.csv", "--unit", "in"],
          {"rec.csv": rows_to_csv(header, rows)}, [err("rec.csv", None, "--unit")])
    # SpatialAnalyzer
    line = "DMU50 Run1 X_r1_0_P_up_0"
    base = ["export.txt", "--pattern", SA_PATTERN, "-o", "out.csv"]
    for cid, text, argv, words, ln in [
        ("tolerance_or_time", f"{line} 70.0 0.0 10.0 0.0025\n", [], ["tolerance"], 1),
        ("duplicate_x_column", "Collection,Group,Target,X,Y,Z,X\nDMU50,Run1,X_r1_0_P_up_0,1,2,3,4\n", [],
         ["ambiguous"], 1),
        ("units_m_on_mm", f"{line} 70.0 0.0 10.0\nDMU50 Run1 X_r1_50_P_up_1 120.0 0.0 10.0\n", ["--units", "m"],
         ["really in m"], 1),
        ("overflow_to_inf", f"{line} 1e308 0.0 10.0\n", ["--units", "m"], ["inf"], 1)]:
        C.add(f"import_sa_{cid}", "import-sa", "SA export", base + argv, {"export.txt": text},
              [err("export.txt", ln, *words)])
    C.add("import_sa_pattern_group_absent", "import-sa", "SA export",
          ["export.txt", "--pattern", r"(?P<axis>Q)?X_r(?P<round>\d+)_(?P<position>[\d.]+)_(?P<point>[A-Z]+)_up_0",
           "-o", "out.csv"], {"export.txt": f"{line} 70.0 0.0 10.0\n"}, [err("export.txt", 1, "took no part")])
    C.add("import_sa_mapping_duplicate_column", "import-sa", "mapping", ["export.txt", "--mapping", "map.csv", "-o",
          "out.csv"], {"export.txt": f"{line} 70.0 0.0 10.0\n",
                       "map.csv": "target,axis,axis,round,position,point\nX_r1_0_P_up_0,X,X,1,0,P\n"},
          [err("map.csv", 1, "twice")])
    # plates
    ccw = plate_csv(turn_deg=-90.0)
    C.add("plate_counter_clockwise", "plate", "plate CSV", ["pos.csv", "--json"], {"pos.csv": ccw},
          [ok({"kind": "stdout_json", "keys": ["notes"]}, say=["counter-clockwise"])])
    C.add("plate_turn_45", "plate", "plate CSV", ["pos.csv", "--json"], {"pos.csv": plate_csv(turn_deg=45.0)},
          [ok({"kind": "stdout_json", "keys": ["alpha"]})])
    lines = plate_csv().splitlines()
    big = "\n".join(lines[:3] + [lines[3].split(",")[0] + ",1e200,5,5,1e200"] + lines[4:]) + "\n"
    C.add("plate_coordinate_1e200", "plate", "plate CSV", ["pos.csv"], {"pos.csv": big}, [err("pos.csv", 4, "beyond")])
    f = lines[5].split(",")
    row_mm = ",".join([f[0]] + [f"{float(v) * 25.4:.6f}" for v in f[1:]])
    C.add("plate_row_in_mm", "plate", "plate CSV", ["pos.csv"],
          {"pos.csv": "\n".join(lines[:5] + [row_mm] + lines[6:]) + "\n"},
          [err("pos.csv", 6, "another unit", "mixed units")])
    # programs
    prog = "G90 G21\nG0 X10 Y10 Z10 B0 C0\n{call}\nG1 X20 Y10 Z10 B0 C0 F100\n"
    argv = ["prog.nc", "--model", "model.json", "-o", "out.nc"]
    for cid, call, extra, expect in [
            ("m98", "M98 P1000", [], [err("prog.nc", 3, "subprogram")]),
            ("m99", "M99", [], [err("prog.nc", 3, "subprogram")]),
            ("call_pgm", "CALL PGM SUB", [], [err("prog.nc", 3, "subprogram")]),
            ("m98_allowed", "M98 P1000", ["--allow-subprograms"], [ok(say=["NOT compensated"])]),
            ("g65", "G65 P9010 A1", [], [err("prog.nc", 3, "macro")]),
            ("g65_allowed", "G65 P9010 A1", ["--allow-subprograms"], [err("prog.nc", 3, "macro")]),
            ("g53_then_feed", "G53 X10 Y10 Z10 B0 C0\nG1 X30 F100", [], [err("prog.nc", 4, "G53")])]:
        C.add(f"compensate_subprogram_{cid}", "compensate", "NC program", argv + extra,
              {"prog.nc": prog.format(call=call), "model.json": jdump(HAND_MODEL)}, expect)
    # names that are no machine
    rec = rows_to_csv(header, rows)
    for cmd, args in [("identify", ["rec.csv"]), ("plan", []), ("simulate", ["-o", "sim.csv"]),
                      ("diagnose", ["rec.csv"]), ("iso230-2", ["rec.csv"]), ("demo", ["--out", "d"])]:
        for name in ("plate", "threepoint"):
            C.add(f"machine_{name}_{cmd}", cmd, "option", [*args, "--machine", name], {"rec.csv": rec},
                  [err(None, None, "unknown machine")])


def ballbar(rows=None, head="angle_deg,deviation_mm,direction", header=("plane: XY", "radius_mm: 100")):
    """A measured circular test (docs/guide/checks.md): a 2 um squareness oval both ways, 5 deg steps."""
    import math
    if rows is None:
        rows = [[f"{a:g}", f"{-0.002 * math.sin(math.radians(2 * a)) / 2:.7f}", d]
                for d in ("1", "-1") for a in range(0, 360, 5)]
    return "".join(f"# {h}\n" for h in header) + rows_to_csv(head.split(","), rows)


def cases_checks(C: Corpus):
    """mtcal check predict | evaluate and mtcal verify (issue 25)."""
    model = jdump(HAND_MODEL)
    pj = {"kind": "stdout_json", "keys": ["model", "tests"]}
    C.add("check_predict_valid", "check", "model JSON",
          ["predict", "--model", "m.json", "--circular", "XY,100", "--rtest", "C,100,0,0", "--json"],
          {"m.json": model}, [ok(pj)])
    C.add("check_predict_plot", "check", "model JSON", ["predict", "--model", "m.json", "--circular", "YZ,50,0,0,0",
                                                         "--plot", "p.png"], {"m.json": model},
          [ok({"kind": "png", "file": "p.png"})])
    for cid, arg, word in [("plane", "XB,100", "plane"), ("radius", "XY,-5", "radius"), ("words", "XY,abc", "number"),
                           ("centre", "XY,100,1,2", "centre")]:
        C.add(f"check_predict_bad_{cid}", "check", "option", ["predict", "--model", "m.json", "--circular", arg],
              {"m.json": model}, [err(None, None, word, "XY", "mm")])
    C.add("check_predict_rtest_linear", "check", "option", ["predict", "--model", "m.json", "--rtest", "X"],
          {"m.json": model}, [err(None, None, "rotary")])
    C.add("check_predict_nothing", "check", "option", ["predict", "--model", "m.json"], {"m.json": model},
          [err(None, None, "--circular", "--rtest")])
    C.add("check_predict_model_missing", "check", "path", ["predict", "--model", "m.json", "--circular", "XY,100"],
          expect=[err("m.json", None, "no such file", "not found", "missing")])
    ej = {"kind": "stdout_json", "keys": ["kind", "measured", "predicted", "residual", "agrees", "findings"]}
    C.add("check_evaluate_valid", "check", "check CSV", ["evaluate", "t.csv", "--model", "m.json", "--json"],
          {"t.csv": ballbar(), "m.json": model}, [ok(ej)])
    rows = [["0", "0.001", "1"], ["5", "x", "1"], ["10", "0", "1"], ["15", "0", "1"]]
    C.add("check_evaluate_bad_cell", "check", "check CSV", ["evaluate", "t.csv", "--model", "m.json"],
          {"t.csv": ballbar(rows), "m.json": model}, [err("t.csv", 5, "deviation_mm", "number")])
    rows = [["0", "0.001", "2"], ["5", "0", "1"], ["10", "0", "1"]]
    C.add("check_evaluate_bad_direction", "check", "check CSV", ["evaluate", "t.csv", "--model", "m.json"],
          {"t.csv": ballbar(rows), "m.json": model}, [err("t.csv", None, "direction")])
    C.add("check_evaluate_no_radius", "check", "check CSV", ["evaluate", "t.csv", "--model", "m.json"],
          {"t.csv": ballbar(header=("plane: XY",)), "m.json": model}, [err("t.csv", None, "radius")])
    C.add("check_evaluate_columns", "check", "check CSV", ["evaluate", "t.csv", "--model", "m.json"],
          {"t.csv": ballbar(head="a,b,c"), "m.json": model}, [err("t.csv", None, "columns")])
    C.add("check_evaluate_empty", "check", "check CSV", ["evaluate", "t.csv", "--model", "m.json"],
          {"t.csv": "", "m.json": model}, [err("t.csv", None, "no data", "empty")])
    C.add("check_evaluate_no_file", "check", "option", ["evaluate", "--model", "m.json"], {"m.json": model},
          [err(None, None, "TEST.csv")])
    C.add("check_plot_overwrites_input", "check", "overwrite", ["evaluate", "t.csv", "--model", "m.json", "--plot",
                                                                "t.csv"], {"t.csv": ballbar(), "m.json": model},
          [err("t.csv", None, "input", "overwrite", "same")])
    header, rows = recording_x_only()
    vj = {"kind": "stdout_json", "keys": ["passed", "errors", "not_covered"]}
    C.add("verify_recording", "verify", "recording CSV", ["rec.csv", "--model", "m.json", "--json"],
          {"rec.csv": rows_to_csv(header, rows), "m.json": model}, [ok(vj)])
    C.add("verify_check_file", "verify", "check CSV", ["t.csv", "--model", "m.json", "--json"],
          {"t.csv": ballbar(), "m.json": model}, [ok({"kind": "stdout_json", "keys": ["passed", "check"]})])
    C.add("verify_model_missing", "verify", "path", ["rec.csv", "--model", "m.json"],
          {"rec.csv": rows_to_csv(header, rows)}, [err("m.json", None, "no such file", "not found", "missing")])


def cases_uncertainty(C: Corpus):
    """mtcal uncertainty (issue 26): a valid run in this process, bad options, outputs onto the input."""
    header, rows = recording_x_only()
    rec = rows_to_csv(header, rows)
    uj = {"kind": "stdout_json", "keys": ["trials", "seed", "errors", "constants", "volumetric"]}
    C.add("uncertainty_valid", "uncertainty", "recording CSV",
          ["rec.csv", "--trials", "2", "--workers", "0", "--tracker=250,-1500,150", "--json"], {"rec.csv": rec},
          [ok(uj)])
    for cid, argv, word in [("trials_one", ["--trials", "1"], "--trials"),
                            ("trials_word", ["--trials", "x"], "--trials"),
                            ("p_high", ["--p", "1.5"], "--p"), ("workers_neg", ["--workers", "-1"], "--workers"),
                            ("centring_nan", ["--centring-um", "nan"], "--centring-um")]:
        C.add(f"uncertainty_opt_{cid}", "uncertainty", "option", ["rec.csv", *argv], {"rec.csv": rec},
              [err(None, None, word, option=True)])
    C.add("uncertainty_store_onto_input", "uncertainty", "overwrite",
          ["rec.csv", "--store", "rec.csv", "--workers", "0", "--tracker=250,-1500,150"], {"rec.csv": rec},
          [err("rec.csv", None, "input", "overwrite", "same")])
    C.add("uncertainty_no_file", "uncertainty", "path", ["rec.csv"],
          expect=[err("rec.csv", None, "no such file", "not found", "missing")])



# ------------------------------------------------------------------- issue 35: inputs as the standard means them

PERFECT_MODEL = {"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": {}, "functions": {}}


def ballbar_setup(c=(0.0, 0.0), radius=100.0, step=2.0, dirs=(1, -1), squareness=0.0, scale=1.0, header=None,
                  head="angle_deg,deviation_mm,direction", extra=0.0, plane="XY"):
    """A double ballbar on a perfect machine (plus a squareness oval -R E sin cos, design contract's sign) with the
    table ball at ``c`` (mm along the plane's two axes) off the circle's centre: deltaR = |R u - c| - R exactly
    (plain geometry; ISO 230-4's set-up offset leaves e^2 sin^2 / 2R beyond its first-order term).  ``scale``
    multiplies the written deviations (1000: um written under deviation_mm); each direction in its order of
    travel."""
    rows = []
    n = int(round(360 / step))
    for d in dirs:
        ks = range(n) if d > 0 else range(n - 1, -1, -1)
        for k in ks:
            a = k * step
            t = math.radians(a)
            L = math.hypot(radius * math.cos(t) - c[0], radius * math.sin(t) - c[1])
            dr = L - radius - radius * squareness * math.sin(t) * math.cos(t) + extra
            rows.append([f"{a:g}", f"{dr * scale:.8f}", str(d)])
    if "direction" not in head:
        rows = [r[:2] for r in rows]
    hdr = header if header is not None else (f"plane: {plane}", f"radius_mm: {radius:g}")
    return "".join(f"# {h}\n" for h in hdr) + rows_to_csv(head.split(","), rows)


def slipped_recording(slip):
    """Rounds 1-2 of X and C of the demo campaign with one unit or frame slip (issue 35)."""
    header, rows = base_recording()
    ix, iy, iz, ip, ia = (header.index(c) for c in ("x", "y", "z", "position", "axis"))
    out = []
    for r in rows:
        r = r[:]
        if slip == "readings_inch":
            for i in (ix, iy, iz):
                r[i] = f"{float(r[i]) / 25.4:.6f}"
        elif slip == "readings_metres":
            for i in (ix, iy, iz):
                r[i] = f"{float(r[i]) / 1000:.9f}"
        elif slip == "positions_inch" and r[ia] == "X":
            r[ip] = f"{float(r[ip]) / 25.4:.6f}"
        elif slip == "radians" and r[ia] == "C":
            r[ip] = f"{math.radians(float(r[ip])):.8f}"
        elif slip == "xy_swapped":
            r[ix], r[iy] = r[iy], r[ix]
        elif slip == "xz_swapped":
            r[ix], r[iz] = r[iz], r[ix]
        elif slip == "identical":
            r[ix], r[iy], r[iz] = rows[0][ix], rows[0][iy], rows[0][iz]
        elif slip == "identical_c" and r[ia] == "C":
            first = next(x for x in rows if x[ia] == "C")
            r[ix], r[iy], r[iz] = first[ix], first[iy], first[iz]
        out.append(r)
    return rows_to_csv(header, out)


SLIP_WORDS = {"readings_inch": ["inch"], "readings_metres": ["metres"], "positions_inch": ["inch"],
              "radians": ["radians"], "xy_swapped": ["x and y columns are swapped"],
              "xz_swapped": ["x and z columns are swapped"], "identical": ["same point"],
              "identical_c": ["same point"]}


def cases_issue35(C: Corpus):
    """Issue 35: ballbar set-up offsets read as set-up, malformed check files refused, verify's options checked,
    plan --floor outside the work volume, unit and frame slips refused before every estimator path."""
    perfect = jdump(PERFECT_MODEL)
    chk = lambda **kw: {"kind": "check_json", **kw}  # noqa: E731
    # A. set-up offsets of 0.1 to 5 mm on a perfect machine: set-up, stated with its size, no machine error
    for k, (c, radius, plane) in enumerate([((0.1, 0.0), 100.0, "XY"), ((0.0, -0.3), 100.0, "XY"),
                                            ((0.5, 0.5), 150.0, "XY"), ((1.0, 0.0), 150.0, "XY"),
                                            ((-1.5, 2.0), 150.0, "YZ"), ((3.0, -4.0), 100.0, "ZX"),
                                            ((0.0, 5.0), 150.0, "XY"), ((-5.0, 0.0), 100.0, "YZ"),
                                            ((2.0, 2.0), 50.0, "XY"), ((0.2, -0.1), 150.0, "ZX")]):
        C.add(f"check35_setup_offset_{k:02d}", "check", "check CSV", ["evaluate", "t.csv", "--model", "m.json",
                                                                      "--json"],
              {"t.csv": ballbar_setup(c, radius, plane=plane), "m.json": perfect},
              [ok(chk(agrees=True, findings=[], offset=math.hypot(*c), G_max_mm=2e-7))])
    for k, c in enumerate([(1.0, 0.0), (-2.5, 3.0)]):  # a squareness of 20 urad read through the offset
        C.add(f"check35_setup_offset_squareness_{k}", "check", "check CSV",
              ["evaluate", "t.csv", "--model", "m.json", "--json"],
              {"t.csv": ballbar_setup(c, 150.0, squareness=2e-5), "m.json": perfect},
              [ok(chk(findings=["squareness"], squareness=2e-5, offset=math.hypot(*c)))])
    C.add("check35_one_direction", "check", "check CSV", ["evaluate", "t.csv", "--model", "m.json", "--json"],
          {"t.csv": ballbar_setup((0.4, 0.0), dirs=(1,)), "m.json": perfect},
          [ok(chk(agrees=True, findings=[], H_null=True, offset=0.4))])
    C.add("check35_one_direction_no_column", "check", "check CSV",
          ["evaluate", "t.csv", "--model", "m.json", "--json"],
          {"t.csv": ballbar_setup(dirs=(1,), head="angle_deg,deviation_mm"), "m.json": perfect},
          [ok(chk(agrees=True, findings=[], H_null=True))])
    C.add("check35_header_twice_same", "check", "check CSV", ["evaluate", "t.csv", "--model", "m.json", "--json"],
          {"t.csv": ballbar_setup(header=("plane: XY", "radius_mm: 100", "radius_mm: 100")), "m.json": perfect},
          [ok(chk(agrees=True, findings=[]))])
    # B. malformed measured files: refused with file, line and problem
    bad = [
        ("radius_twice", ballbar_setup(header=("plane: XY", "radius_mm: 100", "radius_mm: 150")), 3, ["radius"]),
        ("plane_twice", ballbar_setup(header=("plane: XY", "radius_mm: 100", "plane: YZ")), 3, ["plane"]),
        ("no_direction_both", ballbar_setup(head="angle_deg,deviation_mm"), None, ["direction"]),
        ("concatenated", ballbar_setup()[:-1] + "\n" + ballbar_setup().split("direction\n", 1)[1], 364,
         ["two tests"]),
        ("concatenated_no_direction", ballbar_setup(dirs=(1,), head="angle_deg,deviation_mm") +
         ballbar_setup(dirs=(1,), head="angle_deg,deviation_mm").split("deviation_mm\n", 1)[1], None,
         ["two tests", "direction"]),
        ("three_readings", "# plane: XY\n# radius_mm: 100\nangle_deg,deviation_mm,direction\n0,0.001,1\n"
                           "120,0,1\n240,0,1\n", None, ["full circle"]),
        ("twelve_readings", ballbar_setup(step=30.0), None, ["full circle"]),
        ("um_under_mm", ballbar_setup(squareness=3.4e-5, scale=1000.0), None, ["um"]),
        ("um_with_offset", ballbar_setup((0.002, 0.001), squareness=2e-5, scale=1000.0), None, ["um"]),
        ("all_off_radius", ballbar_setup(extra=3.0), None, ["radius"]),
        ("offset_too_large", ballbar_setup((40.0, 0.0)), None, ["set-up", "centre"]),
        ("direction_zero", ballbar_setup().replace(",-1\n", ",0\n", 1), 184,
         ["direction"]),
    ]
    arc = "# plane: XY\n# radius_mm: 100\nangle_deg,deviation_mm,direction\n" + "".join(
        f"{a},0.0001,{d}\n" for d in (1, -1) for a in (range(0, 181, 2) if d > 0 else range(180, -1, -2)))
    bad.append(("half_circle", arc, None, ["full circle"]))
    shuffled = ballbar_setup().splitlines()
    shuffled[10], shuffled[40] = shuffled[40], shuffled[10]
    bad.append(("angles_shuffled", "\n".join(shuffled) + "\n", 12, ["runs back"]))
    for cid, text, line, words in bad:
        C.add(f"check35_bad_{cid}", "check", "check CSV", ["evaluate", "t.csv", "--model", "m.json", "--plot",
                                                           "p.png"],
              {"t.csv": text, "m.json": perfect}, [err("t.csv", line, *words)])
    # C. a circle beyond the model's measured range: end values held and said, as compensate does
    narrow = jdump({"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": {},
                    "functions": {"E_XX": {"axis": "X", "positions": [-50.0, 50.0], "values": [-0.001, 0.001]}}})
    C.add("check35_predict_outside_range", "check", "model JSON",
          ["predict", "--model", "m.json", "--circular", "XY,150,0,0,0"], {"m.json": narrow},
          [ok(say=["outside the measured range"])])
    C.add("check35_evaluate_outside_range", "check", "model JSON", ["evaluate", "t.csv", "--model", "m.json"],
          {"t.csv": ballbar_setup(radius=150.0), "m.json": narrow}, [ok(say=["outside the measured range"])])
    # D. verify
    model = jdump(HAND_MODEL)
    vj = {"kind": "stdout_json", "keys": ["passed", "check"]}
    C.add("verify35_covered_subset", "verify", "check CSV", ["t.csv", "--model", "m.json", "--covered", "E_XX",
                                                             "--json"],
          {"t.csv": ballbar_setup(), "m.json": model}, [ok(vj)])
    for cid, argv, words in [("covered_unknown", ["--covered", "E_XX,E_QQ"], ["E_QQ"]),
                             ("covered_not_held", ["--covered", "E_ZZ"], ["E_ZZ"]),
                             ("covered_empty", ["--covered", ""], ["covered"]),
                             ("machine_other", ["--machine", "xyzac"], ["xyzac"])]:
        C.add(f"verify35_{cid}", "verify", "option", ["t.csv", "--model", "m.json", *argv],
              {"t.csv": ballbar_setup(), "m.json": model}, [err(None, None, *words)])
    C.add("verify35_ballbar_um", "verify", "check CSV", ["t.csv", "--model", "m.json"],
          {"t.csv": ballbar_setup(squareness=3e-5, scale=1000.0), "m.json": model}, [err("t.csv", None, "um")])
    C.add("verify35_ballbar_arc", "verify", "check CSV", ["t.csv", "--model", "m.json"],
          {"t.csv": arc, "m.json": model}, [err("t.csv", None, "full circle")])
    C.add("verify35_recording_inch", "verify", "recording CSV", ["rec.csv", "--model", "m.json"],
          {"rec.csv": slipped_recording("readings_inch"), "m.json": model}, [err("rec.csv", None, "inch")])
    # E. plan --floor inside the work volume
    for cid, floors in [("centre", ["--floor=0,0"]), ("one_of_two", ["--floor=250,-1500", "--floor=100,50"])]:
        C.add(f"plan35_floor_inside_{cid}", "plan", "option", ["--target-um", "3", *floors],
              expect=[err(None, None, "floor", "enclosure")])
    # F. unit and frame slips before every estimator path
    for slip, words in SLIP_WORDS.items():
        rec = slipped_recording(slip)
        C.add(f"identify35_{slip}", "identify", "recording CSV", ["rec.csv", "-o", "model.json"], {"rec.csv": rec},
              [err("rec.csv", None, *words)])
        C.add(f"identify35_three_point_{slip}", "identify", "recording CSV",
              ["rec.csv", "--method", "three-point", "-o", "model.json"], {"rec.csv": rec},
              [err("rec.csv", None, *words)])
        C.add(f"diagnose35_{slip}", "diagnose", "recording CSV", ["rec.csv"], {"rec.csv": rec},
              [err("rec.csv", None, *words)])

def cases_history_and_report(C: Corpus):
    """mtcal history and mtcal report (issue 38): a valid add, results that are not mtcal's, machine IDs a
    filesystem or URL would mangle, dates in the future, an unreachable database, a report of a missing machine."""
    model = jdump(HAND_MODEL)
    hj = {"kind": "stdout_json", "keys": ["machine", "kind", "date", "file_sha256"]}
    C.add("history_add_valid", "history", "model JSON", ["add", "m.json", "--machine", "M-1", "--date", "2024-01-15",
                                                         "--db", "h.db", "--json"], {"m.json": model}, [ok(hj)])
    C.add("history_add_not_mtcal", "history", "model JSON", ["add", "x.json", "--machine", "M-1", "--db", "h.db"],
          {"x.json": jdump({"rows": [1, 2, 3]})}, [err("x.json", None, "not an mtcal result")])
    C.add("history_add_not_json", "history", "model JSON", ["add", "x.json", "--machine", "M-1", "--db", "h.db"],
          {"x.json": "axis,round\nX,1\n"}, [err("x.json", 1, "JSON")])
    for cid, mid in [("slash", "a/b"), ("space", "a b"), ("query", "a?b=1"), ("dotdot", "a..b")]:
        C.add(f"history_add_id_{cid}", "history", "option", ["add", "m.json", "--machine", mid, "--db", "h.db"],
              {"m.json": model}, [err(None, None, "machine ID")])
    C.add("history_add_future", "history", "option", ["add", "m.json", "--machine", "M-1", "--date", "2999-01-01",
                                                      "--db", "h.db"], {"m.json": model}, [err(None, None, "future")])
    C.add("history_add_bad_date", "history", "option", ["add", "m.json", "--machine", "M-1", "--date", "15.01.2026",
                                                        "--db", "h.db"], {"m.json": model},
          [err(None, None, "--date", option=True)])
    C.add("history_add_unreachable", "history", "path", ["add", "m.json", "--machine", "M-1", "--db",
                                                         "postgresql://nobody@127.0.0.1:9/none"], {"m.json": model},
          [err(None, None, "cannot reach")])
    C.add("history_show_no_db", "history", "path", ["show", "M-1", "--db", "h.db"],
          expect=[err(None, None, "no history database")])
    C.add("report_no_file", "report", "path", ["r.json", "-o", "r.html"],
          expect=[err("r.json", None, "not found", "no such file")])
    C.add("report_onto_input", "report", "overwrite", ["m.json", "-o", "m.json"], {"m.json": model},
          [err("m.json", None, "input", "overwrite", "same")])


def thermal_rows(n=400, step_s=60.0):
    """A spindle thermal test (issue 56): time, speed stages, three drift channels that follow lagged temperatures,
    three temperatures; numbers as a logger writes them (deterministic)."""
    rows, lag, T = [], [0.0, 0.0], [22.0, 24.0, 23.0]
    for i in range(n):
        t = i * step_s
        rpm = (0, 3000, 0, 6000)[(i * 4 // n) % 4]
        T = [22.0 + 0.4 * math.sin(t / 5000.0), T[1] + (24.0 + 0.002 * rpm - T[1]) * 0.03,
             T[2] + (23.0 + 0.001 * rpm - T[2]) * 0.01]
        lag = [lag[0] + (T[1] - 24.0 - lag[0]) * 0.05, lag[1] + (T[2] - 23.0 - lag[1]) * 0.02]
        ch = [3.0 * lag[0] + 0.1 * math.sin(i), -5.0 * lag[1] + 0.1 * math.cos(i), 0.2 * math.sin(i * 0.7)]
        rows.append([f"{t:g}", str(rpm)] + [f"{v:.4f}" for v in ch] + [f"{v:.3f}" for v in T])
    return rows


THERMAL_HEAD = ["time (s)", "spindle (rpm)", "ch1 (um)", "ch2 (um)", "ch3 (um)", "t1 (degC)", "t2 (degC)",
                "t3 (degC)"]


def cases_issue56(C: Corpus):
    """Issue 56: a thermal test read without options (the contract's header), `thermal fit --json` and `iso230-3`;
    bad thermal tests refused with file, line and problem: time not increasing, a stuck or missing sensor,
    temperatures in F or K said to be degC, channels without directions, a test too short for its lags, a hold-out
    too short to judge."""
    rows = thermal_rows()
    good = rows_to_csv(THERMAL_HEAD, rows)
    C.add("thermal56_fit_valid", "thermal", "thermal test CSV", ["fit", "t.csv", "--holdout", "0.4", "--json"],
          {"t.csv": good}, [ok({"kind": "stdout_json", "keys": ["channels"]})])
    C.add("thermal56_fit_model_written", "thermal", "thermal test CSV", ["fit", "t.csv", "-o", "m.json"],
          {"t.csv": good}, [ok({"kind": "exists", "paths": ["m.json"]})])
    C.add("thermal56_iso230_3_valid", "iso230-3", "thermal test CSV", ["t.csv", "--json"], {"t.csv": good},
          [ok({"kind": "stdout_json", "keys": ["figures", "clause"]})])
    C.add("thermal56_iso230_3_report", "iso230-3", "thermal test CSV", ["t.csv", "-o", "rep"], {"t.csv": good},
          [ok({"kind": "png", "dir": "rep", "min": 2})])
    back = [r[:] for r in rows]
    back[30][0] = back[28][0]
    stuck = [r[:6] + (["23.500"] if 100 <= i < 330 else r[6:7]) + r[7:] for i, r in enumerate(rows)]
    missing = [r[:] for r in rows]
    missing[57][7] = ""
    kelvin = [r[:7] + [f"{float(r[7]) + 273.15:.3f}"] for r in rows]
    fahrenheit = [r[:5] + [f"{float(v) * 1.8 + 32:.3f}" for v in r[5:]] for r in rows]
    for cid, data, line, words in [("time_back", back, 32, ["time not increasing"]),
                                   ("stuck_sensor", stuck, 102, ["stuck"]),
                                   ("missing_sensor", missing, 59, ["missing"]),
                                   ("kelvin_as_celsius", kelvin, 2, ["K or degF"]),
                                   ("fahrenheit_as_celsius", fahrenheit, 1, ["Fahrenheit"])]:
        for cmd, argv in (("thermal", ["fit", "t.csv", "-o", "m.json"]), ("iso230-3", ["t.csv", "-o", "rep"])):
            C.add(f"thermal56_{cmd.replace('-', '_')}_{cid}", cmd, "thermal test CSV", argv,
                  {"t.csv": rows_to_csv(THERMAL_HEAD, data)}, [err("t.csv", line, *words)])
    C.add("thermal56_no_unit", "thermal", "thermal test CSV", ["fit", "t.csv"],
          {"t.csv": rows_to_csv(THERMAL_HEAD[:-1] + ["t3"], rows)}, [err("t.csv", 1, "no unit")])
    C.add("thermal56_directions_missing", "iso230-3", "thermal test CSV",
          ["t.csv", "--directions", "ch1=X1,ch2=X2", "-o", "rep"], {"t.csv": good},
          [err("t.csv", None, "without a direction")])
    C.add("thermal56_too_short_for_lags", "thermal", "thermal test CSV", ["fit", "t.csv", "--lags", "20000"],
          {"t.csv": good}, [err("t.csv", None, "too short for lag")])
    C.add("thermal56_holdout_too_short", "thermal", "thermal test CSV", ["fit", "t.csv", "--holdout", "0.05"],
          {"t.csv": good}, [err("t.csv", None, "hold-out too short")])
    C.add("thermal56_export_not_a_model", "thermal", "thermal model", ["export", "m.json", "--format", "siemens",
                                                                       "-o", "T.SPF"],
          {"m.json": jdump({"channels": []})}, [err("m.json", None, "not a thermal model")])
# the history's first schema (revision 0001, as docs/guide/history.md's older histories and other programs' Alembic
# databases have it), built here with sqlite3 so that a database's faults can be planted byte by byte
HISTORY_0001 = ["CREATE TABLE alembic_version (version_num VARCHAR(32) NOT NULL PRIMARY KEY)",
                "CREATE TABLE machines (id VARCHAR(64) NOT NULL PRIMARY KEY, spec VARCHAR(64), created_at VARCHAR(32))",
                "CREATE TABLE results (id INTEGER PRIMARY KEY, machine_id VARCHAR(64), kind VARCHAR(16), date DATE, "
                "added_at VARCHAR(32), spec VARCHAR(64), source TEXT, file_sha256 VARCHAR(64), recording_sha256 "
                "VARCHAR(64), model_sha256 VARCHAR(64), tool_version VARCHAR(32), instrument TEXT, environment TEXT, "
                "document TEXT)",
                "CREATE TABLE quantities (id INTEGER PRIMARY KEY, result_id INTEGER, name VARCHAR(32), axis "
                "VARCHAR(16), position FLOAT, value FLOAT, u95 FLOAT, dof FLOAT, unit VARCHAR(16))"]


def sqlite_bytes(statements, rows=(), damage_table=None):
    """A SQLite file's bytes from ``statements`` and ``rows`` [(sql, params)]; ``damage_table``: that table's root
    page overwritten (a malformed page, the rest of the file intact)."""
    import sqlite3
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        f = Path(d) / "x.db"
        c = sqlite3.connect(f)
        for st in statements:
            c.execute(st)
        for sql, params in rows:
            c.execute(sql, params)
        c.commit()
        root = c.execute("SELECT rootpage FROM sqlite_master WHERE name = ?", (damage_table,)).fetchone()
        size = c.execute("PRAGMA page_size").fetchone()[0]
        c.close()
        data = bytearray(f.read_bytes())
    if root:
        start = (root[0] - 1) * size
        data[start:start + size] = b"\xa5" * size
    return bytes(data)


def history_0001(document=None, kind="check", drop=()):
    """An mtcal history of the first schema: machine M-1 (dmu50), one stored result ``document`` of ``kind``."""
    rows = [("INSERT INTO alembic_version VALUES ('0001')", ()),
            ("INSERT INTO machines VALUES ('M-1', 'dmu50', '2024-01-01T00:00:00+00:00')", ())]
    if document is not None:
        rows.append(("INSERT INTO results VALUES (1, 'M-1', ?, '2024-01-15', '2024-01-15T00:00:00+00:00', NULL, "
                     "'r.json', ?, NULL, NULL, '0.9', NULL, '{}', ?)", (kind, "0" * 64, json.dumps(document))))
    return [st for st in HISTORY_0001 if not any(f"TABLE {t} " in st for t in drop)], rows


def check_result(**over):
    """`mtcal check evaluate --json` of a ballbar test (docs/guide/checks.md), with ``over`` replacing fields."""
    trace = [[float(a), 0.001, 0.0009, 0.0002, d] for d in (1, -1) for a in range(0, 360, 30)]
    doc = {"kind": "circular", "source": "ballbar.csv", "plane": "XY", "radius_mm": 150.0,
           "measured": {"G_mm": 0.004, "F_mm": 0.003}, "predicted": {"G_mm": 0.0038, "F_mm": 0.003},
           "residual": {}, "prediction_u95_mm": 0.0008, "noise_sd_mm": 1e-4, "agrees": True, "worst_z": 1.2,
           "k_agree": 4.0, "findings": [], "trace": trace}
    doc.update(over)
    return doc


def cases_issue54_history(C: Corpus):
    """Issue 54, items 1-2: the history database is data no output replaces, read commands never write, every
    fault of the database one line naming it; what is added is checked against its schema and its machine."""
    model = jdump(HAND_MODEL)
    db = sqlite_bytes(*history_0001())
    made = [["history", "add", "m.json", "--machine", "M-1", "--date", "2024-01-15", "--db", "h.db"]]
    dbword = ("history database", "database")
    C.add("history54_trend_plot_onto_db", "history", "overwrite",
          ["trend", "M-1", "--error", "E_C0Y", "--plot", "h.db", "--force", "--db", "h.db"], {"m.json": model},
          [err("h.db", None, *dbword)], setup=made)
    C.add("report54_onto_db", "report", "overwrite", ["M-1", "-o", "h.db", "--force", "--db", "h.db"],
          {"m.json": model}, [err("h.db", None, *dbword)], setup=made)
    C.add("history54_show_empty_file", "history", "path", ["show", "M-1", "--db", "h.db"], {"h.db": b""},
          [err("h.db", None, "empty")])
    C.add("history54_db_empty_url", "history", "option", ["add", "m.json", "--machine", "M-1", "--db", ""],
          {"m.json": model}, [err_also(err(None, None, "empty"), "--db")])
    C.add("history54_list", "history", "path", ["list", "--db", "h.db", "--json"], {"m.json": model},
          [ok({"kind": "stdout_json", "keys": ["machines"]})], setup=made)
    C.add("report54_malformed_page", "report", "path", ["M-1", "-o", "r.html", "--db", "h.db"],
          {"h.db": sqlite_bytes(*history_0001(check_result()), damage_table="results")},
          [err("h.db", None, "malformed")])
    other = sqlite_bytes(["CREATE TABLE alembic_version (version_num VARCHAR(32) NOT NULL PRIMARY KEY)",
                          "CREATE TABLE users (id INTEGER PRIMARY KEY, name TEXT)"],
                         [("INSERT INTO alembic_version VALUES ('0001')", ()),
                          ("INSERT INTO users VALUES (1, 'ada')", ())])
    for action in (["add", "m.json", "--machine", "M-1"], ["show", "M-1"]):
        C.add(f"history54_foreign_alembic_{action[0]}", "history", "path", [*action, "--db", "h.db"],
              {"m.json": model, "h.db": other}, [err("h.db", None, "not an mtcal history")])
    C.add("history54_dropped_table", "history", "path", ["show", "M-1", "--db", "h.db"],
          {"h.db": sqlite_bytes(*history_0001(check_result(), drop=("quantities",)))},
          [err_also(err("h.db", None, "missing"), "quantities")])
    C.add("history54_readonly_add", "history", "path", ["add", "m.json", "--machine", "M-1", "--db", "h.db"],
          {"m.json": model, "h.db": db}, [err("h.db", None, "read-only", "permission")])
    (C.root / "history54_readonly_add" / "h.db").chmod(0o444)
    diag = {"machine": "dmu60", "recording": "rec.csv", "base_sigma": 0.001, "base_sigma_ratio": 1.0,
            "sigma_ratio_after": 1.0, "effects": [], "noise_model": {}}
    for cid, spec in (("unknown_spec", "dmu60"), ("markup_spec", "<script>alert(1)</script>")):
        C.add(f"history54_{cid}", "history", "model JSON", ["add", "d.json", "--machine", "M-1", "--db", "h.db"],
              {"d.json": jdump(dict(diag, machine=spec))}, [err("d.json", None, "machine spec", "spec")])
    C.add("history54_date_year_one", "history", "option",
          ["add", "m.json", "--machine", "M-1", "--date", "0001-01-01", "--db", "h.db"], {"m.json": model},
          [err(None, None, "1970", "plausible", "too early")])
    rec = "axis,round,position,point,x,y,z,temperature_c\nX,1,0,P,0,0,0,20.5\nX,1,0,Q,0,0,0,n/a\n"
    C.add("history54_temperature_na", "history", "recording CSV",
          ["add", "m.json", "--machine", "M-1", "--db", "h.db", "--json"],
          {"m.json": jdump(dict(HAND_MODEL, identified_from="rec.csv")), "rec.csv": rec},
          [ok({"kind": "stdout_json", "keys": ["environment"]}, say=["n/a"])])
    iso = {"file": "r.csv", "standard": "ISO 230-2:2014", "axes": {"X": {
        "axis": "X", "kind": "linear", "unit": "um", "position_unit": "mm", "positions": [0.0, 100.0],
        "parameters": {"A": 3.5, "E": 2.0}}}}
    C.add("history54_iso_without_targets", "history", "model JSON",
          ["add", "r.json", "--machine", "M-1", "--db", "h.db"], {"r.json": jdump(iso)},
          [err("r.json", None, "targets")])
    C.add("history54_check_unknown_kind", "history", "model JSON",
          ["add", "c.json", "--machine", "M-1", "--db", "h.db"], {"c.json": jdump(check_result(kind="laser"))},
          [err("c.json", None, "kind")])
    C.add("report54_check_worst_z_null", "report", "model JSON", ["c.json", "-o", "r.html"],
          {"c.json": jdump(check_result(worst_z=None))}, [ok({"kind": "exists", "paths": ["r.html"]})])
    law = {"radial_um": "0.4", "radial_um_per_m": 0.3, "transverse_um": 15, "transverse_um_per_m": 6, "k": 2}
    C.add("report54_noise_law_strings", "report", "model JSON", ["m.json", "-o", "r.html"],
          {"m.json": jdump(dict(HAND_MODEL, noise_law=law))}, [err("m.json", None, "noise_law")])
    C.add("report54_stored_before_checks", "report", "path", ["M-1", "-o", "r.html", "--db", "h.db"],
          {"h.db": sqlite_bytes(*history_0001(check_result(worst_z="large")))},
          [err_also(err("h.db", None, "worst_z"), "r.json")])


# ------------------------------------------------------------------- issue 54: headers that lie, tables, files

def b02_rows():
    """(target mm, run, direction, measured mm) of the public b02 axis (tests/data/iso230_2_b02_x.csv)."""
    src = Path(__file__).resolve().parents[1] / "data" / "iso230_2_b02_x.csv"
    rows = [ln.split(",") for ln in src.read_text().splitlines() if ln and not ln.startswith("#")][1:]
    return [(float(t), int(r), d, float(m)) for t, r, d, m in rows]


def b02_long(header, cell, sep=","):
    """A row-per-reading export of b02: ``header`` then run and ``cell(t, d, m)``'s fields per reading."""
    return "\n".join([header] + [sep.join([str(r), *cell(t, d, m)]) for t, r, d, m in b02_rows()]) + "\n"


def german(x, decimals):
    """x as a German spreadsheet writes it: '.' between thousands, ',' before the decimals (1.004,972452381)."""
    body = f"{abs(x):,.{decimals}f}"
    body = body.rstrip("0").rstrip(".") if "." in body else body
    return ("-" if x < 0 else "") + body.replace(",", " ").replace(".", ",").replace(" ", ".")


def ballbar_scaled(c, radius=150.0, sx=2e-5, sy=-1e-5, step=2.0):
    """A double ballbar of a machine whose X and Y scales are off by sx and sy (ISO 230-1: E_XX(x) = sx x moves the
    tool tip by sx x along X against the workpiece), its table ball at ``c`` mm off the circle's centre where the
    machine puts the tool: deltaR = |(R cos t (1 + sx) - c_x, R sin t (1 + sy) - c_y)| - R (plain geometry)."""
    rows, n = [], int(round(360 / step))
    for d in (1, -1):
        for k in (range(n) if d > 0 else range(n - 1, -1, -1)):
            t = math.radians(k * step)
            L = math.hypot(radius * math.cos(t) * (1 + sx) - c[0], radius * math.sin(t) * (1 + sy) - c[1])
            rows.append([f"{k * step:g}", f"{L - radius:.9f}", str(d)])
    return f"# plane: XY\n# radius_mm: {radius:g}\n# centre_mm: 0,0,0\n" + rows_to_csv(
        ["angle_deg", "deviation_mm", "direction"], rows)


def scale_model(sx=2e-5, sy=-1e-5):
    return jdump({"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": {},
                  "functions": {"E_XX": {"axis": "X", "positions": [-500.0, 500.0], "values": [-500 * sx, 500 * sx]},
                                "E_YY": {"axis": "Y", "positions": [-500.0, 500.0], "values": [-500 * sy, 500 * sy]}}})


def cases_issue54_inputs(C: Corpus):
    """Issue 54 items 3-6: ISO 230-2 headers whose claims the values contradict, thousands separators, a lab export
    with both the reading and its error; tables beyond the axis' travel or the turn, steps that do not fit; a Monte
    Carlo file of a byte-identical program under another name; a large ballbar set-up offset on a machine with
    scale errors.  Each seen failing on the main of issue 54."""
    rows = b02_rows()
    wide_head = ",".join(["Target (mm)"] + [f"Run {j} {w} Error (mm)" for j in range(1, 6) for w in ("Fwd", "Rev")])
    reached = {(t, r, d): m for t, r, d, m in rows}
    wide = "\n".join([wide_head] + [",".join([f"{t:g}"] + [repr(reached[(t, j, d)]) for j in range(1, 6)
                                                          for d in ("up", "down")])
                                     for t in sorted({t for t, *_ in rows})]) + "\n"
    first_bad = 2 + next(k for k, (t, r, d, m) in enumerate(rows) if (t, d) == (10.0, "down"))
    point_line = 2 + next(k for k, (t, r, d, m) in enumerate(rows) if t == 0.0)
    iso = [
        ("reading_mm_under_um_header", b02_long("Run,Target (mm),Direction,Laser reading (µm)",
                                                lambda t, d, m: [f"{t:g}", d, repr(m)]), [err("r.csv", 1, "span")]),
        ("error_column_holds_positions", wide, [err("r.csv", 1, "positions reached")]),
        ("reading_column_is_the_targets", b02_long("Run,Target (mm),Direction,Laser reading (mm)",
                                                   lambda t, d, m: [f"{t:g}", d, f"{t:g}"]),
         [err("r.csv", 1, "copied", "target column")]),
        ("thousands_separators", b02_long("Lauf;Sollposition [mm];Richtung;Messwert [mm]",
                                          lambda t, d, m: [german(t + 1000, 0), d, german(m + 1000, 9)], sep=";"),
         [ok({"kind": "stdout_json", "keys": ["axes"]}, say=["thousands separators"])]),
        ("decimal_point_among_commas", b02_long("Lauf;Sollposition [mm];Richtung;Messwert [mm]",
                                                lambda t, d, m: [f"{t:g}", d, f"{m:.6f}" if t == 0.0 else
                                                                 f"{m:.6f}".replace(".", ",")], sep=";"),
         [err("r.csv", point_line, "decimal point")]),
        ("reading_and_error_agree", b02_long("Run,Target (mm),Direction,Laser reading (mm),Error (µm)",
                                             lambda t, d, m: [f"{t:g}", d, f"{m:.9f}", f"{(m - t) * 1e3:.3f}"]),
         [ok({"kind": "stdout_json", "keys": ["axes"]}, say=["checked against"])]),
        ("reading_and_error_disagree", b02_long(  # 0.7 um off at target 10 down: run 1's row there is named
            "Run,Target (mm),Direction,Laser reading (mm),Error (µm)",
            lambda t, d, m: [f"{t:g}", d, f"{m:.9f}",
                             f"{(m - t) * 1e3 + (0.7 if (t, d) == (10.0, 'down') else 0):.3f}"]),
         [err("r.csv", first_bad, "disagree")]),
        ("error_written_target_minus_reading", b02_long(
            "Run,Target (mm),Direction,Laser reading (mm),Error (µm)",
            lambda t, d, m: [f"{t:g}", d, f"{m:.9f}", f"{(t - m) * 1e3:.3f}"]), [err("r.csv", 2, "target - reading")]),
    ]
    for cid, text, expect in iso:
        C.add(f"iso54_{cid}", "iso230-2", "ISO 230-2 readings", ["r.csv", "--json"], {"r.csv": text}, expect)
    # tables: beyond the turn, beyond the travel, steps that do not fit
    c_arc = [300.0 + 10.0 * k for k in range(13)]
    c_model = jdump({"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": {},
                     "functions": {"E_CC": {"axis": "C", "positions": c_arc,
                                            "values": [5e-6 + 2e-7 * (c - 300.0) for c in c_arc]}}})
    b_arc = [100.0 + 10.0 * k for k in range(8)]
    b_model = jdump({"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": {},
                     "functions": {"E_CB": {"axis": "B", "positions": b_arc,
                                            "values": [4e-6 + 1e-7 * (b - 100.0) for b in b_arc]}}})
    hand = jdump(HAND_MODEL)
    for cid, files, argv, expect in [
        ("heidenhain_modulo_c_300_420", {"m.json": c_model}, ["--format", "heidenhain", "-o", "tnc"],
         [ok({"kind": "finite_text", "path": "tnc/C.COM"}, say=["modulo"])]),
        ("siemens_b_step_beyond_travel", {"m.json": b_model}, ["--format", "siemens", "-o", "c.mpf", "--step", "50"],
         [ok({"kind": "finite_text", "path": "c.mpf"}, say=["beyond the travel"]),
          err("m.json", None, "travel")]),
        ("siemens_modulo_step_7", {"m.json": c_model}, ["--format", "siemens", "-o", "c.mpf", "--step", "7"],
         [err("m.json", None, "does not divide")]),
        ("linuxcnc_step_5e-324", {"m.json": hand}, ["--format", "linuxcnc", "-o", "lc", "--step", "5e-324"],
         [err("m.json", None, "finer", "step")]),
        ("siemens_step_5e-324", {"m.json": hand}, ["--format", "siemens", "-o", "c.mpf", "--step", "5e-324"],
         [err("m.json", None, "finer", "step")]),
        ("step_larger_than_span", {"m.json": hand}, ["--format", "linuxcnc", "-o", "lc", "--step", "1200"],
         [err("m.json", None, "larger than the measured span")]),
        ("step_not_dividing_span", {"m.json": hand}, ["--format", "linuxcnc", "-o", "lc", "--step", "300"],
         [ok({"kind": "finite_text", "path": "lc/joint0_X.comp"}, say=["does not divide"])]),
    ]:
        C.add(f"export54_{cid}", "export", "option", ["m.json", *argv], files, expect)
    # a Monte Carlo file of the same program under another name (matched by content hash)
    header, rec = recording_x_only()
    prog = (DATA / "sample_5axis.nc").read_bytes()
    tr = "--tracker=250,-1500,150"
    C.add("compensate54_mc_of_a_byte_identical_copy", "compensate", "Monte Carlo JSON",
          ["renamed.nc", "--model", "m.json", "-o", "c.nc", "--uncertainty", "mc.json", "--json"],
          {"rec.csv": rows_to_csv(header, rec), "part.nc": prog, "renamed.nc": prog},
          [ok({"kind": "stdout_json", "keys": ["task_uncertainty"]}, say=["part.nc"])],
          setup=[["identify", "rec.csv", tr, "-o", "m.json", "-q"],
                 ["uncertainty", "rec.csv", "--trials", "2", "--workers", "0", tr, "--program", "part.nc", "-o",
                  "mc.json", "-q"]])
    # a ballbar set-up offset up to a quarter of the radius, on a machine with scale errors: the model agrees
    chk = lambda **kw: {"kind": "check_json", **kw}  # noqa: E731
    for k, c in enumerate([(36.0, 0.0), (0.0, -36.0), (25.5, 25.5)]):
        C.add(f"check54_setup_offset_{k}", "check", "check CSV", ["evaluate", "t.csv", "--model", "m.json", "--json"],
              {"t.csv": ballbar_scaled(c), "m.json": scale_model()},
              [ok(chk(agrees=True, findings=[], offset=math.hypot(*c)))])
    C.add("check54_setup_offset_beyond_the_bound", "check", "check CSV",
          ["evaluate", "t.csv", "--model", "m.json", "--json"], {"t.csv": ballbar_scaled((40.0, 0.0)),
                                                                 "m.json": scale_model()},
          [err("t.csv", None, "37.5 mm")])


def build(root: Path) -> list[dict]:
    root.mkdir(parents=True, exist_ok=True)
    C = Corpus(root)
    rnd = random.Random(SEED)
    cases_identify(C, rnd)
    cases_compensate(C, rnd)
    cases_model_shapes_elsewhere(C)
    cases_simulate(C)
    cases_plan(C)
    cases_diagnose(C, rnd)
    cases_plate(C, rnd)
    cases_demo_and_cli(C)
    cases_real_data(C)
    cases_more_paths(C)
    cases_generated(C, rnd)
    cases_iso230_and_import(C)
    cases_export(C)
    cases_issue20(C)
    cases_export_guard(C)
    cases_signals(C)
    cases_checks(C)
    cases_uncertainty(C)
    cases_issue35(C)
    cases_issue56(C)

    cases_history_and_report(C)
    cases_issue54_history(C)
    cases_issue54_inputs(C)
    C.write()
    return C.cases


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    cs = build(Path(sys.argv[1]))
    print(f"{len(cs)} cases written to {sys.argv[1]}")
