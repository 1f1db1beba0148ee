"""The customer's report: one self-contained HTML file from a machine's history or from one result file
(mtcal.report.html; pictures in mtcal.report.pictures).  Entry point: ``write_report``."""
from mtcal.report.run import write_report

__all__ = ["write_report"]
