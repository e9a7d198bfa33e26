"""The derived equations of a system as mathematics for its report page: ``M(q)`` (5.21), ``C(q, q̇)`` from the
Christoffel symbols (5.95), (5.97), ``g(q)`` (5.96), ``f_q^np`` (5.60), (5.73) and the equations of motion in
the form (5.93), printed as MathML in the lecture's notation (:mod:`harness.report.mathml`); and each printed
equation of the lecture (a claim) beside the derived quantity it is compared with.

Simplification is for reading only: an entry with more than :data:`SIMPLIFY_MAX_OPS` operations is shown as derived,
and so is one whose simplification takes more than :data:`ENTRY_SECONDS` of CPU time, a safety cap no entry of the
catalogue comes near (the page says so when it trips): which entries a page shows simplified depends on the
expressions, not on the machine's speed or load. A quantity with more than
:data:`PRINT_MAX_OPS` operations, or derived per body as an expression graph (the 7-DoF arm), is not printed:
the page says how large it is instead.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from html import escape

import sympy as sp

from harness.limits import OutOfTime, cpu_budget
from harness.report.mathml import LINE_WIDTH, body, bold, bold_argument, broken, math, pieces, signed_terms, width

SIMPLIFY_MAX_OPS = 150
"""Entries with more operations are shown as derived, and an entry with more once expanded is not passed to
``trigsimp``, which cost 1.4-3.2 CPU s for each of the larger ones (toggle_press's M and C, trebuchet's M, tower_crane's
M): the catalogue's 735 entries took 46.5 CPU s to simplify with a limit of 300, 22.9 s with this one (measured)."""
PRINT_MAX_OPS = 1500
ENTRY_SECONDS = 10.0
"""The safety cap of one entry's simplification, CPU seconds: 8 x the slowest entry of the catalogue (1.3 s,
cantilever_beam's equation of motion). It replaced a budget of 2 s per system for all its entries, under which the
entries shown simplified depended on the machine's speed and load: fresh clones on one machine, of commits with the
same report code, showed other entries simplified on the pages of planar_robot, toggle_press and trebuchet_free."""


# the lecture's general equations the derived quantities follow
GENERAL = {"M": "(5.21)", "C": "(5.95), (5.97)", "g": "(5.96)", "f_np": "(5.60), (5.73)", "eom": "(5.93)"}


@dataclass
class Budget:
    """The simplification of one system's entries for reading, and what it left as derived: entries over
    :data:`SIMPLIFY_MAX_OPS` operations, entries over the cap of ``seconds`` of this process's CPU time each."""

    seconds: float = ENTRY_SECONDS
    timed_out: int = 0
    skipped_large: int = 0
    done: dict = field(default_factory=dict)
    """Entry → (what :meth:`simplify` returned, the count it added to): an entry met again (a printed equation's
    derived form that is an entry of ``M``, ``C`` or ``g`` too) is not simplified twice, and counts as before."""

    def simplify(self, expr):
        """``expr`` simplified for reading (multiple angles expanded, expand, trigsimp, common factors), or as it
        is when large or over the cap. Expanding the multiple angles first (measured over the catalogue's M, C, g:
        5 entries shorter, none longer, 3.9 against 5.0 CPU s): the governor's ``M₂₂`` reads ``2 l² m``, not a
        polynomial in ``sin α`` and ``sin 3α``."""
        expr = sp.sympify(expr)
        if isinstance(expr, sp.MatrixBase):
            return expr.applyfunc(self.simplify)
        if expr.is_number or expr.is_Symbol:
            return expr
        if expr not in self.done:
            self.done[expr] = self._simplified(expr)
        out, counted = self.done[expr]
        if counted:
            setattr(self, counted, getattr(self, counted) + 1)
        return out

    def _simplified(self, expr) -> tuple:
        if sp.count_ops(expr) > SIMPLIFY_MAX_OPS:
            return expr, "skipped_large"
        try:
            with cpu_budget(self.seconds):  # multiple angles first: trigsimp does not see sin(3α) in sin(α)
                out = sp.expand(sp.expand_trig(expr))
                if out.has(sp.sin, sp.cos) and sp.count_ops(out) <= SIMPLIFY_MAX_OPS:
                    out = sp.trigsimp(out)
                out = sp.factor_terms(out)
        except OutOfTime:
            return expr, "timed_out"
        return (out if sp.count_ops(out) <= sp.count_ops(expr) else expr), None

    def notes(self) -> list[str]:
        out = []
        def entries(n: int) -> str:
            return f"{n} entr{'y' if n == 1 else 'ies'}"
        if self.timed_out:
            out.append(f"{entries(self.timed_out)} whose simplification took more than {self.seconds:g} s of CPU time "
                       "shown as derived (unsimplified).")
        if self.skipped_large:
            out.append(f"{entries(self.skipped_large)} with more than {SIMPLIFY_MAX_OPS} operations shown as derived "
                       "(unsimplified).")
        return out


