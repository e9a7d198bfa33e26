"""The files of a results document: ``results.json`` (schema: ``docs/results-schema.md``), ``timings.json`` and
``summary.md``, written by one writer (:func:`write_results`) for ``harness check --out`` and ``harness report``.
The document itself is assembled by the application layer (:mod:`harness.run`).

Determinism: the same seed (or the fixed-seed ``ci`` profile) gives a byte-identical ``results.json``. Nothing
measured by a clock goes into it: a system record carries its clock values in its typed field ``timings`` (``seconds``), which
:func:`split_timings` moves to ``timings.json``.
"""

from __future__ import annotations

import json
from pathlib import Path

from harness.checks import json_clean
from harness.io import atomic_write_text, writable_folder
from harness.report.markdown import summary_markdown

TIMINGS = "timings"
"""The field of a system or scene record that holds its clock values (never written to results.json)."""


def split_timings(doc: dict) -> tuple[dict, dict]:
    """``doc`` without the system records' :data:`TIMINGS` fields, and their values by path
    ``systems/<system>/<name>``."""
    timings, systems = {}, []
    for record in doc.get("systems", []):
        record = dict(record)
        where = f"systems/{record.get('system')}"
        timings.update({f"{where}/{k}": v for k, v in (record.pop(TIMINGS, None) or {}).items()})
        systems.append(record)
    return {**doc, "systems": systems} if "systems" in doc else dict(doc), timings


def dumps(doc) -> str:
    """Strict JSON (non-finite numbers as strings, :func:`harness.checks.json_clean`), one value per line."""
    return json.dumps(json_clean(doc), indent=1, ensure_ascii=False, allow_nan=False) + "\n"


def read_timings(out: Path | str) -> dict:
    """``out/timings.json`` if present and readable, else an empty dict."""
    try:
        data = json.loads((Path(out) / "timings.json").read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def write_results(doc: dict, out: Path | str, timings: dict | None = None) -> list[Path]:
    """Write ``results.json`` (deterministic), ``timings.json`` (``timings`` plus the records' clock values) and
    ``summary.md`` into ``out``; every file atomically. A system whose record carries clock values replaces all
    of its earlier ones in ``timings`` (including the scenes' pruning ratios that earlier versions kept there).
    Returns the paths written."""
    out = check_folder(out)
    clean, found = split_timings(doc)
    fresh = tuple(f"systems/{r.get('system')}/" for r in doc.get("systems", []) if r.get(TIMINGS) is not None)
    atomic_write_text(out / "results.json", dumps(clean))
    write_timings(out, found, kept={k: v for k, v in (timings or {}).items() if not k.startswith(fresh)})
    atomic_write_text(out / "summary.md", summary_markdown(clean))
    return [out / "results.json", out / "timings.json", out / "summary.md"]


def write_timings(out: Path | str, values: dict, kept: dict | None = None) -> Path:
    """``values`` (clock values by path) written over ``kept`` (default: what ``out/timings.json`` holds) into
    ``out/timings.json``, atomically, sorted by path."""
    timings = {**(read_timings(out) if kept is None else kept), **values}
    atomic_write_text(Path(out) / "timings.json", dumps(dict(sorted(timings.items()))))
    return Path(out) / "timings.json"


def check_folder(out: Path | str, what: str = "--out") -> Path:
    """The report folder, checked before the work: an existing file in its place, or a folder we cannot write
    into, is bad input (one line, no partial output; :func:`harness.io.writable_folder`)."""
    return writable_folder(out, what)


def load_results(out: Path | str) -> dict | None:
    """``out/results.json`` if present and readable, else None."""
    path = Path(out) / "results.json"
    try:
        doc = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return doc if isinstance(doc, dict) and isinstance(doc.get("systems"), list) else None


def read_claims(out: Path | str) -> list[dict]:
    """The records of ``out/claims.json`` (those naming a system), an empty list when absent or unreadable."""
    try:
        records = json.loads((Path(out) / "claims.json").read_text())
    except (OSError, ValueError):
        return []
    return [r for r in records if isinstance(r, dict) and "system" in r] if isinstance(records, list) else []


def write_claims(records: list[dict], out: Path | str, lecture: set[str] | None = None) -> list[Path]:
    """``claims.json`` (the records, non-finite numbers as strings) and the errata sheet ``errata.md`` and
    ``errata.html`` (:mod:`harness.report.errata`, the page as the report's site has it:
    :func:`harness.report.site.write_errata`; ``lecture``: the lecture systems with printed equations,
    :func:`harness.report.errata.unclaimed`), atomically."""
    from harness.report import errata
    from harness.report.site import write_errata

    out = Path(out)
    atomic_write_text(out / "claims.json", json.dumps(json_clean(records), indent=1) + "\n")
    atomic_write_text(out / "errata.md", errata.markdown(records, lecture))
    return [out / "claims.json", out / "errata.md", write_errata(out, records, lecture)]
