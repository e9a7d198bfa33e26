"""A printed equation of the lecture, as a model module states it (:class:`Claim`), and the check that its
symbols are the system's own — when the module loads. Classifying a claim against the derivation and the
engines is :mod:`harness.compare.claims`."""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from harness.modeling.system import Declared, System, plain

ENGINE_QUANTITIES = {"M", "C", "Cqd", "g"}
QUANTITIES = ENGINE_QUANTITIES | {"f_np", "T", "V", "L", "K", "eom", "parameter", "equilibrium"}
# "K": the stiffness matrix ∂g/∂q of the potential forces (3.74) (its symmetry is the integrability condition (3.73))
# kinds with an argument: "position:<point>", "v:<point>" (its velocity J_v q̇), "a:<point>" (its
# acceleration), "v_squared:<point>" (ṗᵀ ṗ), "J_v:<point>" (its translational
# Jacobian (4.64)), "J_omega:<link>"
# (the link's rotational Jacobian (4.62)), "force:<element>" (the force vector a spring or damper exerts on its
# point b), "f_np:<element>" (that element's generalized force alone; plain "f_np" is the whole vector)
# "holding:<input>" (the value of the input that holds the system at rest at q)
# per body (harness.derivation.bodies): "R:<link>" / "R:<frame>/<link>" (rotation matrix R_0^k, R_j^k), "S:…" (its
# S = Ṙ Rᵀ (4.44)), "omega:<link>" (ω_0^k (4.57)), "I_0:<link>" (inertia tensor in the inertial frame (5.15)),
# "T_t:<link>", "T_r:<link>" (translational, rotational kinetic energy (5.6), (5.12)), "V:<link>" (its gravity
# potential (5.20), up to a constant like V);
# "steady:<coordinate>" (the value of that coordinate in a steady state: at rest in it, no input, the other
# rates as drawn; states where the printed value is not real lie outside its stated domain);
# "L" (the Lagrange function, up to a constant), "dL_dqd:<q>", "ddt_dL_dqd:<q>", "dL_dq:<q>" (the terms of (5.69));
# "constraint:<name>" (the magnitude of a declared ConstraintForce: a rope, rolling contact, ... force)
KINDS_WITH_ARGUMENT = {"position", "v", "a", "v_squared", "J_v", "J_omega", "force", "f_np", "holding", "R", "S",
                       "omega", "I_0", "T_t", "T_r", "V", "steady", "dL_dqd", "ddt_dL_dqd", "dL_dq", "constraint"}
AT_REST = ("equilibrium", "holding:")
"""``Claim.at``: where a statement about the system at rest holds — ``"equilibrium"`` (``q̇ = 0`` at the system's
one equilibrium, no input) or ``"holding:<input>"`` (``q̇ = 0`` at any ``q``, held there by that input, the others
0); empty: at every state, with ``q̈`` from the equations of motion."""


class Printed(Declared):
    """A symbol the lecture prints that the model does not declare: a quantity another claim defines (``m_S``
    defined by the printed mass, the matrix entries of a printed ``C`` that an equation of motion uses), or a
    printed symbol that exists nowhere in the example (``l_e2``). Its unit says which of the model's own symbols
    it could be a misprint of: a claim with an undefined printed symbol is checked under every renaming to a
    model symbol of the same unit (:mod:`harness.compare.errata`)."""

    _meta = ("name", "unit", "description")

    def __new__(cls, name: str, unit: str, description: str = ""):
        return cls._declare(name, "real", unit=unit, description=description)


def printed_matrix(name: str, rows: int, cols: int, unit: str, description: str = "") -> sp.Matrix:
    """A matrix of :class:`Printed` symbols ``<name>_<i><j>`` (1-based), e.g. the printed ``C`` that (A.122)
    uses, defined by the claim of (A.123b)."""
    return sp.Matrix(rows, cols, lambda i, j: Printed(f"{name}_{i + 1}{j + 1}", unit, description))


