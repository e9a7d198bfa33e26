"""The result records of ``harness check`` and ``harness report``, one place: running the checks of each
system (in parallel processes with ``--jobs``), the ``results.json`` document (schema: ``docs/results-schema.md``)
and the split of wall-clock timings into ``timings.json``.

Determinism: the same seed (or the fixed-seed ``ci`` profile) gives a byte-identical ``results.json``. Nothing
measured by a clock goes into it: every key :func:`split_timings` recognises (``seconds``, ``…time ratio…``)
is moved to ``timings.json``.
"""

from __future__ import annotations

import json
import platform
import re
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from multiprocessing import get_context
from pathlib import Path

SCHEMA_VERSION = 2
SCHEMA_DOC = "docs/results-schema.md"
# keys whose values come from a clock (never deterministic): moved to timings.json
_TIMING_KEY = re.compile(r"seconds|time ratio|wall", re.IGNORECASE)


@dataclass(frozen=True)
class Job:
    """What one worker checks: one system, with the hypothesis settings of the run."""

    system: str
    examples: int | None = None
    seed: int | None = None
    scenes: bool = True
    series_dir: str | None = None


# --------------------------------------------------------------------------- hypothesis settings
def apply_seed(seed: int | None) -> None:
    """Load the hypothesis profile; with ``seed``, every check draws from ``Random(seed)`` (no example
    database, so that saved failures cannot change the run)."""
    import hypothesis.core
    from hypothesis import settings

    from harness.settings import load_hypothesis_profile

    name = load_hypothesis_profile()
    if seed is not None:
        settings.register_profile("seeded", parent=settings.get_profile(name), derandomize=False, database=None)
        settings.load_profile("seeded")
        hypothesis.core.global_force_seed = seed


def hypothesis_record(examples: int | None, seed: int | None) -> dict:
    """Profile, seed, example count and database location of a run (in the calling process)."""
    import os

    from hypothesis import settings

    from harness.settings import load_hypothesis_profile

    profile = load_hypothesis_profile()
    current = settings.get_profile(profile)
    db = None if seed is not None else current.database
    return {"profile": profile,
            "seed": seed,
            "derandomize": bool(current.derandomize) and seed is None,
            "seeding": (f"every check draws from Random({seed})" if seed is not None else
                        "each check's seed is derived from the check itself (derandomize)" if current.derandomize
                        else "random seed per check (not reproducible; give --seed)"),
            "max_examples": examples if examples is not None else current.max_examples,
            "database": None if db is None else str(getattr(db, "path", db)),
            "environment": {k: os.environ[k] for k in ("HYPOTHESIS_PROFILE",) if k in os.environ}}


def versions() -> dict:
    """Engine and library versions and the platform the numbers were produced with."""
    import hypothesis
    import mujoco
    import numpy
    import pinocchio
    import scipy
    import sympy

    return {"python": platform.python_version(), "platform": platform.platform(), "pinocchio": pinocchio.__version__,
            "mujoco": mujoco.__version__, "sympy": sympy.__version__, "numpy": numpy.__version__,
            "scipy": scipy.__version__, "hypothesis": hypothesis.__version__}


# --------------------------------------------------------------------------- one system
def _reason(exc: BaseException) -> str:
    from harness.errors import HarnessError

    return str(exc) if isinstance(exc, HarnessError) else f"{type(exc).__name__}: {exc}"


def check_record(system, examples: int | None = None, scenes: bool = True, series_dir: str | None = None) -> dict:
    """The conformance record of one system; a system raising gives a failed record with the reason. With
    ``scenes``, the trajectory checks of its scenes too (their series written into ``series_dir``)."""
    from harness.compare import conformance

    try:
        summary = conformance.run(system, examples=examples)
        record = {"system": system.name, "passed": summary.passed, "examples": summary.examples,
                  "failure": summary.failure, "not_applicable": summary.not_applicable,
                  "checks": [c.record() for c in sorted(summary.worst.values(), key=lambda c: (c.name, c.source))]}
    except Exception as exc:  # noqa: BLE001 - one system raising never loses the others' results
        record = {"system": system.name, "passed": False, "examples": 0, "failure": f"{system.name}: {_reason(exc)}",
                  "not_applicable": {}, "checks": []}
    record["lecture"], record["status"] = system.lecture, system.status
    if scenes:
        from harness.scenes.trajectories import scene_records

        record["scenes"] = scene_records(system, series_dir)
        record["passed"] = record["passed"] and all(s["passed"] for s in record["scenes"])
    return with_warnings(record)


