"""The application layer: what each command does, from a catalogue (:class:`harness.catalogue.Catalogue`) to
records and documents. ``harness.cli`` parses the arguments, calls one function here and prints what it returns;
:mod:`harness.report` renders the documents (Markdown, HTML, figures). Library code never imports ``models``: it
is handed the catalogue (or the systems) from here.

Records
-------
* a **system record** (:func:`check_record`): the conformance checks of one system (:class:`harness.checks.Check`
  records), its scenes, its engine warnings; its clock values in the typed field ``timings``, which the writer
  (:func:`harness.report.results.write_results`) moves to ``timings.json``;
* the **results document** (:func:`results_document`): the records, the bounds they refer to, versions and the
  hypothesis settings (schema ``docs/results-schema.md``);
* a **claim record** (:func:`classify_system`): one printed equation of the lecture with its classification.

Process pools: ``--jobs N`` checks (or classifies) systems in spawned processes; each job carries the catalogue,
which a worker rebuilds from its description. Within :func:`harness.pool.workers_kept` (the main job, ``harness
main``) every phase runs on the same processes: a later phase finds what an earlier one imported, loaded and
compiled. ``--scheduler ADDRESS`` runs the same jobs on a Dask cluster
(:mod:`harness.cluster`); the results come back to this process, which writes the files as with ``--jobs``. A
run over some systems is merged by system into what the report folder holds (:func:`merge_records`,
:func:`merge_claims`).
"""

from __future__ import annotations

import importlib
import json
import math
import os
import platform
import sys
import time
from concurrent.futures import CancelledError, as_completed
from concurrent.futures.process import BrokenProcessPool
from contextlib import closing
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from harness import cluster, profiling
from harness.errors import EngineError, HarnessError, InputError
from harness.io import atomic_write_text, writable_folder
from harness.pool import ended, kept as kept_pool, processes, submitting
from harness.report.results import (check_folder, load_results, read_claims, read_timings, write_claims,
                                    write_results, write_timings)
from harness.settings import draws_from_seed_only, load_hypothesis_profile, seeded

if TYPE_CHECKING:  # the catalogue is handed in; importing it would load the modeling vocabulary (SymPy)
    from harness.catalogue import Catalogue

SCHEMA_VERSION = 2
SCHEMA_DOC = "docs/results-schema.md"


def _reason(exc: BaseException) -> str:
    return str(exc) if isinstance(exc, HarnessError) else f"{type(exc).__name__}: {exc}"


# =========================================================================================== list, eval
def listing(catalogue: Catalogue) -> list[tuple[str, str, str, str]]:
    """``(system, dof, lecture, status)`` of every system, then of every module that does not load; a system from
    an added folder (:meth:`Catalogue.from_lecture`) says which, beside its status."""
    def status(s) -> str:
        if catalogue.from_lecture(s.name):
            return s.status
        return f"{s.status}, outside the lecture's catalogue: {Path(catalogue.module(s.name).__file__).parent}"

    rows = [(s.name, str(len(s.coordinates)), s.lecture, status(s)) for s in catalogue.systems().values()]
    return rows + [(name, "?", "—", "does not load (harness check shows why)") for name in catalogue.failures()]


def evaluate(catalogue: Catalogue, name: str, engine: str, q, qd=None, params=None, inputs=None) -> dict:
    """``M``, ``C``, ``C q̇``, ``g`` and ``q̈`` of system ``name`` at one state from ``engine``, in lecture
    coordinates, with the state used and the engine call that produced each number (``harness eval --json``)."""
    from harness.engines import evaluate as engine_evaluate
    from harness.engines.base import State

    system = catalogue.get(name)
    state = State.make(system, q, qd, params or {}, inputs or {})
    _check_state_regular(state)  # one verdict for every engine at a coordinate singularity
    try:
        with np.errstate(all="ignore"):  # a value that is not finite is an error below, not a warning
            ev = engine_evaluate(engine, state)
    except np.linalg.LinAlgError as exc:
        raise EngineError(f"{system.name}: {engine} failed at q = {state.q.tolist()}: {exc}") from None
    for key in ("M", "C", "Cqd", "g", "f_damper", "qdd"):
        value = getattr(ev, key)
        if value is not None and not np.all(np.isfinite(value)):
            changed = ", ".join(f"{k}={v:g}" for k, v in state.params.items()
                                if v != system.default_parameters()[k]) or "default parameters"
            raise EngineError(f"{system.name}: {engine} gives a non-finite {key} at q = {state.q.tolist()}, "
                              f"qd = {state.qd.tolist()} ({changed})")
    return {"system": system.name, "engine": ev.engine,
            "coordinates": [c.name for c in system.coordinates],
            "q": state.q.tolist(), "qd": state.qd.tolist(), "params": state.params, "inputs": state.u,
            "M": ev.M.tolist(), "C": None if ev.C is None else ev.C.tolist(), "Cqd": ev.Cqd.tolist(),
            "g": ev.g.tolist(), "f_damper": ev.f_damper.tolist(), "qdd": ev.qdd.tolist(), "calls": ev.calls}


