"""Work-precision diagrams in the style of DiffEqBenchmarks: log-log, error against wall time and against
right-hand-side evaluations, one line per method, one colour family per engine; plus the derivation cost and
the evaluation cost. SVG via matplotlib (Agg)."""

from __future__ import annotations

import io
import math
from pathlib import Path

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

matplotlib.rcParams["svg.hashsalt"] = "harness"  # the same figure gives the same file (ids, no date)

from harness.io import atomic_write_text  # noqa: E402

_COLOURS = {"symbolic": plt.cm.Blues, "symbolic-numba": plt.cm.Purples, "pinocchio": plt.cm.Oranges,
            "mujoco": plt.cm.Greens}
_MARKERS = "osD^v<>p"


def _save(fig, path: Path) -> None:
    buf = io.StringIO()
    fig.savefig(buf, format="svg", bbox_inches="tight", metadata={"Date": None, "Creator": None})
    plt.close(fig)
    atomic_write_text(path, buf.getvalue())


def _finite(x) -> bool:
    return isinstance(x, (int, float)) and math.isfinite(x) and x > 0


def workprecision(scene: dict, accuracy: float, path: Path) -> None:
    from harness.bench.workprecision import soft_equalities

    # an error above the state's own scale is a diverged run (an explicit method beyond its stability limit)
    runs = [r for r in scene["runs"] if _finite(r.get("error")) and r["error"] <= 1.0 and _finite(r.get("seconds"))]
    soft = " (the tree, soft equality constraints)" if soft_equalities(scene) else ""
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), sharex=True)
    lines = {}
    for r in runs:
        lines.setdefault((r["engine"], r["method"]), []).append(r)
    for (engine, method), rs in lines.items():
        methods = sorted({m for e, m in lines if e == engine})
        k = methods.index(method)
        colour = _COLOURS[engine](0.45 + 0.5 * k / max(1, len(methods) - 1))
        rs = sorted(rs, key=lambda r: r["rtol"] if r.get("rtol") is not None else -r["dt"], reverse=True)
        for ax, key in zip(axes, ("seconds", "evaluations")):
            ax.plot([r["error"] for r in rs], [r[key] for r in rs], marker=_MARKERS[k % len(_MARKERS)],
                    color=colour, label=f"{engine} {method}" + (soft if engine == "mujoco" else ""), lw=1.5, ms=4)
    agreement = scene["reference"].get("agreement")
    for ax, ylabel in zip(axes, ("wall time (s, median)", "right-hand-side evaluations")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.axvline(accuracy, color="grey", ls="--", lw=0.8)
        if _finite(agreement):
            ax.axvspan(1e-300, agreement, color="grey", alpha=0.12, lw=0)
        ax.set_ylabel(ylabel)
        ax.set_xlabel("max error vs reference (relative to the state's scale)")
        ax.grid(True, which="major", alpha=0.3)
    errors = [r["error"] for r in runs]
    if errors:
        axes[0].set_xlim(max(min(errors) / 3, 1e-16), max(errors) * 3)
    axes[1].legend(fontsize=7, loc="center left", bbox_to_anchor=(1.02, 0.5))
    fig.suptitle(f"{scene['system']} / {scene['scene']}: work-precision (dashed: {accuracy:g}; shaded: below the "
                 "reference's confirmed accuracy; diverged runs, error > 1, not shown)", fontsize=10)
    _save(fig, path)


def derivation(d: dict, path: Path) -> None:
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for side, key, label, style in (("ours", "cold_seconds", "ours, cold", "o-"),
                                    ("ours", "cached_seconds", "ours, cached", "s--"),
                                    ("ours", "simplify_seconds", "ours, simplification", "x:"),
                                    ("mechanics", "seconds", "sympy.physics.mechanics", "D-")):
        pts = [(r["n"], r[side][key]) for r in d["rows"] if key in r[side]]
        if pts:
            axes[0].plot(*zip(*pts), style, label=label)
    for side, label, style in (("ours", "ours", "o-"), ("mechanics", "mechanics", "D-")):
        pts = [(r["n"], r[side]["count_ops_M"]) for r in d["rows"] if "count_ops_M" in r[side]]
        if pts:
            axes[1].plot(*zip(*pts), style, label=label)
    axes[0].set_ylabel("seconds")
    axes[1].set_ylabel("count_ops(M)")
    for ax in axes:
        ax.set_yscale("log")
        ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
        ax.set_xlabel("links n")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"Derivation cost of n-link planar chains (time-out {d['timeout_per_n']:g} s per n)", fontsize=10)
    _save(fig, path)


def evaluation(ev: dict, path: Path) -> None:
    rows = [r for r in ev["systems"] if "symbolic" in r]
    if not rows:
        return
    names = [r["system"] for r in rows]
    series = [("ours, one call (Python floats)", lambda r: r["symbolic"]["terms"]),
              ("ours, one call (numba)", lambda r: r["symbolic"]["terms_native"]),
              ("ours, batched (per state)", lambda r: sum(r["symbolic_batched"][k] for k in ("M", "Cqd", "g"))),
              ("Pinocchio crba + nle + g", lambda r: r["pinocchio"]["M"] + r["pinocchio"]["nle"] + r["pinocchio"]["g"]
               if "M" in r.get("pinocchio", {}) else float("nan")),
              ("MuJoCo M + bias", lambda r: r["mujoco"]["M"] + r["mujoco"]["bias"]
               if "M" in r.get("mujoco", {}) else float("nan"))]
    fig, ax = plt.subplots(figsize=(max(6, 0.6 * len(rows) + 3), 4.2))
    width = 0.8 / len(series)
    for k, (label, fn) in enumerate(series):
        ax.bar([i + k * width for i in range(len(rows))], [fn(r) * 1e6 for r in rows], width, label=label)
    ax.set_xticks([i + 0.4 - width / 2 for i in range(len(rows))], names, rotation=45, ha="right")
    ax.set_yscale("log")
    ax.set_ylabel("µs per state")
    ax.legend(fontsize=8)
    ax.grid(True, axis="y", alpha=0.3)
    ax.set_title("Evaluation cost of M, C·q̇, g", fontsize=10)
    _save(fig, path)


