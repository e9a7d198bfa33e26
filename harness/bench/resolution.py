"""The timing resolution of the pruning bench: an A/A comparison (:data:`harness.scenes.phenomena.pruning.RESOLUTION`).

Each scene with something to prune: its idle run against itself, symbolic and Pinocchio (odeint 1e-10, DOP853 in an
event's plug-in: :func:`~harness.scenes.phenomena.pruning.run_method`, as the bench runs them), through the bench's
own pairs (:func:`~harness.scenes.phenomena.pruning.paired`, :data:`REPEATS`) and interval
(:func:`~harness.scenes.phenomena.pruning.ratio_interval`), twice. Identical runs: every interval should hold 1,
every median be 1. What it prints is how far they are off on this machine::

    .venv/bin/python -m harness.bench.resolution
"""

from __future__ import annotations

from harness.catalogue import repository
from harness.engines import ENGINES
from harness.modeling.scenes import with_idle_effects
from harness.scenes.effects import infer
from harness.scenes.phenomena import motion_of
from harness.scenes.phenomena.pruning import REPEATS, RESOLUTION, paired, ratio_interval, run_method, widened


def a_a(rounds: int = 2, sources=("symbolic", "pinocchio")) -> list[dict]:
    """``{"scene", "source", "ratio", "low", "high"}`` of each A/A comparison (the idle run against itself)."""
    catalogue, out = repository(), []
    for _ in range(rounds):
        for name in catalogue.names():
            for scene in catalogue.scenes(name):
                system = catalogue.get(name)
                idle_system, idle_scene = with_idle_effects(system, scene)
                if idle_scene is scene and infer(system, scene).pruned(system, scene)[1] is scene:
                    continue   # nothing to prune: no ratio in the bench (pruning.measure)
                motion, event = motion_of(idle_scene)
                for source in (s for s in sources if s == "symbolic" or not ENGINES[s].applies(idle_system)):
                    def run(source=source):
                        return motion.simulate(idle_system, idle_scene, event, source,
                                               method=run_method(idle_scene, event), rtol=1e-10, atol=1e-10,
                                               catalogue=catalogue).seconds
                    a, b = paired(run, run, REPEATS)
                    ratio, low, high = ratio_interval(a, b)
                    out.append({"scene": f"{name}/{scene.name}", "source": source, "ratio": ratio, "low": low,
                                "high": high})
                    print(f"{name}/{scene.name} {source}: A/A {ratio:.3f} [{low:.3f}, {high:.3f}]", flush=True)
    return out


def main() -> None:
    rows = a_a()
    missed = [r for r in rows if r["low"] > 1 or r["high"] < 1]
    print(f"{len(missed)} of {len(rows)} intervals miss 1 (by up to "
          f"{max([max(r['low'] - 1, 1 - r['high']) for r in missed], default=0.0) * 100:.1f} %); medians "
          f"{min(r['ratio'] for r in rows):.3f}-{max(r['ratio'] for r in rows):.3f}; with RESOLUTION = "
          f"{RESOLUTION:g} every widened interval holds 1: "
          f"{all(widened(r['low'], r['high'])[0] <= 1 <= widened(r['low'], r['high'])[1] for r in rows)}")


if __name__ == "__main__":
    main()
