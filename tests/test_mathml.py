"""The report's MathML printer: the lecture's symbol rule (harness/report/mathml.py) and well-formed output."""

from xml.dom.minidom import parseString

import sympy as sp

from harness.report.mathml import equation, lecture_parts, mathml


def test_symbol_rule():
    assert lecture_parts("phi_1_dot") == ("phi", ("1",), (), "\u02d9")
    assert lecture_parts("s_ddot") == ("s", (), (), "\u00a8")
    assert lecture_parts("m_S") == ("m", ("S",), (), None)
    assert lecture_parts("I_zz^S") == ("I", ("zz",), ("S",), None)


def test_output_is_well_formed_and_uses_the_lecture_letters():
    phi_dot, m = sp.symbols("phi_1_dot m_S")
    text = mathml(sp.Matrix([[m * phi_dot**2, 0]]), label="(5.92b)")
    dom = parseString(text)
    assert dom.documentElement.tagName == "math"
    letters = "".join(node.firstChild.data for node in dom.getElementsByTagName("mi"))
    assert "\u03c6" in letters and "(5.92b)" in text and "<mover" in text
    parseString(equation(sp.Symbol("M_11"), m, display=False))


def test_override_renders_a_name_the_rule_cannot():
    text = mathml(sp.Symbol("I_zz_S"), names={"I_zz_S": ("I", ("zz",), ("S",))})
    assert "<msubsup>" in text


def test_a_sum_negated_or_nested_keeps_its_parentheses():
    """SymPy's printer takes the minus sign out of ``−(a + b)`` (a product of −1 and a sum, left so by
    ``factor_terms``) and of a nested sum ``c − (a + b)``, and prints the sum without its parentheses: ``− a + b``.
    The corrected Jacobian of (4.69) on the errata sheet read so, with the wrong sign on its second term."""
    import re

    from harness.report.mathml import body

    a, b, c = sp.symbols("a b c")

    def read(expr):
        return " ".join(re.sub(r"<[^>]+>", " ", body(expr)).replace("&#8722;", "−").split())
    assert read(sp.Mul(-1, a + b, evaluate=False)) == "− ( a + b )"
    assert read(sp.Add(c, sp.Mul(-1, a + b, evaluate=False), evaluate=False)) == "c − ( a + b )"
    assert read(sp.Add(c, sp.Add(-a, b, evaluate=False), evaluate=False)) == "c − ( a − b )"
    assert read(sp.factor_terms(-a * sp.sin(b) - c * sp.sin(a + b))).startswith("− (")
    assert read(c - a * b) == "− a &#8290; b + c" and read(-a + c * (a + b)) == "− a + c &#8290; ( a + b )"


def test_minus_signs_powers_of_sines_and_bold_quantities_as_the_lecture_sets_them():
    """A minus sign is −, never the hyphen-minus Chromium sets as a short dash: of a difference, a sign, a negative
    number, an exponent, a term broken onto a line of its own; a power of sin, cos or tan carries the exponent on the
    name, sin²(α), as (2.18) and (5.76) print it, and a function's name in a product follows a thin space (``m sin``,
    not ``msin``); 𝐌(𝐪) is bold and upright (Unicode's bold letters: Chromium sets ``mathvariant="bold"`` italic),
    its brackets as high as the line."""
    from harness.report.mathml import body, bold, pieces, signed_terms

    a, b = sp.symbols("a b")
    shown = [body(a - b), body(-a * b), body(sp.Matrix([0, -1])), body(sp.Float(-2.5e-20) * a),
             signed_terms([a, -b]), "".join(text for _, text in pieces([a, -b * (a + b) ** 2]))]
    assert all("&#8722;" in text and "<mo>-</mo>" not in text and "<mn>-" not in text for text in shown), shown
    assert body(sp.sin(a) ** 2 * b).count("<msup><mi>sin</mi><mn>2</mn></msup><mrow><mo>(</mo><mi>a</mi>") == 1
    assert "<msup><mi>cos</mi><mn>3</mn></msup>" in body(b / sp.cos(a + b) ** 3)
    assert "<msup><mi>cos</mi><mn>2</mn></msup>" in body(sp.cos(a) ** -2)
    assert "<msup><mi>log</mi>" not in body(sp.log(a) ** 2) and "<mi>log</mi>" in body(sp.log(a) ** 2)   # trig only
    spaced = '<mo rspace="0.1667em">&#8290;</mo>'
    assert body(b * sp.sin(a) ** 2).count(spaced) == body(b * sp.cos(a) * sp.asin(b)).count(spaced) - 1 == 1
    assert spaced not in body(a * b) + body(b * (a + sp.sin(a)))   # before a name only, not before a bracket
    assert bold("M", args="q") == ('<mrow><mi>&#119820;</mi><mo stretchy="false">(</mo><mi>&#119850;</mi>'
                                   '<mo stretchy="false">)</mo></mrow>')
    assert "mathvariant" not in bold("C", args="q, qd") + bold("ω", subscript="0")


