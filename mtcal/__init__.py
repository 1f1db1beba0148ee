"""mtcal: machine-tool calibration with a laser tracker (or a 2-D plate, an interferometer).

The user's verbs, each documented where it lives (units mm and rad inside, positions of rotary axes in deg,
readings in the machine frame; docs/design.md):

    rec = mtcal.read_recording("campaign.csv")                       # tidy tracker recording
    res = mtcal.identify(rec, tracker=(250, -1500, 150))             # errors per axis and position, the model
    mtcal.save_model(res.model, "model.json")                        # and mtcal.load_model(path)
    mtcal.compensate_program("part.nc", "part_comp.nc", res.model)   # corrected program, its report
    mtcal.export_model(res.model, mtcal.load_machine(), "linuxcnc", "comp/")   # controller tables
    d = mtcal.diagnose(rec, tracker=(250, -1500, 150))               # what the model leaves out
    ev = mtcal.evaluate_iso230_2(rec, "X")                           # ISO 230-2 A, E, M, R, B
    tm = mtcal.fit_thermal(mtcal.read_thermal_test("thermal.csv"))   # thermal model, judged out of sample

Imports are lazy: ``import mtcal`` loads only what a name asks for.
"""
from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

__version__ = "0.1.0"

_API = {  # name -> (module, attribute)
    "Machine": ("mtcal.kinematics.machine", "Machine"),
    "load_machine": ("mtcal.kinematics.machine", "load_machine"),
    "available_machines": ("mtcal.kinematics.machine", "available_machines"),
    "Recording": ("mtcal.measurement.recordings", "Recording"),
    "read_recording": ("mtcal.measurement.recordings", "read_recording"),
    "ErrorModel": ("mtcal.model.errormodel", "ErrorModel"),
    "load_model": ("mtcal.model.errormodel", "load_model"),
    "save_model": ("mtcal.model.errormodel", "save_model"),
    "identify": ("mtcal.identify.run", "identify"),
    "IdentifyResult": ("mtcal.identify.results", "IdentifyResult"),
    "plan_uncertainty": ("mtcal.planning.plan", "plan_uncertainty"),
    "simulate": ("mtcal.campaign.simulate", "simulate"),
    "compensate_program": ("mtcal.compensate.run", "compensate_program"),
    "export_model": ("mtcal.export", "export_model"),
    "diagnose": ("mtcal.diagnose.run", "diagnose"),
    "fit_plate": ("mtcal.plate.reversal", "fit_plate"),
    "evaluate_iso230_2": ("mtcal.iso230_2.evaluation", "evaluate"),
    "Compensator": ("mtcal.compensate.solver", "Compensator"),
    "monte_carlo": ("mtcal.uncertainty.run", "monte_carlo"),
    "CircleSetup": ("mtcal.check.circular", "CircleSetup"),
    "predict_circular": ("mtcal.check.circular", "predict_circular"),
    "RTestSetup": ("mtcal.check.rtest", "RTestSetup"),
    "predict_rtest": ("mtcal.check.rtest", "predict_rtest"),
    "read_check": ("mtcal.check.files", "read_check"),
    "evaluate_check": ("mtcal.check.evaluate", "evaluate_check"),
    "verify": ("mtcal.check.verify", "verify"),
    "write_report": ("mtcal.report.run", "write_report"),
    "read_thermal_test": ("mtcal.thermal.readings", "read_thermal_test"),
    "fit_thermal": ("mtcal.thermal.model", "fit_thermal"),
    "evaluate_iso230_3": ("mtcal.thermal.iso230_3", "evaluate_iso230_3"),
    "export_thermal": ("mtcal.export.thermal", "export_thermal"),
}
__all__ = ["__version__", "Machine", "load_machine", "available_machines", "Recording", "read_recording", "ErrorModel",
           "load_model", "save_model", "identify", "IdentifyResult", "plan_uncertainty", "simulate",
           "compensate_program", "export_model", "diagnose", "fit_plate", "evaluate_iso230_2", "Compensator",
           "monte_carlo", "CircleSetup", "predict_circular", "RTestSetup", "predict_rtest", "read_check",
           "evaluate_check", "verify", "write_report",
           "read_thermal_test", "fit_thermal", "evaluate_iso230_3", "export_thermal"]

if TYPE_CHECKING:  # for type checkers and IDEs; at run time the names load on first use (__getattr__)
    from mtcal.campaign.simulate import simulate
    from mtcal.check.circular import CircleSetup, predict_circular
    from mtcal.check.evaluate import evaluate_check
    from mtcal.check.files import read_check
    from mtcal.check.rtest import RTestSetup, predict_rtest
    from mtcal.check.verify import verify
    from mtcal.compensate.run import compensate_program
    from mtcal.compensate.solver import Compensator
    from mtcal.diagnose.run import diagnose
    from mtcal.export import export_model
    from mtcal.export.thermal import export_thermal
    from mtcal.identify.results import IdentifyResult
    from mtcal.identify.run import identify
    from mtcal.iso230_2.evaluation import evaluate as evaluate_iso230_2
    from mtcal.kinematics.machine import Machine, available_machines, load_machine
    from mtcal.measurement.recordings import Recording, read_recording
    from mtcal.model.errormodel import ErrorModel, load_model, save_model
    from mtcal.planning.plan import plan_uncertainty
    from mtcal.plate.reversal import fit_plate
    from mtcal.report.run import write_report
    from mtcal.thermal.iso230_3 import evaluate_iso230_3
    from mtcal.thermal.model import fit_thermal
    from mtcal.thermal.readings import read_thermal_test
    from mtcal.uncertainty.run import monte_carlo


def __getattr__(name: str):
    if name not in _API:
        raise AttributeError(f"module 'mtcal' has no attribute {name!r}")
    module, attr = _API[name]
    value = getattr(importlib.import_module(module), attr)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(__all__)
