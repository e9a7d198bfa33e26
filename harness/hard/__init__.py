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


def write_report(results: list, out: Path, quick: bool, pending: list = ()) -> Path:
    """``out/hard.json``, ``out/hard.md`` and ``out/hard/<id>.svg`` (atomic writes; figures first, then the JSON and
    its page)."""
    import matplotlib
    import matplotlib.pyplot as plt

    out = Path(out)
    (out / "hard").mkdir(parents=True, exist_ok=True)
    records = []
    for r in results:
        path = None
        if r.figure is not None:
            buffer = io.StringIO()
            with matplotlib.rc_context({"svg.hashsalt": "harness"}):  # the same figure, the same file
                r.figure.savefig(buffer, format="svg", metadata={"Date": None, "Creator": None})
            plt.close(r.figure)
            atomic_write_text(out / "hard" / f"{r.id}.svg", buffer.getvalue())
            path = f"hard/{r.id}.svg"
        records.append(r.record(path))
    pending = list(pending) + [{"id": rec["id"], "reason": rec["notes"][0]} for rec in records
                               if rec["strategy"] == "pending"]
    bases = sorted({c["basis"] for rec in records for c in rec["checks"]} & set(BOUNDS))
    report = {"schema": "hard-cases/3", "quick": quick, "passed": all(rec["passed"] for rec in records),
              "cases": records, "pending": pending, "bounds": {name: BOUNDS[name].record() for name in bases}}
    target = out / "hard.json"
    atomic_write_text(target, json.dumps(json_clean(report), indent=1, ensure_ascii=False, allow_nan=False) + "\n")
    atomic_write_text(out / "hard.md", hard_markdown(json_clean(report)))  # the page (harness report renders it)
    return target


def run(catalogue, out: Path, quick: bool = False, only=None, echo=print) -> dict:
    """Run every case (or the cases ``only``) on the systems of ``catalogue``, write the report, return it."""
    from harness.hard.common import CaseResult
    unknown = [c for c in (only or ()) if c not in CASES]
    if unknown:
        raise InputError(f"unknown hard case {unknown[0]!r}; cases: {', '.join(CASES)}")
    results = []
    for case_id in (only or CASES):
        try:
            r = run_case(catalogue, case_id, quick)
        except Exception as why:  # noqa: BLE001 - a case that cannot run is a failed case in the report
            r = CaseResult(case_id, case_id, [], "failed to run", "", "")
            r.check("the case runs", "harness", float("inf"), 0.0, f"{type(why).__name__}: {why}"[:500])
        failed = [c for c in r.checks if not c.passed]
        echo(f"{'ok  ' if not failed else 'FAIL'} {case_id:28s} {len(r.checks):3d} checks  {r.seconds:7.1f} s"
             + "".join(f"\n       failed: {c.source}: {c.name}: {c.value:.3g} > {c.bound:.3g}" for c in failed))
        results.append(r)
    target = write_report(results, out, quick)
    return json.loads(target.read_text())