def _check_state_regular(state) -> None:
    """Raise the symbolic model's ModelError where ``M(q)`` is singular (a coordinate singularity) or a force term is
    not finite (a spring between two points at the same place), whatever the engine: Pinocchio would return NaN
    and MuJoCo, with its lower bound on inertias, q̈ = 0 there, or a zero-length tendon's force 0."""
    from harness.derivation.compile import compiled

    with np.errstate(all="ignore"):  # raises its clear error (CompiledModel.not_regular)
        compiled(state.system).forward_dynamics(state.q, state.qd, state.p, state.u_vec)


# =========================================================================================== the results document
def hypothesis_record(examples: int | None, seed: int | None) -> dict:
    """Profile, seed, example count and database location of a run (in the calling process)."""
    from hypothesis import settings

    from harness.compare.strategies import STATES_PER_DRAW

    profile = load_hypothesis_profile()
    current = settings.get_profile(profile)
    db = None if seed is not None else current.database
    return {"profile": profile,
            "seed": seed,
            "derandomize": bool(current.derandomize) and seed is None,
            "seeding": (f"every check draws from Random({seed})" if seed is not None else
                        "each system's states are drawn from a seed of its name (derandomize)" if current.derandomize
                        else "random seed per check (not reproducible; give --seed)"),
            "max_examples": examples if examples is not None else current.max_examples,
            "states_per_draw": STATES_PER_DRAW,
            "database": None if db is None else str(getattr(db, "path", db)),
            "environment": {k: os.environ[k] for k in ("HYPOTHESIS_PROFILE",) if k in os.environ}}


def versions() -> dict:
    """Engine and library versions and the platform the numbers were produced with."""
    from importlib.metadata import version

    import hypothesis
    import mujoco
    import numpy
    import pinocchio
    import scipy
    import sympy

    return {"python": platform.python_version(), "platform": platform.platform(), "pinocchio": pinocchio.__version__,
            "mujoco": mujoco.__version__, "sympy": sympy.__version__, "numpy": numpy.__version__,
            "scipy": scipy.__version__, "hypothesis": hypothesis.__version__, "drake": version("drake")}


def tolerance_policy() -> str:
    from harness.compare import conformance

    text = conformance.__doc__.split("Tolerance policy")[1]
    return text.split("-----\n")[-1].strip() if "-----\n" in text else text.strip(" -\n")


def bounds_used(records: list[dict]) -> dict:
    """The bounds (:class:`harness.checks.Bound`) the records' checks refer to, each stated once with its reason."""
    from harness.checks import BOUNDS

    importlib.import_module("harness.scenes.trajectories")  # declares the bounds of the scenes

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


def merge_records(catalogue: Catalogue, existing: dict | None, records: list[dict]) -> list[dict]:
    """The records of ``existing`` (a results document) with those of ``records`` replacing them by system:
    a run over some systems never drops the others' results. Catalogue order, other systems after it."""
    merged = {r["system"]: r for r in (existing or {}).get("systems", []) if isinstance(r, dict) and "system" in r}
    merged.update({r["system"]: r for r in records})
    order = catalogue.order()
    return sorted(merged.values(), key=lambda r: (order.get(r["system"], len(order)), r["system"]))


# =========================================================================================== one system's checks
def scene_records(catalogue: Catalogue, system, series_dir=None, collected: dict | None = None) -> list[dict]:
    """The records of every scene of ``system``; with ``series_dir``, each scene's series is written to
    ``series_dir/<record['series']>`` (atomically); with ``collected`` (a dict) instead, stored there by that name
    for the caller to write (:func:`write_series`)."""
    from harness.scenes.trajectories import scene_record

    records = []
    for scene in catalogue.scenes(system.name):
        record, data = scene_record(system, scene, catalogue)
        if collected is not None and data:
            collected[record["series"]] = data
        elif series_dir is not None and data:
            write_series(series_dir, {record["series"]: data})
        elif series_dir is None and collected is None:
            record["series"] = None
        records.append(record)
    return records


def write_series(series_dir, series: dict) -> None:
    """Each scene's series ``{name: data}`` to ``series_dir/<name>`` (atomically)."""
    for name, data in series.items():
        atomic_write_text(Path(series_dir) / name, json.dumps(data) + "\n")


