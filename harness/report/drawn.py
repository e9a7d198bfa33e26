"""Pictures drawn once per content: a scene's figure (SVG, matplotlib) or a mechanism's rendering (PNG, MuJoCo) is
kept on disk (``pictures/`` beside the derivation cache) under a SHA-256 of everything it is drawn from — the bytes
of its inputs (the series file, the MJCF text), the catalogue's files, our code and the installed packages
(:func:`harness.kept.installation`), the OpenGL backend — and a report whose pictures have the same
inputs writes the kept bytes instead of drawing them again: both are byte-identical for the same input
(:mod:`harness.report.figures`, :mod:`harness.report.render`). An entry carries the SHA-256 of its bytes; a damaged
one is drawn again; the entries of another installation are removed when a picture is kept. Reading an entry runs
no code: it is JSON, the picture's bytes and what its drawing returned (sizes, a caption)."""

from __future__ import annotations

import base64
import hashlib
import json
from pathlib import Path

from harness import profiling
from harness.errors import OutputError
from harness.io import atomic_write_bytes, atomic_write_text


def folder() -> Path:
    from harness.derivation.cache import cache_dir

    return cache_dir().parent / "pictures"


def key(kind: str, *inputs: bytes | str) -> str:
    """The name of the picture ``kind`` drawn from ``inputs`` by this installation (its name starts with the
    installation's digest)."""
    installed = _installation()
    digest = hashlib.sha256(installed.encode() + b"\0" + kind.encode())
    for part in inputs:
        data = part.encode() if isinstance(part, str) else part
        digest.update(b"\0" + str(len(data)).encode() + b"\0" + data)
    return f"{installed[:12]}-{kind.replace(' ', '-')}-{digest.hexdigest()[:32]}"


def _installation() -> str:
    from harness.kept import installation  # the kept entries' digest of our code and packages

    return installation()


def catalogue_digest(catalogue) -> str:
    """The catalogue's model files (what a mechanism's picture shows: its joints, coordinates, scenes)."""
    from harness.kept import files_digest

    return files_digest(catalogue.path)


def drawn(target: Path, name: str, draw) -> dict:
    """Write the picture ``name`` (:func:`key`) to ``target``: the kept bytes, else ``draw(target)`` (which writes
    ``target`` and returns a JSON-able dict) kept for the next report. Returns what ``draw`` returned (as JSON
    reads it back, on both paths)."""
    entry = folder() / f"{name}.json"
    kept = _load(entry)
    if kept is not None:
        data, info = kept
        atomic_write_bytes(target, data)
        profiling.count("picture read back")
        return info
    info = json.loads(json.dumps(draw(target)))
    _forget_other_installations()
    try:
        data = Path(target).read_bytes()
        atomic_write_text(entry, json.dumps({"sha256": hashlib.sha256(data).hexdigest(), "info": info,
                                             "bytes": base64.b64encode(data).decode()}))
    except (OSError, OutputError):  # a full disk or a read-only folder: the picture itself is written
        pass
    return info


_FORGOTTEN: set = set()


def _forget_other_installations() -> None:
    """Once per process and folder, before the first picture is kept there: the entries another code or set of
    packages drew are removed (a name starts with its installation's digest), so that the folder holds one
    installation's pictures (4.4 MB for the catalogue), not one more set per edit of ``harness/``."""
    where = folder()
    if where in _FORGOTTEN:
        return
    _FORGOTTEN.add(where)
    current = _installation()[:12]
    for entry in where.glob("*.json"):
        if not entry.name.startswith(current + "-"):
            entry.unlink(missing_ok=True)


def _load(entry: Path):
    try:
        doc = json.loads(entry.read_text())
        data = base64.b64decode(doc["bytes"], validate=True)
        if hashlib.sha256(data).hexdigest() != doc["sha256"] or not isinstance(doc["info"], dict):
            return None
        return data, doc["info"]
    except (OSError, ValueError, KeyError, TypeError):  # missing or damaged: drawn again
        return None
