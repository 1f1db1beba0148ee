"""Independent checks of mtcal outputs for the fuzz suite (written from the docs, not from mtcal's code).

The G-code reader here is deliberately plain: lines split on LF, CRLF or lone CR; `( )` and `;` comments per
line; a word is a letter followed by a plain decimal number.  It tracks G90/G91, G20/G21, G93/G94 and skips
G28/G53 blocks (machine coordinates, never compensated).
"""
from __future__ import annotations

import csv
import io
import json
import math
import re
from pathlib import Path

COORD = "XYZBC"
_EOL = re.compile(rb"(\r\n|\r|\n)")
_WORD = re.compile(r"([A-Za-z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")


def split_lines(data: bytes) -> list[tuple[bytes, bytes]]:
    """(content, line end) pairs; a last line without an end has b''."""
    parts = _EOL.split(data)
    out = [(parts[k], parts[k + 1]) for k in range(0, len(parts) - 1, 2)]
    if parts[-1]:
        out.append((parts[-1], b""))
    return out


def code_and_skeleton(line: str) -> tuple[str, str]:
    """Code outside comments, and the skeleton: the line without coordinate words and blanks outside comments
    and F values (comments kept verbatim)."""
    code, skel, k, n = [], [], 0, len(line)
    while k < n:
        ch = line[k]
        if ch == "(":
            end = line.find(")", k)
            end = n if end < 0 else end + 1
            skel.append(line[k:end])
            k = end
            continue
        if ch == ";":
            skel.append(line[k:])
            break
        code.append(ch)
        k += 1
    code_s = "".join(code)
    bare = re.sub(r"[XYZBCxyzbc]\s*[-+]?(?:\d+\.?\d*|\.\d+)", "", code_s)
    bare = re.sub(r"([Ff])\s*[-+]?(?:\d+\.?\d*|\.\d+)", r"\1", bare)   # F may be recomputed (G93)
    skel.insert(0, re.sub(r"\s+", "", bare))
    return code_s, "".join(skel)


def words(code: str) -> list[tuple[str, float]]:
    return [(a.upper(), float(b)) for a, b in _WORD.findall(code)]


class State:
    def __init__(self):
        self.pos = {a: None for a in COORD}
        self.incremental = False
        self.inch = False
        self.inverse_time = False

    def apply(self, code: str) -> dict:
        """Update with one block; return {'move': bool, 'machine': bool, 'F': value or None}."""
        ws = words(code)
        gs = [v for a, v in ws if a == "G"]
        for g in gs:
            if g == 90:
                self.incremental = False
            elif g == 91:
                self.incremental = True
            elif g == 20:
                self.inch = True
            elif g == 21:
                self.inch = False
            elif g == 93:
                self.inverse_time = True
            elif g in (94, 95):
                self.inverse_time = False
        machine = any(g in (28, 53) for g in gs)
        f = next((v for a, v in ws if a == "F"), None)
        coords = [(a, v) for a, v in ws if a in COORD]
        if machine or not coords:
            return {"move": False, "machine": machine, "F": f}
        for a, v in coords:
            if self.incremental and self.pos[a] is not None:
                self.pos[a] += v
            else:
                self.pos[a] = v
        return {"move": True, "machine": False, "F": f}


def first_order_target(p: dict, oracle: dict, inch: bool) -> dict:
    """Commanded X Y Z expected for the hand model (E_XX table + E_C0Y), B = C = 0, tool length 0:
    X' = X - E_XX(X) + Y * E_C0Y (docs/design.md: actual Y direction (-E_C0Y, 1, 0)), Y' = Y, Z' = Z."""
    u = 25.4 if inch else 1.0
    xs, vs = oracle["exx"]
    x, y = p["X"] * u, p["Y"] * u
    exx = _interp(x, xs, vs) * oracle.get("scale", 1.0)
    out = dict(p)
    out["X"] = (x - exx + y * oracle["c0y"]) / u
    return out


def _interp(x, xs, vs):
    if x <= xs[0]:
        return vs[0]
    for k in range(1, len(xs)):
        if x <= xs[k]:
            t = (x - xs[k - 1]) / (xs[k] - xs[k - 1])
            return vs[k - 1] + t * (vs[k] - vs[k - 1])
    return vs[-1]


