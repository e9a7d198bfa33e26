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
