"""A system's conformance summary remembered on disk under a hash of everything that determines it, so that the
test suite reads what the main job computed instead of computing it again (``make check`` then ``make test``).

The examples of a conformance run are fixed by the hypothesis settings (derandomized, no example database, drawn
from the seed only: :func:`harness.settings.draws_from_seed_only`); its numbers by our code, the model files, the
installed packages, Python and the environment variables that change NumPy's or BLAS's kernels. The key hashes all
of them: every file under ``harness/`` and on the catalogue's search path, every installed distribution with its
version, Python's version, the ``OPENBLAS_*``, ``NPY_*``, ``OMP_*``, ``MKL_*`` and ``HYPOTHESIS_*`` variables, the
settings and the run's arguments. A change to any of them computes the summary again. Where the examples are not
fixed by the settings (a random seed, an example database) nothing is remembered. An entry carries a checksum; a
damaged one is computed again. The folder is ``results/`` beside the derivation cache; the tests read a copy of
the project's (``tests/conftest.py``)."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from harness import profiling
from harness.checks import Check
from harness.compare import conformance
from harness.derivation.cache import checksum  # one checksum for what is kept on disk
from harness.errors import OutputError
from harness.io import atomic_write_text
from harness.kept import files_digest, installation, numeric_environment


def folder() -> Path:
    from harness.derivation.cache import cache_dir

    return cache_dir().parent / "results"


def key(catalogue, name: str, examples: int | None) -> str | None:
    """The entry's name, or None when the examples are not fixed by the settings."""
    from harness.settings import fixed_examples

    fixed = fixed_examples()
    if fixed is None:
        return None
    parts = [installation(), files_digest(catalogue.path), numeric_environment(), name, repr(examples), repr(fixed)]
    return f"conformance-{name}-{hashlib.sha256(chr(0).join(parts).encode()).hexdigest()[:24]}"


def _load(path: Path) -> conformance.Summary | None:
    try:
        entry = json.loads(path.read_text())
        doc = entry["summary"]
        if entry["sha256"] != checksum(doc):
            return None
        summary = conformance.Summary(doc["system"], doc["examples"], failure=doc["failure"],
                                      not_applicable=dict(doc["not_applicable"]),
                                      parameter_draws=doc["parameter_draws"])
        for record in doc["worst"]:  # Check.record()'s fields, as results.json holds them
            check = Check(record["check"], record["source"], record["value"], record["bound"], record["basis"],
                          record.get("detail", ""))
            summary.worst[check.name, check.source] = check
        return summary
    except (OSError, ValueError, KeyError, TypeError):  # missing or damaged: computed again
        return None


def _store(path: Path, summary: conformance.Summary) -> None:
    doc = {"system": summary.system, "examples": summary.examples, "parameter_draws": summary.parameter_draws,
           "failure": summary.failure,
           "not_applicable": summary.not_applicable, "worst": [c.record() for c in summary.worst.values()]}
    try:
        atomic_write_text(path, json.dumps({"sha256": checksum(doc), "summary": doc}))
    except OutputError:  # a full disk or a read-only folder: the summary in memory is still good
        pass


def run(catalogue, system, examples: int | None = None, read: bool = True) -> conformance.Summary:
    """:func:`harness.compare.conformance.run` of catalogued ``system`` against every engine that applies, stored
    under its key; with ``read``, read back instead where a run with the same key stored it. The main job computes
    (``harness check``: ``read=False``); the test suite reads what it computed."""
    entry = key(catalogue, system.name, examples)
    path = None if entry is None else folder() / f"{entry}.json"
    if read and path is not None:
        summary = _load(path)
        if summary is not None:
            profiling.count("conformance summary read back")
            return summary
    summary = conformance.run(system, examples=examples)
    if path is not None:
        _store(path, summary)
    return summary
