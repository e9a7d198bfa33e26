"""The sweep runner gives the same results on the local process pool and on a Dask ``LocalCluster``
(the measured wall times aside), in task order; a failing task is a result, not a crash."""

import numpy as np
import pytest

import models
from harness.scenes import simulate as sim
from harness.bench import workprecision as wp
from harness.bench.runner import Task, run_tasks

DETERMINISTIC = ("engine", "method", "rtol", "dt", "error", "evaluations", "skipped", "failed")


@pytest.fixture(scope="module")
def tiny_sweep():
    system, scene = wp.get_scene(models.CATALOGUE, "pendulum", "swing")
    ref = sim.integrate(system, scene, "symbolic", rtol=1e-10, atol=1e-10)  # a cheap stand-in reference
    reference = {"t": ref.t.tolist(), "q": ref.q.tolist(), "qd": ref.qd.tolist()}
    configs = [("symbolic", "DOP853", 1e-4), ("symbolic", "LSODA", 1e-3), ("pinocchio", "RK4", 1),
               ("pinocchio", "semi-implicit Euler", 1), ("mujoco", "RK4", 1), ("mujoco", "implicit", 2)]
    tasks = [Task("harness.bench.workprecision:run_task",
                  {"catalogue": models.CATALOGUE, "system": "pendulum", "scene": "swing", "engine": e, "method": m,
                   "setting": k, "repeats": 1, "budget": 10_000, "reference": reference}, f"{e} {m} {k}")
             for e, m, k in configs]
    tasks.append(Task("harness.bench.runner:no_such_function", {}, "a failing task"))
    return tasks


def _deterministic(results):
    return [{k: r.get(k) for k in DETERMINISTIC if k in r} for r in results]


def test_process_pool_and_dask_local_cluster_agree(tiny_sweep):
    distributed = pytest.importorskip("distributed")
    pool = run_tasks(tiny_sweep, workers=2, quiet=True)
    # one in-process worker thread: a real scheduler and worker without the start-up of another interpreter
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        dask = run_tasks(tiny_sweep, scheduler=cluster.scheduler_address, quiet=True)  # as `--scheduler ADDR`
    serial = run_tasks(tiny_sweep, workers=1, quiet=True)
    assert _deterministic(pool) == _deterministic(dask) == _deterministic(serial)
    # in task order, each a real measurement
    assert [r["method"] for r in pool[:-1]] == [t.args["method"] for t in tiny_sweep[:-1]]
    for r in pool[:-1]:
        assert np.isfinite(r["error"]) and r["seconds"] > 0 and r["evaluations"] > 0
    assert "error" in pool[-1] and "no_such_function" in pool[-1]["error"]
    # RK4 is the same integrator in Pinocchio's forward dynamics and in MuJoCo's mj_step (same dt): same error
    by = {(r["engine"], r["method"]): r for r in pool[:-1]}
    assert by[("pinocchio", "RK4")]["error"] == pytest.approx(by[("mujoco", "RK4")]["error"], rel=1e-6)
