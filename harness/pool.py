"""The worker processes the main job keeps for all its phases (:func:`workers_kept`), and :func:`submit`, which
runs one function there (or here, without them). :func:`harness.run.parallel` runs a phase's jobs on them."""

from __future__ import annotations

import gc
import threading
from concurrent.futures import Future, ProcessPoolExecutor
from contextlib import contextmanager
from multiprocessing import get_context

GC_THRESHOLDS = (100_000, 50, 100)
"""CPython's cyclic-garbage-collector thresholds in a worker process (:func:`processes`; the defaults are 700, 10,
10). A worker keeps large, long-lived object graphs for the rest of the run (the systems' SymPy derivations, their
compiled models, the engines' models, hypothesis's data), and every full collection walks all of them again, while
nearly all of what a check allocates is freed by reference counting. Measured on the main job (warm, 2 cores, four
runs alternating): the collector took 8.3–8.5 CPU s of the workers with the defaults, 2.5 s with these; the job 62.9
and 60.3 s against 58.2 and 57.0 s. No number depends on it."""


def _tuned() -> None:
    gc.set_threshold(*GC_THRESHOLDS)


def processes(workers: int) -> ProcessPoolExecutor:
    """A pool of ``workers`` spawned processes, each with :data:`GC_THRESHOLDS`."""
    return ProcessPoolExecutor(workers, mp_context=get_context("spawn"), initializer=_tuned)


class _KeptPool:
    """The process pool of :func:`workers_kept`: made on first use, made again after a worker died."""

    def __init__(self, workers: int):
        self.workers, self.pool = workers, None
        self.stopped = threading.Event()  # Ctrl-C: the pool was ended, nothing is to be run again
        self.lock = threading.Lock()

    def get(self) -> ProcessPoolExecutor:
        with self.lock:  # phases side by side ask for it from their threads
            if self.pool is None:
                self.pool = processes(self.workers)
            return self.pool

    def discard(self, terminate: bool = False) -> None:
        if self.pool is not None:
            if terminate:
                self.stopped.set()  # the phases running beside this one stop too (harness.run.parallel)
                ended(self.pool)
            else:
                self.pool.shutdown(cancel_futures=True)
            self.pool = None


def ended(executor: ProcessPoolExecutor) -> None:
    """``executor``'s processes terminated at once and its queued jobs cancelled (Ctrl-C)."""
    for process in list(getattr(executor, "_processes", {}).values()):  # the executor has no public terminate
        process.terminate()
    executor.shutdown(wait=False, cancel_futures=True)


_KEPT: list = []


@contextmanager
def workers_kept(workers: int):
    """Within the block, :func:`harness.run.parallel` runs every phase's jobs (``workers > 1``) on one pool of ``workers``
    spawned processes, kept from one call to the next: each process imports the engines, loads the model modules
    and compiles a system's derivation once for the check, the claims and the robots. Measured on the main job
    (warm, 2 cores): a new pool per command cost 4.7 s of wall time between the phases (the interpreter, the
    imports, the catalogue) and the claims 6.4 CPU s to load and compile again what the check had."""
    kept = _KeptPool(workers)
    _KEPT.append(kept)
    try:
        yield kept
    except BaseException:
        kept.discard(terminate=True)
        raise
    finally:
        _KEPT.remove(kept)
        kept.discard()


def kept() -> _KeptPool | None:
    """The pool of the innermost :func:`workers_kept` block, or None."""
    return _KEPT[-1] if _KEPT else None


def submit(work, *args) -> Future:
    """``work(*args)`` on a process of :func:`workers_kept`'s pool (a future), or in this process when there is
    none (a finished future)."""
    if _KEPT:
        return _KEPT[-1].get().submit(work, *args)
    future = Future()
    try:
        future.set_result(work(*args))
    except Exception as exc:  # noqa: BLE001 - handed over as the future's
        future.set_exception(exc)
    return future


# ----------------------------------------------------------------------------- phases running side by side
_TURN = threading.Condition()
_NEXT = [0]            # the phase whose turn it is to submit its jobs
_ORDER = threading.local()


@contextmanager
def phases_in_order():
    """Within the block, phases run side by side in threads (:func:`phase`) submit their jobs to the kept pool in the
    order of their numbers: the pool runs its queue first in, first out, so the workers go from one phase's jobs to
    the next one's without waiting for a phase's last job (measured on the main job: 1-4 s of wall time at each of
    its three barriers, a worker idle while the other ran the phase's last system)."""
    with _TURN:
        _NEXT[0] = 0
    yield


@contextmanager
def phase(number: int):
    """The calling thread runs phase ``number`` (:func:`phases_in_order`); at the end of the block it passes its
    turn on, whether or not it submitted anything."""
    _ORDER.number = number
    try:
        yield
    finally:
        _ORDER.number = None
        _pass_turn(number)


@contextmanager
def submitting():
    """Around the submission of a phase's jobs (:func:`harness.run.parallel`): waits until the phases before it have
    submitted theirs, and passes the turn on after. Outside :func:`phase` it does nothing."""
    number = getattr(_ORDER, "number", None)
    if number is None:
        yield
        return
    with _TURN:
        _TURN.wait_for(lambda: _NEXT[0] >= number)
    try:
        yield
    finally:
        _pass_turn(number)


def _pass_turn(number: int) -> None:
    with _TURN:
        _NEXT[0] = max(_NEXT[0], number + 1)
        _TURN.notify_all()
