"""SymPy derivations for mtcal: the only place where formulas are written by hand.

`python -m derive` writes generated/; `python -m derive --check` compares instead and fails when stale.
"""
