"""From a printed equation that disagrees to a finding a lecturer can act on.

* **Ingredients and blame.** A claim may be built from other claims (``Claim(..., ingredients=("(A.27)",))``):
  it uses the :class:`~harness.modeling.claims.Printed` symbols those claims define (``defines=``), and is
  checked with their printed values. When it fails, it is checked again with their derived values; if it holds
  then, it *follows from* the ingredient's erratum and is not an erratum of its own. If it still fails, its own
  mistake is reported judged with the corrected ingredients.
* **Notation typos.** A printed symbol that the model does not have and no ingredient defines (``l_e2``) is
  itself the finding. Every renaming of it to one of the model's own symbols of the same unit (parameters,
  coordinates, inputs) is tried; a renaming under which the claim holds makes it a *notation typo*
  ("holds after renaming l_e2 → l_2"), found here, never typed into the model.
* **Decided.** Besides the hypothesis states, ``printed − derived`` is tested for being identically zero by a
  decision procedure whose answer is the same on every machine (:func:`identically_zero`: sines and cosines of each
  angle as two variables on the circle, ``s² + c² = 1``, the numerator brought to its normal form; no CPU-time
  budget, a bound on the number of terms instead): a claim it proves is ``decided_by: "symbolic"``, else ``"numeric
  only"``. The classification never depends on it. It replaced a cascade of simplifications under a budget of 2 CPU
  s, whose label a slower CPU could change: (A.174) reached zero after 2.14 CPU s on one run, within 2 s on
  another. The answer is remembered on disk with the derivations (:func:`harness.derivation.cache.remembered`),
  keyed by the expression and this module's code. Where a classification itself rests on an identity (a
  generalized force written out from its printed force), it is decided at random values to 30 digits
  (:func:`same_at_random_values`, ``decided_by: "identity at random values"``), the same on every machine.

Classifications: ``confirmed``, ``C differs, C·q̇ agrees``, ``convention-dependent``, ``notation typo``,
``follows from erratum``, ``erratum`` (substantive), ``engines disagree``.
"""

from __future__ import annotations

import difflib
import itertools
from pathlib import Path

import sympy as sp

from harness import kept, profiling
from harness.derivation import cache, identities
from harness.derivation.bodies import element_generalized_force
from harness.derivation.identities import identically_zero, same_at_random_values
from harness.modeling.claims import Claim, as_matrix
from harness.modeling.system import Point, System

HOLDS = ("confirmed", "C differs, C·q̇ agrees")
AT_RANDOM_VALUES = "identity at random values"   # decided_by of a verdict that rests on same_at_random_values
RENAMINGS = 60             # at most this many renamings are tried per claim
SCREEN_EXAMPLES = 12       # states a renaming is screened on (derivation only) before the full check

_VERDICTS: dict = {}


def _point_or_none(value):
    return value if isinstance(value, Point) else None


# ----------------------------------------------------------------------------- ingredients
def _by_equation(claims) -> dict:
    return {c.equation: c for c in claims}


def ingredients_of(claim: Claim, claims) -> list[Claim]:
    """The claim's ingredients, transitively, innermost first."""
    table, out = _by_equation(claims), []

    def visit(c):
        for equation in c.ingredients:
            ingredient = table[equation]
            visit(ingredient)
            if ingredient not in out:
                out.append(ingredient)
    visit(claim)
    return out


def substitution(system: System, claim: Claim, claims, which: str) -> dict:
    """The defined symbols of the claim's ingredients → their ``printed`` (resolved in turn) or ``derived``
    values."""
    from harness.compare.claims import _derived

    out: dict = {}
    for ingredient in ingredients_of(claim, claims):
        if which == "printed":
            values = as_matrix(ingredient.printed).xreplace(out)
        else:
            values = as_matrix(_derived(system, ingredient))
        out.update(zip(ingredient.defined, list(values)))
    return out


def undefined(claim: Claim, claims) -> list[tuple[sp.Symbol, str]]:
    """Printed symbols that neither the model nor an ingredient defines: (symbol, unit)."""
    defined = {s for c in ingredients_of(claim, claims) for s in c.defined}
    return [(sp.Symbol(n, real=True), unit) for n, unit in claim.printed_only
            if sp.Symbol(n, real=True) not in defined]


def candidates(system: System, unit: str, claims=(), claim=None) -> list[sp.Symbol]:
    """The model's own symbols of ``unit`` — parameters, coordinates, inputs — and the printed symbols of ``unit``
    that the system's ``claims`` other than ``claim`` define (a force the lecture names and another equation prints,
    e.g. ``f_S``; their units are those the claims that use them declare)."""
    out = [p.symbol for p in system.parameters if p.unit == unit]
    out += [c.symbol for c in system.coordinates if c.unit == unit]
    out += [i.symbol for i in system.inputs if i.unit == unit]
    units = {name: u for c in claims for name, u in c.printed_only}
    out += [s for c in claims if c is not claim for s in c.defined if units.get(s.name) == unit and s not in out]
    return out


