"""``harness bench``: what accuracy costs in time — work-precision of the scenes, evaluation cost, derivation
cost, effect pruning. Benchmarks, run on demand and reported; never timed unit tests.

Parts: :mod:`~harness.bench.workprecision` (scenes: reference, sweeps, Pareto frontiers, pruning),
:mod:`~harness.bench.evalcost` (M, C·q̇, g, q̈ per state), :mod:`~harness.bench.derivation` (n-link chains
against ``sympy.physics.mechanics``), :mod:`~harness.bench.runner` (process pool or Dask cluster),
:mod:`~harness.bench.figures` (work-precision diagrams), :mod:`~harness.bench.report` (``bench.md``),
:mod:`~harness.bench.contact_pruning` (the lightweight robot's collision meshes: contact detection on / pruned, with
the ``pruning`` part).
An optional ``harness/bench/lightweight_robot.py`` with ``run(catalogue, quick: bool = False) -> dict`` is called
too. The systems come from the catalogue handed to :func:`run_bench` (:class:`harness.catalogue.Catalogue`); each
task carries it to its worker, which rebuilds it from its description.

Outputs (``--out DIR``, default ``reports``): ``DIR/bench.json``, ``DIR/bench.md`` (headline table),
``DIR/bench/*.svg`` (figures). Wall times depend on the machine and its load: the load average is recorded
beside them; ratios are measured in the same process and run.

Schema of ``bench.json`` (``schema: 2``; times in seconds, errors relative to the state's scale)::

    {
      "schema": 2, "generated": ISO-8601 UTC, "quick": bool, "command": str, "seconds": total wall time,
      "selection": {"systems": [str] | null, "scenes": [str] | null} (``--systems``, ``--scenes``; null: every one),
      "machine": {"cpus": int, "loadavg_start": [1, 5, 15 min], "loadavg_end": [...]},
      "versions": {package: version}, "runner": {"backend": "process pool" | "dask", "workers" | "scheduler"},
      "goals": [{"check": str, "source": "symbolic", "value": float | "nan" (not measured), "bound": float,
                 "ratio": float | "inf", "basis": "bench goal", "passed": bool, "detail": str,
                 "verdict": "met" | "undecided" | "not met" (the pruning goals judged on intervals)}],
                (harness.checks.Check records: measured ratio against its target, where the time goes)
      "workprecision": {
        "accuracy": 1e-6, "grid": {"rtols": [...], "fixed_k": [...], "mujoco_k": [...], "repeats": int,
                                    "budget": int},
        "scenes": [{
          "system": str, "scene": str, "description": str, "horizon": float, "effects": [str], "params": {},
          "reference": {"method", "confirmed_by", "agreement", "tolerance", "confirmed", "seconds",
                        "evaluations", "confirmation_seconds", "confirmation_evaluations"},
          "runs": [{"engine": "symbolic" | "pinocchio" | "mujoco", "method": str, "rtol": float | null,
                    "dt": float | null, "error": float ("inf" when diverged), "seconds": median wall time of
                    the "repeats": int runs, "evaluations": int,
                    "skipped": str (instead of error/seconds), "failed": str (optional)}],
          "summary": {"pareto": {engine: [configuration label, fastest first]},
                      "fastest_at_accuracy": {engine: {"configuration", "seconds", "error", "evaluations"} | null},
                      "symbolic_vs_fastest_engine": {"ratio" (the median of ours / engine over "repeats"
                          alternating pairs of the two configurations, harness.bench.workprecision.duel_task),
                          "ratio_low", "ratio_high" (its interval), "ours_all", "engine_all", "verdict",
                          "sweep_ratio" (the sweep's medians' ratio), "symbolic_configuration",
                          "fastest_engine_configuration" (the duel's: each side's fastest of its candidates,
                          harness.bench.workprecision.candidates)} (when both exist)},
          "figure": path relative to DIR}]},
      "evaluation": {"states": int, "systems": [{"system", "dof", "states",
                     "symbolic": {"terms" (M, C·q̇, g, f_np in one call), "qdd", "terms_native", "qdd_native"
                                  (numba machine code)}, "native_compile_seconds",
                     "qdd_parts": {"terms_arithmetic", "terms", "eigh"},
                     "symbolic_numpy": {"M", "Cqd", "g"}, "symbolic_wrapper": {"M", "Cqd", "g"},
                     "symbolic_batched": {"M", "Cqd", "g", "qdd"} (per state),
                     "pinocchio": {"M", "nle", "g", "Cqd", "qdd"} | {"skipped"},
                     "mujoco": {"M", "bias", "qdd"} | {"skipped"},
                     "ratios": {"one_call_vs_pinocchio", "one_call_native_vs_pinocchio", "batched_vs_pinocchio",
                                "qdd_one_call_vs_aba",
                                "qdd_batched_vs_aba", "qdd_one_call_vs_mj_forward", goals and verdicts}}],
                     "figure": path},
      "derivation": {"timeout_per_n": float, "goal", "goal_n", "goal_ratio", "goal_met",
                     "rows": [{"n", "ours": {"cold_seconds", "derivation_seconds", "cached_seconds",
                               "count_ops_M", "count_ops_C"} | {"timeout"} | {"error"},
                               "mechanics": {"seconds", "count_ops_M"} | {"timeout"}, "ratio_cold", "ratio_cached"}],
                     "figure": path},
      "pruning": [{"system", "scene", "declared", "inferred" (effects that can act, harness.scenes.effects),
                   "inferred_idle" {effect: reason}, "idle_elements" {force element: reason}, "declared_idle",
                   "undeclared_acting", "repeats", "constraint_rows": {"inactive", "why"} (a constrained tree),
                   "nothing": why (nothing to prune: no ratio) | "left_out": [effect], "left_out_elements":
                   [force element found idle inside an acting effect],
                   "sources": {"symbolic" | "pinocchio" | "mujoco": {"pruned_seconds", "idle_seconds" (the fastest of
                               the repeats each), "ratio" (idle / pruned: the median of the alternating pairs'
                               ratios), "ratio_low", "ratio_high" (its ≥ 99.5 % confidence interval), "pruned_all",
                               "idle_all" (every run's seconds), "error" (pruned vs idle trajectory),
                               "evaluations": [pruned, idle], "method", "per_call" (symbolic, Pinocchio:
                               one call of the right-hand side, the same keys per call and "calls"), "acting" (MuJoCo:
                               the acting tree's runs against the idle ones, the same keys: pruning.acting_tree),
                               "machine_code" (symbolic: the runs in machine code, the same keys, or {"skipped"}:
                               pruning.machine_code)} |
                               {"skipped": why}},
                   "rows": {"left_out": [constraint row], "proof", "sources": {"pinocchio" | "mujoco": the same keys}}
                   (where the tree's constraint rows are proved inactive: the open tree against the constrained)}],
                  (before: {"system", "scene", "pruned_seconds", "idle_seconds", "speedup", …} of the symbolic
                  path alone)
      "pruning_contact": {"system", "scene", "source": "mujoco", "method", "collision_geoms", "left_out",
                          "first_contact" (s, or null), "first_contact_pairs", "certified_contact_free" (s: contact
                          proved idle before it), "certificate_ends_at" (the geom pair), "collision_pairs",
                          "pruned_geoms" (the pruned model's geoms: visual only), "whole_horizon_error",
                          "measured_horizon", "pruned_seconds", "idle_seconds", "ratio", "ratio_low", "ratio_high",
                          "idle_all", "pruned_all", "error", "repeats"}
                         (harness.bench.contact_pruning: the robot's collision meshes, contact detection on /
                         mjDSBL_CONTACT, over the contact-free part of the scene),
      "lightweight_robot": {...} (when harness/bench/lightweight_robot.py exists),
      "updates": [{"parts", "command", "generated", "seconds", "machine", "versions", "selection" (a run of some
                 systems or scenes: only their rows merged)}] (parts re-measured by a later run and merged,
                 ``harness bench --merge``)
    }

Non-finite numbers are the strings ``"inf"``, ``"-inf"``, ``"nan"`` (:func:`harness.checks.json_clean`).
Schema history: 2 — goals are check records (``goal``, ``target``, ``measured``, ``met``, ``where`` of schema 1
are ``check``, ``bound``, ``value``, ``passed``, ``detail``).
"""