def check_record(catalogue: Catalogue, system, examples: int | None = None, scenes: bool = True,
                 series_dir: str | None = None, collected: dict | None = None) -> dict:
    """The conformance record of one system; a system raising gives a failed record with the reason. With
    ``scenes``, the trajectory checks of its scenes too (their series written into ``series_dir``, or stored in
    ``collected``: :func:`scene_records`)."""
    from harness.compare import remembered

    try:
        summary = remembered.run(catalogue, system, examples, read=False)  # computed, and stored for the tests
        record = {"system": system.name, "passed": summary.passed, "examples": summary.examples,
                  "parameter_draws": summary.parameter_draws, "failure": summary.failure,
                  "not_applicable": summary.not_applicable,
                  "checks": [c.record() for c in sorted(summary.worst.values(), key=lambda c: (c.name, c.source))]}
    except Exception as exc:  # noqa: BLE001 - one system raising never loses the others' results
        record = {"system": system.name, "passed": False, "examples": 0, "failure": f"{system.name}: {_reason(exc)}",
                  "not_applicable": {}, "checks": []}
    record["lecture"], record["status"] = system.lecture, system.status
    if scenes:
        record["scenes"] = scene_records(catalogue, system, series_dir, collected)
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


def _failed_record(name: str, failure: str, status: str) -> dict:
    return {"system": name, "passed": False, "examples": 0, "checks": [], "not_applicable": {}, "failure": failure,
            "lecture": "", "status": status}


@dataclass(frozen=True)
class Job:
    """What one worker checks: one system of ``catalogue`` (rebuilt in the worker from its description), with
    the hypothesis settings of the run."""

    catalogue: Catalogue
    system: str
    examples: int | None = None
    seed: int | None = None
    scenes: bool = True
    series_dir: str | None = None
    profile: bool = False
    series_back: bool = False  # the scenes' series come back in the record (``series_data``) for the client to
    # write, instead of being written by the worker (the workers of a Dask cluster need not share its file system)
    claims: bool = False  # also classify the system's printed equations (:func:`classify_system`) on the states
    # the conformance run evaluated, their numbers kept (:mod:`harness.compare.evaluations`): the main job


class Interrupted(HarnessError):
    """Ctrl-C during a run: the records of the systems that finished (written by the caller), then exit 130."""

    exit_code = 130

    def __init__(self, finished: list, total: int):
        super().__init__(f"interrupted: {len(finished)} of {total} systems finished; their results are kept")
        self.finished = finished


def longest_first(jobs: list, seconds) -> list:
    """``jobs`` ordered for a pool: the longest first, by ``seconds(job)`` the previous run took (None: not known,
    put first, it may be long). With the jobs in catalogue order the longest system (tower_crane, 40 s cold) was
    started last and ran alone at the end; the results do not depend on the order (each is kept by its name)."""
    known = [seconds(job) for job in jobs]
    return [job for _, job in sorted(zip(known, jobs), key=lambda pair: -math.inf if pair[0] is None else -pair[0])]


def _seconds_before(path: Path, items: str, key: str) -> dict:
    """``{record[key]: record["seconds"]}`` of the records ``items`` of the document at ``path`` (a previous run's,
    for :func:`longest_first`); empty where there is none or it has another shape."""
    try:
        return {r[key]: r.get("seconds") for r in json.loads(path.read_text())[items]}
    except (OSError, ValueError, KeyError, TypeError):
        return {}


def parallel(work, jobs: list, workers: int, done, lost, announce=None, scheduler=None) -> bool:
    """Run ``work(job)`` for every job, ``workers`` at a time in spawned processes (in this process with one
    worker), or with ``scheduler`` on that Dask cluster (:func:`harness.cluster.results`; ``workers`` unused),
    handing each result to ``done``. A worker that dies (killed, out of memory, a crash in an engine)
    loses no other job: the jobs its pool had not finished run again, each in a fresh process of its own, and
    only a job that kills its own process is given up (``done(lost(job, reason))``). On Ctrl-C the workers are
    stopped, nothing more is started and ``True`` is returned (the finished results have been handed over)."""
    if scheduler is not None:
        try:
            with closing(cluster.results(scheduler, work, jobs, lost)) as finished:
                for _, result in finished:
                    done(result)
        except KeyboardInterrupt:
            return True
        return False
    if workers <= 1 or len(jobs) <= 1:
        try:
            for job in jobs:
                announce and announce(job)
                done(work(job))
        except KeyboardInterrupt:
            return True
        return False
    kept = kept_pool()
    pool, unfinished = None, []
    try:
        with submitting():  # phases side by side (harness main): the pool runs their jobs in the phases' order
            pool = kept.get() if kept is not None else processes(min(workers, len(jobs)))
            futures = {pool.submit(work, job): job for job in jobs}
        for future in as_completed(futures):
            try:
                done(future.result())
            except (BrokenProcessPool, CancelledError):
                unfinished.append(futures[future])
        if kept is not None and kept.stopped.is_set():  # Ctrl-C in the main job: its pool was ended
            return True
        if kept is None:
            pool.shutdown()
        elif unfinished:  # a worker died: the next phase gets new processes
            kept.discard()
        for job in [j for j in jobs if j in unfinished]:  # isolated: a job that kills its process is found out
            single = processes(1)
            pool = single
            try:
                done(single.submit(work, job).result())
            except BrokenProcessPool:
                done(lost(job, "its worker process died twice (killed, out of memory or a crash in an engine)"))
            single.shutdown()
    except KeyboardInterrupt:
        if kept is not None and (pool is None or pool is kept.pool):
            kept.discard(terminate=True)
        elif pool is not None:
            ended(pool)
        return True
    return False


