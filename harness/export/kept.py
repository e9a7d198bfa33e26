"""The texts we export for a numeric tree, kept for the next run (:mod:`harness.kept`, ``exports/``).

A conformance run loads one model per engine and parameter draw (2400 trees in the main job): writing the MJCF
(``MjSpec`` built, compiled, printed, every number rewritten at full precision) took 2-6 ms of a 3-8 ms MuJoCo
model, the URDF 0.15-0.9 ms. A text is a function of the tree and of our code: it is kept under a hash of the tree
(its pickle: every number's bits, every name) and of our installation (the code that writes it, the packages'
versions). What an engine makes of the text is computed again on every run; only our writing of it is kept.
``harness export`` and its ``--check`` write every text afresh."""

from __future__ import annotations

import hashlib
import pickle

from harness import kept
from harness.export.numeric import NumericTree


def exported(tree: NumericTree, language: str, write, warned_at: str | None = None) -> str:
    """``write(tree)``, the text of ``tree`` in ``language`` (``"urdf"``, ``"mjcf"``), read back where kept. With
    ``warned_at``, the MuJoCo warnings that writing it logged there (:mod:`harness.engines.warnings_log`) are kept
    with it and logged again when it is read back, as writing it logs them."""
    from harness.engines import warnings_log

    where = kept.path("exports", f"{tree.system}.{language}", hashlib.sha256(pickle.dumps(tree, 4)).hexdigest())
    doc = kept.read_kept(where)
    if isinstance(doc, dict) and isinstance(doc.get("text"), str) and isinstance(doc.get("warnings"), list):
        if warned_at is not None:
            warnings_log.record("mujoco", warned_at, tree, doc["warnings"])
        return doc["text"]
    start = warnings_log.logged()
    text = write(tree)
    warned = [] if warned_at is None else warnings_log.messages_since(start)
    kept.keep(where, {"text": text, "warnings": warned})
    return text
