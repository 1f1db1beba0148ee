"""GUM Supplement 1 Monte Carlo through the whole estimator: ``monte_carlo(rec, ...)``.

Each trial draws the recording's readings from their PDFs (mtcal.uncertainty.inputs), runs ``identify`` with the
options the user ran it with (method, tracker, degree selection: the whole nonlinear estimator) and keeps the
model's errors at their table positions, its constants and the tool tip's deviation at a fixed set of poses.
Trials run on Dask (``dask.distributed``): a local cluster of processes by default (no set-up), or an existing
cluster (``scheduler`` address).  Trial k is seeded from (seed, k), so the result is the same whatever the number of
workers and their order.  Results go to a store (``store``, an .npz written atomically) that a later run extends;
Ctrl-C keeps what is done.

Reduction (GUM-S1 7.7): the estimate is the mean, the standard uncertainty the standard deviation of the trials,
coverage intervals for probability p from the order statistics: probabilistically symmetric (the (1-p)/2 and
(1+p)/2 quantiles) and shortest (the narrowest window holding p of the trials); an error function the degree
selection sets to zero is stated with its table values' intervals (``zero_fits``).  Adaptive stopping (GUM-S1 7.9):
trials in stages of ``stage`` until twice the standard deviation of the stages' interval limits is below the
numerical tolerance (``tolerance_mm``; angles scaled by 1/1000 mm, i.e. 1 urad as 1 um)."""
from __future__ import annotations

import logging
import os
import signal
import time
import zipfile
import zlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mtcal.errors import InputError
from mtcal.io import atomic_open, replace_allowed
from mtcal.measurement.recordings import Recording
from mtcal.uncertainty.inputs import TERMS, Inputs
from mtcal.uncertainty.trials import Outputs, trackers_of, trial_block

log = logging.getLogger(__name__)
BATCH = 4  # trials per Dask task: a task runs ~1-4 s


class Store:
    """The trials done: their indices and output vectors, with what they were drawn under (``key``) and the
    readings they were drawn about (``recording_sha256``, ``readings_sha256``).  Blocks added are joined when read
    (10^5 trials arrive in 500 blocks)."""

    def __init__(self, key: str, index: np.ndarray, values: np.ndarray, recording_sha256: str = ""):
        self.key, self.recording_sha256 = key, recording_sha256
        self._parts = [(np.asarray(index, dtype=np.int64), np.asarray(values, dtype=float))]

    def _joined(self) -> tuple[np.ndarray, np.ndarray]:
        if len(self._parts) > 1:
            self._parts = [(np.concatenate([i for i, _ in self._parts]), np.vstack([v for _, v in self._parts]))]
        return self._parts[0]

    @property
    def index(self) -> np.ndarray:
        return self._joined()[0]

    @property
    def values(self) -> np.ndarray:
        return self._joined()[1]

    def __len__(self) -> int:
        return sum(len(i) for i, _ in self._parts)

    @classmethod
    def load(cls, path: Path | None, key: str, size: int, recording_sha256: str = "") -> "Store":
        """The store at ``path`` (empty when there is none); refused (InputError, one line) when it is not a
        readable trial store, or was drawn from another recording, seed, options or output layout."""
        if path is None or not Path(path).exists():
            return cls(key, np.zeros(0, dtype=np.int64), np.zeros((0, size)), recording_sha256)
        try:
            with np.load(path, allow_pickle=False) as z:
                stored = {k: z[k] for k in z.files}
        except (OSError, ValueError, EOFError, zipfile.BadZipFile, zlib.error) as e:  # truncated, not an npz
            raise InputError(f"{path}: not a readable trial store of `mtcal uncertainty` ({type(e).__name__}: {e}); "
                             f"remove it or give another `store`") from None
        index, values = stored.get("index"), stored.get("values")
        if ("key" not in stored or index is None or values is None or index.ndim != 1 or values.ndim != 2
                or len(index) != len(values) or not np.issubdtype(index.dtype, np.integer)):
            raise InputError(f"{path}: not a trial store of `mtcal uncertainty` (its arrays key, index, values are "
                             f"missing or of the wrong shape); remove it or give another `store`")
        theirs = str(stored["recording_sha256"]) if "recording_sha256" in stored else ""
        if str(stored["key"]) != key:
            what = ("another recording (readings sha256 " + theirs[:12] + ", this one " + recording_sha256[:12] + ")"
                    if theirs and recording_sha256 and theirs != recording_sha256 else
                    "another seed, options or noise law, or kept another layout of outputs (an older mtcal)")
            raise InputError(f"{path}: its trials were drawn from {what}; give a new store (or the same inputs) "
                             f"to extend it")
        if values.shape[1] != size or not np.all(np.isfinite(values)):
            raise InputError(f"{path}: a trial store with {values.shape[1]} outputs per trial where {size} are "
                             f"expected, or with a non-finite value: corrupt; remove it or give another `store`")
        return cls(key, index.astype(np.int64), values, recording_sha256)

    def save(self, path: Path | None) -> None:
        """Write the trials to ``path`` atomically; an existing file there is the store ``load`` read and checked
        (a trial store of these inputs), so extending it replaces it even where mtcal's ledger does not know it
        (a store copied from another machine)."""
        if path is None:
            return
        with replace_allowed(), atomic_open(path, "wb") as fh:
            np.savez(fh, key=np.array(self.key), index=self.index, values=self.values,
                     recording_sha256=np.array(self.recording_sha256))

    def add(self, ks: list[int], v: np.ndarray) -> None:
        self._parts.append((np.asarray(ks, dtype=np.int64), np.asarray(v, dtype=float)))