def run_job(job: Job) -> dict:
    """Check one system (in a worker process with ``--jobs``): its record, the wall time it took in its
    ``timings``; with ``job.claims``, then its printed equations, classified on the states the check evaluated (the
    result of :func:`classify_system` in the record's ``claims``)."""
    from harness.compare import evaluations

    # the run's seed for the check and the claims, the process's own after them; the numbers at the check's states
    with seeded(job.seed), evaluations.sharing():
        record = _checked(job)
        if job.claims:
            record["claims"] = classify_system((job.catalogue, job.system, job.examples, job.profile))
    return record


def _checked(job: Job) -> dict:
    start = time.perf_counter()
    if job.profile:
        profiling.enable()
        profiling.reset()
        profiling.instrument_scenes()
    with draws_from_seed_only():
        try:
            with profiling.phase("load the model module"):
                system = job.catalogue.get(job.system)
        except Exception as exc:  # noqa: BLE001 - a model that does not load is a failed record, not a lost run
            record = _failed_record(job.system, f"{job.system}: {_reason(exc)}", "does not load")
        else:
            collected = {} if job.series_back else None
            record = check_record(job.catalogue, system, job.examples, job.scenes, job.series_dir, collected)
            if collected is not None:
                record["series_data"] = collected
    record["timings"] = {"seconds": round(time.perf_counter() - start, 2)}
    if job.profile:
        record["profile"] = profiling.snapshot()
        profiling.enable(False)
    return record


def run_checks(catalogue: Catalogue, names: list[str], examples: int | None = None, seed: int | None = None,
               jobs: int = 1, progress=None, scenes: bool = True, series_dir: str | None = None,
               profiles: dict | None = None, scheduler=None, previous: dict | None = None,
               claims: dict | None = None) -> list[dict]:
    """Check ``names`` (in that order in the result; started longest first by the ``previous`` run's timings.json),
    ``jobs`` systems at a time in spawned processes, or on the
    Dask cluster at ``scheduler`` (the scenes' series then come back and are written here). Each record holds its
    wall time in ``timings``. Progress goes to ``progress`` (stderr). With ``profiles`` (a dict), each system's
    phases (:mod:`harness.profiling`) are stored there by system name. With ``claims`` (a dict), each job also
    classifies its system's printed equations (``Job.claims``): the results are stored there by system name."""
    progress = sys.stderr if progress is None else progress
    remote = scheduler is not None
    todo = [Job(catalogue, name, examples, seed, scenes, None if series_dir is None or remote else str(series_dir),
                series_back=remote and series_dir is not None, claims=claims is not None)
            for name in names]
    if profiles is not None:
        todo = [replace(job, profile=True) for job in todo]
    records: dict[str, dict] = {}

    def done(record):
        series = record.pop("series_data", None)
        if series:
            write_series(series_dir, series)
        classified = record.pop("claims", None)
        if claims is not None and classified is not None:
            claims[record["system"]] = classified
        snapshot = record.pop("profile", None)
        if profiles is not None and snapshot is not None:
            profiles[record["system"]] = snapshot
        records[record["system"]] = record
        verdict = "ok" if record["passed"] else "FAILED"
        print(f"[{len(records)}/{len(todo)}] {record['system']}: {verdict} ({record['timings']['seconds']:.1f} s)",
              file=progress, flush=True)

    def lost(job, reason):
        return {**_failed_record(job.system, f"{job.system}: {reason}", "check crashed"), "timings": {"seconds": 0.0}}

    previous = previous or {}
    todo = longest_first(todo, lambda job: previous.get(f"systems/{job.system}/seconds"))
    if not remote:
        if jobs > 1 and len(todo) > 1:
            print(f"checking {len(todo)} systems in {min(jobs, len(todo))} processes …", file=progress, flush=True)
        interrupted = parallel(run_job, todo, jobs, done, lost,
                               announce=lambda job: print(f"checking {job.system} …", file=progress, flush=True))
    else:
        with cluster.client(scheduler) as dask:  # a bad address: one line before anything is printed or run
            print(f"checking {len(todo)} systems on the Dask cluster at {dask.scheduler.address} "
                  f"({cluster.workers(dask)} worker processes) …", file=progress, flush=True)
            interrupted = parallel(run_job, todo, jobs, done, lost, scheduler=dask)
    if interrupted:
        raise Interrupted([records[n] for n in names if n in records], len(todo))
    return [records[name] for name in names]


