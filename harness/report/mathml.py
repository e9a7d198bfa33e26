"""Equations as mathematics in the report: SymPy expressions printed as presentation MathML (Chromium renders
it without scripts), in the lecture's notation.

Our symbol names map to the lecture's by one rule, stated here once: ``<base>_<sub>_…`` is the base with the
parts as subscripts (``phi_1`` → φ₁, ``m_S`` → m_S, ``I_zz1`` → I_zz1), a trailing ``_dot``/``_ddot`` is the
time derivative written as an accent (``phi_1_dot`` → φ̇₁, ``s_ddot`` → s̈), Greek names are letters. A name the
rule renders wrongly takes an override (``names={"I_zz_S": ("I", ("zz",), ("S",))}``: base, subscripts,
superscripts). A minus sign is set as the lecture sets it, − (U+2212), where SymPy writes the hyphen-minus, which a
browser sets as a short dash; a power of sin, cos or tan carries its exponent on the function's name, sin²(α), as the
lecture writes it ((2.18), (5.76)), and a function's name in a product follows a thin space."""

from __future__ import annotations

import re
from html.entities import html5
from xml.sax.saxutils import escape

import sympy as sp
from sympy.printing.conventions import split_super_sub
from sympy.printing.mathml import MathMLPresentationPrinter
from sympy.printing.precedence import PRECEDENCE
from sympy.printing.printer import Printer
from sympy.printing.pretty.pretty_symbology import greek_unicode

_ACCENTS = {"dot": "\u02d9", "ddot": "\u00a8"}  # ˙ and ¨ above the base letter

Override = tuple[str, tuple[str, ...], tuple[str, ...]]

MINUS = "\u2212"
"""The minus sign (−) of every sign, difference and negative number on a page (module docstring)."""
MINUS_SIGN = f"<mo>&#{ord(MINUS)};</mo>"
TRIGONOMETRIC = ("sin", "cos", "tan", "cot", "sec", "csc", "sinh", "cosh", "tanh")
"""The functions whose powers the lecture sets with the exponent on the name: sin²(φ) (2.18), (5.76)."""
FUNCTIONS = (*TRIGONOMETRIC, "arcsin", "arccos", "arctan", "log", "ln", "sign")
FUNCTION_SPACE = "0.1667em"
"""The thin space before a function's name in a product, as the lecture's ``m l \\sin(θ)`` sets it: ``2 l² m sin(α)``
had read ``2l²msin(α)``, the name run into the factor before it."""


def lecture_parts(name: str) -> tuple[str, tuple[str, ...], tuple[str, ...], str | None]:
    """``name`` as (base, subscripts, superscripts, accent) by the module's rule."""
    parts = name.split("_")
    accent = None
    if len(parts) > 1 and parts[-1] in _ACCENTS:
        accent = _ACCENTS[parts.pop()]
    base, supers, subs = split_super_sub("_".join(parts))
    return base, tuple(subs), tuple(supers), accent