def _too_large(expr) -> int:
    """The operation count of ``expr`` when it is too large to print, else 0."""
    ops = sp.count_ops(expr)
    return ops if ops > PRINT_MAX_OPS else 0


def _equation(lhs: str, expr, *, label: str = "", lecture: str = "", names=None, letter: str = "",
              superscript: str = "", vector: bool = False) -> dict:
    """``lhs = expr``; a matrix too wide for a line (:func:`_wide`) entry by entry, each ``letter`` with its indices
    (one for a ``vector``) and ``superscript`` (:func:`_entries`)."""
    size = _too_large(expr)
    if size:
        return {"math": math(lhs, "<mo>=</mo>", "<mo>…</mo>"), "label": label, "lecture": lecture,
                "note": f"{size} operations: too large to print here"}
    if letter and _wide(expr):
        written, note = _entries(letter, expr, superscript, vector)
        text = broken(written)
        return {"math": text, "label": label, "lecture": lecture, "note": note}
    return {"math": math(lhs, "<mo>=</mo>", body(expr, names=names)), "label": label, "lecture": lecture, "note": ""}


def _wide(matrix) -> bool:
    """Whether ``matrix`` printed is wider than a line (:data:`~harness.report.mathml.LINE_WIDTH`): its columns'
    widest entries together."""
    return sum(max(width(matrix[i, j]) for i in range(matrix.rows)) for j in range(matrix.cols)) > LINE_WIDTH


def _terms(expr) -> list:
    return list(expr.as_ordered_terms()) if isinstance(expr, sp.Add) else [expr]


def _entries(letter: str, matrix, superscript: str = "", vector: bool = False, name=None) -> tuple[list, str]:
    """A matrix too wide for a line as its entries ``letter_ij = …``, the equations
    :func:`~harness.report.mathml.broken` sets (each broken after its terms), and what the page says of the entries
    not written: a symmetric matrix (M) is written by its entries on and above the diagonal. ``name(index)``: each
    entry's left-hand side instead (a printed equation's, :func:`wide_math`), every entry written: a printed matrix
    is read entry by entry against the derived one."""
    symmetric = name is None and matrix.is_square and matrix.rows > 1 and matrix == matrix.T
    written = []
    for i in range(matrix.rows):
        for j in range(i if symmetric else 0, matrix.cols):
            index = str(i + 1) if vector else (f"{i + 1}{j + 1}" if matrix.rows < 10 else f"{i + 1},{j + 1}")
            left = name(index) if name else bold(letter, subscript=index, superscript=superscript)
            written.append((left, "<mo>=</mo>", _terms(matrix[i, j])))
    return written, f"{letter} is symmetric: its entries on and above the diagonal are written." if symmetric \
        else ""


ABBREVIATION_MIN_WIDTH = 20
"""A common subexpression of the entries wider than a line is named (:func:`abbreviated`) when it is at least this
wide (:func:`~harness.report.mathml.width`); a narrower one reads better in place than as a name to look up."""