def cores() -> int:
    """The cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def local_workers(workers: int | None) -> int:
    """The local worker processes to start: ``workers`` (default: the cores), capped at the cores with a warning
    (each worker is a process and its nanny: more than the cores only share them, and hundreds exhaust the
    process limit)."""
    n = cores()
    if workers is None:
        return n
    if workers > n:
        log.warning("warning: `workers` %d is more than this machine's %d cores: running %d worker processes (more "
                    "would only share the cores; a cluster: `scheduler`)", workers, n, n)
        return n
    return workers


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during the trials: what was kept (its message is the CLI's one line)."""


def _client(workers: int | None, scheduler: str | None):
    """A Dask client: the cluster at ``scheduler``, else a local cluster of ``workers`` processes (default: the
    machine's cores, capped there: ``local_workers``).  The worker processes are started with SIGINT blocked
    (the mask is inherited): Ctrl-C reaches this process only, which stops them; a Ctrl-C during the start-up is
    raised here once the cluster is up."""
    from dask.distributed import Client, LocalCluster

    if scheduler:
        return Client(scheduler), None
    n = local_workers(workers)
    from multiprocessing import resource_tracker

    resource_tracker.ensure_running()  # now: starting it unblocks SIGINT in the thread that does (CPython 3.11)
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    cluster = client = None
    try:
        import dask

        # glibc's own (dynamic) mmap threshold for the workers: Dask's MALLOC_TRIM_THRESHOLD_ fixes it at 128 kB, so
        # each block's arrays are mapped and unmapped afresh: 480 instead of 681 batched trials per CPU-second, the
        # system time doubled (benchmarks/uncertainty_mc.py one-core with and without it)
        with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}):
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                                   silence_logs=logging.CRITICAL)  # a heartbeat in flight as the cluster closes
            # logged a worker's traceback after a finished run (seen once in 3 runs of 10^5 trials); a task's error
            # reaches this process as its exception
        client = Client(cluster)
    finally:
        try:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)  # a pending Ctrl-C is raised here
        except KeyboardInterrupt:
            _close(client, cluster)
            raise
    return client, cluster