def with_warnings(record: dict) -> dict:
    """The engine warnings raised while checking the system (:mod:`harness.engines.warnings_log`); an
    unexplained one fails the system."""
    from harness.engines import warnings_log

    record["warnings"] = warnings_log.drain(record["system"])
    unexplained = [w for w in record["warnings"] if not w["explained"]]
    if unexplained:
        record["passed"] = False
        reasons = "; ".join(f"unexplained {w['engine']} warning in {w['where']} ({w['count']}x): {w['message']} "
                            f"[{w['reason']}]" for w in unexplained)
        record["failure"] = f"{record['failure']}; {reasons}" if record["failure"] else f"{record['system']}: {reasons}"
    return record


def run_job(job: Job) -> tuple[dict, float]:
    """Check one system (in a worker process with ``--jobs``): its record and the wall time it took."""
    from harness.settings import draws_from_seed_only

    start = time.perf_counter()
    apply_seed(job.seed)
    with draws_from_seed_only():
        record = _record(job)
    return record, time.perf_counter() - start


def _record(job: Job) -> dict:
    import models

    try:
        system = models.get(job.system)
    except Exception as exc:  # noqa: BLE001 - a model that does not load is a failed record, not a lost run
        record = {"system": job.system, "passed": False, "examples": 0, "failure": f"{job.system}: {_reason(exc)}",
                  "not_applicable": {}, "checks": [], "lecture": "", "status": "does not load"}
    else:
        record = check_record(system, job.examples, job.scenes, job.series_dir)
    return record


def run_checks(names: list[str], examples: int | None = None, seed: int | None = None, jobs: int = 1,
               progress=None, scenes: bool = True, series_dir: str | None = None) -> tuple[list[dict], dict]:
    """Check ``names`` (in that order in the result), ``jobs`` systems at a time in spawned processes.
    Returns the records and the wall time per system. Progress goes to ``progress`` (stderr)."""
    progress = sys.stderr if progress is None else progress
    todo = [Job(name, examples, seed, scenes, None if series_dir is None else str(series_dir)) for name in names]
    records: dict[str, dict] = {}
    seconds: dict[str, float] = {}

    def done(record, wall):
        records[record["system"]] = record
        seconds[record["system"]] = round(wall, 2)
        verdict = "ok" if record["passed"] else "FAILED"
        print(f"[{len(records)}/{len(todo)}] {record['system']}: {verdict} ({wall:.1f} s)", file=progress, flush=True)

    if jobs > 1 and len(todo) > 1:
        print(f"checking {len(todo)} systems in {min(jobs, len(todo))} processes …", file=progress, flush=True)
        with ProcessPoolExecutor(min(jobs, len(todo)), mp_context=get_context("spawn")) as pool:
            futures = {pool.submit(run_job, job): job for job in todo}
            for future in as_completed(futures):
                try:
                    done(*future.result())
                except (BrokenProcessPool, Exception) as exc:  # noqa: BLE001 - a crashed worker loses one system
                    name = futures[future].system
                    done({"system": name, "passed": False, "examples": 0, "checks": [], "not_applicable": {},
                          "failure": f"{name}: worker process failed: {_reason(exc)}", "lecture": "",
                          "status": "check crashed"}, 0.0)
    else:
        for job in todo:
            print(f"checking {job.system} …", file=progress, flush=True)
            done(*run_job(job))
    return [records[name] for name in names], seconds


# --------------------------------------------------------------------------- the document
def tolerance_policy() -> str:
    from harness.compare import conformance

    text = conformance.__doc__.split("Tolerance policy")[1]
    return text.split("-----\n")[-1].strip() if "-----\n" in text else text.strip(" -\n")