@dataclass(frozen=True)
class Claim:
    """One printed equation. ``printed`` is a sympy expression or Matrix in the model's symbols (its
    coordinates, their ``.rate`` and ``.accel``, parameters, inputs); stored with plain symbols."""

    equation: str                       # "(5.112)"
    quantity: str                       # "M", "C", "Cqd", "g", "f_np", "T", "V", "eom", "position:<point>", "parameter"
    printed: object                     # sympy Expr or Matrix, as printed
    description: str = ""
    index: tuple | None = None          # only this element/row of the quantity, e.g. (1, 0) or (0,)
    reference: object = None            # derived expression for "parameter" claims, or a function of no
    #                                     arguments returning it (derived when first compared: see derived_reference)
    conventions: dict = field(default_factory=dict)  # name -> substitution dict (alternative conventions)
    note: str = ""                      # transcription remarks (notation mappings, never corrections)
    defines: object = None              # Printed symbol(s) whose printed value this claim states (e.g. m_S)
    ingredients: tuple = ()             # equations of the claims whose defined symbols this claim uses
    printed_only: tuple = ()            # (name, unit) of every Printed symbol used; filled in, not given
    at: str = ""                        # "", "equilibrium" or "holding:<input>": a statement at rest (AT_REST)

    def __post_init__(self):
        kind = self.quantity.split(":")[0]
        if kind not in QUANTITIES | KINDS_WITH_ARGUMENT:
            raise ValueError(f"claim {self.equation}: unknown quantity {self.quantity!r}: Claim(equation, quantity, "
                             f"printed, ...) takes one of {', '.join(sorted(QUANTITIES))} or "
                             f"{', '.join(k + ':<name>' for k in sorted(KINDS_WITH_ARGUMENT))}")
        if self.at and (not (self.at == AT_REST[0] or self.at.startswith(AT_REST[1]))
                        or kind in ("equilibrium", "holding", "steady")):
            raise ValueError(f"claim {self.equation}: at={self.at!r}: use 'equilibrium' or 'holding:<input>', "
                             f"and not with a {kind} claim (which is at rest already)")
        if isinstance(self.ingredients, str):
            object.__setattr__(self, "ingredients", (self.ingredients,))
        found: list = []
        for name in ("printed", "reference", "conventions"):
            object.__setattr__(self, name, plain(getattr(self, name), found))
        object.__setattr__(self, "defines", plain(self.defines))
        if not self.printed_only:
            units = {s.name: s.unit for s in found if isinstance(s, Printed)}
            object.__setattr__(self, "printed_only", tuple(sorted(units.items())))

    def derived_reference(self):
        """The ``reference`` expression (plain symbols); a function given as the reference — a cut force, a volume
        integral: a derivation of its own — is called once, when the claim is first compared, not whenever the
        catalogue loads."""
        if not callable(self.reference):
            return self.reference
        kept = self.__dict__.get("_reference")
        if kept is None:
            kept = plain(self.reference())
            object.__setattr__(self, "_reference", kept)  # frozen: a cache, not state
        return kept

    @property
    def where(self) -> str:
        """Where the statement holds, in words (``at``): empty for every state."""
        if not self.at:
            return ""
        if self.at == "equilibrium":
            return "at rest at the equilibrium"
        return f"at rest, held by the input {self.at.split(':', 1)[1]}"

    @property
    def defined(self) -> list:
        """The symbols this claim defines, in the order of its printed matrix."""
        return [] if self.defines is None else list(as_matrix(self.defines))


def symbols(system: System):
    """The argument groups of a compiled claim: q, q̇, q̈, parameters, inputs."""
    accel = [c.accel for c in system.coordinates]
    return [system.q, system.qd, accel, system.p, system.u]