def _unevaluated_sums():
    """Sums, products, powers and quotients of symbols, sines, roots and small integers built unevaluated, nested
    as ``factor_terms`` and a derivation leave them (``−(a + b)``, ``c + (−a + b)``, ``(−a)²``): the shapes whose
    signs or brackets a printer can lose."""
    from hypothesis import strategies as st

    a, b, c = sp.symbols("a b c")
    leaves = st.sampled_from([a, b, c, sp.sin(a), sp.cos(b), 2 * a, 3 * b * c, sp.sqrt(c), a / 2, sp.Rational(1, 3)])

    def grow(children):
        pairs = st.lists(children, min_size=2, max_size=3)
        return st.one_of(pairs.map(lambda xs: sp.Add(*xs, evaluate=False)),
                         pairs.map(lambda xs: sp.Mul(*xs, evaluate=False)),
                         children.map(lambda x: sp.Mul(-1, x, evaluate=False)),
                         children.map(lambda x: sp.Pow(x, 2, evaluate=False)),
                         children.map(lambda x: sp.Pow(x, -1, evaluate=False)),
                         children.map(lambda x: sp.Pow(x, -2, evaluate=False)),
                         children.map(lambda x: sp.cos(x, evaluate=False)))
    return st.recursive(leaves, grow, max_leaves=8)


def test_the_page_reads_back_as_the_expression_it_shows():
    """Each printed expression, read back as a reader reads its MathML (tests/mathml_reading.py), is the
    expression: no sign is lost to a bracket left out (property-based over nested, unevaluated sums, products,
    powers and quotients); also an equation's terms, each after its sign, whole or broken into pieces over lines."""
    from hypothesis import given
    from hypothesis import strategies as st

    from harness.report.mathml import body, pieces, signed_terms

    from tests.mathml_reading import Reader

    at = dict(zip(sp.symbols("a b c"), (0.31, 0.73, 1.13)))   # the expressions are left unevaluated: at values

    def reads_as(mathml, expr):
        reader = Reader()
        read, want = reader.at(reader.expression(mathml), at), complex(expr.subs(at))
        assert abs(read - want) < 1e-9 * (1 + abs(want)), (sp.srepr(expr), mathml)

    @given(_unevaluated_sums())
    def check(expr):
        reads_as(body(expr), expr)

    @given(st.lists(_unevaluated_sums(), min_size=1, max_size=4))
    def check_terms(terms):
        reads_as(signed_terms(terms), sp.Add(*terms))
        reads_as("".join(text for _, text in pieces(terms)), sp.Add(*terms))
    check()
    check_terms()


def test_a_tree_joints_coordinate_carries_the_joints_name_as_its_subscript():
    """The joint table's ``θ = φ(q)`` and the joint springs' and dampers' laws print a tree joint's coordinate as θ
    with the joint's name, printed by the lecture's rule, as its one subscript: θ_{φ₁} for joint ``phi_1``, θ_{θ₂}
    for a paper's joint ``theta_2`` (read as θ_{φ,1} and θ_{θ,2} before, as if θ had two indices)."""
    import models
    from harness.report.mathml import body
    from harness.report.model_text import force_rows, joint_rows

    theta, dot = "<mi>&#952;</mi>", '<mo>&#729;</mo>'
    assert body(sp.Symbol("theta_theta_2"), joints=("theta_2",)) == f"<msub>{theta}{body(sp.Symbol('theta_2'))}</msub>"
    assert body(sp.Symbol("theta_theta_2_dot"), joints=("theta_2",)) == (
        f'<msub><mover accent="true">{theta}{dot}</mover>{body(sp.Symbol("theta_2"))}</msub>')
    assert body(sp.Symbol("theta_theta_2")) == f"<msub>{theta}<mrow><mi>&#952;</mi><mo>,</mo><mi>2</mi></mrow></msub>"
    system = models.get("planar_manipulator")
    for joint, row in zip(system.joints, joint_rows(system)):
        assert f"<msub>{theta}{body(sp.Symbol(joint.name))}</msub><mo>=</mo>" in row["phi"], row["phi"]
    dampers = [r["sentence"] for s in map(models.get, models.names()) for r in force_rows(s) if r["kind"] == "joint damper"]
    assert dampers and all("<mo>,</mo>" not in d for d in dampers), dampers
