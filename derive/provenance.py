"""Hashes recorded in generated/manifest.json (no SymPy import: the runtime uses this for its staleness check)."""
from __future__ import annotations

import hashlib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def sha256(text: str | bytes) -> str:
    data = text.encode() if isinstance(text, str) else text
    return hashlib.sha256(data).hexdigest()


def derive_hash() -> str:
    """sha256 over every source file of derive/ (paths and bytes), the input the manifest records."""
    h = []
    for p in sorted((ROOT / "derive").rglob("*")):
        if p.is_file() and p.suffix in (".py", ".toml"):
            h.append(f"{p.relative_to(ROOT).as_posix()}\0{sha256(p.read_bytes())}")
    return sha256("\n".join(h))