WIDE_SUMS_NAMED = 40
"""The most names :func:`abbreviated` gives in all (common subexpressions and single wide sums): past it an entry
scrolls rather than send the reader through a longer list."""


def _scrolls(expr, deep: bool = False) -> bool:
    """Whether ``expr`` broken after its terms, its products opened one level (``deep``: level after level,
    :func:`~harness.report.mathml.pieces`), still has a piece wider than a line."""
    return any(w > LINE_WIDTH for w, _ in pieces(_terms(expr), deep=deep))


def abbreviated(matrices: list) -> tuple[list, list[tuple[sp.Symbol, sp.Expr]]]:
    """``matrices`` with the common subexpressions of their entries that would scroll (:func:`_scrolls`) named
    ``ξ₁, ξ₂, …`` (``sympy.cse``; one named only when at least :data:`ABBREVIATION_MIN_WIDTH` wide), and the names
    with what they stand for, in the order they are defined (a later one may use an earlier one), the way a
    derivation by hand writes ``with ξ₁ = …``. Other entries are left as they are. The trebuchet's map
    ``θ_sling = −θ + arccos(L (sin θ₀ − sin θ) / r)`` and its derivative recur in every entry of its M and C: its
    ``M₁₁`` printed 616 characters wide, 36 with them named. What still does not fit once opened level after level
    has its widest sum named too, though it occurs once (at most :data:`WIDE_SUMS_NAMED` names in all)."""
    wide = [(k, index) for k, m in enumerate(matrices) for index in range(len(m)) if _scrolls(m[index])]
    if not wide:
        return matrices, []
    taken = {s.name for m in matrices for s in m.free_symbols}
    letter = next((x for x in ("xi", "eta", "zeta", "chi") if not any(n.split("_")[0] == x for n in taken)), "Xi")
    named, reduced = sp.cse([matrices[k][index] for k, index in wide], symbols=sp.numbered_symbols("_cse"),
                            order="none")
    inline, kept = {}, []
    for symbol, expr in named:
        expr = expr.xreplace(inline)
        if width(expr) < ABBREVIATION_MIN_WIDTH:
            inline[symbol] = expr
        else:
            kept.append((symbol, expr))
    names = {symbol: sp.Symbol(f"{letter}_{n + 1}", real=True) for n, (symbol, _) in enumerate(kept)}
    out = [sp.Matrix(m) for m in matrices]
    for (k, index), expr in zip(wide, reduced):
        out[k][index] = expr.xreplace(inline).xreplace(names)
    where = [(names[symbol], expr.xreplace(names)) for symbol, expr in kept]
    _name_long_sums(out, where, wide, letter)
    return out, where


def _name_long_sums(out: list, where: list, wide: list, letter: str) -> None:
    """What still does not fit, even opened level after level — an entry ``out[k][index]`` of ``wide`` or a name's
    value in ``where`` — has its widest sum named (``letter`` numbered on), though it occurs once (a long denominator,
    a function's argument: a single term wider than a line), until it fits; in place."""
    fresh = (sp.Symbol(f"{letter}_{n}", real=True) for n in itertools.count(len(where) + 1))
    todo = [("entry", k, index) for k, index in wide] + [("name", n, None) for n in range(len(where))]
    while todo and len(where) < WIDE_SUMS_NAMED:
        kind, k, index = todo.pop(0)
        expr = out[k][index] if kind == "entry" else where[k][1]
        if not _scrolls(expr, deep=True):
            continue
        sums = [s for s in sp.preorder_traversal(expr) if isinstance(s, sp.Add) and s != expr
                and width(s) >= ABBREVIATION_MIN_WIDTH]
        if not sums:
            continue
        widest, name = max(sums, key=width), next(fresh)
        if kind == "entry":
            out[k][index] = expr.xreplace({widest: name})
        else:
            where[k] = (where[k][0], expr.xreplace({widest: name}))
        where.append((name, widest))
        todo += [(kind, k, index), ("name", len(where) - 1, None)]