from __future__ import annotations

import datetime
import importlib
import json
import math
import os
import platform
import sys
import time
from pathlib import Path

from harness import allocator
from harness.bench import contact_pruning, derivation, evalcost, workprecision as wp
from harness.bench.runner import Task, run_tasks
from harness.checks import json_clean, json_restore
from harness.errors import InputError
from harness.io import atomic_write_text

SCHEMA = 2


def _log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def _versions() -> dict:
    import distributed
    import mujoco
    import numpy
    import pinocchio
    import scipy
    import sympy

    return {"python": platform.python_version(), "pinocchio": pinocchio.__version__, "mujoco": mujoco.__version__,
            "sympy": sympy.__version__, "numpy": numpy.__version__, "scipy": scipy.__version__,
            "distributed": distributed.__version__}


QUICK_SCENES = (("pendulum", "swing"), ("planar_manipulator", "driven"), ("quarter_car", "bump"))


RUNS = ("workprecision", "evaluation", "derivation", "pruning", "lightweight_robot")
"""The parts ``harness bench --parts`` chooses among (:func:`default_parts` without it; ``lightweight_robot`` where
``harness/bench/lightweight_robot.py`` exists and the run covers that system)."""


def default_parts(systems=None, scenes=None) -> tuple:
    """What ``harness bench`` measures without ``--parts``: every part (:data:`RUNS`); a run of some systems or
    scenes the parts measured per system or scene (:data:`ROWS`), and the lightweight robot's study where it is
    among the systems (the derivation of n-link chains is no system's)."""
    if not (systems or scenes):
        return RUNS
    return (*ROWS, *(["lightweight_robot"] if "lightweight_robot" in (systems or ()) else []))


