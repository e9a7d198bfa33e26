"""Derivation cost: planar n-link pendulum chains, our derivation against ``sympy.physics.mechanics``.

The chain (n = 1 … 8): link ``i`` turns by the *relative* angle ``phi_i`` about ``z`` at the end of link
``i − 1`` (length ``l_{i-1}``), centre of mass at ``[l_si, 0, 0]``, diagonal inertia ``I_xxi, I_yyi, I_zzi`` about
it, gravity along ``−y`` — the planar manipulator of Examples 4.1/5.1 extended link by link. The same chain is
built with our vocabulary (:mod:`harness.modeling.system`) and with ``sympy.physics.mechanics`` (``LagrangesMethod``:
equations formed, ``mass_matrix`` taken, never solved).

Measured per n, each in a fresh process with a time-out (what does not finish is reported as such):

* **ours, cold**: :func:`harness.derivation.derive.derive` with an empty ``HARNESS_CACHE_DIR`` (M, C from Christoffel symbols,
  g, f_np, T, V, Ṁ, the map — everything the harness uses), including writing the cache entry;
* **ours, cached**: the second :func:`derive` in the same process, read from the on-disk cache (``cache_reused``
  says whether the entry was read back; an entry that does not parse is rebuilt, see :mod:`harness.derivation.cache`);
  ``derivation_seconds`` is the derivation alone, ``store_seconds`` writing the cache entry;
* **mechanics**: frames, points, rigid bodies, Lagrangian, ``form_lagranges_equations()``, ``mass_matrix``;
* **size**: ``count_ops`` of ``M`` from each;
* **where the time goes**: the seconds our derivation spends simplifying (``harness.derivation.derive._simplify``: expand,
  trigsimp, factor_terms), timed by wrapping it in the child process.
"""

from __future__ import annotations

import multiprocessing
import os
import queue
import sys
import tempfile
import time

GOAL = 0.1          # ours ≤ 0.1 × mechanics at n = GOAL_N
GOAL_N = 6


def chain(n: int):
    """The n-link planar chain in our vocabulary."""
    from harness.modeling.system import Coordinate, Gravity, Inertia, Joint, Link, Parameter, System, WORLD

    params, links, joints, coords, lengths = [], [], [], [], []
    g = Parameter("g", 9.81, "m/s^2", "acceleration due to gravity")
    for i in range(1, n + 1):
        m = Parameter(f"m_{i}", 1.0, "kg", f"mass of link {i}")
        length = Parameter(f"l_{i}", 1.0, "m", f"length of link {i}")
        ls = Parameter(f"l_s{i}", 0.5, "m", f"joint {i} to centre of mass of link {i}")
        inertia = [Parameter(f"I_{a}{i}", v, "kg m^2", f"inertia of link {i} about {a[0]}_{i}")
                   for a, v in (("xx", 0.01), ("yy", 0.09), ("zz", 0.09))]
        params += [m, length, ls, *inertia]
        coords.append(Coordinate(f"phi_{i}", "rad", f"angle of link {i} relative to link {i - 1}"))
        links.append(Link(f"link_{i}", m.symbol, (ls.symbol, 0, 0), Inertia(*(p.symbol for p in inertia))))
        origin = (0, 0, 0) if i == 1 else (lengths[-1].symbol, 0, 0)  # at the end of link i - 1
        lengths.append(length)
        joints.append(Joint(f"phi_{i}", "revolute", WORLD if i == 1 else f"link_{i - 1}", f"link_{i}", axis="z",
                            origin=origin))
    return System(name=f"chain_{n}", title=f"{n}-link planar pendulum chain", lecture="Examples 4.1, 5.1 (extended)",
                  parameters=(*params, g), coordinates=tuple(coords), links=tuple(links), joints=tuple(joints),
                  gravity=Gravity(g.symbol, (0, -1, 0)))


def ours(n: int) -> dict:
    """Cold (empty cache) and cached derivation of the n-link chain (run in a fresh process)."""
    import sympy as sp

    # inside an empty folder: what else a run keeps goes beside the derivations (kept.path), not into /tmp itself
    os.environ["HARNESS_CACHE_DIR"] = os.path.join(tempfile.mkdtemp(prefix="bench-derivation-"), "derivations")
    from harness.derivation import derive as derive_module

    simplify, spent = derive_module._simplify, [0.0]

    def timed_simplify(expr):  # where the time goes: the simplification of the derived expressions
        start = time.perf_counter()
        try:
            return simplify(expr)
        finally:
            spent[0] += time.perf_counter() - start

    derive_module._simplify = timed_simplify
    system = chain(n)
    start = time.perf_counter()
    d = derive_module.derive(system)
    cold = time.perf_counter() - start
    derive_module._simplify = simplify
    derive = derive_module.derive
    start = time.perf_counter()
    cached = derive(system)
    warm = time.perf_counter() - start
    return {"cold_seconds": cold, "derivation_seconds": d.seconds, "cached_seconds": warm,
            "store_seconds": cold - d.seconds, "cache_reused": cached.from_cache,
            "simplify_seconds": spent[0],
            "count_ops_M": int(sp.count_ops(d.M)), "count_ops_C": int(sp.count_ops(d.C))}


