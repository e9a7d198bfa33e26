"""Figures of a scene from its series file (``trajectories/<system>.<scene>.json``): the trajectories of every
engine overlaid, the error over time, the energy. SVG with text kept as text and at most :data:`MAX_POINTS`
points per line, so that the whole ``reports/`` folder stays small; byte-identical for the same input."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

MAX_POINTS = 250


def _matplotlib():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    matplotlib.rcParams.update({"svg.fonttype": "none", "svg.hashsalt": "harness", "font.size": 8,
                                "axes.grid": True, "grid.alpha": 0.3})
    return plt


def _thin(t: np.ndarray, *ys: np.ndarray):
    """Every k-th sample (keeping the last) so that a line has at most MAX_POINTS points."""
    step = max(1, int(np.ceil(len(t) / MAX_POINTS)))
    idx = np.r_[np.arange(0, len(t), step), len(t) - 1] if len(t) else np.arange(0)
    idx = np.unique(idx)
    return (t[idx],) + tuple(y[idx] for y in ys)


def _time_major(values, n_t: int) -> np.ndarray:
    """Samples as rows: accepts ``[[q_1, …, q_n] per time]`` and ``[[q_j over time] per coordinate]``."""
    a = np.asarray(values, dtype=float)
    if a.ndim == 1:
        return a.reshape(-1, 1)
    if a.shape[0] != n_t and a.shape[1] == n_t:
        return a.T
    return a


def _svg(fig) -> str:
    buf = io.StringIO()
    fig.savefig(buf, format="svg", metadata={"Date": None, "Creator": None})
    return buf.getvalue()


def scene_figure(series: dict) -> str:
    """One SVG with three panels: q(t) per source, error(t) per source (log), energy(t) per source."""
    plt = _matplotlib()
    t_all = np.asarray(series.get("t", []), dtype=float)
    coords = series.get("coordinates") or []
    sources = series.get("sources") or {}
    errors = series.get("error") or {}
    has_energy = any(s.get("energy") is not None for s in sources.values())
    panels = 1 + bool(errors) + has_energy
    fig, axes = plt.subplots(panels, 1, figsize=(7, 2.3 * panels), sharex=True, squeeze=False, layout="constrained")
    axes = list(axes[:, 0])
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    styles = ["-", "--", ":", "-."]
    color_of = {name: colors[k % len(colors)] for k, name in enumerate([*sources, *errors])}
    ax = axes.pop(0)
    for k, (name, src) in enumerate(sources.items()):
        t = np.asarray(src.get("t", t_all), dtype=float)
        if src.get("q") is None or not len(t):
            continue
        q = _time_major(src["q"], len(t))
        tt, qq = _thin(t, q)
        for j in range(qq.shape[1]):
            label = f"{name}: {coords[j] if j < len(coords) else f'q{j + 1}'}"
            color = colors[(k if qq.shape[1] == 1 else j) % len(colors)]
            ax.plot(tt, qq[:, j], styles[k % len(styles)], color=color, lw=1.2 if k else 2.2,
                    alpha=1.0 if k else 0.45, label=label)
    ax.set_ylabel("q (lecture coordinates)")
    ax.set_title(f"{series.get('system', '')} — {series.get('scene', '')}: trajectories of each source overlaid")
    ax.legend(fontsize=6, ncol=2, loc="best")
    if errors:
        ax = axes.pop(0)
        for k, (name, err) in enumerate(errors.items()):
            t = np.asarray(sources.get(name, {}).get("t", t_all), dtype=float)
            e = np.abs(np.asarray(err, dtype=float))
            if len(e) != len(t):
                continue
            tt, ee = _thin(t, e)
            ax.semilogy(tt, np.maximum(ee, 1e-18), styles[k % len(styles)], color=color_of[name], lw=1.2, label=name)
        # "1e-12" instead of mathtext's $10^{-12}$: parsing the tick labels' mathtext (again at every layout pass)
        # was 40 % of the report's figure time (584 -> 347 ms a figure, measured over ten scenes)
        from matplotlib.ticker import LogFormatter, NullFormatter
        ax.yaxis.set_major_formatter(LogFormatter())
        ax.yaxis.set_minor_formatter(NullFormatter())
        ax.set_ylabel("error vs reference")
        ax.legend(fontsize=6, loc="best")
    if has_energy:
        ax = axes.pop(0)
        for k, (name, src) in enumerate(sources.items()):
            if src.get("energy") is None:
                continue
            t = np.asarray(src.get("t", t_all), dtype=float)
            e = np.asarray(src["energy"], dtype=float)
            if len(e) != len(t):
                continue
            tt, ee = _thin(t, e)
            ax.plot(tt, ee, styles[k % len(styles)], color=color_of[name], lw=1.2, label=name)
        ax.set_ylabel("energy T + V [J]")
        ax.legend(fontsize=6, loc="best")
    fig.axes[-1].set_xlabel("t [s]")
    text = _svg(fig)
    plt.close(fig)
    return text


def draw_scene_figure(series: dict, target: Path) -> dict:
    """Write the figure of ``series`` to ``target`` (atomically); what :func:`harness.report.drawn.drawn` keeps
    beside it: nothing."""
    from harness.io import atomic_write_text

    atomic_write_text(target, scene_figure(series))
    return {}


def profile_figure(sections: dict, top: int = 12) -> str:
    """Where the time went (``profile.json`` of ``harness check --profile`` and ``claims --profile``): per command,
    a bar per phase that has no named sub-phase, CPU seconds summed over the systems, the ``top`` largest (a
    scene's phases as one bar, the others as one), largest first."""
    plt = _matplotlib()
    names = [k for k in ("check", "claims") if k in sections] + sorted(set(sections) - {"check", "claims", "main"})
    fig, axes = plt.subplots(len(names), 1, figsize=(7, 0.25 * (top + 2) * len(names) + 0.6), squeeze=False,
                             layout="constrained")
    for ax, name in zip(axes[:, 0], names):
        doc = sections[name]
        phases = [r["phase"] for r in doc["phases"]]
        bars: dict[str, float] = {}
        for r in doc["phases"]:
            if any(p.startswith(r["phase"] + "/") for p in phases):
                continue  # timed in its named sub-phases and its (rest)
            label = "scenes" if r["phase"].startswith("scenes/") else r["phase"].replace("/", " / ")
            bars[label] = bars.get(label, 0.0) + r["cpu"]
        ranked = sorted(bars.items(), key=lambda kv: -kv[1])
        shown = ranked[:top] + ([(f"{len(ranked) - top} other phases", sum(v for _, v in ranked[top:]))]
                                if len(ranked) > top else [])
        ax.barh([k for k, _ in shown][::-1], [v for _, v in shown][::-1], color="#4c72b0")
        for y, (_, v) in enumerate(shown[::-1]):
            ax.text(v, y, f" {v:.1f}", va="center", fontsize=6)
        ax.tick_params(axis="y", labelsize=6)
        ax.set_xlabel("CPU s (summed over the systems)")
        wall = ("in the check's jobs" if doc.get("classified_in_check") == len(doc.get("systems", ()))
                else f"{doc['seconds']:.1f} s wall")  # the main job: the check's wall time holds the claims'
        ax.set_title(f"harness {name}: {doc['cpu_seconds']:.1f} CPU s in the phases, {wall}, jobs {doc['jobs']}")
    text = _svg(fig)
    plt.close(fig)
    return text