# =========================================================================================== harness check, report
@dataclass
class CheckRun:
    """What ``harness check`` produced: the results document of this run (records with their ``timings``) and
    the files written (``--out``: merged by system into what the folder held)."""

    document: dict
    written: list = field(default_factory=list)
    profile: dict | None = None  # with --profile: where the time went (harness.profiling.document)

    @property
    def passed(self) -> bool:
        return self.document["passed"]


def _systems(catalogue: Catalogue, names) -> list[str]:
    """The names asked for (unknown or broken ones fail before any work), else every name of the catalogue (a
    module that does not load is reported as that system's failure)."""
    catalogue.require(names)
    return list(names) if names else catalogue.names()


def check(catalogue: Catalogue, names=None, examples: int | None = None, seed: int | None = None, jobs: int = 1,
          scenes: bool = True, out=None, progress=None, profile: bool = False, scheduler=None,
          claims: dict | None = None) -> CheckRun:
    """Conformance (and scenes) of each system, ``jobs`` at a time or on the Dask cluster at ``scheduler``; with
    ``out``, results.json, timings.json and summary.md there, merged by system into what the folder holds. With
    ``profile``, where the time went (per phase, per system; :mod:`harness.profiling`), also written to
    ``out/profile.json`` and ``out/profile.md``. With ``claims`` (a dict), each system's printed equations are
    classified in its job, on the states its check evaluated, the results put there for :func:`claims` (the main
    job)."""
    start, cpu = time.perf_counter(), time.process_time()
    profiles = {} if profile else None
    names = _systems(catalogue, names)
    if out:
        check_folder(out)
    try:
        records = run_checks(catalogue, names, examples=examples, seed=seed, jobs=jobs, scenes=scenes,
                             series_dir=out, progress=progress, profiles=profiles, scheduler=scheduler,
                             previous=read_timings(out) if out else None, claims=claims)
    except Interrupted as stop:  # what finished is kept
        if out and stop.finished:
            merged = results_document(merge_records(catalogue, load_results(out), stop.finished), examples, seed)
            write_results(merged, out, timings=read_timings(out))
        raise
    run = CheckRun(results_document(records, examples, seed))
    if out:  # merged by system into what the folder holds: other systems' results are kept
        merged = results_document(merge_records(catalogue, load_results(out), records), examples, seed)
        run.written = write_results(merged, out, timings=read_timings(out))
    if profile:
        run.profile = _profile_document("check", profiles, start, cpu, jobs)
        if out:
            run.written += profiling.write(run.profile, out)
    return run


def _profile_document(command: str, profiles: dict, start: float, cpu: float, jobs: int) -> dict:
    """The profile of a run: the systems' phases summed, each system's own, the parent process's CPU time."""
    total: dict = {}
    for snapshot in profiles.values():
        profiling.merge(total, snapshot)
    doc = profiling.document(command, total, profiles, time.perf_counter() - start, jobs, sys.argv[1:])
    doc["parent_cpu_seconds"] = round(time.process_time() - cpu, 2)
    return doc


def report(catalogue: Catalogue, out, names=None, jobs: int = 1, examples: int | None = None,
           seed: int | None = None, rerun: bool = False, scenes: bool = True, progress=None) -> dict:
    """Check the systems that ``out/results.json`` does not hold yet (all with ``rerun``), write the results,
    then the site. Returns {"passed": bool, "ran": [...], "failed": {...}, "pages": [...]}."""
    from harness.report.site import build_site

    progress = sys.stderr if progress is None else progress
    out = check_folder(out)
    requested = _systems(catalogue, names)
    existing = load_results(out)
    known = {r["system"] for r in (existing or {}).get("systems", [])}
    todo = [name for name in requested if rerun or name not in known]
    if todo or existing is None:
        print(f"checking {len(todo)} system(s) not in {out / 'results.json'} …", file=progress, flush=True)
        try:
            fresh = run_checks(catalogue, todo, examples=examples, seed=seed, jobs=jobs, progress=progress,
                               scenes=scenes, series_dir=out, previous=read_timings(out))
        except Interrupted as stop:  # what finished is kept
            if stop.finished:
                write_results(results_document(merge_records(catalogue, existing, stop.finished), examples, seed),
                              out, timings=read_timings(out))
            raise
        doc = results_document(merge_records(catalogue, existing, fresh), examples, seed)
    else:
        doc = existing
    write_results(doc, out, timings=read_timings(out))  # summary.md from the same writer
    print(f"rendering {out / 'index.html'} …", file=progress, flush=True)
    site = build_site(out, catalogue, progress=progress, jobs=jobs)
    shown = [r for r in doc["systems"] if r["system"] in requested]
    return {"passed": all(r["passed"] for r in shown) and not site["failed"], "ran": todo, **site}