def check_gcode(case_dir: Path, chk: dict) -> list[str]:
    """Compare a compensated program with its input: every input line is in the output, in order, with its line
    end and everything but coordinate words unchanged; the blocks inserted next to a line (a subdivided move,
    before or after it) are plain moves on its segment; every number is finite; where each input line's run of
    output blocks ends, the position is within `bound` of the input (and on the first-order oracle when given);
    machine-coordinate blocks are byte-identical; G93 pieces carry F and together keep the block's time."""
    src = case_dir / chk.get("same_as", chk["input"])
    out_p = case_dir / chk["output"]
    if not out_p.is_file():
        return [f"output {chk['output']} was not written"]
    a = split_lines(src.read_bytes())
    b = split_lines(out_p.read_bytes())
    probs: list[str] = []
    sa, sb = State(), State()
    ptr, ins_total = 0, 0
    run = None   # {"lno", "start", "inserted": [(lno, pos, F)], "F": [..], "move", "f_orig", "g93"}
    for lno, (content, eol) in enumerate(b, start=1):
        text = content.decode("latin-1")
        code, skel = code_and_skeleton(text)
        if re.search(r"nan|inf", code, re.I):
            probs.append(f"output line {lno}: {text!r} has nan/inf")
        a_code = a_skel = None
        if ptr < len(a):
            a_code, a_skel = code_and_skeleton(a[ptr][0].decode("latin-1"))
        if a_skel == skel and a[ptr][1] == eol:
            if run:
                probs += _finish_run(run, sa, sb, chk)
            start = dict(sb.pos)
            info_a, info_b = sa.apply(a_code), sb.apply(code)
            if ptr + 1 in chk.get("passthrough", []) and content != a[ptr][0]:
                probs.append(f"line {ptr + 1} (machine coordinates) changed: {a[ptr][0]!r} -> {content!r}")
            run = {"lno": lno, "start": start, "inserted": [], "F": [info_b["F"]], "move": info_a["move"],
                   "f_orig": info_a["F"], "g93": sb.inverse_time}
            if not sb.inverse_time and info_a["F"] != info_b["F"]:
                probs.append(f"output line {lno}: feed F {info_b['F']} differs from the input's {info_a['F']}")
            ptr += 1
            continue
        info_b = sb.apply(code)
        if not info_b["move"] or not re.fullmatch(r"(?:N\d+|G\d+(?:\.\d+)?|F)*", skel):
            probs.append(f"output line {lno} {text!r} matches no input line and is not a plain move")
            continue
        if run is None:
            probs.append(f"output line {lno} {text!r} inserted before the first input line")
            continue
        if sb.inverse_time and info_b["F"] is None and chk.get("g93"):
            probs.append(f"inserted G93 block at output line {lno} has no F: {text!r}")
        run["inserted"].append((lno, dict(sb.pos), info_b["F"]))
        run["F"].append(info_b["F"])
        ins_total += 1
    if run:
        probs += _finish_run(run, sa, sb, chk)
    if ptr != len(a):
        probs.append(f"input line {ptr + 1} {a[ptr][0][:60]!r} not found in the output (matched {ptr}/{len(a)})")
    if ins_total < chk.get("min_inserted", 0):
        probs.append(f"expected >= {chk['min_inserted']} inserted blocks, got {ins_total}")
    return probs[:12]


def _finish_run(run, sa, sb, chk):
    probs = []
    bound, oracle = chk["bound"], chk.get("oracle")
    if not _close(sa.pos, sb.pos, bound):
        probs.append(f"output line {run['lno']}: position {sb.pos} is more than {bound} from the input {sa.pos}")
    if oracle and run["move"]:
        probs += _oracle_diff(run["lno"], sa, sb, oracle)
    if run["inserted"]:
        probs += _inside(run["inserted"], run["start"], sb.pos, bound)
        if chk.get("g93") and run["g93"]:
            probs += _g93_time(run["lno"], run["F"], run["f_orig"])
    return probs


def _close(pa, pb, bound):
    return all(pa[k] is None or pb[k] is None or abs(pa[k] - pb[k]) <= bound for k in COORD)


def _oracle_diff(lno, sa, sb, oracle):
    if any(sa.pos[k] is None for k in "XYZ") or any(sb.pos[k] is None for k in "XYZ"):
        return []
    want = first_order_target(sa.pos, oracle, sa.inch)
    tol = 3e-4 / (25.4 if sa.inch else 1.0)
    bad = [f"{k}: got {sb.pos[k]:.6f}, want {want[k]:.6f}" for k in "XYZ" if abs(sb.pos[k] - want[k]) > tol]
    bad += [f"{k}: got {sb.pos[k]}, want {sa.pos[k]}" for k in "BC"
            if sa.pos[k] is not None and sb.pos[k] is not None and abs(sb.pos[k] - sa.pos[k]) > 1e-6]
    return [f"output line {lno} (input target {sa.pos}): " + "; ".join(bad)] if bad else []


