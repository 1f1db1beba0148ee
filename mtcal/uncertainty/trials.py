"""One Monte Carlo trial: the recording's readings drawn from their PDFs (mtcal.uncertainty.inputs), the same
estimator the user ran (``identify`` with the same options: method, tracker, degree selection), and the trial's
output vector (the layout ``Outputs``).  Trial k draws from ``np.random.default_rng([seed, k])``: its result does
not depend on which worker runs it, or in which order."""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from mtcal.errors import InputError
from mtcal.measurement import tracker as trk
from mtcal.measurement.recordings import Recording
from mtcal.model.errormodel import ErrorModel
from mtcal.uncertainty.inputs import Inputs


@dataclass
class Outputs:
    """Where each output sits in a trial's vector: every error function at its table positions (mm or rad; the
    fitted function the model evaluates -- reported with its table values' statistics where the degree selection
    set it to zero, mtcal.uncertainty.run.zero_fits -- or with ``tables`` the table values, linear in the
    readings), every
    constant, and the tool tip's first-order deviation (x, y, z, mm) at each of ``poses`` (n, n_axes); for the
    fitted functions also their table values (``shadow``, not reported: mtcal.uncertainty.run.zero_fits)."""

    functions: dict[str, tuple[str, np.ndarray, slice]]
    constants: dict[str, int]
    poses: np.ndarray
    volumetric: slice
    size: int
    tables: bool = False
    shadow: slice = field(default_factory=lambda: slice(0, 0))  # fitted functions' table values (``zero_fits``)

    @classmethod
    def of(cls, model: ErrorModel, poses: np.ndarray, tables: bool = False) -> "Outputs":
        k, funcs, consts = 0, {}, {}
        for n, f in sorted(model.functions.items()):
            funcs[n] = (f.axis, f.positions.copy(), slice(k, k + len(f.positions)))
            k += len(f.positions)
        n_values = k
        for n in sorted(model.constants):
            consts[n] = k
            k += 1
        vol = slice(k, k + 3 * len(poses))
        shadow = slice(vol.stop, vol.stop + (0 if tables else n_values))
        return cls(funcs, consts, np.asarray(poses, dtype=float), vol, shadow.stop, tables, shadow)

    def vector(self, model: ErrorModel) -> np.ndarray:
        """A trial's model as the output vector (an error the trial's model lacks is 0, as the model file says)."""
        out = np.zeros(self.size)
        for n, (_, pos, sl) in self.functions.items():
            f = model.functions.get(n)
            out[sl] = 0.0 if f is None else np.interp(pos, f.positions, f.values) if self.tables else f(pos, "hold")
            if f is not None and not self.tables:
                out[self.shadow.start + sl.start:self.shadow.start + sl.stop] = np.interp(pos, f.positions, f.values)
        for n, i in self.constants.items():
            out[i] = model.constants.get(n, 0.0)
        m = model.kinematics
        if len(self.poses):
            out[self.volumetric] = m.deviation(self.poses, model.errors_at(m, self.poses, "hold"))[:, :3].ravel()
        return out


@dataclass
class Prepared:
    """What every trial's ``draw`` shares: the Cholesky factors (n, 3, 3) of the readings' noise covariance (None:
    the law is off), each station's rows, each row's reflector (index into the sorted labels) and their count."""

    factor: np.ndarray | None
    stations: list[np.ndarray]
    label_index: np.ndarray
    labels: int


def prepare_draw(rec: Recording, trackers: np.ndarray, inputs: Inputs) -> Prepared:
    """``Prepared`` for ``draw`` (computed once for many trials)."""
    spec = inputs.noise
    factor = None
    if spec.radial_um or spec.radial_um_per_m or spec.transverse_um or spec.transverse_um_per_m:
        factor = np.linalg.cholesky(trk.covariance(rec.xyz, trackers, spec))
    st = rec.stations()
    labels = np.unique(rec.point)
    return Prepared(factor, [st == s for s in np.unique(st)], np.searchsorted(labels, rec.point), len(labels))


