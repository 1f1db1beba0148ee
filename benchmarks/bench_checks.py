"""Check tests against identified models (benchmarks/check_rates.py) as figures for docs/guide/checks.md."""
from __future__ import annotations

import check_rates


def run(n: int = 60) -> dict:
    r = check_rates.run(n)
    return {"check_campaigns": r["campaigns"], "check_tests": r["tests"], "check_clean_agree": r["clean_agree"],
            "check_clean_cyclic": r["clean_findings"].get("cyclic", 0.0),
            "check_clean_other_findings": sum(v for k, v in r["clean_findings"].items() if k != "cyclic"),
            "check_backlash_named": r["backlash_named"], "check_servo_named": r["servo_mismatch_named_dynamic"],
            "check_backlash_size_sd_um": r["backlash_size_error_um"]["sd"],
            "check_u95_median_um": r["prediction_u95_um_median"],
            "check_changed_15_urad": r["changed_squareness_found"]["15_urad"],
            "check_changed_40_urad": r["changed_squareness_found"]["40_urad"]}
