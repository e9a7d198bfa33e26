"""Independent jobs on a Dask cluster (``--scheduler ADDRESS``): the one Dask path of ``harness check``,
``claims`` and ``robots`` (:func:`harness.run.parallel`) and of ``harness bench``
(:func:`harness.bench.runner.run_tasks`).

The client (the command) submits every job, receives each result as it finishes and writes the result files
itself, as with the local process pool: the workers need the same commit of the project in the pinned environment
(``make setup``; a folder of ``HARNESS_MODELS_PATH`` at the same path, since a catalogue pickles as its package and
search path), nothing else of the client's file system. A worker process runs one job at a time (the checks keep per-process state: hypothesis seeding, the engine
warning log, profiling), so start workers with ``--nthreads 1`` and as many processes as cores
(``dask worker tcp://HOST:8786 --nworkers N --nthreads 1``). A worker that dies is replaced by Dask and its jobs
retried elsewhere; a job whose workers died more than the scheduler's ``allowed-failures`` times (default 3; a job
queued on a dying worker counts too, none is with ``worker-saturation`` 1.0) is given up (Dask's
``KilledWorker``), as the local pool gives up a job that kills its own process twice. A scheduler that cannot be reached, or an address that is not one, is one
:class:`InputError` before any job runs.
"""

from __future__ import annotations

import asyncio
import sys
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from harness.errors import InputError

CONNECT_TIMEOUT = "10s"
"""How long to try reaching the scheduler before giving up (Dask's connect retries until then)."""

_ONE_AT_A_TIME = threading.Lock()


def _one_job(work: Callable, job):
    """``work(job)`` in a worker, never two at once in one process (a worker started with several threads)."""
    with _ONE_AT_A_TIME:
        return work(job)


@contextmanager
def client(scheduler):
    """A ``distributed.Client`` of ``scheduler`` (an address, closed at the end; or a client, left open). The
    address is tried first with a bare connection, so that a bad one is one line, without the traceback a
    half-started client prints when it is collected."""
    from distributed import Client
    from distributed.comm import connect as open_comm

    if isinstance(scheduler, Client):
        yield scheduler
        return

    async def probe():
        comm = await open_comm(scheduler, timeout=CONNECT_TIMEOUT)
        await comm.close()

    try:
        asyncio.run(probe())
        own = Client(scheduler, timeout=CONNECT_TIMEOUT, set_as_default=False)
    except (OSError, ValueError, TypeError) as exc:
        raise InputError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
    try:
        yield own
    finally:
        own.close()


def workers(client) -> int:
    """The number of worker processes the scheduler of ``client`` has now."""
    return len(client.scheduler_info().get("workers", {}))


def results(scheduler, work: Callable, jobs: list, lost: Callable) -> Iterator[tuple[int, object]]:
    """``(k, work(jobs[k]))`` for every job, as each finishes, computed on the Dask cluster at ``scheduler``
    (``tcp://host:port`` or a ``distributed.Client``); a job whose workers kept dying gives
    ``(k, lost(job, reason))``. Any other exception of ``work`` is raised here, as the local pool raises it.
    Leaving early (an exception, Ctrl-C) cancels the jobs not finished."""
    from distributed import KilledWorker
    from distributed import as_completed as finished

    jobs = list(jobs)
    with client(scheduler) as dask:
        futures = []
        try:
            futures = [dask.submit(_one_job, work, job, pure=False) for job in jobs]
            index = {future.key: k for k, future in enumerate(futures)}
            for future in finished(futures, loop=dask.loop):
                k = index[future.key]
                try:
                    result = future.result()
                except KilledWorker as exc:
                    result = lost(jobs[k], f"its worker process died on every try (Dask: {exc})")
                yield k, result
        finally:
            if futures and not all(f.done() for f in futures):
                dask.cancel(futures)


def echo(*args, file=None) -> None:
    """``print(*args, file=file, flush=True)``, and on a Dask worker also to the client's stream (``sys.stdout`` or
    ``sys.stderr``), as a worker of the local pool prints to the terminal of the command."""
    if "distributed" in sys.modules:
        from distributed import print as remote_print

        remote_print(*args, file=file if file is not None else sys.stdout, flush=True)
    else:
        print(*args, file=file, flush=True)
