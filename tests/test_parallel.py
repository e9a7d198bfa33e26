"""One worker that dies loses no other system; Ctrl-C keeps what finished (harness.run.parallel)."""

import os
import signal

from harness.run import parallel


def work(job):
    if job == "killed":
        os.kill(os.getpid(), signal.SIGKILL)  # as the kernel's OOM killer or a segfault in an engine would
    if job == "ctrl-c":
        raise KeyboardInterrupt
    return job


def _run(jobs, workers):
    done, lost = [], []
    interrupted = parallel(work, jobs, workers, done.append, lambda job, reason: lost.append((job, reason)) or job)
    return interrupted, done, lost


def test_a_killed_worker_loses_only_its_own_job():
    interrupted, done, lost = _run(["a", "killed", "b", "c", "d"], 2)
    assert not interrupted
    assert sorted(d for d in done if d != "killed") == ["a", "b", "c", "d"]
    assert [job for job, _ in lost] == ["killed"] and "died twice" in lost[0][1]


def test_ctrl_c_stops_and_keeps_what_finished():
    interrupted, done, _ = _run(["a", "ctrl-c", "b"], 1)
    assert interrupted and done == ["a"]
    interrupted, done, _ = _run(["a", "ctrl-c"], 2)
    assert interrupted and set(done) <= {"a"}


def pid(job):
    return os.getpid()


def test_the_kept_workers_serve_every_phase():
    """Within workers_kept, every parallel() call (a phase of the main job) and every submit() runs on the same
    processes, none of them this one; the block ends them."""
    from harness.pool import kept, submit, workers_kept

    with workers_kept(2) as pool:
        first, second = [], []
        parallel(pid, list(range(8)), 2, first.append, None)
        parallel(pid, list(range(8)), 2, second.append, None)
        assert os.getpid() not in first and len(set(first)) <= 2
        assert set(second) <= set(pool.get()._processes) and set(first) <= set(pool.get()._processes)
        assert submit(pid, None).result() in pool.get()._processes
    assert kept() is None and pool.pool is None


def test_a_killed_kept_worker_loses_only_its_own_job_and_the_next_phase_gets_new_processes():
    from harness.pool import workers_kept

    with workers_kept(2) as pool:
        old = set(pool.get()._processes)
        interrupted, done, lost = _run(["a", "killed", "b", "c"], 2)
        assert not interrupted and [job for job, _ in lost] == ["killed"]
        assert sorted(d for d in done if d != "killed") == ["a", "b", "c"]
        after = []
        parallel(pid, list(range(4)), 2, after.append, None)
        assert not set(after) & old


def fails(job):
    raise ValueError(job)


def test_without_kept_workers_submit_runs_here():
    import pytest

    from harness.pool import submit

    assert submit(pid, None).result() == os.getpid()
    with pytest.raises(ValueError, match="broken"):  # raised where the result is asked for, as from a worker
        submit(fails, "broken").result()


def started(job):
    import time

    time.sleep(0.2)
    return job, time.monotonic()


def test_phases_side_by_side_keep_their_order_in_the_pool_and_in_the_log(capsys):
    """harness main with --jobs > 1 (cli._side_by_side): phases run in threads, but the kept pool takes their jobs in
    phase order (a later phase that is ready first waits for the earlier ones' submissions), and what each prints
    comes out phase after phase."""
    import time

    from harness.cli import _side_by_side
    from harness.pool import workers_kept

    starts = {}

    def phase(number, delay):
        def work():
            time.sleep(delay)  # the first phase is the slowest to submit
            print(f"phase {number} starts")
            parallel(started, [(number, k) for k in range(4)], 2,
                     lambda result: starts.setdefault(result[0][0], []).append(result[1]), None)
            print(f"phase {number} ends")
        return work

    with workers_kept(2):
        _side_by_side([(phase(0, 0.5), 0), (phase(1, 0.0), 1), (phase(2, 0.0), 2)])
    out = capsys.readouterr().out.splitlines()
    assert out == ["phase 0 starts", "phase 0 ends", "phase 1 starts", "phase 1 ends", "phase 2 starts",
                   "phase 2 ends"]
    assert max(starts[0]) <= min(starts[1]) and max(starts[1]) <= min(starts[2])


def thresholds(job):
    import gc

    return gc.get_threshold()


def test_workers_collect_garbage_with_the_tuned_thresholds():
    """Every worker process of a phase (kept or not) runs with pool.GC_THRESHOLDS."""
    from harness.pool import GC_THRESHOLDS, workers_kept

    seen = []
    parallel(thresholds, [1, 2], 2, seen.append, None)
    with workers_kept(2):
        parallel(thresholds, [3, 4], 2, seen.append, None)
    assert seen == [GC_THRESHOLDS] * 4
