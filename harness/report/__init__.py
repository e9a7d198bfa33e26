"""Reports people can read (``harness report``): ``results.json`` with a documented schema
(``docs/results-schema.md``), ``timings.json``, ``summary.md`` and a static, offline ``index.html`` with one page
per system, the errata, hard cases, benchmarks and importer findings when their JSON is present.

``harness check --out`` and ``harness report`` write through the same functions (:func:`write_results`).
"""

from __future__ import annotations

import sys
from pathlib import Path

from harness.report.results import (check_folder, load_results, merge_records, read_timings, results_document,
                                    run_checks, timings_of, write_results)
from harness.report.site import build_site

__all__ = ["build_report", "build_site", "load_results", "results_document", "run_checks", "write_results"]


def build_report(out: Path | str, names: list[str] | None = None, jobs: int = 1, examples: int | None = None,
                 seed: int | None = None, rerun: bool = False, scenes: bool = True, progress=None) -> dict:
    """Check the systems that ``out/results.json`` does not hold yet (all with ``rerun``), write the results,
    then the site. Returns {"passed": bool, "ran": [...], "failed": {...}, "pages": [...]}."""
    progress = sys.stderr if progress is None else progress
    import models

    out = check_folder(out)
    requested = names or models.names()   # a module that does not load gets a failed record and page
    for name in names or []:
        models.get(name)  # unknown or broken names given by the user fail before any work
    existing = load_results(out)
    known = {r["system"] for r in (existing or {}).get("systems", [])}
    todo = [name for name in requested if rerun or name not in known]
    if todo or existing is None:
        print(f"checking {len(todo)} system(s) not in {out / 'results.json'} …", file=progress, flush=True)
        fresh, seconds = run_checks(todo, examples=examples, seed=seed, jobs=jobs, progress=progress, series_dir=out)
        doc = results_document(merge_records(existing, fresh), examples, seed)
        timings = read_timings(out)
        timings.update(timings_of(seconds))
        write_results(doc, out, timings=timings)
    else:
        doc = existing
        write_results(doc, out, timings=read_timings(out))  # summary.md from the same writer
    print(f"rendering {out / 'index.html'} …", file=progress, flush=True)
    site = build_site(out, progress=progress)
    shown = [r for r in doc["systems"] if r["system"] in requested]
    return {"passed": all(r["passed"] for r in shown) and not site["failed"], "ran": todo, **site}

