"""Where the time of a run goes (``harness check --profile``, ``harness claims --profile``).

Cheap instrumentation, off unless a command asks for it: named phases accumulate wall time
(``time.perf_counter``), CPU time of this process (``time.process_time``) and a call count; counters (cache hit or
miss) only a count. Phase names are paths (``conformance/engine mujoco/model``); a phase's time includes its
sub-phases', and :func:`table` adds the remainder of a phase its named sub-phases do not cover as ``…/(rest)``
(for the conformance run: hypothesis's own machinery, drawing excluded). Worker processes return their
:func:`snapshot` with each system's record; the parent merges them (:func:`merge`) and writes ``profile.json``
and ``profile.md`` (:func:`document`, :func:`markdown`).
"""

from __future__ import annotations

import functools
import os
import time
from contextlib import contextmanager

_enabled = False
_totals: dict[str, list] = {}   # name -> [wall s, cpu s, calls]
_counts: dict[str, int] = {}
_stack: list[str] = []            # the full names of the phases being timed (a phase inside another is its child)


def enable(on: bool = True) -> None:
    global _enabled
    _enabled = on


def enabled() -> bool:
    return _enabled


def reset() -> None:
    _totals.clear()
    _counts.clear()
    _stack.clear()


@contextmanager
def phase(name: str):
    """Accumulate the time spent inside the block under ``name`` — below the phase being timed, if any:
    ``conformance/engine mujoco/model`` (nothing when profiling is off)."""
    if not _enabled:
        yield
        return
    full = f"{_stack[-1]}/{name}" if _stack else name
    _stack.append(full)
    wall, cpu = time.perf_counter(), time.process_time()
    try:
        yield
    finally:
        _stack.pop()
        entry = _totals.setdefault(full, [0.0, 0.0, 0])
        entry[0] += time.perf_counter() - wall
        entry[1] += time.process_time() - cpu
        entry[2] += 1


def timed(name: str):
    """A decorator: every call of the function is the phase ``name``."""
    def wrap(fn):
        @functools.wraps(fn)
        def inner(*args, **kwargs):
            if not _enabled:
                return fn(*args, **kwargs)
            with phase(name):
                return fn(*args, **kwargs)
        return inner
    return wrap


def count(name: str, n: int = 1) -> None:
    """Count an event (a cache hit or miss), not nested."""
    if _enabled:
        _counts[name] = _counts.get(name, 0) + n


def snapshot() -> dict:
    """This process's phases and counters (JSON): ``{"phases": {name: {wall, cpu, calls}}, "counts": {…}}``."""
    return {"phases": {k: {"wall": v[0], "cpu": v[1], "calls": v[2]} for k, v in _totals.items()},
            "counts": dict(_counts)}


def merge(into: dict, other: dict) -> dict:
    """Add the snapshot ``other`` to ``into`` (both JSON snapshots)."""
    phases = into.setdefault("phases", {})
    for name, v in other.get("phases", {}).items():
        entry = phases.setdefault(name, {"wall": 0.0, "cpu": 0.0, "calls": 0})
        for key in ("wall", "cpu", "calls"):
            entry[key] += v[key]
    counts = into.setdefault("counts", {})
    for name, n in other.get("counts", {}).items():
        counts[name] = counts.get(name, 0) + n
    return into


def table(snap: dict) -> list[dict]:
    """Rows ``{"phase", "wall", "cpu", "calls", "per_call_ms"}`` in tree order, with a ``(rest)`` row under every
    phase whose named sub-phases leave at least 1 % of it uncovered."""
    phases = snap.get("phases", {})
    names = sorted(phases)
    rows = []
    for name in names:
        v = phases[name]
        rows.append({"phase": name, "wall": round(v["wall"], 3), "cpu": round(v["cpu"], 3), "calls": v["calls"],
                     "per_call_ms": round(1e3 * v["wall"] / v["calls"], 3) if v["calls"] else None})
        children = [n for n in names if n.startswith(name + "/") and "/" not in n[len(name) + 1:]]
        if children:
            wall = v["wall"] - sum(phases[c]["wall"] for c in children)
            cpu = v["cpu"] - sum(phases[c]["cpu"] for c in children)
            if wall > 0.01 * v["wall"]:
                rows.append({"phase": f"{name}/(rest)", "wall": round(wall, 3), "cpu": round(cpu, 3),
                             "calls": v["calls"], "per_call_ms": None})
    rows.sort(key=lambda r: r["phase"].split("/"))
    return rows


