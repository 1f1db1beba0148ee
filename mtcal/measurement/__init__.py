"""Recordings and what a tracker reads: the recording type and readers, passes and reference readings, tracker noise
laws, the station estimate, SpatialAnalyzer exports."""
