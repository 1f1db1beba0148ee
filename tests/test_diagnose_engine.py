"""The diagnosis engine's separability and overlap against plain least squares written here (the F test against
a plain least-squares F test: tests/test_diagnose.py)."""
from __future__ import annotations

import numpy as np

from mtcal.diagnose import Engine
from mtcal.diagnose.strata import against, lack_of_fit, pure_error


def test_engine_refuses_a_column_inside_the_base():
    rng = np.random.default_rng(1)
    X = rng.normal(size=(30, 3))
    eng = Engine([(np.arange(30), X)], rng.normal(size=30))
    s = eng.score(X @ np.array([[1.0], [2.0], [-1.0]]))
    assert not s.separable and s.sep < 1e-6
    # overlap after the base: |cos| between the two columns with the base projected out (written here)
    a, b = rng.normal(size=(30, 1)), rng.normal(size=(30, 1))
    b = b + 2.0 * a
    ra, rb = (v[:, 0] - X @ np.linalg.lstsq(X, v[:, 0], rcond=None)[0] for v in (a, b))
    cos = abs(ra @ rb) / (np.linalg.norm(ra) * np.linalg.norm(rb))
    assert abs(eng.overlap(a, b) - cos) < 1e-9 and 0.5 < cos < 1.0


def test_a_column_of_rounding_size_is_no_column():
    """A harmonic that vanishes at every measured position (cos 4q - 1 at q = 0, 90, 180, 270 deg) comes out as
    rounding, ~1e-13 of its neighbours.  Scaled to unit norm it was a column of noise: it took a degree of freedom
    and one planted campaign's block (mtcal's own generator, planted 18) failed the SVD with "did not converge"
    (a traceback out of `diagnose`).  It is dropped: the base keeps the columns that exist."""
    rng = np.random.default_rng(0)
    n = 40
    x = rng.normal(size=(n, 1))
    X = np.hstack([x, 1e-13 * rng.normal(size=(n, 1))])
    eng = Engine([(np.arange(n), X)], rng.normal(size=n))
    assert eng.p == 1


def test_many_located_levels_of_one_factor_are_one_entry():
    """scans.collapsed: five displaced rounds of X are one entry listing them, sized by the largest shift; two
    located positions stay two entries (MAX_LEVELS = 3)."""
    from mtcal.diagnose.scans import MAX_LEVELS, Located, collapsed

    rounds = [Located("X", "round", k, 10.0 + k, 10.0 ** -(10 + k), "mean", 3, 5.0, 1.0, 0.001 * k)
              for k in range(1, 6)]
    positions = [Located("X", "position", q, 4.0, 1e-4, "mean", 6, 3.0, 1.0, 0.002) for q in (100.0, 200.0)]
    out = collapsed(rounds + positions)
    assert MAX_LEVELS == 3 and len(out) == 3
    (one,) = [u for u in out if u.by == "round"]
    assert one.where == {"levels": [1, 2, 3, 4, 5]} and one.shift_mm == 0.005 and one.readings == 15
    assert one.p_adjusted == 1e-15 and "5 levels of round of axis X" in one.note
    assert sorted(u.where for u in out if u.by == "position") == [100.0, 200.0]


