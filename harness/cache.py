"""On-disk cache of symbolic derivations, keyed by a hash of the model.

Entries are JSON files of ``srepr`` strings with a SHA-256 checksum of their content. An entry that does
not parse or whose checksum does not match is not trusted: it is discarded and the derivation rebuilt.
Set ``HARNESS_CACHE_DIR`` to move the cache (default: ``.cache/derivations`` in the project).
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import sympy as sp

from harness.io import atomic_write_text

PROJECT_ROOT = Path(__file__).resolve().parent.parent


# The derivation's source is part of the cache key: a changed derivation never reads old entries.
_DERIVATION_SOURCES = ("model.py", "kinematics.py", "derive.py", "cache.py")


def code_version() -> str:
    digest = hashlib.sha256()
    for name in _DERIVATION_SOURCES:
        digest.update((Path(__file__).parent / name).read_bytes())
    return digest.hexdigest()[:12]


def cache_dir() -> Path:
    return Path(os.environ.get("HARNESS_CACHE_DIR", PROJECT_ROOT / ".cache" / "derivations"))


def _checksum(entries: dict[str, str]) -> str:
    return hashlib.sha256(json.dumps(entries, sort_keys=True).encode()).hexdigest()


def load(key: str) -> dict | None:
    path = cache_dir() / f"{key}.json"
    if not path.exists():
        return None
    try:
        doc = json.loads(path.read_text())
        entries = doc["entries"]
        if doc["sha256"] != _checksum(entries):
            raise ValueError("checksum mismatch")
        return {name: sp.sympify(text) for name, text in entries.items()}
    except Exception:  # noqa: BLE001 - any damage means: do not trust, rebuild
        path.unlink(missing_ok=True)
        return None


def store(key: str, values: dict) -> None:
    entries = {name: sp.srepr(value) for name, value in values.items()}
    atomic_write_text(cache_dir() / f"{key}.json", json.dumps({"sha256": _checksum(entries), "entries": entries}))