def _g93_time(lno, fs, f_orig):
    """Inverse-time feed: the pieces of a block (the block's own line + the inserted ones) take its time together."""
    if any(f is None or not f > 0 for f in fs) or f_orig is None:
        return [f"G93 block ending at output line {lno}: pieces without a valid F: {fs}"]
    t_pieces, t_orig = sum(1.0 / f for f in fs), 1.0 / f_orig
    if abs(t_pieces - t_orig) > 0.02 * t_orig:
        return [f"G93 block ending at output line {lno}: pieces take {t_pieces:.4f} min, the block {t_orig:.4f} min "
                f"(F {fs} vs {f_orig})"]
    return []


def _inside(pending, start, end, bound):
    out = []
    for ln, pos, _ in pending:
        for k in COORD:
            if None in (pos[k], start[k], end[k]):
                continue
            lo, hi = min(start[k], end[k]) - bound, max(start[k], end[k]) + bound
            if not lo <= pos[k] <= hi:
                out.append(f"inserted output line {ln}: {k}={pos[k]} outside the segment [{lo}, {hi}]")
    return out


def check_cl_output(case_dir: Path, chk: dict) -> list[str]:
    p = case_dir / chk["output"]
    if not p.is_file():
        return [f"output {chk['output']} was not written"]
    moves, probs = 0, []
    for lno, (content, _) in enumerate(split_lines(p.read_bytes()), start=1):
        code, _ = code_and_skeleton(content.decode("latin-1"))
        ws = [(w, v) for w, v in words(code) if w in COORD]
        if re.search(r"nan|inf", code, re.I):
            probs.append(f"line {lno}: nan/inf")
        if ws:
            moves += 1
        for w, v in ws:
            if w == "B" and not -1e-9 <= v <= 180 + 1e-9:
                probs.append(f"line {lno}: B = {v} outside [0, 180]")
    if moves < chk["moves"]:
        probs.append(f"{moves} moves written, want {chk['moves']}")
    return probs


def strict_json(text: str):
    """json.loads that refuses NaN / Infinity (not JSON)."""
    def bad(tok):
        raise ValueError(f"non-standard JSON constant {tok}")
    return json.loads(text, parse_constant=bad)


def all_finite(obj) -> bool:
    if isinstance(obj, bool) or obj is None or isinstance(obj, str):
        return True
    if isinstance(obj, (int, float)):
        return math.isfinite(obj)
    if isinstance(obj, dict):
        return all(all_finite(v) for v in obj.values())
    if isinstance(obj, (list, tuple)):
        return all(all_finite(v) for v in obj)
    return True


def check_model_json(case_dir: Path, chk: dict) -> list[str]:
    p = case_dir / chk["path"]
    if not p.is_file():
        return [f"model {chk['path']} was not written"]
    try:
        m = strict_json(p.read_text())
    except ValueError as exc:
        return [f"model is not strict JSON: {exc}"]
    probs = []
    if not isinstance(m.get("functions"), dict) or not isinstance(m.get("constants", {}), dict):
        return ["model has no functions/constants objects"]
    if m.get("units", {}).get("length") not in ("mm", "um", "m"):
        probs.append(f"model units {m.get('units')}")
    if not all_finite(m):
        probs.append("model has non-finite numbers")
    axes = {f.get("axis") for f in m["functions"].values()}
    probs += [f"no error function of axis {a}" for a in chk.get("axes", []) if a not in axes]
    return probs


def read_recording(p: Path) -> tuple[list[str], list[list[str]]]:
    rows = list(csv.reader(io.StringIO(p.read_text())))
    rows = [r for r in rows if r and not r[0].startswith("#")]
    return rows[0], rows[1:]


def check_recording_csv(case_dir: Path, chk: dict) -> list[str]:
    p = case_dir / chk["path"]
    if not p.is_file():
        return [f"recording {chk['path']} was not written"]
    h, rows = read_recording(p)
    miss = [c for c in ("axis", "round", "position", "point", "x", "y", "z") if c not in h]
    if miss:
        return [f"recording lacks columns {miss}"]
    probs = []
    if len(rows) != chk["rows"]:
        probs.append(f"{len(rows)} readings, want {chk['rows']}")
    for k, r in enumerate(rows, start=2):
        for c in ("position", "x", "y", "z"):
            try:
                v = float(r[h.index(c)])
            except ValueError:
                v = float("nan")
            if not math.isfinite(v):
                probs.append(f"line {k}: {c} = {r[h.index(c)]!r}")
                break
        if len(probs) > 5:
            break
    return probs