# =========================================================================================== harness claims
def classify_system(job: tuple) -> dict:
    """Classify the claims of one system (in a worker process with ``--jobs``): ``{"system", "failure",
    "records"}``; a module that does not load, or a claim that cannot be evaluated, is a failure of its own."""
    from harness.compare import claims
    from harness.derivation.compile import compiled as compiled_model
    from harness.engines import warnings_log

    catalogue, name, examples, *profile = job
    start = time.perf_counter()
    if profile and profile[0]:
        profiling.enable()
        profiling.reset()
    load_hypothesis_profile()
    with draws_from_seed_only():  # the examples depend on the seed only, not on our source's literals
        try:
            with profiling.phase("load the model module"):
                system, printed = catalogue.get(name), catalogue.claims(name)
        except HarnessError as exc:
            return {"system": name, "failure": str(exc), "records": [], **_profile_snapshot()}
        with profiling.phase("derivation and compilation"):
            try:
                compiled_model(system).warm()
            except Exception:  # noqa: BLE001 - the claims below report it, one by one
                pass
        out, failures = [], []
        with claims.shared_evaluations():  # the same drawn states for every claim of the system
            for claim in printed:
                cluster.echo(f"classifying {name} {claim.equation} …", file=sys.stderr)
                try:
                    with profiling.phase("classify"):
                        v = claims.classify(system, claim, examples=examples, claims=printed)
                        extra = claims.record_fields(system, v, printed)
                except Exception as exc:  # noqa: BLE001 - one claim that cannot be evaluated does not lose the others
                    failures.append(f"{name} {claim.equation}: cannot be evaluated: {type(exc).__name__}: {exc}")
                    continue
                out.append({**claim_record(v), **extra})
    failures += [f"{name}: unexplained {w['engine']} warning in {w['where']} ({w['count']}x): {w['message']}"
                 for w in warnings_log.drain(name) if not w["explained"]]
    return {"system": name, "failure": "; ".join(failures) or None, "records": out,
            "seconds": round(time.perf_counter() - start, 2), **_profile_snapshot()}


def _profile_snapshot() -> dict:
    """``{"profile": …}`` of this process's phases when profiling (and profiling switched off), else ``{}``."""
    if not profiling.enabled():
        return {}
    snapshot = profiling.snapshot()
    profiling.enable(False)
    return {"profile": snapshot}


def claim_record(v) -> dict:
    """A :class:`harness.compare.claims.Classification` as a ``claims.json`` record."""
    return {"system": v.system, "equation": v.claim.equation, "quantity": v.claim.quantity,
            "description": v.claim.description, "classification": v.classification,
            "printed": str(v.claim.printed), "corrected": v.corrected, "convention": v.convention,
            "counterexample": v.counterexample, "note": v.claim.note, "examples": v.examples,
            "errors_over_tolerance": v.errors}


def merge_claims(catalogue: Catalogue, existing: list[dict], ran, records: list[dict]) -> list[dict]:
    """The claim records of the systems ``ran`` replace theirs in ``existing``, the others are kept; catalogue
    order (stable: equation order within a system)."""
    kept = [r for r in existing if r.get("system") not in set(ran)]
    order = catalogue.order()
    return sorted(kept + records, key=lambda r: order.get(r["system"], len(order)))


@dataclass
class ClaimsRun:
    """What ``harness claims`` produced: the claim records of this run, the failures (a module that does not
    load, a claim that cannot be evaluated, an unexplained engine warning) and the files written."""

    records: list
    failed: list
    written: list = field(default_factory=list)
    profile: dict | None = None  # with --profile: where the time went (harness.profiling.document)

    @property
    def passed(self) -> bool:
        """Errata are findings; a failure or engines that disagree fail the run."""
        return not self.failed and not any(r["classification"] == "engines disagree" for r in self.records)