def _claim_labels(claims, quantity: str) -> str:
    return ", ".join(dict.fromkeys(c.equation for c in claims if c.quantity == quantity))


def derived_equations(system, claims=(), budget: Budget | None = None) -> dict:
    """The derived quantities of ``system`` as MathML: ``{"quantities": [...], "eom": [...], "notes": [...]}``;
    each entry ``{"title", "math", "label" (the lecture's general equation), "lecture" (the system's own printed
    equations of that quantity, from its claims), "note"}``."""
    from harness.derivation.derive import derive, is_per_body

    if is_per_body(system):  # decided before deriving: the page needs nothing of such a derivation
        return {"quantities": [], "eom": [], "notes": [
            "Derived per body as an expression graph (one shared subexpression per body pose): the entries of M, "
            "C, g are far too large to print; their values are what the checks compare."]}
    budget = budget or Budget()
    d = derive(system)
    q = sp.Matrix(system.q)
    qd = sp.Matrix(system.qd)
    qdd = sp.Matrix([c.accel for c in system.coordinates])
    (M, C, g, f), abbreviations = abbreviated([budget.simplify(x) for x in (d.M, d.C, d.g, d.f_np)])
    quantities = [
        {"title": "Mass matrix", **_equation(bold("M", args="q"), M, label=GENERAL["M"],
                                            lecture=_claim_labels(claims, "M"), letter="M")},
        {"title": "Coriolis matrix from the Christoffel symbols", **_equation(
            bold("C", args="q, qd"), C, label=GENERAL["C"], lecture=_claim_labels(claims, "C"), letter="C")},
        {"title": "Potential forces", **_equation(bold("g", args="q"), g, label=GENERAL["g"],
                                                 lecture=_claim_labels(claims, "g"), letter="g",
                                                 vector=True)},
        {"title": "Non-potential generalized forces", **_equation(
            bold("f", subscript="q", superscript="np"), f, label=GENERAL["f_np"],
            lecture=_claim_labels(claims, "f_np"), letter="f", superscript="np", vector=True)},
    ]
    if abbreviations:
        quantities.append({"title": "where", "label": "", "lecture": "", "math": broken(
            [(body(name), "<mo>=</mo>", _terms(expr)) for name, expr in abbreviations]),
            "note": "Common subexpressions of the entries wider than a line, named (sympy.cse)."})
    eom = []
    by_row = {}
    for c in claims:
        if c.quantity == "eom":
            for k in (range(len(q)) if c.index is None else [c.index[0]]):
                by_row.setdefault(k, []).append(c.equation)
    Cqd = C * qd
    for k in range(len(q)):
        # the terms of M q̈, C q̇ and g, in that order, each with its own sign (:func:`signed_terms`)
        terms = [t for t in [M[k, j] * qdd[j] for j in range(len(q))] + [*sp.Add.make_args(budget.simplify(Cqd[k])),
                                                                          *sp.Add.make_args(g[k])] if t != 0]
        lhs = sp.Add(*terms, evaluate=False) if terms else sp.S.Zero
        if _too_large(lhs) or _too_large(f[k]):
            eom.append({"math": "", "label": GENERAL["eom"], "lecture": ", ".join(by_row.get(k, [])),
                        "note": f"row {k + 1}: {sp.count_ops(lhs) + sp.count_ops(f[k])} operations, too large to print"})
            continue
        wide = terms and sum(map(width, terms)) + width(f[k]) > LINE_WIDTH   # broken after its terms, "= f" last
        eom.append({"math": broken([("", "", terms), ("", "<mo>=</mo>", _terms(f[k]))]) if wide else
                    math(signed_terms(terms) if terms else body(lhs), "<mo>=</mo>", body(f[k])),
                    "label": GENERAL["eom"],
                    "lecture": ", ".join(by_row.get(k, [])), "note": ""})
    return {"quantities": quantities, "eom": eom, "notes": []}


