"""Cost of the symbolic path for the 7-DoF lightweight robot (``models/lightweight_robot.py``) against Pinocchio.

Measured (wall time, ``time.perf_counter``; the machine's load average is recorded beside):

* **derivation, cold**: :func:`harness.derivation.derive.derive` in a fresh Python process with an empty
  ``HARNESS_CACHE_DIR`` (SymPy's own caches empty too), and **compilation**: ``lambdify`` with CSE of every
  quantity (:class:`harness.derivation.compile.CompiledModel`), in the same child process;
* **derivation, cached**: a second :func:`derive` in that process, read back from the on-disk cache, where the
  per-body derivation is stored as a graph (:mod:`harness.derivation.cache`; ``srepr`` of its trees would not end);
* **evaluation**: one call of :meth:`CompiledModel.terms` (``M``, ``C·q̇``, ``g``, ``f_np`` together, the function
  the simulations call) and of the NumPy function of each quantity (``C·q̇``: ``C`` then the product), and the
  same batched over ``N`` states (NumPy broadcasting, :meth:`CompiledModel.batched`), per state; Pinocchio
  (from the exported URDF): ``crba``, ``nonLinearEffects − computeGeneralizedGravity``,
  ``computeGeneralizedGravity`` per call, looped over the same states;
* **size**: ``count_ops`` of the tree is not computable for these graphs (it walks the tree); reported are the
  number of distinct sub-expressions (graph nodes) of ``M``, ``C``, ``g`` and ``count_ops`` of their
  common-subexpression-eliminated form (replacements + reduced expressions: the operations the compiled
  code performs).

* **Drake** (the third engine, :mod:`harness.engines.drake_engine`; pinned ``drake==1.51.1``, the newest release
  the package registry offers here; 1.58.0 is not on it): our exported ``urdf/lightweight_robot.urdf`` in a ``MultibodyPlant``,
  ``ToSymbolic()``, symbolic ``q``, ``v``: ``CalcMassMatrix``, ``CalcBiasTerm`` (``C·q̇``; Drake gives no
  Christoffel ``C``) and ``CalcGravityGeneralizedForces`` (``= −g``: opposite sign). Timed: building the
  expressions, and ``Evaluate`` of all three at one state; size: characters of ``to_string()`` of ``M[0,0]`` and
  ``(C·q̇)[0]`` (Drake's expressions are trees to its printer too); agreement with ours at that state.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

SYSTEM = "lightweight_robot"

_CHILD = r"""
import json, sys, time
t0 = time.perf_counter()
from harness.catalogue import rebuild
from harness.derivation import derive as derive_module
from harness.derivation.compile import CompiledModel
system = rebuild(*json.loads(sys.argv[1])).get("lightweight_robot")
t1 = time.perf_counter()
d = derive_module.derive(system)
t2 = time.perf_counter()
compiled = CompiledModel(system, d)
compiled.compile_quantities()
t3 = time.perf_counter()
derive_module.derive(system)
t4 = time.perf_counter()
print(json.dumps({"import_seconds": t1 - t0, "cold_seconds": t2 - t1, "compile_seconds": t3 - t2,
                  "cached_seconds": t4 - t3, "from_cache": derive_module.derive(system).from_cache,
                  "per_body": derive_module.is_per_body(system)}))
