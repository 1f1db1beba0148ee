"""What measurement separates two candidates the campaign cannot tell apart (``confounded_with``'s
``separate_by``), generated from their grammar attributes (mtcal.diagnose.effects.Grammar), never from a table of
name pairs.

The first attribute in which the two differ decides the measurement, one short template per attribute:

1. *how* -- what they depend on (fx.HOW: the temperature, the direction of approach, the round, the time, the
   position; the first variable, in MEASURE_HOW's order, that one depends on and the other not): the measurement
   that varies that variable alone;
2. *where* -- the place they act (fx.WHERE): a reading that sees each place alone (WITNESS);
3. *what* -- what moves there (a translation, a rotation, an expansion): reflectors at several distances and
   offsets (a turn grows with the lever, an expansion with the distance, a shift does neither);
4. the *law* of the same dependence (a step or a gradual change in time; a periodic or a smooth error along the
   travel): the measurement that resolves that law.

Nothing differs: DEFAULT_SEPARATE.
"""
from __future__ import annotations

from mtcal.diagnose import effects as fx

DEFAULT_SEPARATE = "repeat the campaign with the axes in another order and from a second tracker station"

MEASURE_HOW = {  # in the order tried
    "temperature": "record a temperature that does not follow the warm-up (e.g. a pause or a cool-down)",
    "direction": "measure the axis bidirectionally in every round",
    "round": "measure the same positions again in another round",
    "time": "measure the first positions again at the end of the campaign and log the times",
    "position": "measure at more positions over the whole travel, at a finer, non-uniform step, in more rounds",
}
ON_WORDS = {"temperature": "the temperature", "direction": "the direction of approach", "round": "the round",
            "time": "the time", "position": "the position"}
WITNESS = {  # in the order the sentence names two places (the sentence is the same for (a, b) and (b, a))
    "air": "from a second station at a right angle to the first, with the air's temperature and pressure logged at "
           "the beam",
    "frame": "a fixed reference nest off the machine before and after each round",
    "side": "a second nest far from the others on the same side",
    "nest": "a second reflector in the same nest (or swap reflectors between nests)",
    "axis": "the axis again at the end of the campaign, or from a second tracker station",
    "reading": "the same stop again within the round",
}
WHAT_SHOWS = {"translation": "moves every reflector alike", "rotation": "grows with the lever (Abbe)",
              "expansion": "grows with the distance from its centre", "scatter": "differs from stop to stop at random"}
MEASURE_LAW = {"time": "log the times and measure the first positions again at the end of the campaign",
               "position": "measure at a finer, non-uniform position step (below half the shortest pitch)"}
LAW_WORDS = {fx.LAW_STEP: "is a step that stays", "ramp": "grows steadily", "lag": "grows and settles",
             "periodic": "repeats along the travel", "polynomial": "is smooth along the travel", "": "is constant"}


def separate_by(a: fx.Candidate, b: fx.Candidate) -> str:
    """The measurement that would separate candidates ``a`` and ``b`` (module docstring), a sentence."""
    ga, gb = a.grammar, b.grammar
    if ga is None or gb is None:
        return DEFAULT_SEPARATE
    for v in MEASURE_HOW:
        if (v in ga.how.on) != (v in gb.how.on):
            x, y = (a, b) if v in ga.how.on else (b, a)
            return f"{MEASURE_HOW[v]}: {x.title} changes with {_on(x)}, {y.title} " + (
                f"with {_on(y)} only" if y.grammar.how.on else "stays constant")
    if (ga.where.at, ga.where.key) != (gb.where.at, gb.where.key):
        x, y = sorted((a, b), key=lambda c: list(WITNESS).index(c.grammar.where.at))
        seen = WITNESS[x.grammar.where.at] + ("" if x.grammar.where.at == y.grammar.where.at
                                              else f", and {WITNESS[y.grammar.where.at]}")
        return f"measure {seen}: {x.title} moves {_at(x)}, {y.title} {_at(y)}"
    if ga.what != gb.what:
        return (f"measure with reflectors at several distances and offsets (from the axis, the tracker, the "
                f"side's centre): {a.title} {WHAT_SHOWS[ga.what]}, {b.title} {WHAT_SHOWS[gb.what]}")
    if ga.how.law != gb.how.law:
        v = "time" if "time" in ga.how.on else "position"
        return (f"{MEASURE_LAW[v]}: {a.title} {LAW_WORDS.get(ga.how.law, 'has its own law')}, "
                f"{b.title} {LAW_WORDS.get(gb.how.law, 'has its own law')}")
    return DEFAULT_SEPARATE


def _on(c: fx.Candidate) -> str:
    return " and ".join(ON_WORDS[v] for v in MEASURE_HOW if v in c.grammar.how.on)


def _at(c: fx.Candidate) -> str:
    """Words for where ``c`` acts."""
    w = c.grammar.where
    of = f" of station {w.station}" if w.station else ""
    return {"axis": f"the error motions of {w.key}", "side": f"the {w.key} side's nests",
            "nest": f"the nest of {w.key}", "frame": f"every reading about the tracker{of}",
            "air": "every distance about its station", "reading": "one reading"}[w.at]
