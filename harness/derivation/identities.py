"""Whether an expression of the mechanics is identically zero, the same on every machine (no answer depends on a
CPU-time budget).

:func:`identically_zero` decides it exactly: the printed equations' symbolic decision
(:func:`harness.compare.errata.is_zero`) and the proof that a scene's constraint rows are idle
(:mod:`harness.scenes.effects`) rest on it, and its "yes" is a proof. :func:`same_at_random_values` compares two
expressions at random values to 30 digits: a classification that rests on an identity, and the errata sheet's
choice of words, rest on it."""

from __future__ import annotations

import math
import random

import sympy as sp

from harness.modeling.claims import as_matrix

TERMS = 100_000
"""Terms of a numerator's expansion (a bound counted before expanding) above which :func:`identically_zero` does not
decide: 25 times the largest a lecture claim needs (4 044, rotating_body's (A.28))."""


def identically_zero(expr, limit: int = TERMS) -> bool | None:
    """Whether ``expr`` vanishes for all values of its symbols: True (proved), False (proved not), None (not
    decided). Floats made exact rationals (their binary values: float arithmetic in the expansion would round a
    small term away and prove what is not so); tangents written as sines over cosines; sums and multiples of angles
    expanded (``sin(a + b)``, ``cos 3α``); each angle's sine and cosine two variables ``s, c`` on the circle; the
    numerator over one denominator expanded and brought to its normal form modulo ``s² + c² − 1`` (each ``s^k``,
    ``k ≥ 2``, as ``s^(k mod 2) (1 − c²)^(k div 2)``; the relations are a Gröbner basis, their leading terms being
    coprime, so the normal form is 0 exactly when the numerator vanishes on every circle). Any other function (a
    square root, an absolute value, an arcsine, the sine of a half angle beside the whole one) is taken as a variable
    of its own: a 0 then is still a proof, a remainder is not (None). A numerator whose expansion could exceed
    ``limit`` terms is not decided."""
    e = sp.sympify(expr)
    e = e.xreplace({f: sp.Rational(f) for f in e.atoms(sp.Float)})
    if e == 0:
        return True
    e = e.replace(sp.tan, lambda a: sp.sin(a) / sp.cos(a)).replace(sp.cot, lambda a: sp.cos(a) / sp.sin(a))
    e = sp.expand_trig(e)
    angles = sorted({f.args[0] for f in e.atoms(sp.sin, sp.cos)}, key=sp.default_sort_key)
    sines = [sp.Dummy(f"s{k}") for k in range(len(angles))]
    cosine_of = dict(zip(sines, (sp.Dummy(f"c{k}") for k in range(len(angles)))))
    e = e.xreplace({**{sp.sin(a): s for a, s in zip(angles, sines)},
                    **{sp.cos(a): cosine_of[s] for a, s in zip(angles, sines)}})
    numerator, _ = sp.fraction(sp.together(e))
    if terms_bound(numerator) > limit:
        return None
    normal = sp.expand(sp.expand(numerator).replace(
        lambda x: x.is_Pow and x.base in cosine_of and x.exp.is_Integer and x.exp >= 2,
        lambda x: x.base ** (x.exp % 2) * (1 - cosine_of[x.base] ** 2) ** (x.exp // 2)))
    if normal == 0:
        return True
    polynomial = all(a.is_Symbol for a in angles) and not normal.atoms(sp.Function) and all(
        p.exp.is_Integer for p in normal.atoms(sp.Pow))
    return False if polynomial else None


def terms_bound(e) -> int:
    """An upper bound on the number of terms of ``expand(e)``: sums add, products multiply, a power ``p^n`` of a sum
    of ``t`` terms has at most C(t + n − 1, n)."""
    if e.is_Add:
        return sum(terms_bound(a) for a in e.args)
    if e.is_Mul:
        return math.prod(terms_bound(a) for a in e.args)
    if e.is_Pow and e.exp.is_Integer and e.exp > 0:
        return math.comb(terms_bound(e.base) + int(e.exp) - 1, int(e.exp))
    return 1


def same_at_random_values(a, b, points: int = 3, seed: int = 0) -> bool:
    """Whether the expressions (or matrices) ``a`` and ``b`` agree at ``points`` random values in [0.3, 1.7] of
    their symbols (seeded), evaluated to 30 digits: two forms of one expression then differ by about 1e-28 of
    their size, two different ones by a part of it, so the bound 1e-20 has a margin of eight digits on either
    side. A verdict that rests on an identity is decided so, not by a reduction under a CPU budget, whose answer
    depends on the machine's speed: (5.110), a generalized force written out from its printed force, took 2.01 CPU
    s of the 2 s budget cold on one machine (no: "erratum") and 1.5 s on another (yes: "follows from erratum")."""
    a, b = as_matrix(a), as_matrix(b)
    if a.shape != b.shape:
        if len(a) != len(b):
            return False
        a = a.reshape(*b.shape)
    symbols = sorted((a.free_symbols | b.free_symbols), key=str)
    rng = random.Random(seed)
    for _ in range(points):
        at = {x: sp.Float(rng.uniform(0.3, 1.7), 30) for x in symbols}
        for x, y in zip(a, b):
            u, v = complex(x.xreplace(at).evalf(30)), complex(y.xreplace(at).evalf(30))
            if abs(u - v) > 1e-20 * (abs(u) + abs(v)) + 1e-300:
                return False
    return True
