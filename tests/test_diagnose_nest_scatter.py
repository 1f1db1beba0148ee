"""A reflector that scatters more than the law at every reading (dirty, chipped, a weak return) is no outlier and no
re-seated reflector: a displacement of some readings of one nest in one round is a contrast between that nest's
readings, tested against their own scatter (mtcal.diagnose.selection._within_its_scatter, strata.against).  The extra
scatter is made here from the physics: every reading of one nest moves by independent normal errors along its beam
and across it, a few times the AT960's, written on the simulated recording; a single gross reading at an ordinary
nest is still an outlier."""
from __future__ import annotations

from dataclasses import replace

import campaigns as C
import numpy as np
import pytest

from mtcal.diagnose import diagnose

pytestmark = pytest.mark.slow  # two diagnoses each: 5-15 s

ROUND_NAMES = {"outlier", "offset"}  # the members that move some readings of one nest in one round


def _dirty(c: C.Campaign, point: str, along_um: float, across_um: float, seed: int):
    """The campaign's recording with every reading of nest ``point`` scattered by a further ``along_um`` along its
    beam (from the true tracker) and ``across_um`` across it (1 sigma, independent per reading)."""
    rec = c.recording
    rng = np.random.default_rng(seed)
    on = rec.point == point
    u = rec.xyz[on] - np.asarray(c.tracker_true)
    u /= np.linalg.norm(u, axis=1)[:, None]
    a = np.cross(u, [0.0, 0.0, 1.0])
    a /= np.linalg.norm(a, axis=1)[:, None]
    b = np.cross(u, a)
    n = int(on.sum())
    xyz = rec.xyz.copy()
    xyz[on] += 1e-3 * (along_um * rng.standard_normal(n)[:, None] * u
                       + across_um * (rng.standard_normal(n)[:, None] * a + rng.standard_normal(n)[:, None] * b))
    return replace(rec, xyz=xyz)


@pytest.mark.parametrize("seed", [1, 2])
def test_a_reflector_scattering_beyond_the_law_is_no_outlier_and_no_reseated_nest(seed):
    c = C.make(C.Design(rounds=4), (), seed)
    point = str(c.recording.point[np.flatnonzero(c.recording.axis == "C")[0]])  # a nest the rotary axes read
    rec = _dirty(c, point, 4.0, 10.0, seed)
    for tracker in (c.tracker, None):
        d = diagnose(rec, tracker=tracker)
        named = [(f.name, f.get("point")) for f in d.effects if f.significant and f.name in ROUND_NAMES]
        assert named == [], (tracker, named, [f.get("where") for f in d.effects if f.significant])


def _shaken(c: C.Campaign, t0: float, t1: float, angular_urad: float, radial_um: float, seed: int):
    """The campaign's recording with every reading between ``t0`` and ``t1`` s scattered across its beam by
    ``angular_urad`` times its distance from the true tracker and along it by ``radial_um`` (1 sigma per
    direction): the stand shaking."""
    rec = c.recording
    rng = np.random.default_rng(seed)
    on = (rec.time_s >= t0) & (rec.time_s <= t1)
    d = rec.xyz[on] - np.asarray(c.tracker_true)
    L = np.linalg.norm(d, axis=1)
    u = d / L[:, None]
    a = np.cross(u, [0.0, 0.0, 1.0])
    a /= np.linalg.norm(a, axis=1)[:, None]
    b = np.cross(u, a)
    s = angular_urad * 1e-6 * L[:, None]
    xyz = rec.xyz.copy()
    xyz[on] += s * (rng.standard_normal(len(L))[:, None] * a + rng.standard_normal(len(L))[:, None] * b)
    xyz[on] += 1e-3 * radial_um * rng.standard_normal(len(L))[:, None] * u
    return replace(rec, xyz=xyz), on


@pytest.mark.parametrize("seed", [1, 2])
def test_readings_of_a_while_the_stand_shook_are_no_outliers(seed):
    """The tracker's stand shaking for two minutes (a forklift passing): every reading then scatters 3 urad across
    its beam and 3 um along it, seven times the AT960's.  Its largest readings are no outliers: against the
    readings nearest them in time they are not beyond the scatter."""
    c = C.make(C.Design(rounds=4), (), seed)
    t = c.recording.time_s
    t0 = float(np.quantile(t, 0.6))
    rec, on = _shaken(c, t0, t0 + 120.0, 3.0, 3.0, seed)
    assert on.sum() >= 15
    for tracker in (c.tracker, None):
        d = diagnose(rec, tracker=tracker)
        named = [(f.name, f.get("where")) for f in d.effects if f.significant and f.name in ROUND_NAMES]
        assert named == [], (tracker, named)
