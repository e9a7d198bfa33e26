"""On-disk cache of symbolic derivations, keyed by a hash of the model.

Entries are JSON files of ``srepr`` strings with a SHA-256 checksum of their content. An entry that does
not parse or whose checksum does not match is not trusted: it is discarded and the derivation rebuilt.
A derivation whose expressions are small graphs but huge trees (the per-body derivation of
:func:`harness.derive.derive`) is stored as a graph (``graph=True``): its common subexpressions as numbered
replacements, each written once, and rebuilt in order with ``xreplace`` (``srepr`` of the trees would not end).
Set ``HARNESS_CACHE_DIR`` to move the cache (default: ``.cache/derivations`` in the project).
"""

from __future__ import annotations

import hashlib
import json
import os
import re
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
        replacements = doc.get("replacements", [])
        if doc["sha256"] != _checksum({"entries": entries, "replacements": replacements} if replacements
                                      else entries):
            raise ValueError("checksum mismatch")
        shared: dict = {}
        for symbol, text in replacements:  # in order: each refers to earlier ones only
            shared[symbol] = _build(text, shared)
        return {name: _build(text, shared) for name, text in entries.items()}
    except Exception:  # noqa: BLE001 - any damage means: do not trust, rebuild
        path.unlink(missing_ok=True)
        return None


GRAPH_SYMBOLS = "_cse_"  # names of the stored replacements (no model symbol starts with an underscore)
_REPLACEMENT = re.compile(r"Symbol\('(" + GRAPH_SYMBOLS + r"\d+)'\)")
_SYMPY = {"__builtins__": {}, **{name: getattr(sp, name) for name in dir(sp) if not name.startswith("_")}}


def _build(text: str, shared: dict):
    """The expression of an ``srepr`` text whose replacement symbols stand for the expressions in ``shared``,
    built once: what ``sympify`` does — ``eval`` in SymPy's namespace — without its tokenizer (3.8 of the 6.2 s of
    the 7-DoF arm's entry; 8.4 of the 11.6 s of the 5-link chain's) and without rebuilding every node a second
    time by ``xreplace`` (2.5 s)."""
    return eval(_REPLACEMENT.sub(r"\1", text), _SYMPY, shared)  # noqa: S307


def store(key: str, values: dict, graph: bool = False) -> None:
    if graph:
        reduced_names = list(values)
        replacements, reduced = sp.cse([values[name] for name in reduced_names], order="none",
                                       symbols=sp.numbered_symbols(GRAPH_SYMBOLS))
        entries = {name: sp.srepr(value) for name, value in zip(reduced_names, reduced)}
        pairs = [[symbol.name, sp.srepr(expr)] for symbol, expr in replacements]
        doc = {"sha256": _checksum({"entries": entries, "replacements": pairs}), "entries": entries,
               "replacements": pairs}
    else:
        entries = {name: sp.srepr(value) for name, value in values.items()}
        doc = {"sha256": _checksum(entries), "entries": entries}
    atomic_write_text(cache_dir() / f"{key}.json", json.dumps(doc))