def _close(client, cluster) -> None:
    """Close a Dask client and its local cluster quietly (after Ctrl-C Dask logs the cancelled tasks)."""
    quiet = [logging.getLogger(n) for n in ("distributed", "tornado", "asyncio")]
    levels = [q.level for q in quiet]
    for q in quiet:
        q.setLevel(logging.CRITICAL + 1)
    try:
        for c in (client, cluster):
            if c is not None:
                try:
                    c.close()
                except Exception:  # noqa: BLE001 - shutting down after an interrupt: nothing left to save
                    pass
    finally:
        for q, lv in zip(quiet, levels):
            q.setLevel(lv)


def run_trials(rec: Recording, ks: list[int], *, inputs: Inputs, options: dict, outputs: Outputs, seed: int,
               store: Store, store_path: Path | None, workers: int | None = None, scheduler: str | None = None,
               progress=None, fast=None) -> None:
    """Run trials ``ks`` into ``store`` (saved as blocks arrive and on the way out; Ctrl-C keeps what is done and
    raises ``Interrupted`` saying so).  ``fast``: the batched path (mtcal.uncertainty.fast.Batched), else each
    trial runs ``identify``."""
    if not ks:
        return
    trackers = trackers_of(rec, options.get("tracker"))
    size = BATCH if fast is None else fast.block
    blocks = [ks[i:i + size] for i in range(0, len(ks), size)]
    before = len(store)
    try:
        saver = _Saver(store, store_path)
        started = None if workers == 0 else _start(workers, scheduler)
        if started is None:  # in this process (tests, debugging; a local cluster that failed to start, said)
            for b in blocks:
                res = _block(rec, trackers, inputs, options, outputs, seed, b, fast)
                store.add(*res[:2])
                if fast is not None:
                    fast.merge(res[2])
                if progress:
                    progress(len(b))
                saver.tick()
            return
        _on_dask(rec, trackers, inputs, options, outputs, seed, blocks, store, saver, started, progress, fast)
    except KeyboardInterrupt:
        store.save(store_path)
        done = len(store) - before
        raise Interrupted(f"{done} trials of this run done" + (f", {len(store)} kept in {store_path} (a "
                                                               f"later run with the same inputs extends them)"
                                                               if store_path else " (give `store` to keep trials)")
                          ) from None
    finally:
        store.save(store_path)


def _block(rec, trackers, inputs, options, outputs, seed, ks, fast):
    """Trials ``ks`` on a worker: (ks, their output vectors, the batched path's counts or None)."""
    if fast is None:
        return (*trial_block(rec, trackers, inputs, options, outputs, seed, ks), None)
    from mtcal.uncertainty.fast import fast_block

    return fast_block(fast, rec, trackers, inputs, options, outputs, seed, ks)


class _Saver:
    """Saves the store as blocks arrive: every 30 s, or less often where a save takes longer (at most a tenth of
    the time: 10^5 trials of the demo campaign are ~1 GB)."""

    def __init__(self, store: Store, path: Path | None):
        self.store, self.path, self.last, self.cost = store, path, time.monotonic(), 0.0

    def tick(self) -> None:
        if self.path is None or time.monotonic() - self.last <= max(30.0, 10 * self.cost):
            return
        t = time.monotonic()
        self.store.save(self.path)
        self.last = time.monotonic()
        self.cost = self.last - t


CLUSTER_START_ERRORS = (RuntimeError, OSError, TimeoutError)  # "Nanny failed to start", fork / file limits, timeouts


def _start(workers: int | None, scheduler: str | None):
    """(client, cluster) of ``_client``; None when a local cluster fails to start (Dask's "Nanny failed to start"
    on a loaded machine, a process or file limit, a start-up timeout): said on its own line (the library's log,
    stderr under the CLI), and the caller runs the trials in this process -- the same result, trial k being seeded
    from (seed, k), only slower.  A cluster at ``scheduler`` that cannot be reached is not replaced: its OSError
    is the CLI's one line naming the address."""
    if scheduler:
        return _client(workers, scheduler)
    try:
        return _client(workers, scheduler)
    except CLUSTER_START_ERRORS as exc:
        log.warning("warning: the local Dask cluster failed to start (%s: %s): running the trials in this process "
                    "instead, on one core (as --workers 0)", type(exc).__name__,
                    (str(exc).splitlines() or ["no message"])[0])
        return None


