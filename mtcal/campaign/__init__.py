"""Campaign plans and the physical simulator: planted effects as physics, one or several tracker stations."""
