"""Recordings and what a tracker reads: the Recording type and its readers (tidy CSV, Inspire,
SpatialAnalyzer exports), passes and reference readings (one rule), tracker noise laws, the station estimate.
Readings in mm, machine frame."""
from mtcal.measurement.recordings import Recording, format_recording, read_recording, write_recording

__all__ = ["Recording", "read_recording", "write_recording", "format_recording"]
