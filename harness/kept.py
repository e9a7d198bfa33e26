"""What a run keeps on disk for the next one, under a hash of everything that decides it.

Each kind has its folder beside the derivation cache (``.cache/<kind>/``): the drawn states and the shrunk
counterexamples (:mod:`harness.compare.strategies`, :mod:`harness.compare.claims`), the exported MJCF and URDF of
each numeric tree (:func:`harness.export.kept.exported`), the trajectories of our symbolic model a scene is checked
against (:func:`harness.scenes.simulate.kept_solution`), the printed equations' symbolic decisions
(:func:`harness.compare.errata.decide`), the recipes naming compiled code (``compiled/recipes/``,
:func:`harness.derivation.lambdified.lambdify_built`), the conformance summaries the tests read (``results/``,
:mod:`harness.compare.remembered`). A key always hashes :func:`installation` (our code, the
installed packages, Python), so a change to any of them computes the value again. An entry carries a checksum: a
damaged one is computed again, and a folder we cannot write to only costs the next run the time. Only what our own
code computes is kept; every engine call is made again on every run."""

from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import json
import os
import sys
from pathlib import Path

import harness
from harness.derivation.cache import cache_dir, checksum
from harness.errors import OutputError
from harness.io import atomic_write_text

NUMERIC_ENVIRONMENT = ("OPENBLAS", "NPY_", "OMP_", "MKL_", "HYPOTHESIS")
"""Prefixes of the environment variables that can change a run's numbers or examples."""


def files_digest(folders) -> str:
    """SHA-256 over every file under ``folders`` (its path and bytes), ``__pycache__`` left out."""
    digest = hashlib.sha256()
    for root in folders:
        root = Path(root)
        for path in sorted(p for p in root.rglob("*") if p.is_file() and "__pycache__" not in p.parts):
            digest.update(str(path.relative_to(root)).encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


@functools.cache
def installation() -> str:
    """Our code (every file under ``harness/``), the installed distributions and Python: once per process."""
    # a set: the project's own metadata is found twice when the working directory is on sys.path
    dists = sorted({f"{d.metadata['Name']}=={d.version}" for d in importlib.metadata.distributions()})
    return hashlib.sha256("\n".join([files_digest([Path(harness.__file__).parent]), sys.version, *dists])
                          .encode()).hexdigest()


def numeric_environment() -> str:
    """The environment variables (:data:`NUMERIC_ENVIRONMENT`) that can change NumPy's or BLAS's kernels."""
    return repr(sorted((k, v) for k, v in os.environ.items() if k.startswith(NUMERIC_ENVIRONMENT)))


def path(kind: str, name: str, *parts: str) -> Path:
    """Where an entry of ``kind`` named ``name`` is kept: ``.cache/<kind>/<installation>-<name>-<hash>.json``, the
    hash over :func:`installation` and ``parts`` (the installation's first 12 hex digits lead the name: see
    :func:`keep`)."""
    digest = hashlib.sha256("\0".join((installation(), *parts)).encode()).hexdigest()[:24]
    return cache_dir().parent / kind / f"{installation()[:12]}-{name}-{digest}.json"


def keep(where: Path, doc) -> None:
    """``doc`` written to ``where`` with its checksum (atomically; a full disk or a read-only folder only costs the
    next run the time). Before the first entry a process keeps in a folder, the entries another installation kept
    there are removed: an edit of ``harness/`` makes every key new, and the folder held one more set per edit (the
    exported texts: 21 MB a set)."""
    _forget_other_installations(where.parent)
    try:
        atomic_write_text(where, json.dumps({"sha256": checksum(doc), "doc": doc}))
    except OutputError:
        pass


def read_kept(where: Path):
    """The ``doc`` :func:`keep` wrote to ``where``; None when absent or damaged."""
    try:
        entry = json.loads(where.read_text())
        doc = entry["doc"]
        return doc if entry["sha256"] == checksum(doc) else None
    except (OSError, ValueError, KeyError, TypeError):
        return None


_FORGOTTEN: set = set()


def _forget_other_installations(folder: Path) -> None:
    """Once per process and folder: remove the entries whose name does not start with this installation's digest."""
    if folder in _FORGOTTEN:
        return
    _FORGOTTEN.add(folder)
    current = installation()[:12] + "-"
    try:
        entries = list(folder.glob("*.json"))
    except OSError:
        return
    for entry in entries:
        if not entry.name.startswith(current):
            entry.unlink(missing_ok=True)