_PRUNING_RANGE = (0.8, 6.0)   # the pruning figure's axis: ratios beyond it are written at its right edge


def pruning(entries: list[dict], goal: float, path: Path) -> None:
    """Effect pruning at a glance: one row per thing left out (a scene's effects, its constraint rows), per source
    its ratio idle / pruned (filled marker) with the interval the bench can tell (the bar: ≥ 99.5 % and the
    resolution, :func:`harness.scenes.phenomena.pruning.interval`) and the most the run's ratio can be (open marker
    with its interval: one call of the right-hand side, or MuJoCo's acting tree; :func:`~harness.scenes.phenomena.
    pruning.bound`); lines at 1 × (slower pruned below) and at the ``goal``."""
    from harness.scenes.phenomena.pruning import bound, interval

    sources = [s for s in ("symbolic", "pinocchio", "mujoco") if any("ratio" in e["sources"].get(s, {})
                                                                       for e in entries)]
    rows = [e for e in entries if any("ratio" in e["sources"].get(s, {}) for s in sources)]
    if not rows:
        return
    colours = {s: _COLOURS[s](0.75) for s in sources}
    fig, ax = plt.subplots(figsize=(7.5, 0.42 * len(rows) + 1.4))
    height = 0.8 / len(sources)
    for i, e in enumerate(rows):
        for k, source in enumerate(sources):
            m = e["sources"].get(source, {})
            if "ratio" not in m:
                continue
            y = i + (k - (len(sources) - 1) / 2) * height
            if m["ratio"] > _PRUNING_RANGE[1]:  # a run with nothing left to step (a friction held): off the scale
                ax.plot([_PRUNING_RANGE[1] / 1.04], [y], ">", ms=5, color=colours[source])
                ax.annotate(f"{m['ratio']:.0f} ×", (_PRUNING_RANGE[1] / 1.1, y), fontsize=7, ha="right",
                            va="center", color=colours[source])
                continue
            low, high = interval(m)
            ax.errorbar([m["ratio"]], [y], xerr=[[m["ratio"] - low], [high - m["ratio"]]], fmt="o", ms=5,
                        color=colours[source], capsize=2, lw=1.2)
            if bound(m):
                _, c = bound(m)
                b_low, b_high = interval(c)
                ax.errorbar([c["ratio"]], [y], xerr=[[c["ratio"] - b_low], [b_high - c["ratio"]]], fmt="o", ms=5,
                            mfc="white", color=colours[source], capsize=2, lw=0.6, alpha=0.8)
    for x, style in ((1.0, ":"), (goal, "--")):
        ax.axvline(x, color="0.3", ls=style, lw=0.9)
    ax.set_yticks(range(len(rows)), [f"{e['system']}/{e['scene']}" for e in rows], fontsize=8)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.set_xlim(*_PRUNING_RANGE)
    ax.xaxis.set_major_locator(matplotlib.ticker.FixedLocator([0.8, 1, 1.3, 2, 3, 5]))
    ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g} ×"))
    ax.set_xlabel("idle / pruned (● the run, ○ the most it can be: one call, or MuJoCo's acting tree)", fontsize=8)
    handles = [plt.Line2D([], [], color=colours[s], marker="o", ls="", label=s) for s in sources]
    handles += [plt.Line2D([], [], color="0.3", ls=":", label="1 × (below: slower pruned)"),
                plt.Line2D([], [], color="0.3", ls="--", label=f"{goal:g} × (the goal)")]
    ax.legend(handles=handles, fontsize=7, loc="lower right")
    ax.grid(True, axis="x", which="both", alpha=0.3)
    ax.set_title("Effect pruning: every effect present but idle / only what can act", fontsize=10)
    _save(fig, path)


def draw_all(doc: dict, out: Path) -> None:
    folder = Path(out) / "bench"
    wpd = doc.get("workprecision")
    for scene in (wpd or {}).get("scenes", []):
        if scene.get("runs"):
            workprecision(scene, wpd["accuracy"], Path(out) / scene["figure"])
    if doc.get("derivation"):
        doc["derivation"]["figure"] = "bench/derivation.svg"
        derivation(doc["derivation"], folder / "derivation.svg")
    if doc.get("pruning"):
        from harness.bench.report import measurements
        from harness.scenes.phenomena.pruning import PRUNING_GOAL

        pruning(measurements(doc["pruning"]), PRUNING_GOAL, folder / "pruning.svg")
    if doc.get("evaluation"):
        doc["evaluation"]["figure"] = "bench/evaluation.svg"
        evaluation(doc["evaluation"], folder / "evaluation.svg")