def _defined_values(system: System, claims) -> dict:
    """Each symbol the claims define → its printed value (their own ingredients resolved)."""
    out: dict = {}
    for c in claims:
        if c.defined:
            values = as_matrix(c.printed).xreplace(substitution(system, c, claims, "printed"))
            out.update(zip(c.defined, list(values)))
    return out


# ----------------------------------------------------------------------------- classification
def classify(system: System, claim: Claim, engines, examples, claims=None):
    claims = list(claims) if claims else [claim]
    key = (id(system), id(claim), tuple(engines), examples)
    if key not in _VERDICTS:
        _VERDICTS[key] = _classify(system, claim, engines, examples, claims)
    return _VERDICTS[key]


def _classify(system, claim, engines, examples, claims):
    from harness.compare.claims import classify_as_printed

    printed = substitution(system, claim, claims, "printed")
    missing = undefined(claim, claims)
    if missing:
        return _renamed(system, claim, engines, examples, claims, printed, missing)
    verdict = classify_as_printed(system, claim, engines, examples, printed)
    if verdict.classification not in HOLDS and claim.ingredients:
        wrong = []
        for c in ingredients_of(claim, claims):
            v = classify(system, c, engines, examples, claims)
            if v.classification == "follows from erratum":
                wrong += [e for e in v.blame if e not in wrong]
            elif v.classification not in HOLDS and c.equation not in wrong:
                wrong.append(c.equation)
        if wrong:
            derived = substitution(system, claim, claims, "derived")
            again = classify_as_printed(system, claim, engines, examples, derived)
            if again.classification in HOLDS:
                verdict.classification, verdict.blame = "follows from erratum", wrong
                verdict.decided_by = decide(system, claim, derived)
                return verdict
            if _follows_from_printed(system, claim, claims, printed):
                verdict.classification, verdict.blame = "follows from erratum", wrong
                verdict.decided_by = AT_RANDOM_VALUES
                return verdict
            verdict = again  # its own mistake, judged with the corrected ingredients
            verdict.blame = wrong
    verdict.decided_by = _decided(system, claim, verdict, verdict.substitution or printed)
    return verdict


def _follows_from_printed(system, claim, claims, printed) -> bool:
    """Whether the claim is, exactly, what its printed ingredients give (symbolic cascade): an element's
    generalized force ``J_rᵀ f`` (5.73) printed from the element's printed force ``f``, written out. Such a claim
    repeats its ingredient's mistake and is not one of its own."""
    kind, _, name = claim.quantity.partition(":")
    if kind != "f_np" or not name:
        return False
    for ingredient in ingredients_of(claim, claims):
        if ingredient.quantity == f"force:{name}":
            force = as_matrix(ingredient.printed).xreplace(printed)
            expected = element_generalized_force(system, name, force)
            return same_at_random_values(as_matrix(claim.printed).xreplace(printed), expected)
    return False


def _decided(system, claim, verdict, subst) -> str:
    """How the classification was reached: a holding claim by the symbolic cascade or numerically only; a
    failing one by its counterexample."""
    if verdict.classification in HOLDS or verdict.classification in ("notation typo", "follows from erratum"):
        return decide(system, claim, subst)
    return "counterexample"


def _renamed(system, claim, engines, examples, claims, printed, missing):
    """A claim with printed symbols the model lacks: search the renamings over the model's own symbols."""
    from harness.compare.claims import Classification, classify_as_printed, holds

    options = [[(symbol, y) for y in candidates(system, unit, claims, claim)] for symbol, unit in missing]
    defined = _defined_values(system, [c for c in claims if c is not claim])
    tried = []
    for combination in itertools.islice(itertools.product(*options), RENAMINGS):
        renaming = dict(combination)
        values = {k: defined.get(v, v) for k, v in renaming.items()}  # a printed symbol stands for its value
        full = {**{k: v.xreplace(values) for k, v in printed.items()}, **values}
        tried.append(renaming)
        if not holds(system, claim, (), SCREEN_EXAMPLES, full, shrink=False):
            continue
        verdict = classify_as_printed(system, claim, engines, examples, full)
        if verdict.classification in HOLDS:
            verdict.classification, verdict.renaming = "notation typo", {str(k): str(v) for k, v in renaming.items()}
            verdict.decided_by = _decided(system, claim, verdict, full)
            return verdict
    # no renaming makes it hold: judged under the renaming closest by name, reported as an erratum
    names = [str(s) for s, _ in missing]
    if not tried:
        verdict = Classification(claim, system.name, "erratum", [], corrected=None)
        verdict.renaming = {}
        verdict.decided_by = "counterexample"
        return verdict

    def closeness(renaming):
        return -sum(difflib.SequenceMatcher(None, str(k), str(v)).ratio() for k, v in renaming.items())
    best = min(tried, key=closeness)
    values = {k: defined.get(v, v) for k, v in best.items()}
    full = {**{k: v.xreplace(values) for k, v in printed.items()}, **values}
    verdict = classify_as_printed(system, claim, engines, examples, full)
    verdict.classification = "erratum"
    verdict.renaming = {}
    verdict.convention = None
    verdict.decided_by = "counterexample"
    verdict.counterexample = (verdict.counterexample or "") + (
        f" (printed symbol(s) {', '.join(names)} not in the model; no renaming to a model symbol of the same unit "
        f"makes the equation hold; shown with {', '.join(f'{k} → {v}' for k, v in best.items())})")
    return verdict