def _cases(catalogue, systems, scenes, quick: bool) -> list[tuple[str, str]]:
    """Every scene (``--systems``, ``--scenes`` filter); ``--quick`` without filters: :data:`QUICK_SCENES`;
    stiff variants only in the full run (or by ``--scenes``)."""
    cases = wp.scene_cases(catalogue, systems)
    if quick and not systems and not scenes:
        return [c for c in cases if c in QUICK_SCENES]
    stiff = {(s, v.label) for s, vs in wp.STIFF.items() for v in vs}
    if scenes:
        known = {label for _, label in cases}
        unknown = [s for s in scenes if s not in known]
        if unknown:
            raise InputError(f"unknown scene(s) {', '.join(unknown)}; scenes: {', '.join(sorted(known))}")
        return [c for c in cases if c[1] in scenes]
    return [c for c in cases if not (quick and c in stiff)]  # stiff variants: full run (or --scenes)


def run_bench(catalogue, out="reports", quick: bool = False, scheduler: str | None = None, systems=None,
              scenes=None, workers: int | None = None, parts=None, command: str = "harness bench") -> dict:
    """Run the studies on the systems of ``catalogue``, write ``bench.json``, ``bench.md`` and the figures into
    ``out``; return the document. ``parts`` None: every part (:data:`RUNS`), or with ``systems`` or ``scenes`` those
    measured per system or scene (:data:`ROWS`) and the lightweight robot's study where it is among the systems."""
    from harness.bench import figures, report

    catalogue.require(systems)  # unknown names fail before any work
    parts = default_parts(systems, scenes) if parts is None else parts
    allocator.steady()          # the parts run in this process too (harness.allocator: as every task's)
    unknown = set(parts) - set(RUNS)
    if unknown:
        raise InputError(f"unknown bench part(s) {sorted(unknown)}")
    out = Path(out)
    started = time.perf_counter()
    doc = {"schema": SCHEMA, "generated": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
           "quick": quick, "command": command, "selection": {"systems": list(systems or []) or None,
                                                             "scenes": list(scenes or []) or None},
           "machine": {"cpus": os.cpu_count(), "platform": platform.platform(), "loadavg_start": os.getloadavg()},
           "versions": _versions(),
           "runner": {"backend": "dask", "scheduler": str(scheduler)} if scheduler else
           {"backend": "process pool", "workers": workers or os.cpu_count()}}
    grid = wp.Grid.make(quick)
    cases = _cases(catalogue, systems, scenes, quick) if {"workprecision", "pruning"} & set(parts) else []
    eval_systems = [s for s in (systems or (evalcost.QUICK if quick else list(catalogue.systems())))
                    if s in catalogue] if "evaluation" in parts else []

    # phase 1: references, pruning, evaluation cost (independent tasks)
    first = []
    if "workprecision" in parts:
        first += [Task("harness.bench.workprecision:reference_task", {"catalogue": catalogue, "system": s, "scene": c},
                       f"reference {s}/{c}") for s, c in cases]
    if "pruning" in parts:
        first += [Task("harness.bench.workprecision:pruning_task",
                       {"catalogue": catalogue, "system": s, "scene": c},
                       f"pruning {s}/{c}")
                  for s, c in cases]
    first += [Task("harness.bench.evalcost:task", {"catalogue": catalogue, "system": s, "states": 10_000},
                   f"evaluation cost {s}") for s in eval_systems]
    _log(f"bench: {len(first)} tasks (references, pruning, evaluation cost) …")
    results = run_tasks(first, scheduler=scheduler, workers=workers)
    by_task = dict(zip((t.label for t in first), results))

    # phase 2: the work-precision sweep against the references
    if "workprecision" in parts:
        doc["workprecision"] = _workprecision(catalogue, cases, by_task, grid, scheduler, workers, out)
    if "pruning" in parts:
        doc["pruning"] = [{"system": s, "scene": c, **by_task[f"pruning {s}/{c}"]} for s, c in cases]
        if any(s == contact_pruning.ROBOT and c == contact_pruning.SCENE for s, c in cases):
            _log("bench: lightweight_robot contact detection on / pruned (MuJoCo, collision meshes) …")
            try:
                doc["pruning_contact"] = contact_pruning.task(catalogue)
            except Exception as exc:  # noqa: BLE001 - its failure is reported, the rest is kept
                doc["pruning_contact"] = {"error": f"{type(exc).__name__}: {exc}"}
    if eval_systems:
        rows = [{"system": s, **by_task[f"evaluation cost {s}"]} for s in eval_systems]
        doc["evaluation"] = {"states": 10_000, "systems": rows}
    if "derivation" in parts:
        _log("bench: derivation cost of n-link chains …")
        ns, timeout = (range(1, 3), 30.0) if quick else (range(1, 9), 120.0)
        doc["derivation"] = derivation.run(ns, timeout)
    if "lightweight_robot" in parts and Path(__file__).with_name("lightweight_robot.py").exists() and (
            not systems or "lightweight_robot" in systems):
        _log("bench: lightweight_robot …")
        try:
            doc["lightweight_robot"] = importlib.import_module("harness.bench.lightweight_robot").run(catalogue,
                                                                                                      quick=quick)
        except Exception as exc:  # noqa: BLE001 - its failure is reported, the rest is kept
            doc["lightweight_robot"] = {"error": f"{type(exc).__name__}: {exc}"}
    doc["machine"]["loadavg_end"] = os.getloadavg()
    doc["seconds"] = time.perf_counter() - started
    doc["goals"] = report.goals(doc)
    figures.draw_all(doc, out)
    atomic_write_text(out / "bench.json", dumps(doc))
    atomic_write_text(out / "bench.md", report.markdown(doc))
    _log(f"bench: wrote {out / 'bench.json'}, {out / 'bench.md'} and {out / 'bench'}/*.svg "
         f"in {doc['seconds']:.0f} s")
    return doc


