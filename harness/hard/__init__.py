"""Hard cases stay numerically stable: a catalogue of the cases where a naive simulation goes wrong, what the
harness does instead, and the bounds that must hold (``harness hard``; regression tests in tests/test_hard.py).

Catalogue (module: case id — strategy):

* :mod:`.singular`: ``spherical_pendulum_pole`` — chart switch (5.81); ``governor_pole`` — reduction by the
  conserved momentum (A.67); ``toggle_press_dead_point`` — chart switch (A.100); ``tower_crane_rope`` — event
  location (s_5 → 0). Exactly at a singular ``M`` the forward dynamics raises
  ``coordinate singularity at theta = 0, … in spherical_pendulum`` (:func:`harness.derivation.compile.check_regular`).
* :mod:`.stiff`: ``quarter_car_stiff`` (tyre ×1000), ``flyball_governor_a05`` (IFToMM A05, CPU time to 1e-3 and
  1e-6) — implicit integration.
* :mod:`.chaos`: ``double_pendulum_chaos``, ``planar_robot_chaos`` — measured Lyapunov horizon + invariants.
* :mod:`.mass_ratio`: ``trebuchet_mass_ratio`` — bounds scaled by κ(M), MuJoCo's point-mass inertia stated.
* :mod:`.long_horizon`: ``pendulum_long_horizon`` — symplectic vs non-symplectic over 10⁴ periods.
* :mod:`.events`: the lecture's own event scenes (stick-slip (3.80), the trebuchet's lift-off), included by
  reference to the catalogue's scenes and checked by :func:`harness.scenes.trajectories.run_scene`.

Every case is a function ``case(catalogue, quick=False)``: it takes its systems from the catalogue it is handed
(:class:`harness.catalogue.Catalogue`), never from ``models``.

``reports/hard.json`` (written atomically by :func:`write_report`)::

    {
      "schema": "hard-cases/3",
      "quick": bool,                      # the shortened horizons of the test suite
      "passed": bool,                     # every check of every case
      "cases": [{
        "id": str, "title": str, "systems": [str],
        "strategy": str,                  # chart switch | reduction | event location | implicit integrator | ...
        "problem": str,                   # what goes wrong when done naively
        "remedy": str,                    # what the harness does instead
        "naive": {"what": str, "metric": str, "value": float | "inf" | "nan"},
        "checks": [{"check": str, "source": "symbolic" | "pinocchio" | "mujoco", "value": float | "inf",
                    "bound": float, "ratio": float | "inf", "basis": str, "passed": bool,
                    "detail": str}],      # harness.checks.Check records; detail: the bound's scale or reason
        "numbers": {...},                 # measured numbers of the case (free-form, JSON)
        "notes": [str],
        "figure": "hard/<id>.svg" | null, # relative to the report directory
        "seconds": float,                 # wall time of the case
        "passed": bool
      }],
      "pending": [{"id": str, "reason": str}],  # cases whose scenes do not exist yet
      "bounds": {name: {"name": str, "value": float, "derived": bool, "reason": str}}
    }                                     # the derived bounds the checks' bases name (harness.checks.Bound)

A check whose ``basis`` names no derived bound is on a *margin* bound (round-off, integrator tolerance): as every
check of the harness, it must stay at or below 0.1 of it (:data:`harness.checks.MARGIN`); the page says how many
do not and on which kind of bound (:func:`harness.report.margins.rows`).

Non-finite numbers are written as the strings ``"inf"``, ``"-inf"``, ``"nan"`` (JSON has no such numbers;
:func:`harness.checks.json_clean`).

Schema history: ``hard-cases/3`` — ``bounds`` added, the derived bounds named by the checks' ``basis``;
``hard-cases/2`` — a check is the one check record of the harness (:class:`harness.checks.Check`:
``ratio`` and ``basis`` added, the former ``reason`` is its ``detail``, present when not empty);
``hard-cases/1`` — checks ``{check, source, value, bound, reason, passed}``.
"""

from __future__ import annotations

import importlib
import io
import json
import time
from pathlib import Path

from harness.checks import BOUNDS, json_clean
from harness.errors import InputError
from harness.io import atomic_write_text
from harness.report.markdown import hard_markdown

CASES = {
    "spherical_pendulum_pole": ("harness.hard.singular", "spherical_pendulum_pole"),
    "governor_pole": ("harness.hard.singular", "governor_pole"),
    "toggle_press_dead_point": ("harness.hard.singular", "toggle_press_dead_point"),
    "tower_crane_rope": ("harness.hard.singular", "tower_crane_rope"),
    "quarter_car_stiff": ("harness.hard.stiff", "quarter_car_stiff"),
    "flyball_governor_a05": ("harness.hard.stiff", "flyball_a05"),
    "double_pendulum_chaos": ("harness.hard.chaos", "double_pendulum"),
    "planar_robot_chaos": ("harness.hard.chaos", "planar_robot"),
    "trebuchet_mass_ratio": ("harness.hard.mass_ratio", "trebuchet_mass_ratio"),
    "pendulum_long_horizon": ("harness.hard.long_horizon", "pendulum_energy_drift"),
    "stick_slip_events": ("harness.hard.events", "stick_slip"),
    "trebuchet_lift_off": ("harness.hard.events", "trebuchet_lift_off"),
}


