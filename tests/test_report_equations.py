"""The equations of a system page as mathematics (harness/report/equations.py) and the model section written for
a reader (harness/report/model_text.py): well-formed MathML in the lecture's letters, the lecture's equation
numbers, the simplification budget, no Python reprs."""

from __future__ import annotations

import re
import time
from xml.dom.minidom import parseString

import pytest
import sympy as sp

import models
from harness.report import equations, model_text


def _parses(fragment: str) -> None:
    parseString(fragment)


def test_derived_equations_of_the_cart_pendulum():
    system, claims = models.get("cart_pendulum"), models.claims("cart_pendulum")
    page = equations.page_equations(system, claims, use_cache=False)
    quantities = page["equations"]["quantities"]
    assert [q["label"] for q in quantities] == ["(5.21)", "(5.95), (5.97)", "(5.96)", "(5.60), (5.73)"]
    for entry in quantities + page["equations"]["eom"]:
        _parses(entry["math"])
    eom = page["equations"]["eom"]
    assert [e["lecture"] for e in eom] == ["(5.92a)", "(5.92b)"]     # the claims' equation numbers, per row
    assert "&#966;" in eom[1]["math"] and "<mover" in eom[1]["math"]  # φ and its accents
    rows = page["claims"]
    assert [r["equation"] for r in rows] == [c.equation for c in claims]
    for r in rows:
        _parses(r["printed"])
        _parses(r["derived"])


def test_an_entry_over_the_cap_is_shown_as_derived():
    """The CPU timer fires at the kernel's next tick (a few ms of CPU time), so the entry must take longer than that
    whatever ran before in this worker: sin² + cos² alone took 16–24 ms here, but once a fresh clone's run found it
    done in less (SymPy's cache holding its parts from an earlier test) and the budget never tripped. An entry of
    140–200 ms, in symbols of its own, with SymPy's cache cleared, trips it."""
    x, y = sp.symbols("x_over_cap y_over_cap")
    expr = sp.expand((sp.sin(x) + sp.cos(y)) ** 6) + sp.cos(x) ** 2 * sp.sin(y) ** 2
    sp.core.cache.clear_cache()
    budget = equations.Budget(seconds=1e-6)  # trips at the first tick after a microsecond of CPU time
    assert budget.simplify(expr) == expr and budget.timed_out == 1
    assert "took more than 1e-06 s of CPU time" in budget.notes()[0]
    assert equations.Budget().simplify(sp.sin(x) ** 2 + sp.cos(x) ** 2) == 1


def test_multiple_angles_are_expanded_before_trigsimp():
    """The governor's M₂₂ is derived as a polynomial in sin α and sin 3α; it reads 2 l² m, as (A.66b) prints it."""
    from harness.derivation.derive import derive

    system = models.get("governor")
    M = equations.Budget().simplify(derive(system).M)
    l, m = (sp.Symbol(n, real=True, positive=True) for n in ("l", "m"))
    assert M[1, 1].equals(2 * l**2 * m) and sp.count_ops(M[1, 1]) <= 3


def test_what_a_page_shows_simplified_does_not_depend_on_the_machine_s_speed():
    """A slower machine (here: each entry's simplification made 3x slower by a CPU hog on the same thread) shows
    the same entries simplified: no budget is shared by a system's entries, and the cap of one is far above any.
    The governor's entries take 1.4 s together: under the former budget of 2 s per system the slow run showed
    its last entries unsimplified."""
    system, claims = models.get("governor"), models.claims("governor")
    fast = equations.page_equations(system, claims, use_cache=False)
    simplify = equations.Budget.simplify

    def slowly(self, expr):
        if isinstance(expr, sp.MatrixBase):  # its entries come back here one by one
            return simplify(self, expr)
        start = time.process_time()
        out = simplify(self, expr)
        spent = time.process_time() - start
        while time.process_time() - start < 3 * spent:
            pass
        return out

    equations.Budget.simplify = slowly
    try:
        slow = equations.page_equations(system, claims, use_cache=False)
    finally:
        equations.Budget.simplify = simplify
    assert slow == fast