def draw(rec: Recording, trackers: np.ndarray, inputs: Inputs, rng: np.random.Generator,
         prepared: Prepared | None = None) -> np.ndarray:
    """One draw of the readings (n, 3) mm: the recorded values plus the tracker noise (about each row's tracker
    ``trackers`` (n, 3)), each station's scale error about its tracker, each reflector's centring offset and the
    structure's thermal expansion about the machine origin; ``prepared``: ``prepare_draw`` of these, shared by many
    trials."""
    xyz = rec.xyz.copy()
    pre = prepare_draw(rec, trackers, inputs) if prepared is None else prepared
    if pre.factor is not None:  # as mtcal.measurement.tracker.sample
        xyz += np.einsum("...ij,...j->...i", pre.factor, rng.standard_normal(rec.xyz.shape))
    if inputs.scale_u:
        for on in pre.stations:
            xyz[on] += rng.normal(0.0, inputs.scale_u) * (rec.xyz[on] - trackers[on])
    if inputs.centring_u_um:
        off = rng.normal(0.0, inputs.centring_u_um * 1e-3, (pre.labels, 3))
        xyz += off[pre.label_index]
    if inputs.material_temperature_u_k:
        xyz += rng.normal(0.0, inputs.material_temperature_u_k) * inputs.alpha_per_k * rec.xyz
    return xyz


def draw_many(rec: Recording, trackers: np.ndarray, inputs: Inputs, seed: int, ks: list[int],
              prepared: Prepared | None = None) -> np.ndarray:
    """``draw`` of trials ``ks`` (each from ``np.random.default_rng([seed, k])``, the same numbers in the same
    order) at once: (len(ks), n, 3) mm, trials last in memory (a transposed view); the arithmetic is batched over
    the trials (the batched path's draw, mtcal.uncertainty.fast)."""
    pre = prepare_draw(rec, trackers, inputs) if prepared is None else prepared
    t, n = len(ks), len(rec)
    z = np.zeros((n, 3, t))  # trials last: the products below are (n, 3, 3) @ (n, 3, T)
    scale = np.zeros((len(pre.stations), t))
    off = np.zeros((pre.labels, 3, t))
    temp = np.zeros(t)
    for i, k in enumerate(ks):  # the draws of trial k in draw's order
        rng = np.random.default_rng([seed, k])
        if pre.factor is not None:
            z[..., i] = rng.standard_normal(rec.xyz.shape)
        if inputs.scale_u:
            scale[:, i] = [rng.normal(0.0, inputs.scale_u) for _ in pre.stations]
        if inputs.centring_u_um:
            off[..., i] = rng.normal(0.0, inputs.centring_u_um * 1e-3, (pre.labels, 3))
        if inputs.material_temperature_u_k:
            temp[i] = rng.normal(0.0, inputs.material_temperature_u_k)
    xyz = np.matmul(pre.factor, z) if pre.factor is not None else z
    xyz += rec.xyz[..., None]
    if inputs.scale_u:
        station = np.zeros(n, dtype=int)
        for j, on in enumerate(pre.stations):
            station[on] = j
        xyz += scale[station][:, None, :] * (rec.xyz - trackers)[..., None]
    if inputs.centring_u_um:
        xyz += off[pre.label_index]
    if inputs.material_temperature_u_k:
        xyz += (temp * inputs.alpha_per_k)[None, None, :] * rec.xyz[..., None]
    return xyz.transpose(2, 0, 1)


def trackers_of(rec: Recording, tracker) -> np.ndarray:
    """Each row's tracker position (n, 3) mm: the recording's columns, else the one given; refuses neither."""
    if rec.tracker_xyz is not None:
        return np.asarray(rec.tracker_xyz, dtype=float)
    if tracker is None:
        raise InputError(f"{rec.source}: the Monte Carlo draws each reading about its tracker: give the tracker "
                         f"position (`tracker`) or the tracker_x,y,z columns")
    return np.broadcast_to(np.asarray(tracker, dtype=float).reshape(3), rec.xyz.shape).copy()


def trial_block(rec: Recording, trackers: np.ndarray, inputs: Inputs, options: dict, outputs: Outputs,
                 seed: int, ks: list[int]) -> tuple[list[int], np.ndarray]:
    """Trials ``ks`` of the full path (each runs ``identify`` on readings drawn with seed ``[seed, k]``; on a
    worker or in this process): their output vectors (len(ks), size)."""
    from dataclasses import replace

    from mtcal.identify.run import identify

    out = np.empty((len(ks), outputs.size))
    quiet = logging.getLogger("mtcal")
    level = quiet.level
    quiet.setLevel(logging.ERROR)  # a trial's progress is not the user's (restored: --workers 0 runs in-process)
    prepared = prepare_draw(rec, trackers, inputs)
    try:
        for i, k in enumerate(ks):
            xyz = draw(rec, trackers, inputs, np.random.default_rng([seed, k]), prepared)
            out[i] = outputs.vector(identify(replace(rec, xyz=xyz), worth=False, **options).model)
    finally:
        quiet.setLevel(level)
    return ks, out