def bounds_used(records: list[dict]) -> dict:
    """The bounds (:class:`harness.checks.Bound`) the records' checks refer to, each stated once with its reason."""
    import importlib

    importlib.import_module("harness.scenes.trajectories")  # declares the bounds of the scenes (and structural, constraints)
    from harness.checks import BOUNDS

    used = {c.get("basis") for r in records for c in r.get("checks", [])}
    used |= {c.get("basis") for r in records for s in r.get("scenes") or [] for c in s.get("checks", [])}
    return {name: BOUNDS[name].record() for name in sorted(n for n in used if n in BOUNDS)}


def results_document(records: list[dict], examples: int | None = None, seed: int | None = None) -> dict:
    """``results.json`` (schema version :data:`SCHEMA_VERSION`, described in ``docs/results-schema.md``)."""
    return {"schema": {"version": SCHEMA_VERSION, "description": SCHEMA_DOC},
            "tolerance_policy": tolerance_policy(),
            "bounds": bounds_used(records),
            "versions": versions(),
            "hypothesis": hypothesis_record(examples, seed),
            "systems": records,
            "passed": all(r["passed"] for r in records)}


def split_timings(node, path: str = "") -> tuple[object, dict]:
    """``node`` without clock-derived values, and those values by their path (``systems/pendulum/seconds``)."""
    timings = {}
    if isinstance(node, dict):
        kept = {}
        for key, value in node.items():
            here = f"{path}/{key}" if path else key
            if isinstance(key, str) and _TIMING_KEY.search(key) and not isinstance(value, (dict, list)):
                timings[here] = value
                continue
            kept[key], inner = split_timings(value, here)
            timings.update(inner)
        return kept, timings
    if isinstance(node, list):
        out = []
        for k, item in enumerate(node):
            name = item.get("scene") or item.get("system") if isinstance(item, dict) else None
            kept, inner = split_timings(item, f"{path}/{name or k}")
            out.append(kept)
            timings.update(inner)
        return out, timings
    return node, timings


def dumps(doc) -> str:
    """Strict JSON (non-finite numbers as strings, :func:`harness.checks.json_clean`), one value per line."""
    from harness.checks import json_clean

    return json.dumps(json_clean(doc), indent=1, ensure_ascii=False, allow_nan=False) + "\n"


def merge_records(existing: dict | None, records: list[dict]) -> list[dict]:
    """The records of ``existing`` (a results document) with those of ``records`` replacing them by system:
    a run over some systems never drops the others' results. Catalogue order, other systems after it."""
    import models

    merged = {r["system"]: r for r in (existing or {}).get("systems", []) if isinstance(r, dict) and "system" in r}
    merged.update({r["system"]: r for r in records})
    order = {name: k for k, name in enumerate(models.names())}
    return sorted(merged.values(), key=lambda r: (order.get(r["system"], len(order)), r["system"]))


def read_timings(out: Path | str) -> dict:
    """``out/timings.json`` if present and readable, else an empty dict."""
    try:
        data = json.loads((Path(out) / "timings.json").read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def timings_of(seconds: dict) -> dict:
    """Wall time per system as ``timings.json`` entries."""
    return {f"systems/{name}/seconds": wall for name, wall in seconds.items()}


def write_results(doc: dict, out: Path | str, timings: dict | None = None) -> list[Path]:
    """Write ``results.json`` (deterministic), ``timings.json`` (wall clock: ``timings`` plus every clock value
    found in ``doc``) and ``summary.md`` into ``out``; every file atomically. Returns the paths written."""
    from harness.io import atomic_write_text
    from harness.report.markdown import summary_markdown

    out = check_folder(out)
    clean, found = split_timings(doc)
    timings = {**(timings or {}), **found}
    atomic_write_text(out / "results.json", dumps(clean))
    atomic_write_text(out / "timings.json", dumps(dict(sorted(timings.items()))))
    atomic_write_text(out / "summary.md", summary_markdown(clean))
    return [out / "results.json", out / "timings.json", out / "summary.md"]


def check_folder(out: Path | str) -> Path:
    """The report folder; an existing file in its place is bad input (one line, no partial output)."""
    from harness.errors import InputError

    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out}: exists and is not a folder")
    return out


def load_results(out: Path | str) -> dict | None:
    """``out/results.json`` if present and readable, else None."""
    path = Path(out) / "results.json"
    try:
        doc = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return doc if isinstance(doc, dict) and isinstance(doc.get("systems"), list) else None