# --------------------------------------------------------------------------- claims: printed beside derived
def _claim_lhs(claim) -> str:
    """The left-hand side the printed expression is the value of (none for residuals and parameters)."""
    kind, _, point = claim.quantity.partition(":")
    index = "".join(str(i + 1) for i in claim.index) if claim.index else ""
    lhs = {"M": bold("M", subscript=index), "C": bold("C", subscript=index),
           "g": bold("g", subscript=index), "f_np": bold("f", subscript=index, superscript="np"),
           "K": bold("K", subscript=index),
           "T": "<mi>T</mi>", "V": "<mi>V</mi>",
           "Cqd": f'<mrow>{bold("C")}{bold_argument("qd")}</mrow>'
                  + (f"<msub><mrow/><mi>{index}</mi></msub>" if index else ""),
           "position": bold("p", subscript=point)}.get(kind)
    if kind == "constraint":  # a constraint force by its lecture name (f_S, tau_1)
        lhs = body(sp.Symbol(point, real=True))
    if lhs is None and point:  # the per-point and per-body kinds: symbol, frame 0 (or the given frame), the body
        frame, _, link = point.rpartition("/")
        letter = {"v": "v", "a": "a", "R": "R", "S": "S", "omega": "ω", "I_0": "I", "J_v": "J", "J_omega": "J",
                  "force": "f", "f_np": "f"}.get(kind)
        if letter is not None:
            below = {"J_v": "v", "J_omega": "ω", "f_np": "q"}.get(kind, frame or "0")
            lhs = bold(letter, subscript=below, superscript=link)
            if index:
                lhs = f"<msub>{lhs}<mi>{index}</mi></msub>"
        elif kind in ("T_t", "T_r", "V"):
            lhs = f"<msubsup><mi>{kind[0]}</mi><mi>{kind[2:]}</mi><mi>{escape(link)}</mi></msubsup>" if "_" in kind \
                else f"<msup><mi>V</mi><mi>{escape(link)}</mi></msup>"
    if lhs is None and kind == "L":
        lhs = "<mi>L</mi>"
    if lhs is None and kind in ("dL_dqd", "dL_dq", "ddt_dL_dqd"):
        q = f"<mi>{escape(point)}</mi>"
        by = f'<mover accent="true">{q}<mo>\u02d9</mo></mover>' if kind != "dL_dq" else q
        lhs = f"<mfrac><mrow><mo>∂</mo><mi>L</mi></mrow><mrow><mo>∂</mo>{by}</mrow></mfrac>"
        if kind == "ddt_dL_dqd":
            lhs = f"<mfrac><mi>d</mi><mrow><mi>d</mi><mi>t</mi></mrow></mfrac>{lhs}"
    return lhs or ""


def claim_math(claim, expr, named: bool = False) -> str:
    """A printed equation, or the derived quantity it is compared with, as MathML (:func:`wide_math`): ``lhs = expr``
    with the claim's left-hand side, an equation of motion as its residuals ``… = 0``. ``named``: a derived form,
    never a printed one."""
    return wide_math(expr, _claim_lhs(claim), claim.quantity.split(":")[0] in ("eom", "equilibrium"), named)