def check_sim_exx(case_dir: Path, chk: dict) -> list[str]:
    """Noise-free readings of axis X on a machine with only E_XX(X) acting along X: every reflector moves by
    position + E_XX(position) - E_XX(0) in x from its reading at position 0, and not at all in y and z."""
    h, rows = read_recording(case_dir / chk["path"])
    ix = {c: h.index(c) for c in ("axis", "round", "position", "point", "x", "y", "z")}
    ref = {}
    for r in rows:
        if r[ix["axis"]] == "X" and float(r[ix["position"]]) == 0.0:
            ref.setdefault((r[ix["round"]], r[ix["point"]]), [float(r[ix[c]]) for c in "xyz"])
    xs, vs = chk["exx"]
    probs = []
    for r in rows:
        if r[ix["axis"]] != "X":
            continue
        pos = float(r[ix["position"]])
        x0 = ref[(r[ix["round"]], r[ix["point"]])]
        got = [float(r[ix[c]]) - x0[k] for k, c in enumerate("xyz")]
        want = [pos + _interp(pos, xs, vs) - _interp(0.0, xs, vs), 0.0, 0.0]
        if max(abs(g - w) for g, w in zip(got, want)) > 2e-6:
            probs.append(f"X={pos} point {r[ix['point']]}: moved {got}, want {want}")
    return probs[:5]


def check_model_exx(case_dir: Path, chk: dict) -> list[str]:
    """An identified model from noise-free readings: E_XX at its table positions and the squareness E_C0Y
    equal the planted ones (to 1e-6 mm / 1e-8 rad)."""
    m = json.loads((case_dir / chk["path"]).read_text())
    f = m["functions"].get("E_XX")
    if f is None:
        return ["no E_XX in the identified model"]
    xs, vs = chk["exx"]
    probs = [f"E_XX({p}) = {v}, planted {_interp(p, xs, vs)}" for p, v in zip(f["positions"], f["values"])
             if abs(v - _interp(p, xs, vs)) > 1e-6]
    c0y = m.get("constants", {}).get("E_C0Y")
    if c0y is None or abs(c0y - chk["c0y"]) > 1e-8:
        probs.append(f"E_C0Y = {c0y}, planted {chk['c0y']}")
    return probs


def check_same_as(case_dir: Path, chk: dict) -> list[str]:
    """Same bytes as a reference output once its LF line ends are replaced by `eol`."""
    got = (case_dir / chk["path"]).read_bytes()
    want = (case_dir / chk["ref"]).read_bytes().replace(b"\n", chk["eol"].encode())
    if got == want:
        return []
    ga, wa = got.split(chk["eol"].encode()), want.split(chk["eol"].encode())
    k = next((i for i, (x, y) in enumerate(zip(ga, wa)) if x != y), min(len(ga), len(wa)))
    return [f"differs from the LF program's output at line {k + 1}: {ga[k:k + 1]!r} vs {wa[k:k + 1]!r} "
            f"({len(ga)} vs {len(wa)} lines)"]


