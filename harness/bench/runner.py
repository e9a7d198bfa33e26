"""The sweep runner: independent benchmark tasks on a local process pool (default) or a Dask cluster
(:mod:`harness.cluster`, the Dask path of every command).

A :class:`Task` names its function as ``"module:function"`` and carries plain, picklable arguments; the
function returns a JSON-ready dict. The same task list gives the same results on either back end (up to the
measured wall times, which depend on the machine): the order of the returned list is the order of the tasks,
never the order of completion. Progress goes to stderr.
"""

from __future__ import annotations

import importlib
import multiprocessing
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field


@dataclass(frozen=True)
class Task:
    """One unit of work: ``function(**args)``; ``label`` is only for progress lines."""

    function: str                 # "package.module:function"
    args: dict = field(default_factory=dict)
    label: str = ""


def execute(task: Task) -> dict:
    """Run one task (in a worker); an exception becomes a result with ``error`` instead of losing the sweep. The
    allocator is held at one state first (:func:`harness.allocator.steady`): a timing must not depend on what the
    worker ran before."""
    from harness import allocator

    allocator.steady()
    module, _, name = task.function.partition(":")
    try:
        return getattr(importlib.import_module(module), name)(**task.args)
    except Exception as exc:  # noqa: BLE001 - one failing configuration is a result, not a crash
        return {"error": f"{type(exc).__name__}: {exc}"}


def _progress(done: int, total: int, task: Task, started: float, quiet: bool) -> None:
    if not quiet:
        print(f"  [{done}/{total}] {time.perf_counter() - started:6.1f} s  {task.label}", file=sys.stderr,
              flush=True)


def run_tasks(tasks: list[Task], scheduler: str | None = None, workers: int | None = None,
              quiet: bool = False) -> list[dict]:
    """Results of ``tasks`` in task order: on a Dask cluster at ``scheduler`` (``tcp://host:port``, or a
    ``distributed.Client``), else on ``workers`` local processes (1: in this process)."""
    tasks = list(tasks)
    started = time.perf_counter()
    results: list = [None] * len(tasks)
    if scheduler is not None:
        return _run_dask(tasks, scheduler, started, quiet)
    workers = workers or min(len(tasks), os.cpu_count() or 1) or 1
    if workers <= 1:
        for k, task in enumerate(tasks):
            results[k] = execute(task)
            _progress(k + 1, len(tasks), task, started, quiet)
        return results
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = {pool.submit(execute, task): k for k, task in enumerate(tasks)}
        for done, future in enumerate(as_completed(futures), 1):
            k = futures[future]
            results[k] = future.result()
            _progress(done, len(tasks), tasks[k], started, quiet)
    return results


def _lost(task: Task, reason: str) -> dict:
    """A task whose worker processes kept dying: a result with ``error``, as a task raising is."""
    return {"error": reason}


def _run_dask(tasks: list[Task], scheduler, started: float, quiet: bool) -> list[dict]:
    from harness import cluster

    results: list = [None] * len(tasks)
    for done, (k, result) in enumerate(cluster.results(scheduler, execute, tasks, _lost), 1):
        results[k] = result
        _progress(done, len(tasks), tasks[k], started, quiet)
    return results
