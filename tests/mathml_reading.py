"""A reader of the report's MathML, as a reader of the page reads it: rows in order, an invisible times or two
operands side by side a product, a fraction, a root, a power (also a bracket raised, ``(…)²`` closing a sum opened
over lines, and a function's name raised, sin²(α)), ``|…|``, a function applied to the bracket after it, a table's
rows one after the other, a table in square brackets a matrix; − (U+2212) a minus sign. Each symbol as it is set
(its letter with sub- and superscripts and accent) becomes a name of its own, so a page that sets two symbols alike
reads them as one. Used by tests/test_mathml.py and tests/test_report_equations.py."""

from __future__ import annotations

from xml.dom.minidom import parseString

import sympy as sp

FUNCTIONS = {"sin": "sin", "cos": "cos", "tan": "tan", "arccos": "acos", "arcsin": "asin", "arctan": "atan",
             "sign": "sign", "exp": "exp", "log": "log"}
OPERATORS = {"\u2062": "*", "\u2212": "-", "-": "-", "+": "+", "(": "(", ")": ")", ",": ",", "|": "|", "=": "=",
             "\u2202": "d",   # ∂ of a left-hand side ∂L/∂q̇: read, never evaluated
             ":": "="}   # "column j :" of a matrix set column by column


class Reader:
    """Reads MathML into SymPy; the symbols it met are :attr:`names` (their MathML → the name read)."""

    def __init__(self):
        self.names: dict[str, str] = {}

    def expression(self, mathml: str) -> sp.Expr:
        """One expression (no ``=``)."""
        return sp.sympify(self.text(mathml).replace("\n", ""))

    def equation(self, mathml: str) -> sp.Expr:
        """``left − right`` of one equation, broken over a table's rows or not."""
        left, _, right = self.text(mathml).replace("\n", "").partition("=")
        return sp.sympify(left or "0") - sp.sympify(right or "0")

    def definitions(self, mathml: str) -> dict:
        """``name = …`` per equation of a table (:meth:`statements`): name → expression."""
        return {sp.Symbol(left): sp.sympify(right) for left, right in self.statements(mathml)}

    def at(self, read: sp.Expr, values: dict, where: dict | None = None) -> complex:
        """The value of an expression read from a page at ``values`` of the model's symbols (each as the page
        sets it, :meth:`symbol`), its named subexpressions ``where`` (name → expression read) substituted first."""
        where = where or {}
        for _ in range(len(where) + 1):
            read = read.xreplace(where)
        return complex(read.xreplace({self.symbol(x): v for x, v in values.items()}))

    def error(self, read: sp.Expr, expr, values: dict, where: dict | None = None) -> float:
        """``|read − expr| / (1 + |expr|)`` at ``values`` (:meth:`at`): 0 but for rounding where the page shows
        ``expr``, O(1) where it shows something else (a sign, a term, a bracket)."""
        want = complex(sp.sympify(expr).xreplace(values))
        return abs(self.at(read, values, where) - want) / (1 + abs(want))

    def statements(self, mathml: str) -> list[tuple[str, str]]:
        """``(left, right)`` texts of the equations a table sets: a row ``x = …`` begins one and the rows after it
        continue its right side; rows before a row ``= 0`` are the left side of a residual; an expression set alone
        (no ``=``) is ``("", expression)``. A printed equation's named subexpressions follow it, ``ξ₁ = …``."""
        out, pending = [], ""
        for line in self.text(mathml).split("\n"):
            if line.startswith("="):
                out.append([pending, line[1:]])
                pending = ""
            elif "=" in line:
                if pending:
                    out.append(["", pending])
                    pending = ""
                out.append(line.split("=", 1))
            elif out and not pending and out[-1][1] != "0":
                out[-1][1] += line
            else:
                pending += line
        if pending:
            out.append(["", pending])
        return [(left, right) for left, right in out]

    def claim(self, mathml: str, shape: tuple[int, int], residual: bool = False) -> tuple[sp.Matrix, dict]:
        """A printed equation or its derived form as a page sets it (:func:`harness.report.equations.wide_math`):
        the matrix of ``shape`` it shows (a residual's left side) and its named subexpressions ``ξ = …`` (name →
        expression read). Set in a line, the value is one expression or a matrix in brackets; broken over lines, a
        residual is its rows ``… = 0`` and a matrix its entries in row-major order (every entry), the names after
        them; a matrix without a name is its columns ``column j : […]``."""
        said = self.statements(mathml)   # texts: a left side is read only where it is a value (a residual's)

        def value_of(left: str, right: str):
            if not residual:
                return sp.sympify(right)
            shown = sp.sympify(left or "0")
            return shown if right.strip() == "0" else shown - sp.sympify(right)   # a matrix has no "- 0"

        columns = [sp.sympify(right) for left, right in said if left.startswith("column_")]
        first = value_of(*said[0])
        if columns:
            value, rest = sp.Matrix.hstack(*columns), said[len(columns):]
        elif isinstance(first, sp.MatrixBase):   # in a line
            value, rest = first, said[1:]
        else:
            count = shape[0] * shape[1]
            value, rest = sp.Matrix(*shape, [value_of(*statement) for statement in said[:count]]), said[count:]
        rest = [(sp.sympify(left), sp.sympify(right)) for left, right in rest]
        return value, dict(rest)

    def symbol(self, expr) -> sp.Symbol:
        """The name a model symbol reads as where the page sets it (:func:`harness.report.mathml.body`)."""
        from harness.report.mathml import body

        return sp.Symbol(self.text(body(expr)))

    def text(self, mathml: str) -> str:
        root = parseString(mathml if mathml.startswith("<math") else f"<math>{mathml}</math>").documentElement
        return self._text(root)

    @staticmethod
    def _is(node, tag: str, text: str) -> bool:
        return node.tagName == tag and node.firstChild is not None and node.firstChild.nodeType == node.TEXT_NODE \
            and node.firstChild.data == text

    def _matrix(self, table) -> str:
        """A table in square brackets: a matrix, its cells read as expressions."""
        rows = [",".join(f"({self._text(cell)})" for cell in row.getElementsByTagName("mtd"))
                for row in table.getElementsByTagName("mtr")]
        return "Matrix([" + ",".join(f"[{row}]" for row in rows) + "])"

    def _name(self, node) -> str:
        return self.names.setdefault(node.toxml(), f"_s{len(self.names)}")

    def _text(self, node) -> str:
        tag = node.tagName
        kids = [k for k in node.childNodes if k.nodeType == k.ELEMENT_NODE]
        if tag == "mi":
            name = node.firstChild.data
            if name in ("\u2147", "e"):
                return "E"
            if name == "\u03c0":
                return "pi"
            return FUNCTIONS[name] + " " if name in FUNCTIONS else self._name(node)
        if tag == "mn":
            return node.firstChild.data.replace("\u2212", "-")
        if tag == "mtext":   # "column j" of a matrix set column by column
            return node.firstChild.data.replace(" ", "_")
        if tag == "mo":
            return OPERATORS[node.firstChild.data]
        if tag in ("msub", "msubsup", "mover"):
            return self._name(node)
        if tag == "msup":
            if kids[1].tagName == "mi":    # a superscript of a name (I_zz^S)
                return self._name(node)
            if kids[0].tagName == "mo":    # the closing bracket of a sum opened over lines, raised: (…)²
                return f"{self._text(kids[0])}**({self._text(kids[1])})"
            return f"({self._text(kids[0])})**({self._text(kids[1])})"
        if tag == "mfrac":
            return f"(({self._text(kids[0])})/({self._text(kids[1])}))"
        if tag == "msqrt":
            return f"sqrt({self._row(kids)})"
        if tag == "mtable":
            return "\n".join(self._text(k) for k in kids)
        return self._row(kids)

    def _power_of_function(self, node) -> bool:
        """``<msup><mi>sin</mi>…</msup>``: a function's name raised, as the lecture sets sin²(α)."""
        if node.tagName != "msup":
            return False
        base = next(k for k in node.childNodes if k.nodeType == k.ELEMENT_NODE)
        return base.tagName == "mi" and base.firstChild.data in FUNCTIONS

    def _row(self, kids) -> str:
        out, bars, skip = "", 0, set()
        for k, kid in enumerate(kids):
            if self._is(kid, "mo", "[") or self._is(kid, "mo", "]"):
                continue
            if kid.tagName == "mtable" and k and self._is(kids[k - 1], "mo", "["):
                piece = self._matrix(kid)
            elif self._power_of_function(kid):   # sin²(α): the power of the function applied to the next bracket
                power = [e for e in kid.childNodes if e.nodeType == e.ELEMENT_NODE]
                piece = f"({self._text(power[0])}{self._text(kids[k + 1])})**({self._text(power[1])})"
                skip.add(k + 1)
            elif k in skip:
                continue
            else:
                piece = self._text(kid)
            if piece == "|":
                piece = "Abs(" if bars % 2 == 0 else ")"
                bars += 1
            if out and piece and out[-1] not in "+-*(,/= " and piece[0] not in "+-*),/=" and \
                    not out.endswith("Abs("):
                out += "*"   # side by side: a product
            out += piece
        return out