"""


def _graph_size(expr) -> int:
    """Distinct sub-expressions of ``expr`` (a SymPy graph), each visited once."""
    seen, stack = set(), list(expr) if hasattr(expr, "shape") else [expr]
    while stack:
        node = stack.pop()
        if node in seen:
            continue
        seen.add(node)
        stack.extend(node.args)
    return len(seen)


def _cse_ops(expr) -> dict:
    import sympy as sp

    replacements, reduced = sp.cse(list(expr), order="none")
    return {"replacements": len(replacements),
            "count_ops_after_cse": int(sum(sp.count_ops(e) for _, e in replacements) + sum(sp.count_ops(e) for e in reduced))}


def _best(fn, repeats: int, number: int) -> float:
    """Smallest mean time of ``number`` calls over ``repeats`` rounds (seconds per call)."""
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - start) / number)
    return best


def _derivation_in_child(catalogue, timeout: float) -> dict:
    """Derivation and compilation in a fresh process, which rebuilds ``catalogue`` from its description."""
    env = dict(os.environ)
    with tempfile.TemporaryDirectory() as cache:
        # the derivations' folder inside the empty one: what else a run keeps goes beside it (its parent), where a
        # folder of tempfile's own would find the generated code of the last run
        env["HARNESS_CACHE_DIR"] = os.path.join(cache, "derivations")
        start = time.perf_counter()
        try:
            out = subprocess.run([sys.executable, "-c", _CHILD, json.dumps(catalogue.description())],
                                 capture_output=True, text=True, timeout=timeout,
                                 env=env, cwd=os.path.dirname(os.path.dirname(os.path.dirname(__file__))))
        except subprocess.TimeoutExpired:
            return {"timeout": timeout}
        if out.returncode != 0:
            return {"error": out.stderr.strip().splitlines()[-1] if out.stderr.strip() else f"exit {out.returncode}"}
        doc = json.loads(out.stdout.strip().splitlines()[-1])
        doc["process_seconds"] = time.perf_counter() - start
        return doc


def _drake(c, system, q, qd, p, ours: dict) -> dict:
    """Drake's symbolic path on our exported URDF (see the module docstring) through the Drake adapter
    (:meth:`harness.engines.drake_engine.DrakeModel.symbolic_terms`)."""
    from importlib.metadata import version

    from harness.derivation.cache import PROJECT_ROOT
    from harness.engines import engine
    from harness.export.numeric import instantiate

    start = time.perf_counter()
    tree = instantiate(system, system.default_parameters())
    model = engine("drake")(tree, (PROJECT_ROOT / "urdf" / f"{SYSTEM}.urdf").read_text())
    loaded = time.perf_counter()
    terms = model.symbolic_terms()
    built = time.perf_counter()
    M_n, Cqd_n, g_n = terms["at"](q, qd)
    evaluated = time.perf_counter()
    derivation = ours.get("cold_seconds")
    return {"version": version("drake"),
            "load_seconds": loaded - start, "symbolic_seconds": built - loaded,
            "evaluate_one_state_seconds": evaluated - built,
            "to_string_chars": {"M[0,0]": len(terms["M"][0, 0].to_string()), "Cqd[0]": len(terms["Cqd"][0].to_string())},
            "agreement_abs": {"M": float(np.abs(M_n - c("M", q, qd, p)).max()),
                              "Cqd": float(np.abs(Cqd_n - c("C", q, qd, p) @ qd).max()),
                              "g": float(np.abs(g_n - c("g", q, qd, p).ravel()).max())},
            "ours_cold_over_drake_symbolic": derivation / (built - loaded) if derivation else None}


def run(catalogue, quick: bool = False) -> dict:
    """Derivation, compilation, evaluation and size of the lightweight robot of ``catalogue``; see the module
    docstring."""
    from harness.derivation.compile import compiled
    from harness.engines.base import State
    from harness.engines.pinocchio_engine import PinocchioModel

    load_start = os.getloadavg()
    doc: dict = {"system": SYSTEM, "quick": quick}
    doc["derivation"] = _derivation_in_child(catalogue, timeout=300.0)

    system = catalogue.get(SYSTEM)
    c = compiled(system)  # derives in this process too (not cached, see the docstring)
    d = c.derivation
    doc["size"] = {name: {"graph_nodes": _graph_size(getattr(d, name)), **_cse_ops(getattr(d, name))}
                   for name in ("M", "C", "g")}

    rng = np.random.default_rng(7)
    n = len(system.coordinates)
    N = 1_000 if quick else 10_000
    repeats, number = (3, 50) if quick else (5, 200)
    Q = rng.uniform(-np.pi, np.pi, (N, n))
    QD = rng.uniform(-5, 5, (N, n))
    p = np.array(list(system.default_parameters().values()))
    u = np.zeros(0)
    q, qd = Q[0], QD[0]

    symbolic = {"M": _best(lambda: c("M", q, qd, p, u), repeats, number),
                "Cqd": _best(lambda: c("C", q, qd, p, u) @ qd, repeats, number),
                "g": _best(lambda: c("g", q, qd, p, u), repeats, number)}
    c.terms(q, qd, p, u)  # compiles
    terms = _best(lambda: c.terms(q, qd, p, u), repeats, number)
    c.batched("M", Q[:2], QD[:2], p), c.batched("C", Q[:2], QD[:2], p), c.batched("g", Q[:2], QD[:2], p)  # compile
    batched = {"M": _best(lambda: c.batched("M", Q, QD, p), 3, 1) / N,
               "Cqd": _best(lambda: np.einsum("nij,nj->ni", c.batched("C", Q, QD, p), QD), 3, 1) / N,
               "g": _best(lambda: c.batched("g", Q, QD, p), 3, 1) / N}

    state = State.make(system, q, qd)
    pm = PinocchioModel(state.tree)
    at = pm.kernels(q, qd)   # Pinocchio's raw calls at one state (the identity map: tree coordinates are ours)
    pinocchio = {"M": _best(at["M"], repeats, number),
                 "Cqd": _best(lambda: at["nle"]() - at["g"](), repeats, number),
                 "g": _best(at["g"], repeats, number)}
    every = [pm.kernels(a, b) for a, b in zip(Q, QD)]

    def loop(fn):
        return lambda: [fn(k) for k in every]

    pinocchio_loop = {"M": _best(loop(lambda k: k["M"]()), 3, 1) / N,
                      "Cqd": _best(loop(lambda k: k["nle"]() - k["g"]()), 3, 1) / N,
                      "g": _best(loop(lambda k: k["g"]()), 3, 1) / N}

    # the symbolic and Pinocchio numbers agree on these states (the comparison is the conformance suite's job;
    # this guards the benchmark against timing a wrong function)
    k = N - 1
    agree = max(float(np.abs(c.batched("M", Q[k:], QD[k:], p)[0] - pm.mass_and_bias(Q[k], QD[k])[0]).max()), 0.0)
    doc["evaluation"] = {
        "states": N, "seconds_per_call": {"symbolic": symbolic, "pinocchio": pinocchio},
        "terms_one_call": {"symbolic": terms, "pinocchio_sum": sum(pinocchio.values()),
                           "ratio": terms / sum(pinocchio.values())},
        "seconds_per_state_batched": {"symbolic": batched, "pinocchio_loop": pinocchio_loop},
        "ratios": {f"{key}_one_call_symbolic_over_pinocchio": symbolic[key] / pinocchio[key] for key in symbolic}
        | {f"{key}_batched_symbolic_over_pinocchio_loop": batched[key] / pinocchio_loop[key] for key in batched},
        "M_agreement_abs": agree,
    }
    doc["drake"] = _drake(c, system, q, qd, p, doc["derivation"])
    doc["machine"] = {"cpus": os.cpu_count(), "loadavg_start": list(load_start), "loadavg_end": list(os.getloadavg())}
    return doc


if __name__ == "__main__":
    from harness.catalogue import Catalogue

    print(json.dumps(run(Catalogue("models"), quick="--quick" in sys.argv), indent=1))