# How a quantity of each kind changes with the coordinates, q_printed = φ(q) with a constant Jacobian J = ∂φ/∂q
# (a coordinate counted the other way round, from another zero, or in other units): "both" Jᵀ P J (a matrix of
# coordinate pairs), "rows" Jᵀ P (generalized forces and balances, (5.58)–(5.60)), "columns" P J (a Jacobian onto
# world vectors). The kinds not named are scalars, world or parameter quantities: the substitution alone.
COVARIANCE = {"M": "both", "C": "both", "K": "both", "Cqd": "rows", "g": "rows", "f_np": "rows", "eom": "rows",
              "J_v": "columns", "J_omega": "columns"}
# kinds whose printed value is itself a coordinate, an input or one coordinate's term: a coordinate convention on
# them is refused when the module loads (write them in the model's coordinates)
NOT_UNDER_COORDINATE_CHANGE = {"equilibrium", "steady", "holding", "constraint", "dL_dqd", "ddt_dL_dqd", "dL_dq"}


@dataclass(frozen=True)
class CoordinateChange:
    """A convention that counts coordinates otherwise, ``q_printed = φ(q)``: the substitution completed with the
    rates and accelerations ``q̇ → J q̇``, ``q̈ → J q̈``, and the constant Jacobian ``J = ∂φ/∂q``."""

    substitution: dict
    J: sp.Matrix

    def quantity(self, kind: str, printed: sp.Matrix, index=None) -> sp.Matrix:
        """The printed quantity of ``kind`` (``printed``, the substitution made) in the model's coordinates: Jᵀ P J,
        Jᵀ P or P J (:data:`COVARIANCE`); one entry or row (``index``) by J's diagonal."""
        how = COVARIANCE.get(kind)
        if how is None:
            return printed
        J = self.J
        if index is not None:  # J is diagonal (validate_claims): each entry scales by its coordinates' factors
            n = J.shape[0]
            full = sp.ones(*{"both": (n, n), "rows": (n, 1), "columns": (3, n)}[how])
            factors = J.T * full * J if how == "both" else J.T * full if how == "rows" else full * J
            return printed.multiply_elementwise(select(factors, index).reshape(*printed.shape))
        if how == "both":
            return J.T * printed * J
        if how == "rows":
            column = printed.reshape(len(printed), 1)
            return (J.T * column).reshape(*printed.shape)
        return printed * J

    def back(self, system: System, kind: str, value, index=None) -> sp.Matrix | None:
        """``value``, a quantity of ``kind`` in the model's coordinates, read in the printed ones: the inverse of
        :meth:`quantity` (``J⁻ᵀ P J⁻¹`` at ``q = J⁻¹(q_printed − b)``, an input mapped ``u → a u + b`` taken back
        alike). None where a substitution of something other than a coordinate cannot be inverted so."""
        q = sp.Matrix(system.q)
        phi = q.xreplace(self.substitution)
        inverse = dict(zip(system.q, self.J.inv() * (q - phi.xreplace({x: 0 for x in q}))))
        state = set(system.q) | set(system.qd) | {c.accel for c in system.coordinates}
        for symbol, image in self.substitution.items():
            if symbol in state:
                continue
            a, b = sp.diff(image, symbol), image.xreplace({symbol: 0})
            if not isinstance(symbol, sp.Symbol) or image.free_symbols - {symbol} or a.free_symbols or a == 0:
                return None
            inverse[symbol] = (symbol - b) / a
        back = coordinate_change(system, inverse)
        return back.quantity(kind, as_matrix(value).xreplace(back.substitution), index)