PARTS = ("workprecision", "evaluation", "derivation", "pruning", "pruning_contact", "lightweight_robot")
"""The parts of a bench.json: those a run measures (:data:`RUNS`) and the contact, which the pruning part
measures where the lightweight robot's scene is among its cases."""


ROWS = {"workprecision": ("scenes", ("accuracy", "grid")), "evaluation": ("systems", ("states",)),
        "pruning": (None, ())}
"""The parts measured per system or scene: where their rows are (None: the part is the list) and what a run's rows
must share to sit in one table (the accuracy and grids, the states)."""


def covers(selection: dict | None, row: dict) -> bool:
    """Whether a run of ``selection`` (``harness bench --systems … --scenes …``; None: every system) measured the
    row of a system, or of a system's scene."""
    systems, scenes = (selection or {}).get("systems"), (selection or {}).get("scenes")
    return (not systems or row.get("system") in systems) and (not scenes or "scene" not in row
                                                              or row.get("scene") in scenes)


def _merged_rows(base: list, new: list, selection: dict) -> list:
    """``base``'s rows with those ``selection`` covers replaced by ``new``'s (in their place; a covered row the new
    run did not measure, e.g. of a scene since removed, dropped), the new rows no base row had appended."""
    key = lambda row: (row.get("system"), row.get("scene"))  # noqa: E731
    fresh = {key(row): row for row in new}
    out = [fresh.pop(key(row), None) if covers(selection, row) else row for row in base]
    return [row for row in out if row is not None] + list(fresh.values())