def claims(catalogue: Catalogue, names=None, examples: int | None = None, jobs: int = 1, out=None,
           profile: bool = False, scheduler=None, classified: dict | None = None) -> ClaimsRun:
    """Classify every printed equation of ``names`` (default: the catalogue), ``jobs`` systems at a time (or on
    the Dask cluster at ``scheduler``); with ``out``, claims.json and errata.md there, merged by system. With
    ``profile``, where the time went (:mod:`harness.profiling`; with ``out`` also the ``claims`` section of
    profile.json). ``classified``: the results :func:`check` classified in its jobs, by system (the main job);
    only a system missing there is classified here."""
    start, cpu = time.perf_counter(), time.process_time()
    names = _systems(catalogue, names)
    if out:
        check_folder(out)
    previous = read_timings(out) if out else {}
    finished: dict[str, dict] = {name: classified[name] for name in names if classified and name in classified}
    from_check = len(finished)  # classified in the check's jobs (the main job)
    jobs_ = longest_first([(catalogue, name, examples, profile) for name in names if name not in finished],
                          lambda job: previous.get(f"claims/{job[1]}/seconds"))
    interrupted = parallel(classify_system, jobs_, jobs, lambda result: finished.__setitem__(result["system"], result),
                           lambda job, reason: {"system": job[1], "failure": f"{job[1]}: {reason}", "records": []},
                           scheduler=scheduler)
    per_system = [finished[name] for name in names if name in finished]
    profiles = {result["system"]: result.pop("profile") for result in per_system if "profile" in result}
    run = ClaimsRun([r for result in per_system for r in result["records"]],
                    [result["failure"] for result in per_system if result["failure"]])
    if out:  # merged by system: the classified systems replace their records, the others are kept
        merged = merge_claims(catalogue, read_claims(out), [result["system"] for result in per_system], run.records)
        run.written = write_claims(merged, out, catalogue.lecture_claims())
        run.written.append(write_timings(out, {f"claims/{r['system']}/seconds": r["seconds"]
                                               for r in per_system if "seconds" in r}))
    if profile:
        run.profile = _profile_document("claims", profiles, start, cpu, jobs)
        run.profile["classified_in_check"] = from_check
        if out:
            run.written += profiling.write(run.profile, out)
    if interrupted:
        raise Interrupted(per_system, len(names))
    return run


# =========================================================================================== harness scenes
def select_scenes(catalogue: Catalogue, names=None, scene: str | None = None) -> list[tuple]:
    """``(system, scene)`` of every scene of ``names`` (default: every system that loads), or only the scene
    named ``scene`` (unknown: one line, before any work)."""
    out = []
    for name in names or list(catalogue.systems()):
        system = catalogue.get(name)
        chosen = catalogue.scenes(name)
        if scene:
            known = [s.name for s in chosen]
            if scene not in known:
                raise InputError(f"unknown scene {scene!r} of {name}; known scenes: {', '.join(known) or 'none'}")
            chosen = [s for s in chosen if s.name == scene]
        out += [(system, s) for s in chosen]
    return out


def run_scene(catalogue: Catalogue, system, scene):
    """Simulate ``scene`` and check its trajectories (:func:`harness.scenes.trajectories.run_scene`)."""
    from harness.scenes.trajectories import run_scene as simulate_and_check

    return simulate_and_check(system, scene, catalogue=catalogue)


# =========================================================================================== export, new
def export_folders(catalogue: Catalogue, folder) -> dict[str, Path]:
    """Where each system's exported files live: ``folder`` (the repository's ``urdf/``, or ``--dir``) for a system of
    the catalogue's own folder; ``<added folder>/urdf`` for one of a folder added by ``HARNESS_MODELS_PATH``, beside
    its module (a user's models are exported with them, not into the repository, whose ``export --check`` they would
    otherwise fail)."""
    return {name: Path(folder) if (added := catalogue.added_folder(name)) is None else Path(added) / "urdf"
            for name in catalogue.systems()}


def export(catalogue: Catalogue, folder, check_only: bool = False) -> tuple[dict, list[str]]:
    """The exported files of every system (URDF, MJCF, coordinate maps), by path (:func:`export_folders`), and the
    paths of those that differ from what is there; unless ``check_only``, those written there (atomically; a file
    that is current is left as it is, its time of change too)."""
    from harness.catalogue import MODELS_PATH_VARIABLE
    from harness.export.files import system_files

    folder = Path(folder) if check_only else check_folder(folder, "--dir")
    systems, folders = catalogue.systems(), export_folders(catalogue, folder)
    files = {folders[name] / file: text for name, system in systems.items()
             for file, text in system_files(system).items()}
    stale = [str(path) for path, text in files.items() if not path.exists() or path.read_text() != text]
    if not check_only:
        added = sorted(set(folders.values()) - {folder})
        for where in added:  # every folder checked before the first file is written
            writable_folder(where, f"{MODELS_PATH_VARIABLE}: exported files")
        for where in added:
            where.mkdir(exist_ok=True)
        for path in stale:
            atomic_write_text(Path(path), files[Path(path)])
    return files, stale


def stale_exports(catalogue: Catalogue, folder) -> list[str]:
    """The paths of the exported files that differ from what is there (``harness export --check``; a job of its own in
    the main job, whose process checks systems next: the warnings of building the files are left out, as the
    command's own process leaves them)."""
    from harness.engines import warnings_log

    with warnings_log.discarded():
        return export(catalogue, folder, check_only=True)[1]


def new(catalogue: Catalogue, name: str, folder=None) -> tuple[Path, bool]:
    """Scaffold ``<folder>/<name>.py`` (default: the catalogue's own folder); whether the folder is on the
    catalogue's search path."""
    from harness.scaffold import scaffold

    path = scaffold(name, folder, catalogue)
    return path, str(path.parent.resolve()) in {str(Path(p).resolve()) for p in catalogue.path}