def _on_dask(rec, trackers, inputs, options, outputs, seed, blocks, store, saver, started, progress,
             fast) -> None:
    from dask.distributed import as_completed

    client, cluster = started
    try:
        args = [client.scatter(x, broadcast=True) for x in (rec, trackers, inputs, options, outputs)]
        fa = None if fast is None else client.scatter(fast, broadcast=True)
        futures = [client.submit(_block, *args, seed, b, fa, pure=False) for b in blocks]
        for fut in as_completed(futures):
            res = fut.result()
            store.add(*res[:2])
            if fast is not None:
                fast.merge(res[2])
            if progress:
                progress(len(res[0]))
            saver.tick()
    finally:
        _close(client, cluster)


# ---------------------------------------------------------------------------------------------- reduction
def intervals(samples: np.ndarray, p: float = 0.95) -> dict[str, np.ndarray]:
    """GUM-S1 7.7 over the trials (axis 0): mean, standard uncertainty, the probabilistically symmetric interval
    (lo, hi) and the shortest one (lo_short, hi_short) for probability ``p``."""
    x = np.sort(samples, axis=0)
    n = len(x)
    q = int(round(p * n))
    lo, hi = x[int(np.floor((1 - p) / 2 * n))], x[min(n - 1, int(np.ceil((1 + p) / 2 * n)) - 1)]
    width = x[q - 1:] - x[:n - q + 1]
    j = np.argmin(width, axis=0)
    cols = np.arange(x.shape[1])
    return {"mean": samples.mean(axis=0), "u": samples.std(axis=0, ddof=1), "lo": lo, "hi": hi,
            "lo_short": x[j, cols], "hi_short": x[j + q - 1, cols]}


def zero_fits(stats: dict[str, np.ndarray], outputs: Outputs, model) -> dict[str, np.ndarray]:
    """An error function the degree selection set to zero (``model``'s fit of degree 0: nothing above the noise)
    stated with its table values' interval instead of the trials' fits, which also come out (nearly) zero: the
    error is zero within what the readings resolve, not zero exactly.  Over 240 campaigns of the demo's machine
    from one station the fitted functions' 95 % intervals held the truth 91.9 % of the time without this, 95.4 %
    with it (benchmarks/uncertainty_mc.py coverage, docs/guide/uncertainty.md)."""
    if outputs.shadow.stop == outputs.shadow.start:
        return stats
    out = {k: v.copy() for k, v in stats.items()}
    n = outputs.shadow.start
    for name, (_, _, sl) in outputs.functions.items():
        f = model.functions.get(name)
        if f is None or f.fit is None or getattr(f.fit, "degree", getattr(f.fit, "harmonics", 1)) == 0:
            tab = slice(n + sl.start, n + sl.stop)
            for k in out:
                out[k][sl] = stats[k][tab]
    return out