def test_cpu_budget_interrupts_a_long_computation():
    """harness.limits.cpu_budget counts this process's CPU time, the budget of every symbolic simplification."""
    from harness.limits import OutOfTime, cpu_budget

    start = time.process_time()
    try:
        with cpu_budget(0.05):
            while True:
                pass
    except OutOfTime:
        pass
    assert time.process_time() - start < 2


def test_model_section_has_no_reprs():
    system = models.get("planar_manipulator")
    html = model_text.docstring_html(system.doc)
    assert "``" not in html and "<math" in html
    forces = model_text.force_rows(system)
    assert forces and all("Point(" not in f["sentence"] and "<math" in f["sentence"] for f in forces)
    for row in model_text.link_rows(system) + model_text.joint_rows(system):
        for value in row.values():
            if isinstance(value, str) and value.startswith("<math"):
                _parses(value)


def test_no_model_docstring_shows_a_cross_reference_role_on_its_page():
    """A docstring's Sphinx cross-reference (``:func:`harness.files.from_urdf.from_urdf```) is a name in the code:
    its page sets the name as code. lightweight_robot's page had shown three such roles as typed. A literal is a
    symbol where its base is a letter or a Greek letter's name, code where it is a word: drive_train's page had set
    ``drive_train_armature`` as a symbol "drive" with the subscripts "train, armature"."""
    html = model_text.docstring_html("Built by :func:`harness.files.from_urdf.from_urdf` (why: :mod:`~harness.files`),"
                                     " with ``phi_1``, ``I_zz^{sK}``, ``Delta_z_2``, ``drive_train`` and ``mj_applyFT``.")
    assert "<code>harness.files.from_urdf.from_urdf</code>" in html and "<code>harness.files</code>" in html
    assert "<msub><mi>&#966;</mi><mi>1</mi></msub>" in html   # a literal symbol name is still set as the symbol
    assert html.count("<math") == 3 and "<code>drive_train</code>" in html and "<code>mj_applyFT</code>" in html
    for name in models.names():
        page = model_text.docstring_html(models.get(name).doc or "")
        assert not re.search(r":\w+:`", page), (name, re.search(r".{40}:\w+:`.{40}", page))


def test_large_per_body_derivation_is_not_printed(monkeypatch):
    import harness.derivation.derive as derive

    monkeypatch.setattr(derive, "is_per_body", lambda system: True)  # as the 7-DoF arm (slow to load here)
    system = models.get("pendulum")
    page = equations.derived_equations(system, models.claims("pendulum"))
    assert not page["quantities"] and "too large" in page["notes"][0]
    assert all("too large" in r["note"] for r in equations.claim_equations(system, models.claims("pendulum")))


def test_cpu_budget_never_raises_inside_a_weak_reference_callback():
    """A budget that runs out while the garbage collector runs a weak reference's callback waits for the next tick
    (an exception raised there would be printed as 'Exception ignored' and lost)."""
    import sys

    from harness.limits import _in_collector_callback

    namespace: dict = {}
    exec(compile("def _remove(sys):\n    return sys._getframe()\n", "/usr/lib/python3.11/_weakrefset.py", "exec"),
         namespace)
    assert _in_collector_callback(namespace["_remove"](sys))
    assert not _in_collector_callback(sys._getframe())


def test_equations_simplified_ahead_in_other_processes_are_the_pages_own(monkeypatch, tmp_path):
    """A cold cache's equations computed in two processes while the pages are built: each system's page gets what
    it would have computed itself, and the cache then holds it (the next report reads it, once)."""
    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path / "derivations"))
    names = ["pendulum", "pulley"]
    ahead = equations.PageEquationsAhead(models.CATALOGUE, names, jobs=2)
    assert sorted(ahead.futures) == names and ahead.pool is not None
    try:
        for name in names:
            system, claims = models.CATALOGUE.get(name), models.CATALOGUE.claims(name)
            assert ahead(name) == equations.page_equations(system, claims, use_cache=False)
            assert equations.cached_page_equations(system, claims) is not None
    finally:
        ahead.close()
    again = equations.PageEquationsAhead(models.CATALOGUE, names, jobs=2)
    assert again.futures == {} and again.pool is None and sorted(again.read) == names  # each read once
    assert again("pulley") == equations.page_equations(models.CATALOGUE.get("pulley"),
                                                       models.CATALOGUE.claims("pulley"), use_cache=False)


