"""``--scheduler ADDRESS`` (:mod:`harness.cluster`): the systems checked on a Dask cluster give the result files
of the local run, written by the command; a job whose worker keeps dying is given up alone; a scheduler that
cannot be reached is one line, exit 2, nothing written."""

import json
import os
import signal
import socket

import pytest

from harness import cli, cluster, run

distributed = pytest.importorskip("distributed")

pytestmark = pytest.mark.xdist_group("dask-cluster")  # one cluster of two worker processes at a time

SYSTEMS = ["pendulum", "spring_mass_damper"]
CHEAP = ["--examples", "20"]  # every check and scene, fewer drawn states


@pytest.fixture(scope="module")
def scheduler():
    """The address of a ``LocalCluster`` of two worker processes, one thread each (as ``dask worker --nthreads
    1``). A job is given up when it killed two workers (``allowed-failures`` 1: as the local pool gives up a job
    that killed its process twice), and a worker holds one job at a time (``worker-saturation`` 1: no other job
    dies with it), so that test is short and certain."""
    import dask

    with dask.config.set({"distributed.scheduler.allowed-failures": 1,
                          "distributed.scheduler.worker-saturation": 1.0}):
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                      dashboard_address=":0") as local:
            yield local.scheduler_address


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_check_on_a_cluster_writes_what_the_local_run_writes(scheduler, tmp_path, capsys):
    local, remote = tmp_path / "local", tmp_path / "remote"
    assert cli.main(["check", *SYSTEMS, *CHEAP, "--jobs", "1", "--out", str(local)]) == 0
    capsys.readouterr()
    assert cli.main(["check", *SYSTEMS, *CHEAP, "--scheduler", scheduler, "--out", str(remote)]) == 0
    err = capsys.readouterr().err
    assert f"checking 2 systems on the Dask cluster at {scheduler} (2 worker processes)" in err
    assert "[2/2]" in err and f"wrote {remote / 'results.json'}" in err

    mine, theirs = (json.loads((folder / "results.json").read_text()) for folder in (local, remote))
    assert [r["system"] for r in theirs["systems"]] == SYSTEMS  # the order of the local run
    for a, b in zip(mine["systems"], theirs["systems"]):  # the examples drawn for every check of the system
        assert b["passed"] and a["passed"] == b["passed"] and a["examples"] == b["examples"] > 0
        assert [(c["check"], c["source"], c["passed"]) for c in a["checks"]] == \
            [(c["check"], c["source"], c["passed"]) for c in b["checks"]]
        assert [(s["scene"], s["passed"]) for s in a["scenes"]] == [(s["scene"], s["passed"]) for s in b["scenes"]]
    assert mine == theirs  # byte for byte: the timings are in timings.json
    # the scenes' series came back from the workers and were written by the command
    series = sorted(p.name for p in (local / "trajectories").iterdir())
    assert series == sorted(p.name for p in (remote / "trajectories").iterdir()) and len(series) >= 2
    for name in series:
        assert (local / "trajectories" / name).read_text() == (remote / "trajectories" / name).read_text()


def _dies(job):
    if job == "killed":
        os.kill(os.getpid(), signal.SIGKILL)  # as the kernel's OOM killer or a segfault in an engine would
    return job


def test_a_job_that_kills_its_worker_is_lost_alone(scheduler):
    done, lost = [], []
    interrupted = run.parallel(_dies, ["a", "killed", "b", "c"], 1, done.append,
                               lambda job, reason: lost.append((job, reason)) or f"lost {job}", scheduler=scheduler)
    assert not interrupted
    assert sorted(done) == ["a", "b", "c", "lost killed"]
    assert [job for job, _ in lost] == ["killed"] and "died on every try" in lost[0][1]


def test_an_unreachable_scheduler_is_one_line_and_nothing_written(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", "1s")
    address = f"tcp://127.0.0.1:{_free_port()}"
    out = tmp_path / "out"
    assert cli.main(["check", "pendulum", "--scheduler", address, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"error: --scheduler {address}: cannot connect (Timed out trying to connect to {address} "
                   "after 1 s)"]
    assert not out.exists()


@pytest.mark.parametrize("command", [["check", "pendulum"], ["claims", "pendulum"], ["robots", "TwoDofs"]])
def test_a_bad_scheduler_address_is_one_line(command, tmp_path, capsys):
    out = tmp_path / "out"
    assert cli.main([*command, "--scheduler", "no-port-here", "--out", str(out)]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [
        "error: --scheduler no-port-here: cannot connect (missing port number in address 'no-port-here')"]
    assert not out.exists()
