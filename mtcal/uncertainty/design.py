"""The Monte Carlo of a measurement design (`mtcal plan --target-um U --monte-carlo N`): each step of the design
search's path (mtcal.planning.stations.design: one station, then two, ...) re-evaluated by the GUM-S1 Monte Carlo of
``monte_carlo`` (Dask; trial k seeded from (seed, k)) - the whole estimator ``identify`` will run on that campaign
(the joint fit with its station alignments, the fitted functions' degree selection) - instead of the linear
propagation through per-position estimates, which is an upper bound once functions are fitted.

Each step's campaign is its exact readings (stations aligned exactly) of a machine with errors of the thesis'
magnitudes (mtcal.compensate.examples.example_model: on a machine without errors the degree selection would set
every function to zero and the figure would be that of an estimator shrinking to nothing); a trial adds the
tracker's noise law (AT960, the law the linear propagation uses; the scale, centring and material terms are left
out so the two figures compare) and identifies.  The figure is the linear one's: the RMS over the same poses of the 3-D
standard uncertainty sqrt(u_x^2 + u_y^2 + u_z^2) of the identified model's tool-tip deviation (um).  The
recommendation becomes the first step of the path whose Monte Carlo figure meets the target (the last step when
none does)."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from mtcal.campaign.plans import Plan
from mtcal.compensate.examples import example_model
from mtcal.model.errormodel import ErrorFunction, ErrorModel
from mtcal.planning.stations import Design, Prediction, nominal_campaign, poses
from mtcal.uncertainty.inputs import Inputs
from mtcal.uncertainty.run import monte_carlo


def volumetric_um(plan: Plan, p: Prediction, trials: int, seed: int = 0, workers: int | None = None,
                  scheduler: str | None = None, grid: np.ndarray | None = None, progress=None,
                  exact: bool = False) -> float:
    """The Monte Carlo figure of one candidate campaign ``p`` (module docstring), um; ``exact``: identify in every
    trial (else batched trials, mtcal.uncertainty.fast)."""
    rec = nominal_campaign(plan, [(s, tuple(x)) for s, x in p.stations], p.rounds_per_station, p.reflector_scale,
                           _machine_with_errors(plan))
    g = poses(plan) if grid is None else grid
    r = monte_carlo(rec, trials=trials, seed=seed, inputs=Inputs().only("noise"), workers=workers,
                    scheduler=scheduler, poses=g, progress=progress, machine=plan.machine, exact=exact)
    u = r.stats["u"][r.outputs.volumetric].reshape(len(g), 3)
    return float(np.sqrt(np.mean(np.sum(u**2, axis=1))) * 1e3)


def _machine_with_errors(plan: Plan) -> ErrorModel:
    """The thesis-magnitude example model of the plan's machine as tables over the plan's positions and the
    example's (its values held beyond its own range): a truth defined wherever the plan measures."""
    ex = example_model(plan.machine)
    funcs = {}
    for n, f in ex.functions.items():
        pos = np.union1d(f.positions, plan.positions.get(f.axis, f.positions))
        funcs[n] = ErrorFunction(f.axis, pos, f(pos, "hold"))
    return replace(ex, functions=funcs)


def design_monte_carlo(d: Design, plan: Plan, trials: int, seed: int = 0, workers: int | None = None,
                       scheduler: str | None = None, progress=None, exact: bool = False) -> Design:
    """``d`` with each step's ``monte_carlo_um`` (in order, up to the first that meets the target) and the
    recommendation decided by them (module docstring)."""
    grid = poses(plan)
    steps = []
    for p in d.steps:
        steps.append(replace(p, monte_carlo_um=volumetric_um(plan, p, trials, seed, workers, scheduler, grid,
                                                             progress, exact)))
        if steps[-1].monte_carlo_um <= d.target_um:
            break
    best = steps[-1]
    return replace(d, recommended=best, met=best.monte_carlo_um <= d.target_um,
                   steps=steps + d.steps[len(steps):],
                   decided_by=f"Monte Carlo of identify ({trials} trials per step, seed {seed}; noise law only)")