def _tokens(fragment: str) -> str:
    import re

    return " ".join(re.sub(r"<[^>]+>", " ", fragment).replace("&#8290;", "").replace("&#8722;", "−").split())


def test_a_sum_reads_each_term_with_its_own_sign_in_the_lecture_order():
    """``signed_terms``: SymPy's printer wrote ``a + (−c x + c y)`` as ``a − c x − c y`` (a minus pulled out of the
    nested sum, its negation unbracketed); the equations of motion of 5 systems showed a wrong sign so. The terms
    keep their order (M q̈, C q̇, g) and each its sign; torsion_spring_body's spring term reads ``+ c_F φ``."""
    from harness.report.mathml import body, signed_terms

    a, c, x, y = sp.symbols("a c x y")
    nested = sp.Add(a, -c * x + c * y, evaluate=False)
    assert _tokens(body(nested)) == "a − ( c x − c y )"      # SymPy's own reading, "a − c x − c y", lost c y's sign
    assert _tokens(signed_terms([a, -c * x, c * y])) == "a − c x + c y"
    assert _tokens(signed_terms([-a, c * x])) == "− a + c x"
    page = equations.page_equations(models.get("torsion_spring_body"), models.claims("torsion_spring_body"),
                                    use_cache=False)
    row = page["equations"]["eom"][0]["math"]
    _parses(row)
    assert "+ c F &#966; − L s g m" in _tokens(row)           # M q̈, then g: + c_F φ − L_s g m (…)


def test_a_matrix_wider_than_a_line_is_written_entry_by_entry_each_broken_after_its_terms():
    """A matrix or an equation of motion wider than a line (``LINE_WIDTH``, by ``width``: a stacked fraction as wide
    as its wider part) scrolled sideways on its page, and with it its equation numbers: the tower crane's M is a
    5 × 5 matrix whose M₁₁ has 23 terms. Such a matrix is written entry by entry (M by its upper triangle, being
    symmetric), each entry broken after its terms, a later line beginning with its term's sign; a narrow one stays a
    matrix."""
    from harness.report.mathml import LINE_WIDTH, broken, lines, pieces, width

    x, y, m = sp.symbols("x y m")
    assert width(x / (x + y)) == width(x + y) + 1 < len(str(x / (x + y)))   # stacked: its wider part
    terms = [m * sp.sin(x) ** k for k in range(1, 30)]
    grouped, each = lines(terms), pieces(terms)
    assert [t for line in grouped for t in line] == [text for _, text in each] and len(grouped) > 1
    widths = dict((text, w) for w, text in each)
    assert all(len(line) == 1 or sum(widths[t] for t in line) <= LINE_WIDTH for line in grouped)
    text = broken([("<mi>M</mi>", "<mo>=</mo>", [x, *(-t for t in terms)])])
    _parses(text)
    assert text.count("<mtr>") == len(lines([x, *terms]))
    assert all(row.split('text-align:left">', 1)[1].startswith("<mrow><mo>&#8722;</mo>")
               for row in text.split("<mtr>")[2:])                  # each later line after its own sign
    # a product wider than a line with a sum among its factors (a Christoffel entry grouped by a rate) is opened:
    # "y (" ends its first line, the sum goes on over lines, ")" ends the last
    opened = broken([("<mi>C</mi>", "<mo>=</mo>", [y * sp.Add(*terms)])])
    _parses(opened)
    rows = opened.split("<mtr>")[1:]
    assert len(rows) > 1 and "<mi>y</mi><mo>(</mo>" in rows[0] and rows[-1].count("<mo>)</mo></mrow></mtd>") == 1

    wide = sp.Matrix([[sum(terms), m * x], [m * x, m]])
    entry = equations._equation("<mi>M</mi>", wide, letter="M")
    _parses(entry["math"])
    assert "text-align:left" in entry["math"] and "M is symmetric" in entry["note"]
    assert [s for s in ("11", "12", "21", "22") if f"<mi>{s}</mi>" in entry["math"]] == ["11", "12", "22"]
    narrow = equations._equation("<mi>M</mi>", sp.Matrix([[m, m * x], [m * x, m]]), letter="M")
    assert "text-align:left" not in narrow["math"] and "<mi>11</mi>" not in narrow["math"] and narrow["note"] == ""
    vector = equations._equation("<mi>g</mi>", sp.Matrix([sum(terms), m]), letter="g", vector=True)
    assert "<mi>1</mi>" in vector["math"] and "<mi>2</mi>" in vector["math"] and vector["note"] == ""


