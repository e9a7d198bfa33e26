"""Reports people can read, rendered from documents: ``results.json`` with a documented schema
(``docs/results-schema.md``), ``timings.json`` and ``summary.md`` (:mod:`.results`, :mod:`.markdown`), and a
static, offline ``index.html`` with one page per system, the errata, hard cases, benchmarks and importer findings
when their JSON is present (:mod:`.site`). What runs the checks and assembles the documents is the application
layer, :mod:`harness.run`.
"""

from __future__ import annotations

from harness.report.results import load_results, write_results
from harness.report.site import build_site

__all__ = ["build_site", "load_results", "write_results"]
