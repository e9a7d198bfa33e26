"""Run a sample of checks the way another machine would: in a fresh process whose environment selects other
BLAS kernels or NumPy SIMD paths (set by the caller), optionally with every input nudged by a few ulps.

    python tests/perturbed_checks.py --ulps 3 --systems governor --examples 40 --scenes cable_pulley/haul

prints one JSON object ``{"checks": {"<system>/<scene or ->/<check>/<source>": [passed, ratio]}}``.
Used by tests/test_machine_independence.py; not collected by pytest (no ``test_`` prefix).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys

import numpy as np


def nudge(values, ulps: int, salt: int = 0):
    """Each value moved by ``ulps`` units in its last place, alternately up and down: a rounding difference. An
    exact zero stays zero (no rounding turns the literal 0.0 into a subnormal; at rest is at rest)."""
    out = []
    for k, v in enumerate(np.ravel(np.asarray(values, dtype=float))):
        direction = np.inf if (k + salt) % 2 == 0 else -np.inf
        for _ in range(ulps if v != 0.0 else 0):
            v = np.nextafter(v, direction)
        out.append(float(v))
    return np.reshape(out, np.shape(values))


def install_nudges(ulps: int) -> None:
    """Every state the checks draw and every scene's initial state and parameters, nudged by ``ulps``."""
    from harness.engines import base

    real_make = base.State.make

    def make(system, q, qd=None, params=None, u=None):
        params = {k: float(nudge([v], ulps, salt=i)[0]) for i, (k, v) in enumerate((params or {}).items())}
        qd = None if qd is None else nudge(qd, ulps, salt=1)
        return real_make(system, nudge(q, ulps), qd, params, u)

    base.State.make = staticmethod(make)


def scene_with_nudges(system, scene, ulps: int):
    if not ulps:
        return scene
    params = {**system.default_parameters(), **scene.params}
    params = {k: float(nudge([v], ulps, salt=i)[0]) for i, (k, v) in enumerate(params.items())
              if k in {p.name for p in system.parameters}} | {k: v for k, v in scene.params.items()
                                                               if k not in {p.name for p in system.parameters}}
    return dataclasses.replace(scene, q0=tuple(nudge(scene.q0, ulps)), qd0=tuple(nudge(scene.qd0, ulps, salt=1)),
                               params=params)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--ulps", type=int, default=0)
    parser.add_argument("--systems", nargs="*", default=[])
    parser.add_argument("--examples", type=int, default=40)
    parser.add_argument("--scenes", nargs="*", default=[], metavar="SYSTEM/SCENE")
    args = parser.parse_args(argv)

    from harness.settings import draws_from_seed_only, load_hypothesis_profile

    load_hypothesis_profile()
    if args.ulps:
        install_nudges(args.ulps)
    import models
    from harness.compare import conformance
    from harness.scenes.trajectories import run_scene

    out = {}
    with draws_from_seed_only():
        for name in args.systems:
            summary = conformance.run(models.get(name), examples=args.examples)
            for (check, source), c in summary.worst.items():
                out[f"{name}/-/{check}/{source}"] = [c.passed, c.ratio]
    for item in args.scenes:
        name, scene_name = item.split("/")
        system = models.get(name)
        scene = next(s for s in models.scenes(name) if s.name == scene_name)
        result = run_scene(system, scene_with_nudges(system, scene, args.ulps), catalogue=models.CATALOGUE)
        for c in result.checks:
            out[f"{name}/{scene_name}/{c.name}/{c.source}"] = [c.passed, c.ratio]
    json.dump({"checks": out}, sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main())