@dataclass
class UncertaintyResult:
    """The Monte Carlo's answer: per error, constant and pose the estimate and its intervals (mm and rad).

    ``to_dict()`` is the JSON of `mtcal uncertainty`: ``errors`` {name: axis, positions, mean, u, lo95, hi95,
    shortest interval}, ``constants``, ``volumetric`` (the tool tip's deviation at the poses).

    Attributes
    ----------
    trials : int
        Trials run.
    seed : int
        The seed of the draws.
    p : float
        Coverage probability of the intervals (0.95).
    inputs : dict
        The input quantities' laws (tracker noise, length scale, centring, ...) and the estimator.
    outputs : Outputs
        What each column of ``stats`` is (error functions at positions, constants, poses).
    stats : dict of str to numpy.ndarray
        Per output column: ``mean``, ``u`` (standard uncertainty), ``lo``/``hi`` (probabilistically symmetric
        interval), ``lo_short``/``hi_short`` (shortest interval), mm and rad.
    budget : dict of str to dict
        {input term: u of each output} when asked (``budget=True``).
    convergence : list of dict
        The interval limits' spread after each stage (adaptive runs).
    seconds : float
        Wall time.
    model_sha256 : str
        The identified model the trials vary (``ErrorModel.digest``): a file of these trials is taken only with
        this model.
    path : dict
        Which path ran the trials: batched (mtcal.uncertainty.fast) or identify's, and the trials of each.
    """

    trials: int
    seed: int
    p: float
    inputs: dict
    outputs: Outputs
    stats: dict[str, np.ndarray]
    budget: dict[str, dict] = field(default_factory=dict)
    convergence: list[dict] = field(default_factory=list)
    seconds: float = 0.0
    model_sha256: str = ""  # the identified model the trials vary (ErrorModel.digest)
    path: dict = field(default_factory=dict)  # batched or full path, and the trials of each (mtcal.uncertainty.fast)

    def to_dict(self) -> dict:
        s, o = self.stats, self.outputs

        def pick(sl):
            return {"mean": s["mean"][sl].tolist(), "u": s["u"][sl].tolist(), "lo95": s["lo"][sl].tolist(),
                    "hi95": s["hi"][sl].tolist(), "lo95_shortest": s["lo_short"][sl].tolist(),
                    "hi95_shortest": s["hi_short"][sl].tolist()}

        errors = {n: {"axis": ax, "positions": pos.tolist(), **pick(sl)} for n, (ax, pos, sl) in o.functions.items()}
        consts = {n: {k: float(v[0]) for k, v in pick(slice(i, i + 1)).items()} for n, i in o.constants.items()}
        vol = pick(o.volumetric)
        n = len(o.poses)
        out = {"trials": self.trials, "seed": self.seed, "p": self.p,
               "units": {"length": "mm", "angle": "rad", "positions": "mm or deg"}, "inputs": self.inputs,
               "errors": errors, "constants": consts,
               "volumetric": {"poses": o.poses.tolist(), "deviation_xyz_mm": {k: np.reshape(v, (n, 3)).tolist()
                                                                              for k, v in vol.items()},
                              "u95_max_mm": float(np.max(np.reshape(np.array(vol["hi95"]) - np.array(vol["lo95"]),
                                                                    (n, 3))) / 2) if n else 0.0},
               "seconds": self.seconds, "path": self.path,
               "provenance": {"model_sha256": self.model_sha256}}
        if self.budget:
            out["budget"] = self.budget
        if self.convergence:
            out["convergence"] = self.convergence
        return out


def program_poses(program: str | Path, machine, n: int | None = None) -> np.ndarray:
    """The nominal axes (m, n_axes) of a G-code program's moves, at most ``n`` of them evenly spread (default
    mtcal.compensate.run.TASK_POSES; the poses of the task-specific uncertainty: the tool tip of this program after
    compensation, which `compensate --uncertainty` matches them against)."""
    from mtcal.compensate.run import TASK_POSES, task_poses

    return task_poses(program, machine, TASK_POSES if n is None else n)


def default_poses(machine, model, n: int = 100, seed: int = 0) -> np.ndarray:
    """``n`` random poses (n, n_axes) inside every error function's measured range (the rotary axes' too)."""
    rng = np.random.default_rng(seed)
    q = np.zeros((n, len(machine.axes)))
    for i, a in enumerate(machine.axes):
        pos = [f.positions for f in model.functions.values() if f.axis == a]
        if pos:
            lo, hi = max(p.min() for p in pos), min(p.max() for p in pos)
            q[:, i] = rng.uniform(lo, hi, n)
    return q


def readings_sha256(rec: Recording) -> str:
    """sha256 of what a trial draws about: the readings, their positions, axes, points, rounds and trackers."""
    import hashlib

    h = hashlib.sha256()
    for a in (rec.xyz, rec.position, rec.round, rec.tracker_xyz):
        h.update(b"-" if a is None else np.ascontiguousarray(a).tobytes())
    for a in (rec.axis, rec.point):
        h.update("\x1f".join(map(str, a)).encode())
    return h.hexdigest()