READ_TOLERANCE = 1e-9
"""What a page shows agrees with an expression where :meth:`Reader.error` is at most this: the values are drawn in
[0.3, 1.3], so the rounding of a displayed expression's evaluation is ~1e-15, and a wrong sign or term is O(1)."""


def misread(mathml: str, expr, residual: bool = False, seed: str = "") -> list[tuple[int, float]]:
    """The entries of ``expr`` (an expression or a matrix) that ``mathml``, read as a page sets a printed equation or
    a derived form (:meth:`Reader.claim`, its named subexpressions substituted), does not show: ``(index, error)``
    at random values in [0.3, 1.3] (from ``seed``) of its symbols, beyond :data:`READ_TOLERANCE`."""
    import random

    expr = sp.Matrix(expr) if isinstance(expr, (sp.MatrixBase, list, tuple)) else sp.Matrix([sp.sympify(expr)])
    reader = Reader()
    shown, where = reader.claim(mathml, expr.shape, residual)
    assert shown.shape == expr.shape, (shown.shape, expr.shape)
    rng = random.Random(seed)
    values = {x: rng.uniform(0.3, 1.3) for x in sorted(expr.free_symbols, key=str)}
    errors = [(k, reader.error(a, b, values, where)) for k, (a, b) in enumerate(zip(shown, expr))]
    return [(k, e) for k, e in errors if e > READ_TOLERANCE]
