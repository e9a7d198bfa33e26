"""SymPy's ``lambdify`` with every ``Float`` constant written exactly: the one way the project compiles expressions.

SymPy 1.14's code printers write a ``Float`` of 53-bit precision with 15 significant digits
(``lambdify([], Float(0.014107263642161838))()`` returns ``0.0141072636421618``): a model constant read from a
URDF (the Panda's inertias) lost up to 5e-16 relative, 12 ulp of link 7's inertia, in every compiled function.
Here each ``Float`` is printed as the shortest text of its float64 (``repr``), which reads back as the same
float64; everything else is ``lambdify``'s own printer for the modules asked for, with its own settings.
"""

from __future__ import annotations

import math

import sympy as sp
from sympy.printing.numpy import NumPyPrinter, SciPyPrinter
from sympy.printing.pycode import PythonCodePrinter

_PRINTERS = {"scipy": SciPyPrinter, "numpy": NumPyPrinter, "math": PythonCodePrinter}


def lambdify(args, expr, modules=None, **options):
    """:func:`sympy.lambdify` of ``expr`` (``modules``: ``"math"``, ``"numpy"``, or ``None`` for SciPy with NumPy,
    as SymPy chooses), each ``Float`` printed exactly."""
    names = ["numpy", "scipy"] if modules is None else [modules] if isinstance(modules, str) else list(modules)
    printer = next((_PRINTERS[m] for m in ("scipy", "numpy", "math") if m in names), None)
    if printer is None:
        raise ValueError(f"lambdify: modules {modules!r} (math, numpy or scipy)")
    settings = {"fully_qualified_modules": False, "inline": True, "allow_unknown_functions": True,
                "user_functions": {}}
    return sp.lambdify(args, expr, modules=modules, printer=_exact(printer)(settings), **options)


def _exact(printer: type) -> type:
    if printer not in _EXACT:
        _EXACT[printer] = type(f"Exact{printer.__name__}", (printer,), {"_print_Float": _print_float})
    return _EXACT[printer]


def _print_float(self, expr) -> str:
    value = float(expr)
    return repr(value) if math.isfinite(value) else super(type(self), self)._print_Float(expr)


_EXACT: dict[type, type] = {}