def test_a_closing_bracket_never_begins_a_line_alone():
    """An opened sum's ``)`` is set with its last term: where that term filled its line, the bracket had been put on
    a line of its own (the toggle press's ξ₄ = L₁ cos q + L₂/2 (…), its ``)`` alone under the sum). Each line of
    the sum, nested or raised to a power, begins with a term."""
    from harness.report.mathml import LINE_WIDTH, lines, pieces

    q, L = sp.symbols("q L")
    xi = [sp.Symbol(f"xi_{k}") for k in range(1, 9)]
    inner = sum(x * sp.cos(q + k) for k, x in enumerate(xi))
    for term in (L / 2 * inner, L * (inner + L * sp.sin(q) * sp.Add(*xi)), (inner + L) ** 2):
        for width_ in (LINE_WIDTH, 40, 25):
            for line in lines([L * sp.cos(q), term], width_):
                assert not line[0].startswith(("<mo>)", "<msup><mo>)")), line[0]
    closing = [text for _, text in pieces([L / 2 * inner])][-1]
    assert closing.endswith("<mo>)</mo>") and "&#958;" in closing   # ξ₈ cos(q + 7))


def test_common_subexpressions_of_entries_that_would_scroll_are_named_and_stand_for_them_exactly():
    """The trebuchet's map ``θ_sling = −θ + arccos(L (sin θ₀ − sin θ) / r)`` and its derivative recur in every entry of
    its M and C: ``M₁₁`` printed 616 characters wide and ``C₁₁`` 2043, scrolling sideways in Chromium. The
    entries that broken after their terms would still scroll have their common subexpressions named ``ξ₁, ξ₂, …``
    (``where ξ₁ = …``): every piece then fits a line, and the names put back give the derived entries exactly. A
    system whose entries fit (the tower crane's long sums, broken after their terms) has no names."""
    from harness.derivation.derive import derive
    from harness.report.mathml import LINE_WIDTH, pieces, width

    system = models.get("trebuchet")
    d = derive(system)
    budget = equations.Budget()
    derived = [budget.simplify(x) for x in (d.M, d.C, d.g, d.f_np)]
    assert width(derived[0][0, 0]) > 600 and width(derived[1][0, 0]) > 2000
    named, where = equations.abbreviated(derived)
    assert 0 < len(where) <= 10 and all(name.name.startswith("xi_") for name, _ in where)
    assert all(w <= LINE_WIDTH for m in named for entry in m for w, _ in pieces(equations._terms(entry)))
    assert width(named[0][0, 0]) <= LINE_WIDTH
    for name, expr in reversed(where):   # a later name may use an earlier one: put back from the last
        named = [m.xreplace({name: expr}) for m in named]
    assert all(sp.simplify(a - b) == sp.zeros(*a.shape) for a, b in zip(named, derived))
    page = equations.derived_equations(system)
    assert page["quantities"][-1]["title"] == "where" and "&#958;" in page["quantities"][0]["math"]   # ξ
    _parses(page["quantities"][-1]["math"])
    crane = models.get("tower_crane")
    d = derive(crane)
    assert equations.abbreviated([budget.simplify(x) for x in (d.M, d.C)])[1] == []