def machine() -> dict:
    """The load and CPU count the times were measured at."""
    try:
        load = [round(x, 2) for x in os.getloadavg()]
    except OSError:  # pragma: no cover - not on every platform
        load = None
    return {"cpus": os.cpu_count(), "load_average": load}


def document(command: str, total: dict, per_system: dict, seconds: float, jobs: int, argv=None) -> dict:
    """``profile.json``: the run's phases summed over systems (``phases``, a :func:`table`), each system's own
    table, counters, the wall and CPU time of the command and the machine's load."""
    return {"command": command, "argv": argv, "jobs": jobs, "seconds": round(seconds, 2), "machine": machine(),
            "at": _now(),
            "cpu_seconds": round(sum(v["cpu"] for k, v in total.get("phases", {}).items() if "/" not in k), 2),
            "phases": table(total), "counts": total.get("counts", {}),
            "systems": {name: {"phases": table(snap), "counts": snap.get("counts", {})}
                        for name, snap in per_system.items()}}


def _now() -> str:
    return time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime())


def previous_run(doc: dict) -> dict:
    """What a section of ``profile.json`` keeps of the run it replaces (its ``previous``), for the page's before/after:
    when it ran, its wall and CPU seconds, and per phase the CPU seconds (``harness check``/``claims``) or when it
    ended (the main job)."""
    kept = {"at": doc.get("at"), "seconds": doc.get("seconds"), "machine": doc.get("machine")}
    if doc.get("command") == "main":
        return kept | {"ended": {step["phase"]: step.get("ended_at", step.get("seconds")) for step in doc["steps"]}}
    return kept | {"cpu_seconds": doc.get("cpu_seconds"), "cpu": {row["phase"]: row["cpu"] for row in doc["phases"]}}


FIGURE = "profile/time.svg"
"""The figure of the profile page, drawn by ``harness report`` from ``profile.json``
(:func:`harness.report.figures.profile_figure`)."""


def main_section(ended: list, jobs: int, seconds: float, argv=None, side_by_side: bool = True) -> dict:
    """The ``main`` section of ``profile.json``: how each phase of the main job (``harness main``) ended before
    the report: ``(phase, exit code, seconds)``, the seconds counted from the job's start when its phases run side
    by side, else each phase's own."""
    return {"command": "main", "argv": argv, "jobs": jobs, "seconds": round(seconds, 2), "machine": machine(),
            "at": _now(),
            "steps": [{"phase": name, "exit": code,
                       ("ended_at" if side_by_side else "seconds"): None if took is None else round(took, 1)}
                      for name, code, took in ended]}


def main_markdown(doc: dict) -> str:
    """The main job's overview: when each phase ended, the figure of the check's and the claims' phases."""
    m, overlap, before = doc["machine"], "ended_at" in (doc["steps"] or [{}])[0], doc.get("previous")
    lines = [f"# The main job (`harness {' '.join(doc.get('argv') or ['main'])}`, {doc['at']})", "",
             f"{doc['seconds']:.1f} s wall before the report, jobs {doc['jobs']}, {m['cpus']} CPUs, load average "
             f"{m['load_average']} then. The check's jobs classify each system's printed equations too"
             + (", and the robots' and then the hard cases' jobs follow theirs on the same processes: the phases "
                "overlap, each line says when it ended." if overlap else "; each line gives a phase's own seconds.")
             + " The report follows; the job's last log line gives its time."
             + (f" Before: the main job this folder held before, {_when(before)}." if before else ""), "",
             ("| phase | ended at s | exit |" if overlap else "| phase | s | exit |") + (" before |" if before else ""),
             "|---|---:|---:|" + ("---:|" if before else "")]
    for step in doc["steps"]:
        took = step.get("ended_at", step.get("seconds"))
        was = before["ended"].get(step["phase"]) if before else None
        lines.append(f"| {step['phase']} | {_number(took, 1)} | {step['exit']} |" + (f" {_number(was, 1)} |" if before
                                                                                      else ""))
    return "\n".join(lines) + "\n"


def _when(before: dict) -> str:
    m = before.get("machine") or {}
    return (f"{before.get('at') or 'time not recorded'}: {_number(before.get('seconds'), 1)} s wall"
            + (f", load average {m['load_average']} then" if m.get("load_average") else ""))


def _number(x, digits: int) -> str:
    return "" if x is None else f"{x:.{digits}f}"