def run_case(catalogue, case_id: str, quick: bool = False):
    """One case (a :class:`~harness.hard.common.CaseResult`) on the systems of ``catalogue``, timed."""
    import matplotlib
    matplotlib.use("Agg")
    if case_id not in CASES:
        raise InputError(f"unknown hard case {case_id!r}; cases: {', '.join(CASES)}")
    module, function = CASES[case_id]
    start = time.perf_counter()
    result = getattr(importlib.import_module(module), function)(catalogue, quick=quick)
    result.seconds = time.perf_counter() - start
    return result


def figure_svg(result) -> str | None:
    """The case's figure as SVG text (the same figure, the same text), closed; None without one."""
    if result.figure is None:
        return None
    import matplotlib
    import matplotlib.pyplot as plt

    buffer = io.StringIO()
    with matplotlib.rc_context({"svg.hashsalt": "harness"}):
        result.figure.savefig(buffer, format="svg", metadata={"Date": None, "Creator": None})
    plt.close(result.figure)
    return buffer.getvalue()


def selected(only=None) -> list[str]:
    """The cases ``only`` names (default: the whole catalogue), in the catalogue's order; an unknown one is one
    error."""
    unknown = [c for c in (only or ()) if c not in CASES]
    if unknown:
        raise InputError(f"unknown hard case {unknown[0]!r}; cases: {', '.join(CASES)}")
    return [c for c in CASES if c in only] if only else list(CASES)


def _entry(result, svg: str | None) -> dict:
    record = result.record(f"hard/{result.id}.svg" if svg is not None else None)
    bases = sorted({c["basis"] for c in record["checks"]} & set(BOUNDS))
    return {"record": record, "svg": svg, "bounds": {name: BOUNDS[name].record() for name in bases}}


def case_entry(job: tuple) -> dict:
    """One case, where a worker process runs it (:func:`harness.run.hard`): ``job = (catalogue, case id, quick)``.
    Returns its ``hard.json`` record, its figure as SVG text (``svg``, None without one) and the derived bounds its
    checks name (``bounds``: declared in the case's module, which the writing process may not have imported). A case
    that raises is a failed case in the report. The figure is drawn with Matplotlib's defaults, whatever the process
    drew before: in the main job's workers the report's figures had set a smaller font, and the page's figures
    depended on which worker took the case."""
    import matplotlib

    catalogue, case_id, quick = job
    with matplotlib.rc_context():
        matplotlib.rcdefaults()   # a worker that drew the report's figures (harness.report.figures) has its settings
        try:
            result = run_case(catalogue, case_id, quick)
        except Exception as why:  # noqa: BLE001 - a case that cannot run is a failed case in the report
            return lost(job, f"{type(why).__name__}: {why}"[:500])
        return _entry(result, figure_svg(result))


def lost(job: tuple, reason: str) -> dict:
    """The entry of a case that did not run (it raised, or its worker process died): one failed check saying why."""
    from harness.hard.common import CaseResult

    result = CaseResult(job[1], job[1], [], "failed to run", "", "")
    result.check("the case runs", "harness", float("inf"), 0.0, reason)
    return _entry(result, None)


def line(entry: dict) -> str:
    """The log line of a finished case (and one per failed check)."""
    rec = entry["record"]
    failed = [c for c in rec["checks"] if not c["passed"]]
    verdict = "ok  " if not failed else "FAIL"
    return (f"{verdict} {rec['id']:28s} {len(rec['checks']):3d} checks  {rec['seconds']:7.1f} s"
            + "".join(f"\n       failed: {c['source']}: {c['check']}: {c['value']:.3g} > {c['bound']:.3g}"
                      for c in failed))


def write_report(entries: list, out: Path, quick: bool, pending: list = ()) -> Path:
    """``out/hard.json``, ``out/hard.md`` and ``out/hard/<id>.svg`` from the cases' entries (:func:`case_entry`),
    atomic writes: the figures first, then the JSON and its page."""
    out = Path(out)
    (out / "hard").mkdir(parents=True, exist_ok=True)
    for entry in entries:
        if entry["svg"] is not None:
            atomic_write_text(out / entry["record"]["figure"], entry["svg"])
    records = [entry["record"] for entry in entries]
    pending = list(pending) + [{"id": rec["id"], "reason": rec["notes"][0]} for rec in records
                               if rec["strategy"] == "pending"]
    bounds = {name: b for entry in entries for name, b in entry["bounds"].items()}
    report = {"schema": "hard-cases/3", "quick": quick, "passed": all(rec["passed"] for rec in records),
              "cases": records, "pending": pending, "bounds": dict(sorted(bounds.items()))}
    target = out / "hard.json"
    atomic_write_text(target, json.dumps(json_clean(report), indent=1, ensure_ascii=False, allow_nan=False) + "\n")
    atomic_write_text(out / "hard.md", hard_markdown(json_clean(report)))  # the page (harness report renders it)
    return target
