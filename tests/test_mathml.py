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