def test_columns_on_disjoint_blocks_score_as_the_same_columns_formed_whole():
    """Engine.score_blocks (every stop moving on its own: a thousand columns on a robot's recording) gives the
    F test of Engine.score on the same columns formed as one matrix, where together the blocks span a fitted column
    (each holds a constant on its rows; their sum is the base's offset: one direction dropped)."""
    rng = np.random.default_rng(3)
    n = 90
    X = np.hstack([np.ones((n, 1)), rng.normal(size=(n, 2))])
    eng = Engine([(np.arange(n), X)], rng.normal(size=n))
    eng.add(rng.normal(size=(n, 1)))
    blocks, dense = [], []
    for start in range(0, n, 6):  # fifteen blocks of six rows, two or three columns each
        rows = np.arange(start, start + 6)
        G = np.hstack([np.ones((6, 1)), rng.normal(size=(6, 1 + start % 12 // 6))])
        blocks.append((rows, np.linalg.qr(G)[0]))
        D = np.zeros((n, G.shape[1]))
        D[rows] = G
        dense.append(D)
    dense = np.hstack(dense)
    a, b = eng.score_blocks(blocks), eng.score(dense)
    assert a.k == b.k == dense.shape[1] - 1, (a.k, b.k)
    assert abs(a.delta - b.delta) < 1e-9 * b.delta and abs(a.logp - b.logp) < 1e-9 * abs(b.logp), (a, b)


def test_columns_beside_disjoint_blocks_score_as_beside_the_same_columns_formed_whole():
    """Engine.score_beside_blocks (a nest's step beside every stop moving rigidly: six columns a stop) gives the F
    test of Engine.score after the same block columns are added as one matrix: the same reduction, degrees of
    freedom and p, to round-off."""
    rng = np.random.default_rng(4)
    n = 90
    eng = Engine([(np.arange(n), np.hstack([np.ones((n, 1)), rng.normal(size=(n, 2))]))], rng.normal(size=n))
    blocks, dense = [], np.zeros((n, 0))
    for start in range(0, 60, 6):  # ten blocks of six rows, three columns each; the last 30 rows free
        rows = np.arange(start, start + 6)
        H = np.linalg.qr(rng.normal(size=(6, 3)))[0]
        blocks.append((rows, H))
        D = np.zeros((n, 3))
        D[rows] = H
        dense = np.hstack([dense, D])
    G = rng.normal(size=(n, 2))
    a = eng.score_beside_blocks(G, blocks)
    whole = eng.copy()
    whole.add(dense)
    b = whole.score(G)
    assert (a.k, a.dof) == (b.k, b.dof) == (2, n - 3 - 30 - 2), (a, b)
    assert abs(a.delta - b.delta) < 1e-9 * b.delta and abs(a.logp - b.logp) < 1e-9 * abs(b.logp), (a, b)


def _replicated(rng, sd_along: float, cells: int = 10, rounds: int = 4, others: int = 400):
    """A replicated design, whitened: ``cells`` stops read ``rounds`` times (three coordinates a reading, the first
    "along the beam" with standard deviation ``sd_along``, the others 1), and ``others`` readings elsewhere (sd 1
    in every coordinate).  The base: one translation of all readings.  G: a free mean per stop along the first
    coordinate (a reversal free per position).  Returns (engine, G, units, cells)."""
    n = cells * rounds + others
    y = rng.normal(size=(n, 3))
    y[:cells * rounds, 0] *= sd_along
    eng = Engine([(np.arange(3 * n), np.tile(np.eye(3), (n, 1)))], y.ravel())
    cell = np.repeat(np.arange(cells), rounds)
    G = np.zeros((3 * n, cells))
    G[3 * np.arange(cells * rounds), cell] = 1.0
    units = [(np.arange(3 * i, 3 * i + 3), np.eye(3)) for i in range(cells * rounds)]
    groups = [(np.concatenate([np.arange(3 * i, 3 * i + 3) for i in np.flatnonzero(cell == c)]),
               np.tile(np.eye(3), (rounds, 1)) / np.sqrt(rounds)) for c in range(cells)]
    return eng, G, units, groups


def test_lack_of_fit_against_the_replicates_holds_its_level_where_the_weights_are_off_in_shape():
    """Null true (no stop has a mean of its own), the first coordinate of the stops' readings 3 times noisier than
    the weights say (a law off in shape, an axis repeating worse along its motion): against the fit's residual
    (Engine.score, the residual mostly other readings at sd 1) the free form is "found" in most runs; against the
    replicates' own scatter (Engine.lack_of_fit, a pooled 3 x 3 covariance, Satterthwaite's degrees) at about the
    level.  The pure error's degrees are the readings' less the cells' (40 x 3 - 10 x 3 = 90); those of the test's
    denominator the units' less the cells' (40 - 10 = 30): G moves one coordinate, whose scatter 30 units estimate
    (with 90, as before, 11 of these 300 runs' successors rejected at 0.01; with 30, 3)."""
    rng = np.random.default_rng(5)
    plain = lof = 0
    runs = 300
    for _ in range(runs):
        eng, G, units, cells = _replicated(rng, 3.0)
        s = lack_of_fit(eng, G, units, cells)
        assert s is not None and s.dof == 30 and s.k == 10
        lof += s.logp < np.log(0.01)
        plain += eng.score(G).logp < np.log(0.01)
    assert plain > 0.5 * runs and lof < 0.03 * runs, (plain, lof)


def test_lack_of_fit_finds_a_mean_the_replicates_do_not_scatter_by():
    """The same design with one stop's mean off by 4 standard deviations of a reading along the first coordinate:
    found against the replicates (p < 1e-4), with the weights right (sd 1) or off (sd 3, the mean 12)."""
    rng = np.random.default_rng(6)
    for sd in (1.0, 3.0):
        eng, G, units, cells = _replicated(rng, sd)
        eng = Engine([(np.arange(eng.N), np.tile(np.eye(3), (eng.N // 3, 1)))], eng.y + 4 * sd * G[:, 3])
        assert lack_of_fit(eng, G, units, cells).logp < np.log(1e-4)


def _stops(rng, sd_stop: float, cells: int = 10, rounds: int = 4, nests: int = 3, others: int = 100):
    """A replicated design of whole stops, whitened: ``cells`` stops read ``rounds`` times, ``nests`` readings each
    (three coordinates, sd 1), every stop in one round landing off by a draw of sd ``sd_stop`` along the first
    coordinate that its readings share (an axis repeating worse); ``others`` readings elsewhere.  The base: one
    translation of all readings.  Returns (engine, the cells' means along the first coordinate (a reversal free
    per position), a contrast between the cells (a backlash: +1/2 at half of them, -1/2 at the others), one
    within the stops (the first nest against the second at every stop), units (a stop in one round), cells)."""
    units_n = cells * rounds
    n = units_n * nests + others
    y = rng.normal(size=(n, 3))
    y[:units_n * nests, 0] += np.repeat(rng.normal(scale=sd_stop, size=units_n), nests)
    eng = Engine([(np.arange(3 * n), np.tile(np.eye(3), (n, 1)))], y.ravel())
    unit = np.repeat(np.arange(units_n), nests)
    cell, nest = unit // rounds, np.tile(np.arange(nests), units_n)
    rows = 3 * np.arange(units_n * nests)
    free, member, within = np.zeros((3 * n, cells)), np.zeros((3 * n, 1)), np.zeros((3 * n, cells))
    free[rows, cell] = 1.0
    member[rows, 0] = np.where(cell % 2, 0.5, -0.5)
    within[rows, cell] = np.select([nest == 0, nest == 1], [1.0, -1.0], 0.0)
    block = lambda r: (np.concatenate([np.arange(3 * i, 3 * i + 3) for i in r]),  # noqa: E731
                       np.linalg.qr(np.tile(np.eye(3), (len(r), 1)))[0])
    units = [block(np.flatnonzero(unit == u)) for u in range(units_n)]
    groups = [block(np.flatnonzero(cell == c)) for c in range(cells)]
    return eng, free, member, within, units, groups


def test_a_member_and_its_place_are_tested_against_one_error_term_of_the_stops():
    """Null true (no stop has a mean of its own), every stop landing off from round to round by 3 sd of a reading
    (what its three nests share).  A backlash -- a contrast between stops -- tested against the readings' scatter
    (Engine.score, as a member was while its place's free form was tested against the stops': gen2 3515/12 named
    a backlash at F = 99.7) is "found" in 41 of 100 runs at 0.01; against the one error term of its place
    (Engine.pure_error on the fullest model: the member and the free form fitted) it holds the level, and so does
    the free form beside it, on the same degrees of freedom.  A contrast within the stops (one nest against another)
    is set against the readings' own scatter (the within-unit component E, about the unit's mean or, with the nests
    coded, the round x nest interaction): on bc347f2 Engine.lack_of_fit set it against the stops' means only, which
    it does not touch, and rejected it in 30 of 30 runs."""
    rng = np.random.default_rng(7)
    runs, plain, member_lof, free_lof, within_lof, nest_lof = 100, 0, 0, 0, 0, 0
    for _ in range(runs):
        eng, free, member, within, units, cells = _stops(rng, 3.0)
        full = eng.copy()
        full.add(member)
        beside = full.copy()
        full.add(free)
        err = pure_error(full, units, cells)
        a, b = against(eng, member, err), against(beside, free, err)
        assert a.dof == b.dof == 30, (a, b)  # the stops' scatter along the first coordinate: 40 units less 10 cells
        plain += eng.score(member).logp < np.log(0.01)
        member_lof += a.logp < np.log(0.01)
        free_lof += b.logp < np.log(0.01)
        within_lof += lack_of_fit(eng, within, units, cells).logp < np.log(0.01)
        codes = np.concatenate([np.tile(np.arange(3), 40), np.full(eng.N // 3 - 120, -1)])
        nest_lof += lack_of_fit(eng, within, units, cells, codes).logp < np.log(0.01)
    assert plain > 0.3 * runs and member_lof <= 0.03 * runs and free_lof <= 0.03 * runs, (plain, member_lof, free_lof)
    assert within_lof <= 0.03 * runs and nest_lof <= 0.03 * runs, (within_lof, nest_lof)


def test_a_member_against_the_stops_error_term_is_found_where_it_is_there():
    """The same design with a backlash of 3 sd of a reading planted (and the stops landing off by 1): found
    against the place's error term (p < 1e-4) in each of 10 runs."""
    rng = np.random.default_rng(8)
    for _ in range(10):
        eng, free, member, _, units, cells = _stops(rng, 1.0)
        eng = Engine([(np.arange(eng.N), np.tile(np.eye(3), (eng.N // 3, 1)))], eng.y + 3.0 * member[:, 0])
        full = eng.copy()
        full.add(np.hstack([member, free]))
        assert against(eng, member, pure_error(full, units, cells)).logp < np.log(1e-4)