class LecturePrinter(MathMLPresentationPrinter):
    """SymPy's presentation-MathML printer with the lecture's symbol rule (module docstring)."""

    def __init__(self, names: dict[str, Override] | None = None, joints=(), **settings):
        super().__init__(settings)
        self._names = dict(names or {})
        self._joints = {f"theta_{j}": j for j in joints}

    def doprint(self, expr):
        """SymPy's MathML of ``expr``, each minus sign of an operator or a number set as :data:`MINUS`; non-ASCII
        characters as numeric references, as SymPy writes them."""
        node = Printer._print(self, expr)
        for tag in ("mo", "mn"):
            for element in [node] * (node.tagName == tag) + node.getElementsByTagName(tag):
                text = element.firstChild
                if text is not None and text.data.startswith("-") and (tag == "mn" or text.data == "-"):
                    text.data = MINUS + text.data[1:]
                elif text is not None and text.data == "&InvisibleTimes;" and _names_a_function(element.nextSibling):
                    element.setAttribute("rspace", FUNCTION_SPACE)
        return node.toxml().encode("ascii", "xmlcharrefreplace").decode()

    def _print_Pow(self, e):
        """An integer power of a trigonometric function with the exponent on its name, sin²(α), 1/sin²(α)
        (:data:`TRIGONOMETRIC`); any other power as SymPy prints it."""
        if not (isinstance(e.base, sp.Function) and type(e.base).__name__ in TRIGONOMETRIC and e.exp.is_Integer
                and abs(e.exp) > 1):
            return super()._print_Pow(e)
        if e.exp < 0:
            fraction = self.dom.createElement("mfrac")
            fraction.appendChild(self._print(sp.S.One))
            fraction.appendChild(self._print(sp.Pow(e.base, -e.exp)))
            return fraction
        power = self.dom.createElement("msup")
        power.appendChild(self._text("mi", type(e.base).__name__))
        power.appendChild(self._print(e.exp))
        row = self.dom.createElement("mrow")
        row.appendChild(power)
        row.appendChild(self._paren_comma_separated(*e.base.args))
        return row

    def _text(self, tag: str, text: str):
        node = self.dom.createElement(tag)
        node.appendChild(self.dom.createTextNode(text))
        return node

    def _row(self, items):
        if len(items) == 1:
            return self._text("mi", items[0])
        row = self.dom.createElement("mrow")
        for i, item in enumerate(items):
            if i:
                row.appendChild(self._text("mo", ","))
            row.appendChild(self._text("mi", item))
        return row

    def _letter(self, base: str, accent: str | None):
        """The base letter (a Greek one by its name), under its accent where it has one."""
        node = self._text("mi", greek_unicode.get(base, base))
        if accent:
            over = self.dom.createElement("mover")
            over.setAttribute("accent", "true")
            over.appendChild(node)
            over.appendChild(self._text("mo", accent))
            node = over
        return node

    def _joint_coordinate(self, name: str):
        """A tree joint's coordinate ``theta_<joint>`` (and its ``_dot``) as θ with the joint's name, printed by the
        lecture's rule, as its subscript: θ_{φ₁} (read as θ_{φ,1} before, as if the joint had two indices)."""
        accent = name.endswith("_dot") and name.removesuffix("_dot") in self._joints
        joint = self._joints.get(name.removesuffix("_dot") if accent else name)
        if joint is None:
            return None
        script = self.dom.createElement("msub")
        script.appendChild(self._letter("theta", _ACCENTS["dot"] if accent else None))
        script.appendChild(self._print_Symbol(sp.Symbol(joint)))
        return script

    def _print_Symbol(self, sym, style="plain"):
        if self._joints and (node := self._joint_coordinate(sym.name)) is not None:
            return node
        base, subs, supers, accent = lecture_parts(sym.name)
        if sym.name in self._names:
            (base, subs, supers), accent = self._names[sym.name], None
        node = self._letter(base, accent)
        subs = [greek_unicode.get(s, s) for s in subs]
        supers = [greek_unicode.get(s, s) for s in supers]
        if subs and supers:
            script = self.dom.createElement("msubsup")
            for child in (node, self._row(subs), self._row(supers)):
                script.appendChild(child)
            node = script
        elif subs or supers:
            script = self.dom.createElement("msub" if subs else "msup")
            script.appendChild(node)
            script.appendChild(self._row(subs or supers))
            node = script
        if style == "bold":
            node.setAttribute("mathvariant", "bold")
        return node

    _print_Dummy = _print_Symbol

    def _print_Mul(self, expr):
        """SymPy prints ``−(a + b)``, a product of −1 and a sum that stays unevaluated (``factor_terms`` leaves it
        so), as ``− a + b``: it takes the sign out and prints the sum that is left without its parentheses
        (planar_manipulator's page showed the derived ``J_v`` of link 2 as ``− l₁ sin φ₁ + l_s2 sin(φ₁ + φ₂)``)."""
        if expr.could_extract_minus_sign() and isinstance(-expr, sp.Add):
            row = self.dom.createElement("mrow")
            row.appendChild(self._text("mo", MINUS))
            row.appendChild(self.parenthesize(-expr, PRECEDENCE["Mul"]))
            return row
        return super()._print_Mul(expr)

    def _print_Add(self, expr, order=None):
        """A sum, each term after its sign, as SymPy prints it, but a term that is itself a sum (left unevaluated)
        in parentheses, also where a minus sign is taken out of it: SymPy's printer reads ``a − (b + c)`` as
        ``a − b + c``."""
        row = self.dom.createElement("mrow")
        for k, term in enumerate(self._as_ordered_terms(expr, order=order)):
            minus = bool(k) and term.could_extract_minus_sign()
            if k:
                row.appendChild(self._text("mo", MINUS if minus else "+"))
            shown = -term if minus else term
            nested = k and isinstance(shown, sp.Add)
            row.appendChild(self.parenthesize(shown, PRECEDENCE["Add"]) if nested else self._print(shown))
        return row


