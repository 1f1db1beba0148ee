"""The main job on bundled data (mtcal demo)."""