def merge(out="reports", other=None) -> dict:
    """Take the parts another run measured (``other``: its ``bench.json``) into ``out/bench.json``; the merge is
    recorded under ``updates`` (which parts, that run's command, time, machine load, its ``selection``). A run of
    every system replaces those parts; a run of some systems or scenes (``harness bench --systems … --scenes …``)
    replaces their rows of the parts measured per system or scene (:data:`ROWS`), keeping every other row. Runs of
    another kind (``--quick`` against a full run, another accuracy, grid or number of states) are refused."""
    from harness.bench import figures, report

    base, new = _read(Path(out) / "bench.json"), _read(Path(other))
    parts = [k for k in PARTS if k in new]
    if not parts:
        raise InputError(f"{other}: measures none of {', '.join(PARTS)}")
    if bool(new.get("quick")) != bool(base.get("quick")):
        kinds = {True: "a --quick run", False: "a full run"}
        raise InputError(f"{other} is {kinds[bool(new.get('quick'))]} and {Path(out) / 'bench.json'} "
                         f"{kinds[bool(base.get('quick'))]}: their grids and scenes differ; merge a run of the same "
                         "kind")
    selection = new.get("selection")
    if selection is not None and not (isinstance(selection, dict) and all(
            v is None or isinstance(v, list) and all(isinstance(x, str) for x in v) for v in selection.values())):
        raise InputError(f"{other}: its selection is not {{\"systems\": [name] | null, \"scenes\": [name] | null}}")
    selection = selection if selection and any(selection.values()) else None
    for key in parts:
        if selection is None or key not in ROWS or key not in base:
            base[key] = new[key]
            continue
        rows, shared = ROWS[key]
        differ = [field for field in shared if base[key].get(field) != new[key].get(field)]
        if differ:
            raise InputError(f"{other}: its {key} has another {', '.join(differ)} than {Path(out) / 'bench.json'}'s; "
                             "its rows cannot join that table (run it with the same settings)")
        if rows is None:
            base[key] = _merged_rows(base[key], new[key], selection)
        else:
            base[key] = {**base[key], rows: _merged_rows(base[key][rows], new[key][rows], selection)}
    base.setdefault("updates", []).append({k: new.get(k) for k in ("command", "generated", "seconds", "machine",
                                                                   "versions")} | {"parts": parts}
                                          | ({"selection": selection} if selection else {}))
    base["schema"], base["goals"] = SCHEMA, report.goals(base)
    figures.draw_all(base, Path(out))
    atomic_write_text(Path(out) / "bench.json", dumps(base))
    atomic_write_text(Path(out) / "bench.md", report.markdown(base))
    return base


def _read(path: Path) -> dict:
    if not path.exists():
        raise InputError(f"{path}: no such file (run `harness bench` first)")
    try:
        return json_restore(json.loads(path.read_text()))
    except ValueError as exc:
        raise InputError(f"{path}: not a bench.json ({exc})") from None


def render(out="reports") -> dict:
    """Redraw ``bench.md`` and the figures from an existing ``out/bench.json`` (goals recomputed)."""
    from harness.bench import figures, report

    path = Path(out) / "bench.json"
    doc = _read(path)
    doc["schema"], doc["goals"] = SCHEMA, report.goals(doc)
    figures.draw_all(doc, Path(out))
    atomic_write_text(path, dumps(doc))
    atomic_write_text(Path(out) / "bench.md", report.markdown(doc))
    return doc


DIGITS = 7   # significant digits of a float in bench.json: a time is measured to ~1e-4 of itself (its pairs' noise),
             # an error is compared with an accuracy; the 17 of a float's repr made the file 1.92 MB of a 2 MB limit


def dumps(doc: dict) -> str:
    """``bench.json``: non-finite numbers as strings (:func:`harness.checks.json_clean`), every float to
    :data:`DIGITS` significant digits."""
    return json.dumps(_rounded(json_clean(doc)), indent=1, allow_nan=False) + "\n"


def _rounded(node):
    if isinstance(node, dict):
        return {k: _rounded(v) for k, v in node.items()}
    if isinstance(node, list):
        return [_rounded(v) for v in node]
    return float(f"{node:.{DIGITS}g}") if isinstance(node, float) else node


def as_run(result: dict) -> dict:
    """A sweep task's result as a run: a task that raised (:func:`harness.bench.runner.execute`: ``error`` its
    message) is a failed run, ``error`` inf and the message under ``failed`` as :func:`~harness.bench.workprecision.
    run_task` records its own failures, so that the frontiers and the figures read a number (a message there ended
    a 15 min sweep with a TypeError and nothing written)."""
    if isinstance(result.get("error"), str):
        return {**result, "error": math.inf, "failed": result["error"]}
    return result