def _key(rec: Recording, seed: int, options: dict, inputs: Inputs, outputs: Outputs) -> str:
    """What a store's trials were drawn under: the readings, seed, estimator options, inputs and output layout."""
    import hashlib

    h = hashlib.sha256()
    for part in (rec.xyz.tobytes(), rec.position.tobytes(), repr(seed), repr(sorted((k, repr(v)) for k, v in
                                                                                   options.items())),
                 repr(inputs), repr(sorted(outputs.functions)), outputs.poses.tobytes(), repr(outputs.tables),
                 repr(outputs.size)):
        h.update(part if isinstance(part, bytes) else part.encode())
    return h.hexdigest()


def _angular(outputs: Outputs) -> np.ndarray:
    """True where an output is an angle (rad): errors and constants named E_A.., E_B.., E_C.."""
    a = np.zeros(outputs.size, dtype=bool)
    n0 = outputs.shadow.start
    for n, (_, _, sl) in outputs.functions.items():
        a[sl] = n[2] in "ABC"
        if outputs.shadow.stop > n0:  # the table values of the fitted functions (zero_fits)
            a[n0 + sl.start:n0 + sl.stop] = n[2] in "ABC"
    for n, i in outputs.constants.items():
        a[i] = n[2] in "ABC"
    return a


def _stage_spread(values: np.ndarray, stage: int, p: float, scale: np.ndarray) -> float:
    """GUM-S1 7.9.4: twice the standard deviation of the mean of the stages' interval limits (largest over the
    outputs, angles as mm by ``scale``)."""
    h = len(values) // stage
    lims = [intervals(values[i * stage:(i + 1) * stage], p) for i in range(h)]
    worst = 0.0
    for key in ("lo", "hi", "mean"):
        v = np.array([lim[key] for lim in lims]) * scale
        worst = max(worst, float(np.max(2 * v.std(axis=0, ddof=1) / np.sqrt(h))))
    return worst