def test_a_printed_equation_wider_than_a_line_is_broken_as_the_derived_ones_are():
    """The printed equations beside their derived forms were each one line: the tower crane's printed M (5.37)+
    (5.39)+(5.41) was 7617 px wide in Chromium at 1300 px, its T 30216 px; 25 rows of the catalogue's pages scrolled,
    1 does now (a Jacobian printed as a matrix without a name). A wide printed or derived matrix is written entry by
    entry, every entry (the printed one is read entry by entry against the derived one), a wide sum broken after its
    terms, a residual with ``= 0`` last; a derived form that would scroll has its common subexpressions named (the
    trebuchet's projectile velocity (A.180): its sling angle and that angle's derivative)."""
    system, claims = models.get("tower_crane"), models.claims("tower_crane")
    rows = {r["equation"]: r for r in equations.claim_equations(system, claims)}
    M = rows["(5.37)+(5.39)+(5.41)"]
    for form in (M["printed"], M["derived"]):
        _parses(form)
        assert "text-align:left" in form and form.count("<msub><mrow>") == 25      # M_11 … M_55, all of them
    x, m = sp.symbols("x m")
    residual = sp.Add(*(m * sp.sin(x) ** k for k in range(1, 30)))
    from harness.modeling import Claim

    rows = {r["equation"]: r for r in equations.claim_equations(models.get("trebuchet"), models.claims("trebuchet"))}
    assert "&#958;" not in rows["(A.180)"]["printed"] and "&#958;" in rows["(A.180)"]["derived"]   # ξ: derived only
    text = equations.claim_math(Claim("(9.9)", "eom", residual), residual)
    _parses(text)
    assert text.count("<mtr>") > 2 and text.endswith('<mtd><mo>=</mo></mtd><mtd style="text-align:left"><mrow><mn>0</mn>'
                                                    "</mrow></mtd></mtr></mtable></math>")


def test_a_long_sum_that_occurs_once_is_named_when_nothing_else_makes_it_fit():
    """The errata sheet's corrected (5.109) of the planar manipulator had ``ξ₃ = d_e / (…)`` with a denominator of 40
    terms on one line (2010 px at 1300): a sum that occurs once is no common subexpression. What still does not fit,
    opened level after level, has its widest sum named until it fits; the names put back give it exactly."""
    from harness.report.mathml import LINE_WIDTH, pieces

    x, y, d = sp.symbols("x y d")
    denominator = sp.Add(*(sp.sin(x) ** k * sp.cos(y) ** (k % 3) for k in range(1, 40)))
    entry = d / denominator + sp.cos(x)
    (named,), where = equations.abbreviated([sp.Matrix([entry])])
    assert where and all(w <= LINE_WIDTH for w, _ in pieces(equations._terms(named[0])))
    for name, value in reversed(where):
        named = named.xreplace({name: value})
    assert sp.simplify(named[0] - entry) == 0


