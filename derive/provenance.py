"""Hashes recorded in generated/manifest.json (no SymPy import)."""
from __future__ import annotations

import hashlib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def sha256(text: str | bytes) -> str:
    data = text.encode() if isinstance(text, str) else text
    return hashlib.sha256(data).hexdigest()


def derive_files() -> dict[str, str]:
    """{path relative to the checkout: sha256} of every source file of derive/, recorded in the manifest so that
    the runtime can tell a stale generated/ without importing derive/."""
    return {p.relative_to(ROOT).as_posix(): sha256(p.read_bytes()) for p in sorted((ROOT / "derive").rglob("*"))
            if p.is_file() and p.suffix in (".py", ".toml")}


def derive_hash() -> str:
    """sha256 over every source file of derive/ (paths and bytes), the input the manifest records."""
    return sha256("\n".join(f"{k}\0{v}" for k, v in derive_files().items()))
