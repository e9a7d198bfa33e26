"""Reports people can read (``harness report``): ``results.json`` with a documented schema
(``docs/results-schema.md``), ``timings.json``, ``summary.md`` and a static, offline ``index.html`` with one page
per system, the errata, hard cases, benchmarks and importer findings when their JSON is present.

``harness check --out`` and ``harness report`` write through the same functions (:func:`write_results`).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from harness.report.results import check_folder, load_results, results_document, run_checks, timings_of, write_results
from harness.report.site import build_site

__all__ = ["build_report", "build_site", "load_results", "results_document", "run_checks", "write_results"]


def build_report(out: Path | str, names: list[str] | None = None, jobs: int = 1, examples: int | None = None,
                 seed: int | None = None, rerun: bool = False, scenes: bool = True, progress=sys.stderr) -> dict:
    """Check the systems that ``out/results.json`` does not hold yet (all with ``rerun``), write the results,
    then the site. Returns {"passed": bool, "ran": [...], "failed": {...}, "pages": [...]}."""
    import models

    out = check_folder(out)
    requested = names or list(models.catalogue())
    for name in requested:
        models.get(name)  # unknown names fail before any work
    existing = None if rerun else load_results(out)
    known = {r["system"]: r for r in (existing or {}).get("systems", [])}
    todo = [name for name in requested if name not in known]
    if todo or existing is None:
        print(f"checking {len(todo)} system(s) not in {out / 'results.json'} …", file=progress, flush=True)
        fresh, seconds = run_checks(todo, examples=examples, seed=seed, jobs=jobs, progress=progress, series_dir=out)
        for r in fresh:
            known[r["system"]] = r
        order = {name: k for k, name in enumerate(models.catalogue())}
        records = sorted(known.values(), key=lambda r: (order.get(r["system"], len(order)), r["system"]))
        doc = results_document(records, examples, seed)
        timings = _read_timings(out) if existing is not None else {}
        timings.update(timings_of(seconds))
        write_results(doc, out, timings=timings)
    else:
        doc = existing
        write_results(doc, out, timings=_read_timings(out))  # summary.md from the same writer
    print(f"rendering {out / 'index.html'} …", file=progress, flush=True)
    site = build_site(out, progress=progress)
    shown = [r for r in doc["systems"] if r["system"] in requested]
    return {"passed": all(r["passed"] for r in shown) and not site["failed"], "ran": todo, **site}


def _read_timings(out: Path) -> dict:
    try:
        data = json.loads((out / "timings.json").read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}
