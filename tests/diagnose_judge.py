"""What counts as a right answer of ``mtcal diagnose`` on a planted campaign (tests/campaigns.py ``expect``).

Right: every expected effect is named by a significant finding (its name, or one of its "alternatives", or named
in a significant finding's "confounded_with"; the axis when the expectation gives one), or, when it is not
named, the mismatch is reported under "unexplained" on that axis -- and no significant finding carries a name
that is neither expected nor an alternative (a confident wrong name).  A finding that names a wrong effect but
reports an expected one as ``confounded_with`` is one finding naming both, which the campaign cannot tell apart
(issue 13: "report both as one finding"): not a confident wrong name.
"""
from __future__ import annotations


def _names(e: dict) -> set[str]:
    return {e["name"], *e.get("alternatives", [])}


def out_of_reach(d, expect: list[dict]) -> list[str]:
    """Expected effects the answer states it cannot see in this campaign (a "not_separable" entry of that name or
    an alternative): honest, listed as out of reach in the docs's concealment table."""
    ns = {f.name for f in d.effects if f.get("not_separable")}
    return [e["name"] for e in expect if _names(e) & ns]


def judge(d, expect: list[dict]) -> tuple[bool, str]:
    """(right, one-line account) of the diagnosis ``d`` against ``expect``; an expected periodic error with an
    "alias_pitch" must carry its true pitch among the finding's "possible_alias" pitches."""
    sig = [f for f in d.effects if f.significant]
    allowed = set().union(*(_names(e) for e in expect)) if expect else set()
    wrong = [f"{f.name} {f.axis or ''}" for f in sig if f.name not in allowed
             and not any(x["name"] in allowed for x in f.get("confounded_with", []))]
    missing = []
    for e in expect:
        hit = any((f.name in _names(e) and (e.get("axis") in (None, f.axis) or f.name != e["name"])) or
                  any(c["name"] in _names(e) for c in f.get("confounded_with", [])) for f in sig)
        hit = hit or any(u.axis == e.get("axis", u.axis) for u in d.unexplained)
        if hit and "alias_pitch" in e:
            hit = any(abs(a["pitch"] - e["pitch"]) < 0.05 * e["pitch"]
                      for f in sig if f.name == "periodic" for a in f.get("possible_alias", []))
        if not hit:
            missing.append(e["name"])
    found = "; ".join(f"{f.name} {f.axis or ''} {f.get('where', '')}" +
                      (f" [confounded with {', '.join(c['name'] for c in f['confounded_with'])}]"
                       if f.get("confounded_with") else "") for f in sig)
    un = "; ".join(f"unexplained {u.axis} by {u.by}" for u in d.unexplained[:2])
    ok = not wrong and not missing
    reach = [m for m in missing if m in out_of_reach(d, expect)]
    verdict = ("right" if ok else "WRONG" if wrong else
               "out of reach (stated)" if reach == missing else "missed (nothing named)")
    alias = "; ".join(f"possible alias {[round(a['pitch'], 1) for a in f['possible_alias']]}"
                      for f in sig if f.get("possible_alias"))
    found = found + (f" ({alias})" if alias else "")
    return ok, (f"{verdict}: found [{found}]" + (f" {un}" if un else "") +
                (f" missing {missing}" if missing else "") + (f" wrong {wrong}" if wrong else ""))