QUICK_PAIRS = 5   # --quick: alternating pairs of ours against the fastest engine (their [min, max]; the full run 21)


def _duels(catalogue, scenes: list[dict], by_task, grid: wp.Grid, scheduler, workers) -> None:
    """Each scene's ours / the fastest engine at the accuracy, timed again in alternating pairs
    (:func:`~harness.bench.workprecision.duel_task`): the sweep's single ratio becomes the pairs' median with its
    interval and verdict, the sweep's own kept as ``sweep_ratio``."""
    tasks, entries = [], []
    for entry in scenes:
        versus = entry.get("summary", {}).get("symbolic_vs_fastest_engine")
        if not versus:
            continue
        ours, engine = wp.candidates(entry["runs"])
        reference = {k: by_task[f"reference {entry['system']}/{entry['scene']}"][k] for k in ("t", "q", "qd")}
        tasks.append(Task("harness.bench.workprecision:duel_task",
                          {"catalogue": catalogue, "system": entry["system"], "scene": entry["scene"], "ours": ours,
                           "engine": engine, "reference": reference, "budget": grid.budget,
                           "repeats": wp.REPEATS if grid.repeats > 1 else QUICK_PAIRS},
                          f"{entry['system']}/{entry['scene']} ours against the fastest engine"))
        entries.append(versus)
    _log(f"bench: ours against the fastest engine, {len(tasks)} scenes, alternating pairs …")
    for versus, duel in zip(entries, run_tasks(tasks, scheduler=scheduler, workers=workers)):
        versus["sweep_ratio"] = versus["ratio"]
        if isinstance(duel.get("error"), str):   # the task raised: the sweep's ratio alone, no verdict
            versus["duel_error"] = duel["error"]
            continue
        versus.update(duel)


def _workprecision(catalogue, cases, by_task, grid: wp.Grid, scheduler, workers, out: Path) -> dict:
    configs = wp.configurations(grid)
    tasks, scenes = [], []
    for s, c in cases:
        ref = by_task[f"reference {s}/{c}"]
        meta = {k: v for k, v in ref.items() if k not in ("t", "q", "qd")}
        scenes.append({"system": s, "scene": c, "reference": meta})
        if "t" not in ref:  # skipped (structural change) or failed: reported, not swept
            continue
        reference = {k: ref[k] for k in ("t", "q", "qd")}
        for engine, method, setting in configs:
            tasks.append(Task("harness.bench.workprecision:run_task",
                              {"catalogue": catalogue, "system": s, "scene": c, "engine": engine, "method": method,
                               "setting": setting, "repeats": grid.repeats, "budget": grid.budget,
                               "reference": reference},
                              f"{s}/{c} {engine} {method} {setting:g}"))
    _log(f"bench: work-precision sweep, {len(tasks)} runs over {len(cases)} scenes …")
    results = run_tasks(tasks, scheduler=scheduler, workers=workers)
    runs: dict = {}
    for task, r in zip(tasks, results):
        key = (task.args["system"], task.args["scene"])
        base = {k: task.args[k] for k in ("engine", "method")}
        runs.setdefault(key, []).append({**base, **{k: v for k, v in as_run(r).items()
                                                    if k not in ("system", "scene")}})
    for entry in scenes:
        key = (entry["system"], entry["scene"])
        ref = entry.pop("reference")
        for k in ("description", "horizon", "effects", "params"):
            if k in ref:
                entry[k] = ref.pop(k)
        ref.pop("system", None), ref.pop("scene", None)
        entry["reference"] = ref
        entry["runs"] = runs.get(key, [])
        entry["summary"] = wp.summarize_scene(entry["runs"])
        entry["figure"] = f"bench/{entry['system']}-{entry['scene']}.svg" if entry["runs"] else None
    _duels(catalogue, scenes, by_task, grid, scheduler, workers)
    return {"accuracy": wp.ACCURACY, "grid": {"rtols": list(grid.rtols), "fixed_k": list(grid.fixed_k),
                                              "mujoco_k": list(grid.mujoco_k), "repeats": grid.repeats,
                                              "budget": grid.budget,
                                              "pinocchio_methods": list(grid.pinocchio_methods)},
            "scenes": scenes}

