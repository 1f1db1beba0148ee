"""Diagnosis of laser-tracker recordings (package: prepare, engine, candidates, scans, selection, report,
plate): fit a quasi-static base model, locate the mismatch, name the effect.

Base model (frames: machine frame = tracker frame, mm; positions mm or deg; errors mm and rad):
* every reflector reading of axis J is its nominal position plus the first-order effect of J's six error
  motions through the generated point Jacobian (Machine.point_jacobian_errors):
  d = J_point(q) e(q); the nominal position uses the point's position from the reference readings (design.md:
  each round's reading at the position closest to zero);
* the error motions are smooth functions that vanish at the reference position: polynomials in (q - q_ref) for
  X, Y, Z and harmonics (cos k q - cos k q_ref, sin k q - sin k q_ref) for B and C, the degree chosen per axis by
  BIC (1..3) with the selected effects in the fit (an unmodelled backlash inflates the residual and would make
  BIC choose too low a degree); the same in every round, direction and time;
* the reference reading is itself noisy (Hocken & Borchardt 1979: normalising to one reading biases every
  deviation of the round): the reference readings only start the fit; each reflector's position (three
  parameters per axis and reflector) is estimated from all its readings in all rounds, so no single reading is
  trusted.  A shift of one (round, reflector) sequence (a re-seated nest) is the candidate effect "offset",
  and so is a tracker knock (effects.py "offset": every reading from t0 on shifted by one vector; t0 scanned
  over the gaps between reading times, counted in the multiplicity);
* weights: the AT960 covariance (mtcal.tracker) of every reading when the tracker position is known (whitened
  least squares; sigma ratio 1 = the tracker's specification), else unweighted with sigma from the residuals;
* with ``model`` given, the base model is that model (readings minus its simulation) plus the offsets.

Diagnosis: studentized residuals grouped by axis x (direction, round, time, position, point) locate the misfit;
candidate effects (mtcal.diagnose.candidates, signatures derived in derive/signatures.py) are tested by an F test on
the projected (Frisch-Waugh) columns, with a separability (aliasing) check, Bonferroni control over families x
members, forward selection, backward elimination and held-out-round cross-validation.  The null hypothesis of
every test is the quasi-static family itself (every axis at the largest degree, plus the effects selected
before), not the BIC-selected base: BIC may choose a degree below the truth's (a cubic error function fitted
as a quadratic), and a smooth candidate (a periodic error whose pitch is near the travel) would then be
"found" in the cubic misfit.  An effect is reported only if no error function of the family explains it; the
reported base (degrees, sigma before and after, estimates, cross-validation) is the BIC base with the selected
effects.  With ``model`` given the null is that model (plus offsets), as before.
"""
from __future__ import annotations

from mtcal.diagnose.candidates import NOT_SEPARABLE, all_candidates
from mtcal.diagnose.engine import Engine, base_design, engine_for
from mtcal.diagnose.plate import diagnose_plate, format_plate_diagnosis
from mtcal.diagnose.prepare import Prepared, prepare
from mtcal.diagnose.report import Diagnosis, plot_residuals
from mtcal.diagnose.scans import locate
from mtcal.diagnose.selection import MAX_DEGREE, diagnose

__all__ = ["diagnose", "Diagnosis", "prepare", "Prepared", "all_candidates", "NOT_SEPARABLE", "base_design",
           "engine_for",
           "Engine", "locate", "diagnose_plate", "format_plate_diagnosis", "plot_residuals", "MAX_DEGREE"]
