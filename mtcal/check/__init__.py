"""Check tests: the field's checks of a machine predicted from an error model, measured ones evaluated against it,
and a compensation verified by a new measurement.

Entry points: ``predict_circular`` (ISO 230-4 circular test: trace, G, H, F, each error's share),
``predict_circular_compensated`` (the same after compensating with the model), ``predict_rtest`` (ISO 10791-6
R-test sweep of a rotary axis), ``read_check`` and ``evaluate_check`` (a measured test against the model, what its
residual shows), ``verify`` (a recording or check test made after compensation), ``simulate_circular`` /
``simulate_rtest`` (measured tests of a true machine, for tests and the demo)."""
from mtcal.check.circular import CircleSetup, parse_circular, predict_circular, predict_circular_compensated
from mtcal.check.evaluate import evaluate_check
from mtcal.check.files import read_check
from mtcal.check.rtest import RTestSetup, predict_rtest
from mtcal.check.simulate import simulate_circular, simulate_rtest
from mtcal.check.verify import verify

__all__ = ["CircleSetup", "parse_circular", "predict_circular", "predict_circular_compensated", "RTestSetup",
           "predict_rtest", "read_check", "evaluate_check", "verify", "simulate_circular", "simulate_rtest"]