def check_png(case_dir: Path, chk: dict) -> list[str]:
    files = [case_dir / chk["file"]] if "file" in chk else sorted((case_dir / chk["dir"]).rglob("*.png"))
    files = [f for f in files if f.is_file() and f.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"]
    return [] if len(files) >= chk.get("min", 1) else [f"{len(files)} PNG files written, want >= {chk.get('min', 1)}"]


def check_iso_mean(stdout_json: dict, chk: dict) -> list[str]:
    """ISO 230-2 on noise-free readings of an axis with only E_XX acting: the mean positional deviation at each
    target is E_XX(P) - E_XX(P_0) (um), up and down alike (no reversal)."""
    ax = stdout_json["axes"][chk["axis"]]
    xs, vs = chk["exx"]
    probs = []
    for key in ("mean_up", "mean_down", "mean"):
        for p, got in zip(ax["positions"], ax["targets"][key]):
            want = 1000.0 * (_interp(p, xs, vs) - _interp(0.0, xs, vs))
            if abs(got - want) > 1e-3:
                probs.append(f"{key} at {p}: {got} um, want {want} um")
    return probs[:5]


def check_recording_equal(case_dir: Path, chk: dict) -> list[str]:
    """Same readings (axis, round, position, point, direction, x y z to 1e-6 mm) as a reference recording."""
    p = case_dir / chk["path"]
    if not p.is_file():
        return [f"{chk['path']} was not written"]
    def key_rows(path):
        h, rows = read_recording(path)
        ix = [h.index(c) for c in ("axis", "round", "position", "point", "direction")]
        return sorted((tuple(r[i] if k != 2 else float(r[i]) for k, i in enumerate(ix)),
                       tuple(float(r[h.index(c)]) for c in "xyz")) for r in rows)
    got, want = key_rows(p), key_rows(case_dir / chk["ref"])
    if len(got) != len(want):
        return [f"{len(got)} readings, want {len(want)}"]
    probs = []
    for (kg, xg), (kw, xw) in zip(got, want):
        if (kg[0], int(float(kg[1])), kg[2], kg[3], int(float(kg[4]))) != \
                (kw[0], int(float(kw[1])), kw[2], kw[3], int(float(kw[4]))) or \
                max(abs(a - b) for a, b in zip(xg, xw)) > 1e-6:
            probs.append(f"reading {kg} {xg} vs {kw} {xw}")
    return probs[:5]


def check_linuxcnc_comp(case_dir: Path, chk: dict) -> list[str]:
    """LinuxCNC COMP_FILE of an axis (docs, mtcal export): lines `nominal forward reverse`; type 1 holds the
    trims -E(x), type 0 the positions reached, x + E(x); E is the hand model's E_XX."""
    files = sorted((case_dir / chk["dir"]).glob(f"*_{chk['axis']}.comp"))
    if len(files) != 1:
        return [f"want one *_{chk['axis']}.comp in {chk['dir']}, got {[f.name for f in files]}"]
    xs, vs = chk["exx"]
    probs, n = [], 0
    for lno, line in enumerate(files[0].read_text().splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        pos, fwd, rev = (float(v) for v in line.split())
        want = -_interp(pos, xs, vs) if chk["type"] == 1 else pos + _interp(pos, xs, vs)
        n += 1
        if max(abs(fwd - want), abs(rev - want)) > 1e-8:
            probs.append(f"{files[0].name}:{lno}: {line.strip()} (want {want:.9f})")
    return (probs or ([] if n >= 2 else [f"only {n} table lines"]))[:5]


def check_finite_text(case_dir: Path, chk: dict) -> list[str]:
    """Every output file exists, is not empty and has no nan/inf numbers."""
    p = case_dir / chk["path"]
    files = [p] if p.is_file() else sorted(f for f in p.rglob("*") if f.is_file()) if p.is_dir() else []
    if not files:
        return [f"{chk['path']} was not written"]
    bad = [f.name for f in files if not f.stat().st_size
           or re.search(r"(?<![A-Za-z])(nan|inf)(?![A-Za-z])", f.read_text(errors="replace"), re.I)]
    return [f"empty or non-finite: {bad}"] if bad else []


def check_check_json(js: dict, chk: dict) -> list[str]:
    """``mtcal check evaluate --json`` of a ballbar test written from plain geometry (tests/fuzz/make_corpus.py,
    ballbar_setup): the verdict, the findings' names, the set-up offset's size (mm, to 1e-4), a squareness's size
    (rad, to 5 %), G (mm) at most, H null for one direction."""
    probs = []
    names = [f["signature"] for f in js.get("findings", [])]
    if "agrees" in chk and js.get("agrees") is not chk["agrees"]:
        probs.append(f"agrees {js.get('agrees')}, want {chk['agrees']} (findings {names})")
    if "findings" in chk and names != chk["findings"]:
        probs.append(f"findings {names}, want {chk['findings']}")
    if "offset" in chk and not abs(js.get("setup_offset_size_mm", math.inf) - chk["offset"]) <= 1e-4:
        probs.append(f"set-up offset {js.get('setup_offset_size_mm')} mm, want {chk['offset']}")
    if "squareness" in chk:
        sq = [f["size"] for f in js.get("findings", []) if f["signature"] == "squareness"]
        if not sq or abs(abs(sq[0]) - chk["squareness"]) > 0.05 * chk["squareness"]:
            probs.append(f"squareness {sq}, want {chk['squareness']} rad")
    if "G_max_mm" in chk and not js["measured"]["G_mm"] <= chk["G_max_mm"]:
        probs.append(f"measured G {js['measured']['G_mm']} mm on a perfect machine, want <= {chk['G_max_mm']}")
    if chk.get("H_null") and js["measured"].get("H_mm") is not None:
        probs.append(f"H {js['measured'].get('H_mm')} stated for one direction")
    return probs