def markdown(doc: dict, systems: bool = True) -> str:
    """``profile.md``: the summed table, then (``systems``) the systems by their CPU time."""
    if doc.get("command") == "main":
        return main_markdown(doc)

    def rows(table_rows, before=None):
        out = ["| phase | wall s | CPU s | calls | ms per call |" + (" CPU s before |" if before else ""),
               "|---|---:|---:|---:|---:|" + ("---:|" if before else "")]
        for r in table_rows:
            label = r["phase"].replace("/", " / ")
            per = "" if r["per_call_ms"] is None else f"{r['per_call_ms']:.3f}"
            out.append(f"| {label} | {r['wall']:.3f} | {r['cpu']:.3f} | {r['calls']} | {per} |"
                       + (f" {_number(before['cpu'].get(r['phase']), 3)} |" if before else ""))
        return out

    m, before = doc["machine"], doc.get("previous")
    lines = [f"# Profile of `harness {doc['command']}`", "",
             f"{doc['seconds']:.1f} s wall, {doc['cpu_seconds']:.1f} CPU s in the phases, jobs {doc['jobs']}, "
             f"{m['cpus']} CPUs, load average {m['load_average']} at the end; phases summed over the systems (a "
             "worker's phases run in parallel with the others')."
             + (f" {doc['classified_in_check']} of its {len(doc['systems'])} systems were classified in the check's "
                "jobs, on the states their conformance run evaluated: their CPU seconds are counted here, their "
                "wall time is the check's." if doc.get("classified_in_check") else "")
             + (f" Before: the run this folder held before, {_when(before)}, {_number(before.get('cpu_seconds'), 1)} "
                "CPU s in the phases." if before else ""), ""]
    lines += rows(doc["phases"], before)
    if doc.get("counts"):
        lines += ["", "| counter | count |", "|---|---:|"]
        lines += [f"| {k} | {v} |" for k, v in sorted(doc["counts"].items())]

    def cpu(entry):
        return sum(r["cpu"] for r in entry["phases"] if "/" not in r["phase"])

    for name, entry in sorted(doc["systems"].items() if systems else (), key=lambda kv: -cpu(kv[1])):
        lines += ["", f"## {name} ({cpu(entry):.2f} CPU s)", ""]
        lines += rows(entry["phases"])
    return "\n".join(lines) + "\n"


def instrument_scenes() -> None:
    """Time every scene :func:`harness.scenes.trajectories.scene_record` runs as ``scenes/<scene>`` (its call is
    wrapped once per process, only when a command profiles)."""
    from harness.scenes import trajectories

    real = trajectories.scene_record
    if getattr(real, "_profiled", False):
        return

    @functools.wraps(real)
    def scene_record(system, scene, *args, **kwargs):
        with phase("scenes"), phase(scene.name):
            return real(system, scene, *args, **kwargs)

    scene_record._profiled = True
    trajectories.scene_record = scene_record


def write(doc: dict, out) -> list:
    """``out/profile.json`` (one section per command: a ``check`` run replaces the ``check`` section and keeps a
    ``claims`` one; the section keeps what the one it replaces measured, :func:`previous_run`, shown beside it as
    "before") and ``out/profile.md``, written atomically; the paths written."""
    import json
    from pathlib import Path

    from harness.io import atomic_write_text

    path = Path(out) / "profile.json"
    try:
        sections = json.loads(path.read_text()) if path.exists() else {}
        if not isinstance(sections, dict):
            sections = {}
    except (OSError, ValueError):
        sections = {}
    replaced = sections.get(doc["command"])
    if isinstance(replaced, dict):  # before/after on the page; one level: the previous' own previous is dropped
        try:
            doc = doc | {"previous": previous_run(replaced)}
        except (KeyError, TypeError, AttributeError):  # a section of another shape: no before
            pass
    sections[doc["command"]] = doc
    atomic_write_text(path, json.dumps(sections, indent=1, sort_keys=True) + "\n")
    md = Path(out) / "profile.md"
    order = sorted(sections, key=lambda k: (k != "main", k))  # the main job's overview first, then its figure
    parts = [markdown(sections[k]) for k in order]
    parts.insert(1 if order[0] == "main" else 0,
                 f"![CPU seconds per phase (drawn by harness report from profile.json)]({FIGURE})\n")
    atomic_write_text(md, "\n".join(parts))
    return [str(path), str(md)]