def monte_carlo(rec: Recording, *, trials: int = 1000, seed: int = 0, p: float = 0.95, inputs: Inputs | None = None,
                workers: int | None = None, scheduler: str | None = None, store: str | Path | None = None,
                poses: np.ndarray | None = None, budget: bool = False, tolerance_mm: float | None = None,
                stage: int = 100, progress=None, tables: bool = False, exact: bool = False,
                **identify_options) -> UncertaintyResult:
    """GUM Supplement 1 Monte Carlo through the whole estimator: ``identify(rec, **identify_options)`` re-run on
    readings drawn from the input quantities' laws (module docstring), on Dask or in this process.

    Parameters
    ----------
    rec : Recording
        The readings (mm, machine frame).
    trials : int, optional
        Trials (the most with ``tolerance_mm``: adaptive); default 1000.
    seed : int, optional
        Seed of the draws (default 0).
    p : float, optional
        Coverage probability of the intervals (default 0.95).
    inputs : Inputs, optional
        The input quantities and their laws (default ``Inputs()``: tracker noise, length scale from air temperature
        and pressure, reflector centring; mtcal.uncertainty.inputs).
    workers : int, optional
        Local processes (default: the cores; 0: in this process).
    scheduler : str, optional
        The address of an existing Dask cluster (``tcp://HOST:8786``).
    store : str or pathlib.Path, optional
        A file that keeps the trials and extends them on the next run.
    poses : numpy.ndarray, optional
        Axis positions (n, n_axes) at which the tool tip's deviation is evaluated (default: over the work volume).
    budget : bool, optional
        Also run each input term alone (a quarter of the trials each, at least 50).
    tolerance_mm : float, optional
        Stop when twice the standard deviation of the interval limits is below this, mm (adaptive, in stages).
    stage : int, optional
        Trials per stage of the adaptive run (default 100).
    progress : callable, optional
        Called as trials complete.
    tables : bool, optional
        The errors' table values instead of the fitted functions (linear in the readings).
    exact : bool, optional
        Every trial runs ``identify`` (default False: the batched path, mtcal.uncertainty.fast, where the recording
        allows it and its check trials agree with identify; else identify, said in the notes).
    **identify_options
        Passed to ``identify`` (tracker, method, ...).

    Returns
    -------
    UncertaintyResult
        Per error, constant and pose the mean, u and 95 % intervals (mm, rad).

    Raises
    ------
    mtcal.errors.InputError
        As ``identify`` does; a bad option or store.

    Examples
    --------
    >>> import mtcal
    >>> rec, _ = mtcal.simulate(rounds=3, seed=1, plan={"axes": {"X": {}}})
    >>> mc = mtcal.monte_carlo(rec, trials=20, workers=0, tracker=(250, -1500, 150))  # 20: a demonstration
    >>> mc.trials, mc.p, sorted(mc.stats)
    (20, 0.95, ['hi', 'hi_short', 'lo', 'lo_short', 'mean', 'u'])
    """
    from mtcal.identify.run import identify

    t0 = time.perf_counter()
    base = identify(rec, worth=False, **identify_options)
    inputs = drawn_law(inputs or Inputs(), base)
    options = {**identify_options, "method": base.method}
    if options.get("tracker") is None and rec.tracker_xyz is None and "tracker_estimated" in base.model.meta:
        options["tracker"] = np.asarray(base.model.meta["tracker_estimated"]["position_mm"])  # as identify did
    m = base.model.kinematics
    outputs = Outputs.of(base.model, default_poses(m, base.model) if poses is None else poses, tables)
    path = None if store is None else Path(store)
    # `exact` is part of what the trials were drawn under: a store of batched trials is never reported as identify's
    st = Store.load(path, _key(rec, seed, {**options, "exact": exact}, inputs, outputs), outputs.size,
                    readings_sha256(rec))
    scale = np.where(_angular(outputs), 1e3, 1.0)
    history = []
    target = trials if tolerance_mm is None else min(trials, stage)
    fast, path_report = None, {"batched": False, "why": "`exact` asked for"} if exact else None
    while True:
        done = set(st.index.tolist())
        pending = [k for k in range(target) if k not in done]
        if path_report is None and pending:
            try:
                fast, path_report = _batched_path(rec, options, outputs, inputs, seed, pending, st, progress)
            except KeyboardInterrupt:
                raise Interrupted("0 trials of this run done" + (f", {len(st)} kept in {path}" if path else "")
                                  ) from None
            pending = [k for k in pending if k not in set(st.index.tolist())]
        run_trials(rec, pending, inputs=inputs, options=options, outputs=outputs, seed=seed, store=st,
                   store_path=path, workers=workers, scheduler=scheduler, progress=progress, fast=fast)
        vals = _ordered(st, target)
        if tolerance_mm is None or target >= trials:
            break
        spread = _stage_spread(vals, stage, p, scale) if target >= 2 * stage else np.inf
        history.append({"trials": target, "twice_sd_of_limits_mm": spread})
        if spread <= tolerance_mm:
            break
        target = min(trials, target + stage)
    res = UncertaintyResult(len(vals), seed, p, {**inputs.to_dict(), "estimator": options["method"]}, outputs,
                            zero_fits(intervals(vals, p), outputs, base.model), convergence=history,
                            model_sha256=base.model.digest())
    if budget:
        n = max(50, trials // 4)
        for term in TERMS:
            sub = inputs.only(term)
            if sub == inputs.only("none"):
                continue
            bs = Store(term, np.zeros(0, dtype=np.int64), np.zeros((0, outputs.size)))
            run_trials(rec, list(range(n)), inputs=sub, options=options, outputs=outputs, seed=seed + 1, store=bs,
                       store_path=None, workers=workers, scheduler=scheduler, progress=progress, fast=fast)
            res.budget[term] = _budget_line(_ordered(bs, n), outputs, base.model)
    res.path = {**(path_report or {"batched": False, "why": "no trial to run (the store held them all)"}),
                **({"trials": dict(fast.counts)} if fast is not None else {})}
    res.seconds = time.perf_counter() - t0
    return res


MIN_BATCHED = 12  # fewer pending trials run the full path (the batched path's check alone runs 3 of them)


def _batched_path(rec: Recording, options: dict, outputs: Outputs, inputs: Inputs, seed: int, pending: list[int],
                  st: Store, progress) -> tuple[object, dict]:
    """The batched estimator (mtcal.uncertainty.fast) and its report, after its check on the first trials (whose
    batched values go to ``st``), or (None, why the full path runs)."""
    from mtcal.uncertainty import fast as fp

    if len(pending) < MIN_BATCHED:
        return None, {"batched": False, "why": f"fewer than {MIN_BATCHED} trials to run"}
    b, why = fp.prepare(rec, options, outputs)
    if b is None:
        log.info("each trial runs identify (%s)", why)
        return None, {"batched": False, "why": why}
    trackers = trackers_of(rec, options.get("tracker"))
    first = pending[:min(len(pending), b.block)]
    ok, check, block = fp.self_check(b, rec, trackers, inputs, options, outputs, seed, first)
    if not ok:
        log.warning("warning: the batched trials do not reproduce identify on this recording (an output differs by "
                    "%.3g of its 95 %% half-width on %d check trials, more than %g): every trial runs identify",
                    check["largest_difference_of_half_width"], check["trials"], fp.CHECK_TOLERANCE)
        return None, {"batched": False, "why": "its check trials disagree with identify", "check": check}
    log.info("batched trials agree with identify (%d check trials, within %.2g %% of a half-width); %d of the %d "
             "trials to run done with the check, %d left", check["trials"],
             100 * check["largest_difference_of_half_width"], len(first), len(pending), len(pending) - len(first))
    st.add(*block[:2])
    b.merge(block[2])
    if progress:
        progress(len(first))
    return b, {"batched": True, "check": check}


def drawn_law(inputs: Inputs, base) -> Inputs:
    """``inputs`` with the noise law the trials draw from (mtcal.uncertainty.inputs): the one given, else the law
    identify weighted by (``base``'s model meta ``noise_law``; the AT960's without one), times the joint fit's Birge
    ratio when it exceeds 1."""
    from dataclasses import replace

    from mtcal.measurement import tracker as trk

    if inputs.noise is not None:
        return replace(inputs, noise_how=inputs.noise_how or "given")
    law = base.model.meta.get("noise_law")
    named = law and law["source"] == "prior" and law["instrument"] != "given numbers"
    spec = trk.AT960 if not law else trk.TrackerSpec(**{k: law[k] for k in trk.AT960.mpe()},
                                                     name=law["instrument"] if named else "")
    how = "the law identify weighted by" + (f" ({law['obtained']})" if law else " (the AT960's)")
    birge = float((base.joint or {}).get("birge_ratio", 1.0))
    if birge > 1.0:
        spec = replace(spec, **{k: v * birge for k, v in spec.mpe().items() if k != "k"})
        how += f", times the joint fit's Birge ratio {birge:.3f} (the readings scatter more than it says)"
    return replace(inputs, noise=spec, noise_how=how)


def _ordered(st: Store, n: int) -> np.ndarray:
    """The first ``n`` trials' values in trial order (the result does not depend on when each arrived)."""
    order = np.argsort(st.index)
    keep = order[st.index[order] < n]
    return st.values[keep]


def _budget_line(values: np.ndarray, outputs: Outputs, model) -> dict:
    """One input term's share: the largest standard uncertainty of each error over its positions (as reported:
    ``zero_fits``), of each constant, and of the tool tip over the poses (mm, rad)."""
    u = zero_fits({"u": values.std(axis=0, ddof=1)}, outputs, model)["u"]
    return {"errors": {n: float(u[sl].max()) for n, (_, _, sl) in outputs.functions.items()},
            "constants": {n: float(u[i]) for n, i in outputs.constants.items()},
            "volumetric_u_max_mm": float(u[outputs.volumetric].max()) if len(outputs.poses) else 0.0}