def wide_math(expr, lhs: str = "", residual: bool = False, named: bool = False) -> str:
    """``lhs = expr`` (MathML of ``lhs``; ``residual``: ``expr = 0``) as one ``<math>`` element, broken as the
    derived equations are where wider than a line: a matrix entry by entry (every entry: a printed one is read entry
    by entry against the derived one), a sum after its terms. ``named``: the common subexpressions of an entry that
    would scroll named, ``where ξ₁ = …`` after it (:func:`abbreviated`). A matrix without a left-hand side (a printed
    Jacobian) is written column by column. The system pages' printed equations and the errata sheet are set by it."""
    expr = sp.Matrix(expr) if isinstance(expr, (sp.MatrixBase, list, tuple)) else sp.sympify(expr)
    if isinstance(expr, sp.MatrixBase) and expr.shape == (1, 1):
        expr = expr[0, 0]
    if _too_large(expr):
        return math("<mo>…</mo>", "<mo>=</mo>", "<mn>0</mn>") if residual else \
            math(lhs, "<mo>=</mo>", "<mo>…</mo>") if lhs else math("<mo>…</mo>")
    matrix = isinstance(expr, sp.MatrixBase)
    if matrix and not lhs and not residual:  # a matrix without a name (a printed Jacobian): column by column
        if not _wide(expr):
            return math(body(expr))
        return broken([(f"<mtext>column {j + 1}</mtext>", "<mo>:</mo>", [expr[:, j]]) for j in range(expr.cols)])
    where = []
    if named:
        (entries,), where = abbreviated([expr if matrix else sp.Matrix([expr])])
        expr = entries if matrix else entries[0, 0]
    if not where and not (_wide(expr) if matrix else width(expr) > LINE_WIDTH):
        if residual:
            return math(body(expr), "<mo>=</mo>", "<mn>0</mn>")
        return math(lhs, "<mo>=</mo>", body(expr)) if lhs else math(body(expr))
    if residual:  # each residual after its terms, "= 0" last
        written = [part for row in (list(expr) if matrix else [expr])
                   for part in (("", "", _terms(row)), ("", "<mo>=</mo>", [sp.S.Zero]))]
    elif matrix:
        def entry(index):
            return f"<msub><mrow>{lhs}</mrow><mi>{index}</mi></msub>"
        written = _entries("", expr, vector=expr.cols == 1, name=entry)[0]
    else:
        written = [(lhs, "<mo>=</mo>" if lhs else "", _terms(expr))]
    return broken(written + [(body(name), "<mo>=</mo>", _terms(value)) for name, value in where])


def entry_by_entry(letter: str, matrix, superscript: str = "") -> str:
    """A matrix too wide for a table's cell as the derived equations write one wider than a line: ``letter`` with
    its indices and ``superscript`` entry by entry, a symmetric one on and above its diagonal (:func:`_entries`),
    each broken after its terms, common subexpressions named after them (:func:`abbreviated`). The bodies' table
    sets a body's inertia tensor so (the tower crane's tower, by Steiner's theorem from its solids: 477 characters
    wide in one row; the rotating body's three bars and point mass: 692)."""
    (matrix,), where = abbreviated([sp.Matrix(matrix)])
    written, _ = _entries(letter, matrix, superscript)
    return broken(written + [(body(name), "<mo>=</mo>", _terms(value)) for name, value in where])


def claim_equations(system, claims, budget: Budget | None = None) -> list[dict]:
    """Per printed equation: ``{"equation", "quantity", "description", "printed", "derived", "note"}`` with the
    printed form and the derived quantity it is compared with as MathML (the derived one simplified within the
    budget; an equation of motion both as residuals ``… = 0``)."""
    from harness.compare.claims import _derived
    from harness.derivation.derive import is_per_body

    budget = budget or Budget()
    per_body = is_per_body(system)
    out = []
    for claim in claims:
        row = {"equation": claim.equation, "quantity": claim.quantity,
               "description": f"{claim.description} ({claim.where})" if claim.where else claim.description,
               "printed": claim_math(claim, claim.printed), "derived": "", "note": ""}
        if per_body:
            row["note"] = "derived per body as an expression graph: too large to print"
            out.append(row)
            continue
        try:
            derived = _derived(system, claim)
            row["derived"] = claim_math(claim, budget.simplify(derived), named=True)
        except Exception as exc:  # noqa: BLE001 - a claim whose quantity cannot be derived keeps its printed form
            row["note"] = f"derived form not available: {type(exc).__name__}: {exc}"
        out.append(row)
    return out


