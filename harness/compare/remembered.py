"""A system's conformance summary remembered on disk under a hash of everything that determines it, so that the
test suite reads what the main job computed instead of computing it again (``make check`` then ``make test``).

The examples of a conformance run are fixed by the hypothesis settings (derandomized, no example database, drawn
from the seed only: :func:`harness.settings.draws_from_seed_only`); its numbers by our code, the model files, the
installed packages, Python and the environment variables that change NumPy's or BLAS's kernels. The key hashes all
of them: every file under ``harness/`` and on the catalogue's search path, every installed distribution with its
version, Python's version, the ``OPENBLAS_*``, ``NPY_*``, ``OMP_*``, ``MKL_*`` and ``HYPOTHESIS_*`` variables, the
settings and the run's arguments. A change to any of them computes the summary again. Where the examples are not
fixed by the settings (a random seed, an example database) nothing is remembered. An entry is kept as every entry of
:mod:`harness.kept` (its checksum, another installation's entries removed); a damaged one is computed again. The
folder is ``results/`` beside the derivation cache; the tests read a copy of the project's (``tests/conftest.py``)."""

from __future__ import annotations

from pathlib import Path

from harness import kept, profiling
from harness.checks import Check
from harness.compare import conformance


def folder() -> Path:
    from harness.derivation.cache import cache_dir

    return cache_dir().parent / "results"


def path(catalogue, name: str, examples: int | None) -> Path | None:
    """Where the summary of ``name`` is kept (:func:`harness.kept.path`, ``results/``: our installation, the model
    files, the numeric environment, the run's arguments and settings), or None when the examples are not fixed by
    the settings."""
    from harness.settings import fixed_examples

    fixed = fixed_examples()
    if fixed is None:
        return None
    return kept.path("results", f"conformance-{name}", kept.files_digest(catalogue.path), kept.numeric_environment(),
                     name, repr(examples), repr(fixed))


def key(catalogue, name: str, examples: int | None) -> str | None:
    """The entry's name in :func:`folder` (:func:`path` without its suffix), or None when the examples are not fixed
    by the settings."""
    where = path(catalogue, name, examples)
    return None if where is None else where.stem


def _load(where: Path) -> conformance.Summary | None:
    doc = kept.read_kept(where)
    try:
        summary = conformance.Summary(doc["system"], doc["examples"], failure=doc["failure"],
                                      not_applicable=dict(doc["not_applicable"]),
                                      parameter_draws=doc["parameter_draws"])
        for record in doc["worst"]:  # Check.record()'s fields, as results.json holds them
            check = Check(record["check"], record["source"], record["value"], record["bound"], record["basis"],
                          record.get("detail", ""))
            summary.worst[check.name, check.source] = check
        return summary
    except (ValueError, KeyError, TypeError):  # missing or damaged: computed again
        return None


def _store(where: Path, summary: conformance.Summary) -> None:
    kept.keep(where, {"system": summary.system, "examples": summary.examples,
                      "parameter_draws": summary.parameter_draws, "failure": summary.failure,
                      "not_applicable": summary.not_applicable, "worst": [c.record() for c in summary.worst.values()]})


def run(catalogue, system, examples: int | None = None, read: bool = True) -> conformance.Summary:
    """:func:`harness.compare.conformance.run` of catalogued ``system`` against every engine that applies, stored
    under its key; with ``read``, read back instead where a run with the same key stored it. The main job computes
    (``harness check``: ``read=False``); the test suite reads what it computed."""
    where = path(catalogue, system.name, examples)
    if read and where is not None:
        summary = _load(where)
        if summary is not None:
            profiling.count("conformance summary read back")
            return summary
    summary = conformance.run(system, examples=examples)
    if where is not None:
        _store(where, summary)
    return summary
