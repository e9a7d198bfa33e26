"""A printed equation of the lecture, as a model module states it (:class:`Claim`), and the check that its
symbols are the system's own — when the module loads. Classifying a claim against the derivation and the
engines is :mod:`harness.compare.claims`."""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from harness.modeling.system import System, plain

ENGINE_QUANTITIES = {"M", "C", "Cqd", "g"}
QUANTITIES = ENGINE_QUANTITIES | {"f_np", "T", "V", "eom", "parameter", "equilibrium"}


@dataclass(frozen=True)
class Claim:
    """One printed equation. ``printed`` is a sympy expression or Matrix in the model's symbols (its
    coordinates, their ``.rate`` and ``.accel``, parameters, inputs); stored with plain symbols."""

    equation: str                       # "(5.112)"
    quantity: str                       # "M", "C", "Cqd", "g", "f_np", "T", "V", "eom", "position:<point>", "parameter"
    printed: object                     # sympy Expr or Matrix, as printed
    description: str = ""
    index: tuple | None = None          # only this element/row of the quantity, e.g. (1, 0) or (0,)
    reference: object = None            # derived expression for "parameter" claims
    conventions: dict = field(default_factory=dict)  # name -> substitution dict (alternative conventions)
    note: str = ""                      # transcription remarks (e.g. "printed l_e2 read as l_2")

    def __post_init__(self):
        kind = self.quantity.split(":")[0]
        if kind not in QUANTITIES | {"position"}:
            raise ValueError(f"claim {self.equation}: unknown quantity {self.quantity!r}")
        for name in ("printed", "reference", "conventions"):
            object.__setattr__(self, name, plain(getattr(self, name)))


def symbols(system: System):
    """The argument groups of a compiled claim: q, q̇, q̈, parameters, inputs."""
    accel = [c.accel for c in system.coordinates]
    return [system.q, system.qd, accel, system.p, system.u]


def as_matrix(expr) -> sp.Matrix:
    return sp.Matrix(expr) if isinstance(expr, (sp.MatrixBase, list, tuple)) else sp.Matrix([expr])


def validate_claims(system: System, claims) -> None:
    """Every symbol a claim uses is one the system declares (same name *and* assumptions): a coordinate, its
    rate or acceleration, a parameter or an input. Raises :class:`ModelError` naming the claim, the symbol and
    the fix — when the module loads, not deep inside a classification run."""
    from harness.errors import ModelError

    declared = {s for group in symbols(system) for s in group}
    by_name = {s.name: s for s in declared}
    for claim in claims:
        if not isinstance(claim, Claim):
            raise ModelError(f"CLAIMS holds {type(claim).__name__}, not Claim")
        parts = [("printed", claim.printed), ("reference", claim.reference)]
        parts += [(f"convention {name!r}", sp.Matrix([*sub.keys(), *sub.values()]) if sub else None)
                  for name, sub in claim.conventions.items()]
        for what, expr in parts:
            if expr is None:
                continue
            try:
                used = as_matrix(expr).free_symbols
            except (TypeError, ValueError, sp.SympifyError) as exc:
                raise ModelError(f"claim {claim.equation}: {what} is not a sympy expression ({exc})") from None
            for symbol in sorted(used - declared, key=lambda s: s.name):
                if symbol.name in by_name:
                    fix = (f"use the model's own Parameter, Coordinate (.rate, .accel) or Input; it has other "
                           f"assumptions than sp.Symbol({symbol.name!r})")
                else:
                    fix = ("declare it as a Parameter or Input of the system (a parameter the system's expressions do "
                           "not use: System(parameters=...)), or write it in the model's symbols")
                raise ModelError(f"claim {claim.equation} ({what}) uses {symbol.name!r}, which {system.name} does "
                                 f"not declare: {fix}")