def mechanics(n: int) -> dict:
    """The same chain with ``sympy.physics.mechanics.LagrangesMethod`` (mass matrix only, never solved)."""
    import sympy as sp

    start = time.perf_counter()
    M, _ = mechanics_mass_matrix(n)
    seconds = time.perf_counter() - start
    return {"seconds": seconds, "count_ops_M": int(sp.count_ops(M))}


def mechanics_mass_matrix(n: int):
    """``(M, q)`` of the chain from ``LagrangesMethod`` (``q`` are dynamicsymbols named ``phi_i``)."""
    import sympy as sp
    from sympy.physics import mechanics as me

    q = me.dynamicsymbols(f"phi_1:{n + 1}")
    g = sp.Symbol("g", positive=True)
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    frame, joint, bodies, length = N, O, [], None
    for i in range(1, n + 1):
        if i > 1:  # joint i at the end of link i - 1
            previous = joint
            joint = previous.locatenew(f"O_{i}", length * frame.x)
            joint.v2pt_theory(previous, N, frame)
        m, length, ls = sp.symbols(f"m_{i} l_{i} l_s{i}", positive=True)
        Ixx, Iyy, Izz = sp.symbols(f"I_xx{i} I_yy{i} I_zz{i}", positive=True)
        A = frame.orientnew(f"A_{i}", "Axis", [q[i - 1], frame.z])
        G = joint.locatenew(f"G_{i}", ls * A.x)
        G.v2pt_theory(joint, N, A)
        body = me.RigidBody(f"B_{i}", G, A, m, (me.inertia(A, Ixx, Iyy, Izz), G))
        body.potential_energy = m * g * G.pos_from(O).dot(N.y)
        bodies.append(body)
        frame = A
    L = me.Lagrangian(N, *bodies)
    lm = me.LagrangesMethod(L, q)
    lm.form_lagranges_equations()
    return lm.mass_matrix, q


def _child(fn_name: str, n: int, out) -> None:
    try:
        out.put(globals()[fn_name](n))
    except Exception as exc:  # noqa: BLE001
        out.put({"error": f"{type(exc).__name__}: {exc}"})


def in_fresh_process(fn_name: str, n: int, timeout: float) -> dict:
    """``fn(n)`` in a fresh (spawned) process; ``{"timeout": …}`` when it does not finish in time."""
    ctx = multiprocessing.get_context("spawn")
    out = ctx.Queue()
    proc = ctx.Process(target=_child, args=(fn_name, n, out))
    proc.start()
    try:
        result = out.get(timeout=timeout)
    except queue.Empty:
        result = {"timeout": timeout}
    proc.join(5)
    if proc.is_alive():
        proc.terminate()
        proc.join()
    return result


def run(ns=range(1, 9), timeout: float = 120.0, quiet: bool = False) -> dict:
    rows = []
    skip = set()  # once an n times out, larger n are not tried for that side
    for n in ns:
        row = {"n": n}
        for side in ("ours", "mechanics"):
            if side in skip:
                row[side] = {"timeout": timeout, "not_tried": f"n = {n - 1} already timed out"}
                continue
            if not quiet:
                print(f"  derivation n={n} {side} …", file=sys.stderr, flush=True)
            row[side] = in_fresh_process(side, n, timeout)
            if "timeout" in row[side]:
                skip.add(side)
        a, b = row["ours"].get("cold_seconds"), row["mechanics"].get("seconds")
        if a is not None and b is not None:
            row["ratio_cold"] = a / b
            row["ratio_cached"] = row["ours"]["cached_seconds"] / b
            row["ratio_derivation_only"] = row["ours"]["derivation_seconds"] / b
        rows.append(row)
    goal = next((r for r in rows if r["n"] == GOAL_N), None)
    return {"timeout_per_n": timeout, "rows": rows, "goal": GOAL, "goal_n": GOAL_N,
            "goal_ratio": None if goal is None else goal.get("ratio_cold"),
            "goal_met": None if goal is None or "ratio_cold" not in goal else goal["ratio_cold"] <= GOAL}