# one worker for the tests that read every page's equations: on a cold cache the first computes them, the others
# read them (not each worker all of them again)
@pytest.mark.xdist_group("page-equations")
def test_every_pages_equations_of_motion_read_back_as_derived():
    """Each system page's M, C, g, f_np (as a matrix or entry by entry) and equations of motion, read as a reader
    reads the page (tests/mathml_reading.py: every line, bracket and sign, the named subexpressions ``where ξ = …``
    substituted), are the derived ones, ``M q̈ + C q̇ + g = f_np``, at random values. A long term opened over lines
    whose other factor is a sum was set with that sum unbracketed before the opened one: rotating_body's first row
    ``(…)² (2 b d l₂ ρ + … + m_m)`` read ``2 b d l₂ ρ + … + m_m (…)²``, tower_crane's M₁₅ and spring_mass_damper's
    page alike."""
    import random

    from harness.derivation.derive import derive, is_per_body
    from tests.mathml_reading import READ_TOLERANCE, Reader

    rows = 0
    for name, system in models.CATALOGUE.systems().items():
        if is_per_body(system):
            continue
        page = equations.page_equations(system, models.CATALOGUE.claims(name))["equations"]
        reader = Reader()
        where = {}
        for q in page["quantities"]:
            if q["title"] == "where":
                where = reader.definitions(q["math"])
        d = derive(system)
        qdd = sp.Matrix([c.accel for c in system.coordinates])
        residual = d.M * qdd + d.C * sp.Matrix(system.qd) + d.g - d.f_np
        rng = random.Random(name)
        values = {s: rng.uniform(0.3, 1.3) for s in sorted(residual.free_symbols, key=str)}
        assert len({reader.symbol(s) for s in values}) == len(values), f"{name}: two symbols set alike"

        def error(read, expr):
            return reader.error(read, expr, values, where)

        for q, derived, letter, superscript, vector in zip(page["quantities"], (d.M, d.C, d.g, d.f_np), "MCgf",
                                                           ("", "", "", "np"), (False, False, True, True)):
            if not q["math"]:
                continue
            if q["math"].startswith('<math xmlns="http://www.w3.org/1998/Math/MathML" display="block"><mtable>'):
                entries = reader.definitions(q["math"])   # entry by entry: M₁₁ = …, the upper triangle of M
                for i in range(derived.rows):
                    for j in range(derived.cols):
                        index = str(i + 1) if vector else f"{i + 1}{j + 1}"
                        left = sp.Symbol(reader.text(equations.bold(letter, subscript=index, superscript=superscript)))
                        if left in entries:
                            assert error(entries[left], derived[i, j]) <= READ_TOLERANCE, (name, letter, index)
                            rows += 1
                continue
            shown = reader.claim(q["math"], derived.shape)[0]   # M(q) = […]: its left side not read
            assert all(error(a, b) <= READ_TOLERANCE for a, b in zip(shown, derived)), (name, letter)
            rows += 1
        for k, row in enumerate(page["eom"]):
            if not row["math"]:
                continue   # too large to print
            assert error(reader.equation(row["math"]), residual[k]) <= READ_TOLERANCE, (name, k + 1)
            rows += 1
    assert rows >= 200, rows   # 242: 57 rows of equations of motion, 185 entries or matrices


# one worker for the tests that read every page's equations: on a cold cache the first computes them, the others
# read them (not each worker all of them again)
@pytest.mark.xdist_group("page-equations")
def test_every_pages_printed_equations_and_their_derived_forms_read_back_as_they_are():
    """Each printed equation on a system page, and the derived form beside it (its named subexpressions
    substituted), read as a reader reads the page (tests/mathml_reading.py, ``Reader.claim``: in a line, entry by
    entry or row by row), is the claim's printed expression and the derived quantity at random values, entry by
    entry: the transcription the page shows is the one the harness checks."""
    from harness.compare.claims import _derived
    from harness.derivation.derive import is_per_body
    from harness.modeling.claims import as_matrix
    from tests.mathml_reading import misread

    read = matrices = 0
    for name, system in models.CATALOGUE.systems().items():
        if is_per_body(system):
            continue
        claims = models.CATALOGUE.claims(name)
        for claim, row in zip(claims, equations.page_equations(system, claims)["claims"]):
            residual = claim.quantity.split(":")[0] in ("eom", "equilibrium")
            derived = as_matrix(_derived(system, claim)) if row["derived"] else None
            for column, expr in (("printed", as_matrix(claim.printed)), ("derived", derived)):
                if expr is not None:
                    assert not misread(row[column], expr, residual, f"{name} {claim.equation}"), (
                        name, claim.equation, column)
                    read += 1
                    matrices += expr.shape != (1, 1)
    assert read >= 450 and matrices >= 200, (read, matrices)   # 610 forms, 263 of them matrices
