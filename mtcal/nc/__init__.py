"""NC programs read as rows of axis positions (G-code)."""