# =========================================================================================== hard, bench, importer
def hard(catalogue: Catalogue, out, quick: bool = False, only=None, echo=print, jobs: int = 1) -> dict:
    """The hard cases (:mod:`harness.hard`, or those ``only`` names), ``jobs`` at a time in worker processes, the
    longest first by the ``hard.json`` already in ``out``: ``out/hard.json``, ``out/hard.md`` and ``out/hard/*.svg``;
    the document. One line per case goes to ``echo`` as it finishes; on Ctrl-C nothing is written."""
    from harness import hard as cases

    out = check_folder(out)
    names = cases.selected(only)
    previous = _seconds_before(Path(out) / "hard.json", "cases", "id")
    todo = longest_first([(catalogue, name, quick) for name in names], lambda job: previous.get(job[1]))
    finished: dict[str, dict] = {}

    def done(entry):
        finished[entry["record"]["id"]] = entry
        echo(cases.line(entry))

    if parallel(cases.case_entry, todo, jobs, done, cases.lost):
        raise Interrupted(list(finished), len(todo))
    target = cases.write_report([finished[name] for name in names], out, quick)
    return json.loads(target.read_text())


def bench(catalogue: Catalogue, **options) -> dict:
    """The performance studies (:func:`harness.bench.run_bench`): bench.json, bench.md and the figures."""
    from harness.bench import run_bench

    check_folder(options.get("out", "reports"))
    return run_bench(catalogue, **options)


def bench_render(out) -> dict:
    """Redraw bench.md and the figures from ``out/bench.json`` (:func:`harness.bench.render`)."""
    from harness.bench import render

    return render(check_folder(out))


def bench_merge(out, other) -> dict:
    """Take the parts another run measured (its bench.json) into ``out/bench.json`` (:func:`harness.bench.merge`)."""
    from harness.bench import merge

    return merge(check_folder(out), other)


def validate(path, root=None, states: int = 20):
    """A user's own URDF or MJCF: safe parse, checks, load in the engines (:func:`harness.files.validate.validate`)."""
    from harness.files.validate import validate_isolated

    return validate_isolated(path, root=root, states=states)


def importer(catalogue: Catalogue, names=None, states: int = 20, seed: int = 0, out=None) -> tuple[dict, list]:
    """MuJoCo's URDF importer against our MJCF and Pinocchio (:mod:`harness.files.importer`): the document and,
    with ``out``, importer.json and importer.md written there."""
    from harness.files import importer as study

    if out:
        check_folder(out)
    catalogue.require(names)
    systems = [catalogue.get(n) for n in names] if names else list(catalogue.systems().values())
    folders = export_folders(catalogue, study.PROJECT_ROOT / "urdf")   # a user's system: its own folder's urdf/
    doc = study.run(systems, states=states, seed=seed, folders=folders)
    return doc, (study.write(doc, Path(out)) if out else [])


def robots(names=None, out=None, states: int | None = None, seed: int = 0, jobs: int = 1, echo=None,
           command: str = "harness robots", scheduler=None, symbolic: bool = False) -> tuple[dict, list]:
    """Every robot of the pinned example-robot-data package (or ``names``) in every engine
    (:mod:`harness.files.robots`): the document and, with ``out``, robots.json and robots.md written there. One
    line per robot goes to ``echo`` as it finishes; ``jobs`` robots run at a time in spawned processes (or on the
    Dask cluster at ``scheduler``)."""
    from harness.files import robots as sweep

    if out:
        check_folder(out)
    selected = sweep.select(names)
    states = sweep.STATES if states is None else states
    todo = [(name, str(path), states, seed, None, symbolic) for name, path in selected.items()]
    if out:  # started longest first by the previous robots.json (kinova, so101: 20 s each, cold)
        previous = _seconds_before(Path(out) / "robots.json", "robots", "robot")
        todo = longest_first(todo, lambda job: previous.get(job[0]))
    finished: dict[str, dict] = {}
    start = time.perf_counter()

    def done(record):
        finished[record["robot"]] = record
        if echo:
            echo(f"[{len(finished)}/{len(todo)}] {sweep.line(record)}")

    if scheduler is None:
        interrupted = parallel(sweep.sweep_robot, todo, jobs, done, sweep.lost)
    else:
        with cluster.client(scheduler) as dask:
            jobs = cluster.workers(dask)  # robots.json's "jobs": the robots run at a time, here the worker processes
            interrupted = parallel(sweep.sweep_robot, todo, jobs, done, sweep.lost, scheduler=dask)
    records = [finished[name] for name in selected if name in finished]
    doc = sweep.document(records, states, seed, time.perf_counter() - start, jobs, command, symbolic)
    written = sweep.write(doc, Path(out)) if out else []
    if interrupted:
        raise Interrupted(records, len(todo))
    return doc, written