# --------------------------------------------------------------------------- one system's page, cached
def _cache_key(system, claims) -> str:
    import hashlib
    from pathlib import Path

    digest = hashlib.sha256(system.fingerprint().encode())
    for claim in claims:
        digest.update(sp.srepr((claim.equation, claim.quantity, claim.printed, claim.index)).encode())
    here = Path(__file__).parent
    for name in ("equations.py", "mathml.py"):
        digest.update((here / name).read_bytes())
    return f"{system.name}-{digest.hexdigest()[:20]}"


def _page_path(system, claims):
    from harness.derivation.cache import cache_dir

    return cache_dir().parent / "equations" / f"{_cache_key(system, claims)}.json"


def cached_page_equations(system, claims) -> dict | None:
    """What :func:`page_equations` would return, if the cache holds it (else None)."""
    import json

    try:
        return json.loads(_page_path(system, claims).read_text())
    except (OSError, ValueError):
        return None


def page_equations(system, claims, use_cache: bool = True) -> dict:
    """``{"equations": derived_equations(...), "claims": claim_equations(...), "notes": [...]}`` of one system,
    cached on disk (next to the derivation cache) by the model's fingerprint, its claims and this code."""
    import json

    from harness.derivation.cache import once
    from harness.io import atomic_write_text

    if not use_cache:
        return _computed_page_equations(system, claims)
    if (page := cached_page_equations(system, claims)) is not None:
        return page
    with once(f"equations-{_cache_key(system, claims)}"):  # another process computing it: read what it stored
        if (page := cached_page_equations(system, claims)) is not None:
            return page
        out = _computed_page_equations(system, claims)
        try:
            atomic_write_text(_page_path(system, claims), json.dumps(out))
        except OSError:
            pass  # a read-only cache folder costs the speed-up only
    return out


def _computed_page_equations(system, claims) -> dict:
    budget = Budget()
    out = {"equations": derived_equations(system, claims, budget), "claims": claim_equations(system, claims, budget)}
    out["notes"] = budget.notes()
    return out


def _page_equations_of(job: tuple) -> dict:
    catalogue, name = job
    return page_equations(catalogue.get(name), catalogue.claims(name))


class PageEquationsAhead:
    """:func:`page_equations` of the systems ``names``: those the cache holds read once here, the others started in
    ``jobs`` processes (a cold cache costs up to 11 s of SymPy a system, 67 s for the catalogue, measured with the
    derivations kept) while the caller builds the rest of the pages. ``self(name)`` returns one system's, waiting for
    it if it is being computed (computed in this process when it was not started, or its process failed, so that an
    error is raised where the page is built); ``close()`` ends the processes. What is simplified does not depend on
    where (:data:`ENTRY_SECONDS`)."""

    def __init__(self, catalogue, names: list[str], jobs: int):
        from concurrent.futures import ProcessPoolExecutor
        from multiprocessing import get_context

        self.catalogue, self.futures, self.pool, self.read = catalogue, {}, None, {}
        for name in names:
            try:
                page = cached_page_equations(catalogue.get(name), catalogue.claims(name))
            except Exception:  # noqa: BLE001 - a system that does not load: its page says so, when it is built
                continue
            if page is not None:
                self.read[name] = page
        missing = [n for n in names if n not in self.read]
        if jobs > 1 and len(missing) > 1:
            try:
                self.pool = ProcessPoolExecutor(min(jobs, len(missing)), mp_context=get_context("spawn"))
                self.futures = {n: self.pool.submit(_page_equations_of, (catalogue, n)) for n in missing}
            except Exception:  # noqa: BLE001 - no processes: each page computes its own
                self.close()

    def __call__(self, name: str) -> dict:
        if name in self.read:
            return self.read.pop(name)
        future = self.futures.pop(name, None)
        if future is not None:
            try:
                return future.result()
            except Exception:  # noqa: BLE001 - this process computes it (and raises, if it must)
                pass
        return page_equations(self.catalogue.get(name), self.catalogue.claims(name))

    def close(self) -> None:
        if self.pool is not None:
            self.pool.shutdown(cancel_futures=True)
        self.pool, self.futures = None, {}