# ----------------------------------------------------------------------------- symbolic decision
DECISION_CODE = (Path(__file__), Path(identities.__file__))
"""The modules whose code decides a zero test: part of the key under which its answer is remembered."""


def is_zero(matrix) -> bool:
    """Whether every entry is identically zero (:func:`identically_zero`). Remembered on disk
    (:func:`harness.derivation.cache.remembered`): a later run reads the answer instead of deciding again."""
    matrix = as_matrix(matrix)
    def decide():
        return sp.true if all(identically_zero(e) is True for e in matrix) else sp.false
    return cache.remembered("is-zero", DECISION_CODE, (matrix,), decide) is sp.true


def difference(system: System, claim: Claim, subst: dict | None):
    """``printed − derived`` in the model's symbols (None for kinds compared only numerically), as the kind
    defines equality: V up to a constant (its gradient), C·q̇ for Cqd, eom rows up to a factor."""
    from harness.compare.claims import _derived, _printed, at_rest, on_motion

    printed = _printed(system, claim, subst or None)
    if claim.at:
        printed = printed.xreplace(at_rest(system, claim))
    kind = claim.quantity.split(":")[0]
    if kind == "constraint" and not claim.at:  # holds on the motion: q̈ from the equations of motion
        motion = on_motion(system)
        return None if motion is None else (printed - as_matrix(_derived(system, claim))).xreplace(motion)
    if kind == "equilibrium":
        d = _derived(system, claim)
        return d.xreplace(dict(zip(system.q, list(printed))))
    if kind == "steady":  # the derived steady-state equation at the printed value
        from harness.compare.claims import _steady_coordinate, _steady_rest

        k = _steady_coordinate(system, claim)
        value = printed[0].xreplace(_steady_rest(system, claim))
        return _derived(system, claim).xreplace({system.q[k]: value})
    derived = as_matrix(_derived(system, claim))
    if printed.shape != derived.shape:
        if len(printed) != len(derived):
            return None
        printed = printed.reshape(*derived.shape)
    if kind == "V":
        return (printed - derived).jacobian(system.q)
    if kind == "L":  # up to a constant, as V
        return (printed - derived).jacobian([*system.q, *system.qd])
    if kind == "eom":
        return sp.Matrix([r - row_factor(system, r, e, own) * e
                          for r, e, own in zip(printed, derived, rows(claim, len(derived)))])
    return printed - derived


def rows(claim: Claim, n: int) -> list[int]:
    """The coordinates whose equations of motion the ``n`` rows of an eom claim are: its ``index`` row, or all."""
    return [claim.index[0]] if claim.index else list(range(n))


def row_factor(system: System, printed_row, derived_row, own: int | None = None):
    """The factor a printed equation-of-motion row may carry against the derived row (divided through by a
    mass, or written with the other sign): the ratio of their q̈ coefficients when it is free of the state,
    else 1. The row's ``own`` coordinate's acceleration first (its coefficient, an entry on M's diagonal, is never
    0): a coupling term printed with the wrong sign would otherwise give the factor −1, and the correction would
    blame every other term of the row."""
    state = set(system.q) | set(system.qd) | {c.accel for c in system.coordinates} | set(system.u)
    order = list(system.coordinates)
    if own is not None and own < len(order):
        order.insert(0, order.pop(own))
    for c in order:
        de, dr = sp.diff(derived_row, c.accel), sp.diff(printed_row, c.accel)
        if de != 0 and dr != 0:
            factor = sp.cancel(dr / de)
            return factor if not (factor.free_symbols & state) else 1
    return 1


@profiling.timed("symbolic decision")
def decide(system: System, claim: Claim, subst: dict | None) -> str:
    """"symbolic" where ``printed − derived`` (:func:`difference`) is identically zero (:func:`is_zero`), else
    "numeric only". Kept for the
    next run (:mod:`harness.kept`, ``decisions/``) under our installation, what decides the derived expression
    (:func:`~harness.compare.claims.derivation_of`) and the printed one with ``subst`` made (its ``srepr``): a
    holding claim's warm run neither derives nor reduces it again. A parameter claim is decided every run."""
    from harness.compare.claims import derivation_of, printed_text

    identity = derivation_of(system, claim)
    if identity is None:
        return _decide(system, claim, subst)
    where = kept.path("decisions", system.name, *identity, printed_text(system, claim, subst or None))
    doc = kept.read_kept(where)
    if doc in ("symbolic", "numeric only"):
        return doc
    decided = _decide(system, claim, subst)
    kept.keep(where, decided)
    return decided


def _decide(system: System, claim: Claim, subst: dict | None) -> str:
    try:
        diff = difference(system, claim, subst)
    except Exception:  # noqa: BLE001 - a form the symbolic comparison does not cover stays numeric
        return "numeric only"
    if diff is None:
        return "numeric only"
    return "symbolic" if is_zero(diff) else "numeric only"
