"""One record for "a number against a bound", returned by every oracle (conformance, scenes, claims, hard
cases), and the one relative error they measure with.

A :class:`Bound` is a tolerance stated once, with its reason; a :class:`Check` is one measured value against
a bound, with the name of that bound (its *basis*). The *ratio* ``value / bound`` is what the margin report
shows: a verdict is only as good as its margin. A lower bound (an order of convergence) is written as an upper
bound on its deficit (``p − p̂ ≤ 1``), so that its margin is measured too. Two kinds of bound:

* a **margin** bound (``derived=False``): a round-off or integrator tolerance chosen well above what the
  computation produces, so that rounding on another machine cannot flip the verdict. A check of this kind
  must stay at or below :data:`MARGIN` (0.1) of its bound; one above it is a finding of the margin report.
* a **derived** bound (``derived=True``): the bound itself follows from first principles (a first-order
  method's error ``K dt`` with ``K`` measured, quantization to a time step, …); the measured value may come
  close to it because it is not round-off but a deterministic property of the method.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

MARGIN = 0.1
BOUNDS: dict[str, "Bound"] = {}
"""Every bound by name, as declared by the modules that use them (the ``bounds`` table of results.json)."""


@dataclass(frozen=True)
class Bound:
    """A tolerance, stated once: its name (the basis checks refer to), value and reason."""

    name: str
    value: float
    reason: str
    derived: bool = False

    def __post_init__(self):
        known = BOUNDS.setdefault(self.name, self)
        if known != self:
            raise ValueError(f"bound {self.name!r} is declared twice with different values")

    def check(self, name: str, source: str, value: float, scale: float = 1.0, detail: str = "") -> "Check":
        """``value`` against this bound (times ``scale``, e.g. κ(M) or a time step)."""
        return Check(name, source, float(value), self.value * scale, self.name, detail)

    def record(self) -> dict:
        return {"name": self.name, "value": self.value, "derived": self.derived, "reason": self.reason}


@dataclass(frozen=True)
class Check:
    """A measured ``value`` against ``bound``: ``value <= bound``.

    ``source`` names what produced the value (``symbolic``, ``pinocchio``, ``mujoco``, ``derivation``);
    ``basis`` the :class:`Bound` the bound comes from (the bound may be scaled per state, e.g. by κ(M));
    ``detail`` says where the value was found (an exported item, a step size)."""

    name: str
    source: str
    value: float
    bound: float
    basis: str = ""
    detail: str = ""

    @property
    def ratio(self) -> float:
        """``value / bound``: at most 1 passes; the margin is 1 − ratio."""
        if math.isnan(self.value) or math.isnan(self.bound):
            return math.inf
        if self.value == 0.0:
            return 0.0
        return self.value / self.bound if self.bound > 0 else math.inf

    @property
    def passed(self) -> bool:
        return self.ratio <= 1.0

    def record(self) -> dict:
        out = {"check": self.name, "source": self.source, "value": self.value, "bound": self.bound,
               "ratio": self.ratio, "basis": self.basis, "passed": self.passed}
        if self.detail:
            out["detail"] = self.detail
        return out


def flag(name: str, source: str, ok: bool, basis: str = "flag", detail: str = "") -> Check:
    """A yes/no check (rolls or slips as predicted, …): value 0 when it holds, 1 when not, bound 0."""
    return Check(name, source, 0.0 if ok else 1.0, 0.0, basis, detail=detail)


def max_abs(x) -> float:
    """``max |x|`` (0 for an empty array)."""
    x = np.asarray(x, dtype=float)
    return float(np.abs(x).max()) if x.size else 0.0  # the method: np.max's dispatch costs more than a small max


def relative_error(a, b, scale: float = 0.0, symmetric: bool = True) -> float:
    """``max |a − b|`` relative to ``max(scale, |a|, |b|)``: 0 when equal, inf when not finite.

    ``symmetric=False``: ``b`` is the reference and the error is relative to ``max(scale, |b|)`` only, so that a
    diverged ``a`` shows its size instead of being divided by it (a naive run against the reference)."""
    diff = max_abs(np.asarray(a, dtype=float) - np.asarray(b, dtype=float)) if np.size(a) else 0.0
    if diff == 0.0:
        return 0.0
    if not math.isfinite(diff):
        return math.inf
    return diff / max(scale, max_abs(a) if symmetric else 0.0, max_abs(b), 1e-300)


def relative_error_rows(a: np.ndarray, b: np.ndarray, scale: float) -> list[float]:
    """``relative_error(a[k], b[k], scale, symmetric=False)`` of every row ``k`` at once (``b`` the reference: relative
    to ``max(scale, max|b[k]|)``): the same numbers, 0 where equal, inf where the difference is not finite."""
    n = len(a)
    if not n:
        return []
    diff = np.abs(a - b).reshape(n, -1).max(axis=1)
    size = np.maximum(np.maximum(np.abs(b).reshape(n, -1).max(axis=1), scale), 1e-300)
    with np.errstate(over="ignore", invalid="ignore"):
        out = np.where(diff == 0.0, 0.0, np.where(np.isfinite(diff), diff / size, math.inf))
    return out.tolist()


# --------------------------------------------------------------------------- the JSON codec of every document
NON_FINITE = ("inf", "-inf", "nan")
"""How JSON documents (results, claims, hard cases, benchmarks) hold non-finite numbers: as these strings."""


def json_number(value):
    """A float as JSON can hold it: non-finite values as the strings ``"inf"``, ``"-inf"``, ``"nan"``."""
    if isinstance(value, (float, np.floating)):
        value = float(value)
        return value if math.isfinite(value) else str(value)
    return value


def json_clean(node):
    """``node`` as strict JSON holds it: every non-finite float replaced by its string (no ``Infinity``), NumPy
    arrays as lists, NumPy integers and booleans as Python's, tuples as lists, keys as strings."""
    if isinstance(node, dict):
        return {k if isinstance(k, str) else str(k): json_clean(v) for k, v in node.items()}
    if isinstance(node, (list, tuple)):
        return [json_clean(v) for v in node]
    if isinstance(node, np.ndarray):
        return json_clean(node.tolist())
    if isinstance(node, np.integer):
        return int(node)
    if isinstance(node, np.bool_):
        return bool(node)
    return json_number(node)


def json_restore(node):
    """The inverse of :func:`json_clean` for numbers: the strings ``"inf"``, ``"-inf"``, ``"nan"`` as floats."""
    if isinstance(node, str) and node in NON_FINITE:
        return float(node)
    if isinstance(node, dict):
        return {k: json_restore(v) for k, v in node.items()}
    if isinstance(node, list):
        return [json_restore(v) for v in node]
    return node