def coordinate_change(system: System, substitution: dict | None, where: str = "") -> CoordinateChange | None:
    """The coordinate change a convention's ``substitution`` makes (None: it renames no coordinate). Each coordinate
    it maps, ``q_k → φ_k(q)``, must be affine in the coordinates (a constant Jacobian: the quantities then change
    by it alone, :meth:`CoordinateChange.quantity`) with ``J`` regular; its rates and accelerations follow
    (``q̇ → J q̇``), and a rate or acceleration given must be that one. Otherwise :class:`ModelError` (``where``
    names the claim and convention)."""
    from harness.errors import ModelError

    if not substitution:
        return None
    q, qd = list(system.q), list(system.qd)
    qdd = [c.accel for c in system.coordinates]
    if not any(k in substitution for k in q):
        for k in substitution:
            if k in qd or k in qdd:
                raise ModelError(f"{where}: it substitutes {k}, a rate or acceleration, and not its coordinate: give "
                                 "the coordinate's substitution (its rate and acceleration follow from it)")
        return None
    phi = sp.Matrix([substitution.get(c, c) for c in q])
    J = phi.jacobian(q)
    state = set(q) | set(qd) | set(qdd)
    if J.free_symbols & state:
        raise ModelError(f"{where}: the coordinates are mapped by {list(phi)}, which is not affine in them (its "
                         "Jacobian depends on the state): a convention may count a coordinate the other way round, "
                         "from another zero or in other units, q -> a q + b")
    if J.det() == 0:
        raise ModelError(f"{where}: the coordinates are mapped by {list(phi)}, whose Jacobian is singular")
    completed = dict(substitution)
    for symbols, image in ((qd, J * sp.Matrix(qd)), (qdd, J * sp.Matrix(qdd))):
        for symbol, value in zip(symbols, image):
            given = substitution.get(symbol)
            if given is not None and sp.simplify(given - value) != 0:
                raise ModelError(f"{where}: it substitutes {symbol} -> {given}, but its coordinates' map gives "
                                 f"{value}: leave it out (it follows from the coordinates)")
            completed[symbol] = value
    return CoordinateChange(completed, J)


def _check_conventions(system: System, claim: Claim) -> None:
    """Each convention of ``claim`` that counts coordinates otherwise (:func:`coordinate_change`) is one the
    claim's kind can be taken through: not the value of a coordinate or input, nor one coordinate's term; one entry
    or row only under a diagonal Jacobian (a convention mixing coordinates needs the whole quantity)."""
    from harness.errors import ModelError

    kind = claim.quantity.split(":")[0]
    for name, substitution in claim.conventions.items():
        where = f"claim {claim.equation}, convention {name!r}"
        change = coordinate_change(system, substitution, where)
        if change is None:
            continue
        if kind in NOT_UNDER_COORDINATE_CHANGE:
            raise ModelError(f"{where}: a {kind} claim cannot be taken to other coordinates; write the printed "
                             "expression in the model's coordinates and say so in note=")
        if claim.index is not None and COVARIANCE.get(kind) and not change.J.is_diagonal():
            raise ModelError(f"{where}: the convention mixes coordinates, so one entry of {kind} is not one entry "
                             "of the model's; claim the whole quantity (no index)")


def as_matrix(expr) -> sp.Matrix:
    return sp.Matrix(expr) if isinstance(expr, (sp.MatrixBase, list, tuple)) else sp.Matrix([expr])


def select(m: sp.Matrix, index) -> sp.Matrix:
    """What a claim's ``index`` takes of a quantity: all of it (None), one entry ``(i, j)``, or ``(i,)`` one row of a
    matrix or one entry of a vector."""
    if index is None:
        return m
    if len(index) == 2:
        return sp.Matrix([m[index]])
    return m[index[0], :] if m.shape[0] > 1 and m.shape[1] > 1 else sp.Matrix([m[index[0]]])


def _check_point(system: System, claim: Claim) -> None:
    """A claim of a point (``position:``, ``v:``, ``a:``, ``v_squared:``, ``J_v:``) names one of the system
    (:meth:`System.point`); otherwise :class:`ModelError` with the names it knows, when the module loads."""
    from harness.errors import ModelError

    kind, _, name = claim.quantity.partition(":")
    if kind in ("position", "v", "a", "v_squared", "J_v"):
        try:
            system.point(name)
        except ModelError as exc:
            raise ModelError(f"claim {claim.equation}: {exc}") from None