def _names_a_function(node) -> bool:
    """Whether ``node`` begins with a function's name (:data:`FUNCTIONS`): ``sin(α)``, ``sin²(α)``, ``sin(α)²``."""
    while node is not None and node.nodeType == node.ELEMENT_NODE and node.tagName in ("mrow", "msup", "msub"):
        node = next((k for k in node.childNodes if k.nodeType == k.ELEMENT_NODE), None)
    return node is not None and node.nodeType == node.ELEMENT_NODE and node.tagName == "mi" and \
        node.firstChild is not None and node.firstChild.data in FUNCTIONS


def _numeric_entities(text: str) -> str:
    """Named entities SymPy writes (``&InvisibleTimes;``) as numeric references: valid XML, not only HTML."""
    def numeric(match):
        name = match.group(1) + ";"
        if name in ("lt;", "gt;", "amp;", "quot;", "apos;") or name not in html5:
            return match.group(0)
        return "".join(f"&#{ord(c)};" for c in html5[name])
    return re.sub(r"&([A-Za-z][A-Za-z0-9]*);", numeric, text)


def readable(expr, digits: int = 6):
    """``expr`` with its floating-point numbers rounded to ``digits`` significant digits, for reading (an inertia
    ``0.00666666666666667 m_W`` reads as ``0.00666667 m_W``); exact numbers are kept."""
    expr = sp.sympify(expr)
    floats = {f: sp.Float(f, digits) for f in expr.atoms(sp.Float)}
    return expr.xreplace(floats) if floats else expr


def body(expr, *, names: dict[str, Override] | None = None, joints=()) -> str:
    """``expr`` as presentation MathML without the ``<math>`` element (to be composed with :func:`math`);
    floating-point numbers rounded for reading (:func:`readable`); the coordinates of the tree joints ``joints``
    as θ with the joint's name as subscript."""
    return _numeric_entities(LecturePrinter(names, joints, mat_delim="[").doprint(readable(expr)))


def signed_terms(terms) -> str:
    """The sum of ``terms`` as presentation MathML in the given order, each term after its own sign. SymPy's printer
    sorts a sum's terms, and prints a sum nested in a sum that it can pull a minus sign out of as ``−`` and the
    negated sum without parentheses: ``a + (−c x + c y)`` read ``a − c x − c y`` (the equations of motion of 5
    systems on their report pages had a wrong sign so, e.g. torsion_spring_body's ``− c_F φ`` for ``+ c_F φ``)."""
    out = []
    for k, term in enumerate(terms):
        minus = term.could_extract_minus_sign()
        if minus:
            out.append(MINUS_SIGN)
            term = -term
        elif k:
            out.append("<mo>+</mo>")
        out.append(f"<mo>(</mo>{body(term)}<mo>)</mo>" if minus and term.is_Add else body(term))   # −(a + b)
    return f"<mrow>{''.join(out)}</mrow>"


LINE_WIDTH = 80
"""What one line of a broken sum (:func:`broken`) holds, in characters as :func:`width` counts them: at the report's
1300 px beside an equation's title and numbers, a line of 80 of them fits with its numbers (the trebuchet's, toggle
press's and cart pendulum's equations in Chromium); a single term wider than a line is a line of its own."""


def width(expr) -> float:
    """How wide ``expr`` prints, in characters, roughly as the page sets it: a fraction as wide as the wider of its
    numerator and denominator (stacked), an exponent or subscript at 0.7 of a character, parentheses around a sum
    inside a product or power, a sign or operator as one character (:data:`LINE_WIDTH`)."""
    expr = sp.sympify(expr)
    if isinstance(expr, sp.MatrixBase):  # its columns side by side, each as wide as its widest entry
        return sum(max(width(expr[i, j]) for i in range(expr.rows)) + 1 for j in range(expr.cols)) + 2
    if isinstance(expr, sp.Symbol):
        base, subs, supers, accent = lecture_parts(expr.name)
        return len(greek_unicode.get(base, base)) + 0.7 * sum(len(s) for s in (*subs, *supers))
    if expr.is_Number or expr.is_NumberSymbol or expr.is_Atom:
        return len(sp.sstr(readable(expr)))
    if isinstance(expr, sp.Add):
        return sum(width(a) for a in expr.args) + 3 * (len(expr.args) - 1)
    if isinstance(expr, sp.Mul):
        numerator, denominator = sp.fraction(expr)
        if denominator != 1:
            return max(width(numerator), width(denominator)) + 1
        return sum(width(a) + 2 * isinstance(a, sp.Add) for a in expr.args)
    if isinstance(expr, sp.Pow):
        if expr.exp.is_negative:
            return width(1 / expr) + 1
        return width(expr.base) + 2 * isinstance(expr.base, (sp.Add, sp.Mul)) + 0.7 * width(expr.exp)
    if isinstance(expr, sp.Function):
        return len(type(expr).__name__) + 2 + sum(width(a) for a in expr.args) + (len(expr.args) - 1)
    return len(sp.sstr(expr))


