"""Diagnosis of laser-tracker recordings (package; one job per module): fit a quasi-static base model, locate the
mismatch, name the effect.

Base model (frames: machine frame = tracker frame, mm; positions mm or deg; errors mm and rad):
* every reflector reading of axis J is its nominal position plus the first-order effect of J's six error
  motions through the generated point Jacobian (Machine.point_jacobian_errors):
  d = J_point(q) e(q); the nominal position uses the point's position from the reference readings (docs/design.md:
  each round's reading at the position closest to zero);
* the error motions are smooth functions that vanish at the reference position: polynomials in (q - q_ref) for
  X, Y, Z and harmonics (cos k q - cos k q_ref, sin k q - sin k q_ref) for B and C, the degree chosen per axis by
  BIC (1..3) with the selected effects in the fit (an unmodelled backlash inflates the residual and would make
  BIC choose too low a degree); the same in every round, direction and time;
* the reference reading is itself noisy (Hocken & Borchardt 1979: normalising to one reading biases every
  deviation of the round): the reference readings only start the fit; each reflector's position (three
  parameters per axis and reflector) is estimated from all its readings in all rounds, so no single reading is
  trusted.  Positions are shared across axes where that is physics (mtcal.diagnose.prepare, design): the axes
  whose reference readings were taken at the same full machine pose (own reference position, the other axes
  parked at their pos_<AXIS> columns or zero, equal within 1e-9) read the same reflector (same side, same label)
  at the same place, so they share its position, and each such axis keeps a free rigid motion of its side (six
  parameters: the unmeasured error state of a parked axis, e.g. the side of a backlash it was last approached
  from); other axes keep one position per (axis, reflector).  A shift of one (round, reflector) sequence (a
  re-seated nest) is the candidate effect "offset", and so is a tracker knock (effects.py "offset": every reading
  from t0 on shifted by one vector; t0 scanned over the gaps between reading times, counted in the multiplicity);
  one nest knocked (every later reading of that reflector shifted in its side's frame) is "nest_knock", scanned
  the same way;
* weights: the AT960 covariance (mtcal.measurement.tracker) of every reading about the tracker position, given or
estimated
  from the scatter of the repeated rounds (mtcal.diagnose.noise; whitened least squares; sigma ratio 1 = the
  tracker's specification), else (one round, no tracker shape in the scatter) unweighted;
* with ``model`` given, the base model is that model (readings minus its simulation) plus the offsets;
* several tracker stations (docs/design.md: station and tracker_x,y,z columns) are one fit: each reading weighted
  about its own station's tracker, each station's rigid alignment (6 parameters; the first station's is the
  frame) among the base's unknowns, the error functions and reflector positions common to every station; the
  tracker effects (drift, settling, scale relative to the first station, knock) are candidates per station, the
  machine effects common, which is what separates the two.

Diagnosis: studentized residuals grouped by axis x (direction, round, time, position, point) locate the misfit;
candidate effects (mtcal.diagnose.effects, signatures derived in derive/signatures.py) are tested by an F test on
the projected (Frisch-Waugh) columns, with a separability (aliasing) check, Bonferroni control over families x
members, forward selection, backward elimination and held-out-round cross-validation.  The null hypothesis of
every test is the quasi-static family itself (every axis at the largest degree, plus the effects selected
before), not the BIC-selected base: BIC may choose a degree below the truth's (a cubic error function fitted
as a quadratic), and a smooth candidate (a periodic error whose pitch is near the travel) would then be
"found" in the cubic misfit.  An effect is reported only if no error function of the family explains it; the
reported base (degrees, sigma before and after, estimates, cross-validation) is the BIC base with the selected
effects.  With ``model`` given the null is that model (plus offsets), as before.  Sizes are what the readings
observe: a side's drift starts no earlier than the side is first read, its interval covers the onset and time
constant (profile); error motions that change while their axis is measured are located ("position x time") and
left unexplained; every finding has a picture (pictures).

Modules: prepare (nominal positions, Jacobians), noise (weights), design (base columns), engine (F tests by
projection), effects (each candidate effect's columns), candidates (the candidate list), scans (locate by factors
and pairs of factors; outlier and knock scans), selection (forward / backward, confounding, validation), profile
(intervals over nuisance parameters), report (typed findings, JSON), predictive (each named finding planted through
the physical simulator must reproduce its pattern), pictures (one per finding), plate (plate fits), run
(``diagnose()``), calibrate (the whole diagnosis' level measured on null campaigns simulated from its fit)."""
from mtcal._verb import callable_package
from mtcal.diagnose.engine import Engine, Score
from mtcal.diagnose.pictures import plot_findings
from mtcal.diagnose.plate import diagnose_plate, format_plate_diagnosis
from mtcal.diagnose.prepare import prepare
from mtcal.diagnose.prepared import Prepared
from mtcal.diagnose.report import Diagnosis, Finding, plot_residuals
from mtcal.diagnose.run import MAX_DEGREE, diagnose

__all__ = ["diagnose", "diagnose_plate", "format_plate_diagnosis", "plot_findings", "plot_residuals", "prepare",
           "Prepared",
           "Diagnosis", "Finding", "Engine", "Score", "MAX_DEGREE"]

callable_package(__name__, diagnose)  # mtcal.diagnose(...) is the verb even once the package is imported