def _check_shape(system: System, claim: Claim) -> None:
    """A claim of a whole quantity (no ``index``) has its shape: ``M``, ``C`` ``n × n``; ``Cqd``, ``g``, ``f_np``,
    ``eom`` ``n`` entries; ``T``, ``V``, ``L`` one; a ``position:`` three. Otherwise :class:`ModelError` naming both
    shapes, when the module loads (it had failed the classification with NumPy's "cannot reshape")."""
    from harness.errors import ModelError

    if claim.index is not None:
        return
    n, kind = len(system.coordinates), claim.quantity
    expected = {"M": (n, n), "C": (n, n), "Cqd": (n, 1), "g": (n, 1), "f_np": (n, 1), "eom": (n, 1), "T": (1, 1),
                "V": (1, 1), "L": (1, 1)}.get(kind, (3, 1) if kind.startswith("position:") else None)
    if expected is None or not isinstance(claim.printed, (sp.MatrixBase, sp.Expr, list, tuple)):
        return
    shape = as_matrix(claim.printed).shape
    if shape not in (expected, expected[::-1]):
        raise ModelError(f"claim {claim.equation}: the printed {kind} is {shape[0]} × {shape[1]}, {system.name}'s is "
                         f"{expected[0]} × {expected[1]} ({n} coordinate(s)); give the whole quantity, or one entry "
                         "with Claim(..., index=(i, j)) or one row with index=(i,)")


def validate_claims(system: System, claims) -> None:
    """Every symbol a claim uses is one the system declares (same name *and* assumptions): a coordinate, its
    rate or acceleration, a parameter or an input. Raises :class:`ModelError` naming the claim, the symbol and
    the fix — when the module loads, not deep inside a classification run."""
    from harness.errors import ModelError

    declared = {s for group in symbols(system) for s in group}
    by_name = {s.name: s for s in declared}
    claims = list(claims)
    for claim in claims:
        if not isinstance(claim, Claim):
            raise ModelError(f"CLAIMS holds {type(claim).__name__}, not Claim")
    by_equation = {c.equation: c for c in claims}
    for claim in claims:
        printed_only = {sp.Symbol(name, real=True) for name, _ in claim.printed_only}
        for name, _ in claim.printed_only:
            if name in by_name:
                raise ModelError(f"claim {claim.equation}: the printed symbol {name!r} is a symbol of {system.name}: "
                                 f"use the model's own")
        _check_point(system, claim)
        _check_shape(system, claim)
        _check_conventions(system, claim)
        if claim.defines is not None and as_matrix(claim.defines).shape != as_matrix(claim.printed).shape:
            raise ModelError(f"claim {claim.equation}: defines has another shape than the printed expression")
        for equation in claim.ingredients:
            if equation not in by_equation or by_equation[equation].defines is None:
                raise ModelError(f"claim {claim.equation}: ingredient {equation!r} is not a claim of {system.name} "
                                 f"that defines printed symbols (Claim(..., defines=...))")
        declared_here = declared | printed_only
        parts = [("printed", claim.printed), ("reference", None if callable(claim.reference) else claim.reference)]
        parts += [(f"convention {name!r}", sp.Matrix([*sub.keys(), *sub.values()]) if sub else None)
                  for name, sub in claim.conventions.items()]
        for what, expr in parts:
            if expr is None:
                continue
            try:
                used = as_matrix(expr).free_symbols
            except (TypeError, ValueError, sp.SympifyError) as exc:
                raise ModelError(f"claim {claim.equation}: {what} is not a sympy expression ({exc})") from None
            for symbol in sorted(used - declared_here, key=lambda s: s.name):
                if symbol.name in by_name:
                    fix = (f"use the model's own Parameter, Coordinate (.rate, .accel) or Input; it has other "
                           f"assumptions than sp.Symbol({symbol.name!r})")
                else:
                    fix = ("declare it as a Parameter or Input of the system (a parameter the system's expressions do "
                           "not use: System(parameters=...)), or write it in the model's symbols")
                raise ModelError(f"claim {claim.equation} ({what}) uses {symbol.name!r}, which {system.name} does "
                                 f"not declare: {fix}")