def pieces(terms, deep: bool = True) -> list[tuple[float, str]]:
    """The sum of ``terms`` in their order as pieces to set on lines, ``(width, MathML)`` each, every term after its
    own sign (:func:`signed_terms`; the first without a ``+``). A term wider than a line that is a product with a
    sum among its factors (``φ̇₃ (…)``, a Christoffel entry grouped by the velocity) is opened: its other factors and
    ``(`` as one piece, the sum's own pieces, the last of them with the ``)``, so that the sum is broken over lines
    too and its bracket never begins a line alone (:func:`_opened`; ``deep``: also where the sum's own terms are
    opened in turn)."""
    out = []
    for k, term in enumerate(terms):
        minus = not isinstance(term, sp.MatrixBase) and term.could_extract_minus_sign()   # a matrix: one piece
        term = -term if minus else term
        sign = MINUS_SIGN if minus else ("<mo>+</mo>" if k else "")
        inner = (sp.S.One, term, None) if minus and term.is_Add else _opened(term, deep)   # −(a + b): bracketed
        if inner is None:
            out.append((width(term) + bool(sign), sign + body(term)))
            continue
        factor, total, power = inner
        # the other factor may itself be a sum (rotating_body's M₁₁: (…)² (2 b d l₂ ρ + … + m_m)): bracketed, or the
        # page read "2 b d l₂ ρ + … + m_m (…)²"
        shown = "" if factor == 1 else f"<mo>(</mo>{body(factor)}<mo>)</mo>" if factor.is_Add else body(factor)
        out.append((width(factor) * (factor != 1) + 2 + 2 * factor.is_Add, sign + shown + "<mo>(</mo>"))
        out += pieces(list(total.as_ordered_terms()), deep)
        closing = (1, "<mo>)</mo>") if power is None else (2, f"<msup><mo>)</mo>{body(power)}</msup>")
        out[-1] = (out[-1][0] + closing[0], out[-1][1] + closing[1])
    return out


def _opened(term, deep: bool = True):
    """``(other factors, sum, power)`` of a term wider than a line whose widest factor is a sum, or a sum to a
    positive integer power (``(…)²`` of a kinetic energy; ``power`` None for the sum itself), of terms that each fit
    on a line or (``deep``) are opened themselves, else None. Opened level after level, nested roots and
    arccosines ran down the page a bracket per line, harder to read than the one line it scrolls in: where one
    level does not make an entry fit, the report names its common subexpressions first
    (:func:`harness.report.equations.abbreviated`), and only then opens deeper."""
    if width(term) <= LINE_WIDTH or not isinstance(term, (sp.Mul, sp.Pow)):
        return None
    widest = max(term.args, key=width) if isinstance(term, sp.Mul) else term
    total, power = widest, None
    if isinstance(widest, sp.Pow) and widest.exp.is_Integer and widest.exp > 1:
        total, power = widest.base, widest.exp
    if not isinstance(total, sp.Add) or any(width(t) > LINE_WIDTH and (not deep or _opened(t) is None)
                                            for t in total.args):
        return None
    rest = sp.Mul(*(a for a in term.args if a is not widest)) if isinstance(term, sp.Mul) else sp.S.One
    return rest, total, power


def lines(terms, line_width: int = LINE_WIDTH) -> list[list]:
    """The :func:`pieces` of ``terms`` grouped into lines of at most ``line_width`` (:func:`width`) each (a piece
    wider than a line alone on its own)."""
    out: list[list] = []
    used = 0
    for w, piece in pieces(terms):
        if out and used + w <= line_width:
            out[-1].append(piece)
            used += w
        else:
            out.append([piece])
            used = w
    return out


def broken(equations) -> str:
    """Equations too wide for a line as one ``<math>`` element, each broken after its terms: ``equations`` are
    ``(left, relation, terms)`` (MathML of the left-hand side, e.g. :func:`bold`, and of the relation, the sum's terms
    in their order), a table row per line of terms (:func:`lines`), the left-hand side and the relation on the first,
    each later line beginning with the sign of its first term."""
    rows = []
    for left, relation, terms in equations:
        for k, line in enumerate(lines(terms) or [[body(sp.S.Zero)]]):
            rows.append(f'<mtr><mtd style="text-align:right">{left if k == 0 else ""}</mtd>'
                        f'<mtd>{relation if k == 0 else ""}</mtd>'
                        f'<mtd style="text-align:left"><mrow>{"".join(line)}</mrow></mtd></mtr>')
    return f'<math xmlns="http://www.w3.org/1998/Math/MathML" display="block"><mtable>{"".join(rows)}</mtable></math>'


_BOLD = {**{chr(ord("A") + k): 0x1D400 + k for k in range(26)}, **{chr(ord("a") + k): 0x1D41A + k for k in range(26)},
         **{chr(0x3B1 + k): 0x1D6C2 + k for k in range(25)}}
"""Latin and small Greek letters → Unicode's mathematical bold letters (𝐌, 𝐪, 𝛚)."""


def bold_letter(letter: str) -> str:
    """A letter set bold and upright as the lecture's ``\\mathbf`` sets it: Unicode's mathematical bold letter (𝐌),
    which Chromium shows; ``mathvariant="bold"``, which MathML Core leaves out, had set an italic M. A letter
    without a bold form keeps the attribute."""
    if letter in _BOLD:
        return f"<mi>&#{_BOLD[letter]};</mi>"
    return f'<mi mathvariant="bold">{escape(letter)}</mi>'


def bold(letter: str, *, subscript: str = "", superscript: str = "", args: str = "") -> str:
    """The lecture's bold quantity symbol (``M``, ``C``, ``g``, ``f``, :func:`bold_letter`) with optional sub- and
    superscript and argument list (``args="q"`` gives M(q), ``"q, qd"`` gives C(q, q̇)) as MathML, for left-hand
    sides."""
    node = bold_letter(letter)
    if subscript and superscript:
        node = f"<msubsup>{node}<mi>{escape(subscript)}</mi><mi>{escape(superscript)}</mi></msubsup>"
    elif subscript or superscript:
        tag = "msub" if subscript else "msup"
        node = f"<{tag}>{node}<mi>{escape(subscript or superscript)}</mi></{tag}>"
    if args:
        inner = "<mo>,</mo>".join(bold_argument(a.strip()) for a in args.split(","))
        node += f'<mo stretchy="false">(</mo>{inner}<mo stretchy="false">)</mo>'   # M(q) as set in a line
    return f"<mrow>{node}</mrow>"


def bold_argument(name: str) -> str:
    """``q``, ``qd`` or ``qdd`` as the bold 𝐪, 𝐪̇ or 𝐪̈ of an argument list or a product (``𝐂 𝐪̇``)."""
    letter = bold_letter(name.removesuffix("dd").removesuffix("d"))
    accent = {"dd": _ACCENTS["ddot"], "d": _ACCENTS["dot"]}
    for suffix in ("dd", "d"):
        if name.endswith(suffix) and len(name) > len(suffix):
            return f'<mover accent="true">{letter}<mo>{accent[suffix]}</mo></mover>'
    return letter


def math(*rows: str, display: bool = True) -> str:
    """MathML fragments (from :func:`body`, :func:`bold`, ``<mo>=</mo>``) joined into one ``<math>`` element."""
    attributes = ' display="block"' if display else ""
    return f'<math xmlns="http://www.w3.org/1998/Math/MathML"{attributes}><mrow>{"".join(rows)}</mrow></math>'


def mathml(expr, *, names: dict[str, Override] | None = None, display: bool = True, label: str = "") -> str:
    """``expr`` (an expression, a matrix or an ``Eq``) as one ``<math>`` element; ``label`` (an equation number
    such as ``(5.92b)``) is set at the right as the lecture sets it."""
    printer = LecturePrinter(names, mat_delim="[")
    body = _numeric_entities(printer.doprint(sp.sympify(expr)))
    attributes = ' display="block"' if display else ""
    if label:
        body = (f'<mtable><mlabeledtr><mtd><mtext>{escape(label)}</mtext></mtd><mtd>{body}</mtd>'
                f'</mlabeledtr></mtable>')
    return f'<math xmlns="http://www.w3.org/1998/Math/MathML"{attributes}>{body}</math>'


def equation(lhs, rhs, **kwargs) -> str:
    """``lhs = rhs`` as one ``<math>`` element (:func:`mathml`)."""
    return mathml(sp.Eq(sp.sympify(lhs), sp.sympify(rhs), evaluate=False), **kwargs)
