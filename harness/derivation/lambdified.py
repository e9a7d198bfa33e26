"""SymPy's ``lambdify`` with every ``Float`` constant written exactly, and its generated code kept on disk: the one way
the project compiles expressions.

SymPy 1.14's code printers write a ``Float`` of 53-bit precision with 15 significant digits
(``lambdify([], Float(0.014107263642161838))()`` returns ``0.0141072636421618``): a model constant read from a
URDF (the Panda's inertias) lost up to 5e-16 relative, 12 ulp of link 7's inertia, in every compiled function.
Here each ``Float`` is printed as the shortest text of its float64 (``repr``), which reads back as the same
float64; everything else is ``lambdify``'s own printer for the modules asked for, with its own settings.

**Compiled code on disk.** Printing an expression (and searching it for common subexpressions) is SymPy work that a
warm main job repeated for every compiled function in every process: about 20 CPU s of ~160, the same text each time.
The generated source of each function is kept under ``compiled/`` beside the derivation cache
(:func:`compiled_dir`), keyed by a SHA-256 of what decides it: the arguments and the expression (``srepr``), the
modules, ``lambdify``'s options (a ``cse`` function by its ``cache_key``), this module's source and the SymPy and
Python versions. A call whose key cannot be formed (an option without a stable text) compiles as always.
Nothing read from the cache can run code beyond arithmetic: an entry is accepted only when its checksum matches and
its source parses to one function of the shape ``lambdify`` writes — positional arguments unpacked into names,
assignments of expressions, one ``return`` — whose expressions use numbers, the function's own names and
:data:`ALLOWED` (the functions and constants SymPy's printers write: ``sin``, ``sqrt``, ``array``, ``select``, …),
no attribute, subscript of anything but a name, string (but ``float('nan')``), keyword other than ``axis`` and
``default``, lambda or comprehension. Anything else makes the entry a miss: it is compiled again and rewritten.
"""

from __future__ import annotations

import ast
import functools
import hashlib
import inspect
import json
import linecache
import math
import sys
from pathlib import Path

import sympy as sp
from sympy.printing.numpy import NumPyPrinter, SciPyPrinter, _known_constants_numpy, _known_functions_numpy
from sympy.printing.pycode import (PythonCodePrinter, _known_constants_math, _known_functions,
                                   _known_functions_math)

_PRINTERS = {"scipy": SciPyPrinter, "numpy": NumPyPrinter, "math": PythonCodePrinter}


def lambdify(args, expr, modules=None, **options):
    """:func:`sympy.lambdify` of ``expr`` (``modules``: ``"math"``, ``"numpy"``, or ``None`` for SciPy with NumPy,
    as SymPy chooses), each ``Float`` printed exactly; its generated source read from the on-disk cache when kept
    there (see the module docstring), else generated and kept."""
    return _lambdify_keyed(args, expr, modules, options)[0]


def lambdify_built(recipe: tuple[str, ...], args, build, modules=None, **options):
    """:func:`lambdify` of the expression ``build()`` returns, where ``recipe`` (texts) decides that expression
    completely: the code that builds it and its inputs (``srepr``). The kept source is found by the recipe's hash (a
    file in ``compiled/recipes/`` naming its key) without building the expression or printing it, SymPy work that a
    warm run repeated: the claims' terms sizes (``Abs`` of each term) and ``∂R/∂q̈``, 2.3 of 17.8 profiled CPU s of
    eight systems' claims. The alias is kept like every entry of :mod:`harness.kept` (keyed by our installation too,
    those of another removed). A missing or damaged recipe, or a kept source that does not load, builds and
    compiles as :func:`lambdify` does."""
    from harness import kept, profiling

    alias = kept.path("compiled/recipes", "recipe", _code_version(), repr(modules), *recipe,
                      *(f"{k}={options[k]!r}" for k in sorted(options)))
    key = kept.read_kept(alias)
    if isinstance(key, str):
        found = _load(key, modules, _printer_of(modules))
        if found is not None:
            profiling.count("compiled code read from the cache by its recipe")
            return found
    fn, key = _lambdify_keyed(args, build(), modules, options)
    if key is not None and _path(key).is_file():
        kept.keep(alias, key)
    return fn


def _printer_of(modules) -> type:
    names = ["numpy", "scipy"] if modules is None else [modules] if isinstance(modules, str) else list(modules)
    printer = next((_PRINTERS[m] for m in ("scipy", "numpy", "math") if m in names), None)
    if printer is None:
        raise ValueError(f"lambdify: modules {modules!r} (math, numpy or scipy)")
    return printer


def _lambdify_keyed(args, expr, modules, options: dict):
    """``(function, key)`` of :func:`lambdify` (``key`` None where it cannot be formed)."""
    printer = _printer_of(modules)
    from harness import profiling

    key = _key(args, expr, modules, options)
    if key is not None:
        kept = _load(key, modules, printer)
        if kept is not None:
            profiling.count("compiled code read from the cache")
            return kept, key
    fn = sp.lambdify(args, expr, modules=modules, printer=_printer(printer), **options)
    profiling.count("compiled code generated")
    if key is not None and not _store(key, fn):
        profiling.count("compiled code not kept (outside the accepted shape)")
    return fn, key


def _printer(printer: type):
    settings = {"fully_qualified_modules": False, "inline": True, "allow_unknown_functions": True,
                "user_functions": {}}
    return _exact(printer)(settings)


def _exact(printer: type) -> type:
    if printer not in _EXACT:
        _EXACT[printer] = type(f"Exact{printer.__name__}", (printer,), {"_print_Float": _print_float})
    return _EXACT[printer]


def _print_float(self, expr) -> str:
    value = float(expr)
    return repr(value) if math.isfinite(value) else super(type(self), self)._print_Float(expr)


_EXACT: dict[type, type] = {}


# ----------------------------------------------------------------------------------------- the code kept on disk
def compiled_dir() -> Path:
    """Where generated sources are kept: ``compiled/`` beside the derivation cache (``HARNESS_CACHE_DIR``)."""
    from harness.derivation.cache import cache_dir

    return cache_dir().parent / "compiled"


def _code_version() -> str:
    if not _VERSION:
        digest = hashlib.sha256(Path(__file__).read_bytes())
        digest.update(f"{sp.__version__} {sys.version_info[:2]}".encode())
        _VERSION.append(digest.hexdigest())
    return _VERSION[0]


_VERSION: list = []


def _key(args, expr, modules, options: dict) -> str | None:
    """The SHA-256 of everything that decides the generated source, or None when an option has no stable text."""
    parts = [_code_version(), repr(modules)]
    for name in sorted(options):
        value = options[name]
        if callable(value):
            value = getattr(value, "cache_key", None)
            if value is None:
                return None
        elif not isinstance(value, (bool, int, str, type(None))):
            return None
        parts.append(f"{name}={value!r}")
    try:
        parts += [sp.srepr(args), sp.srepr(expr)]
    except Exception:  # noqa: BLE001 - an argument srepr does not print: compiled, not kept
        return None
    return hashlib.sha256("\n".join(parts).encode()).hexdigest()


def _path(key: str) -> Path:
    return compiled_dir() / f"{key}.json"


def _store(key: str, fn) -> bool:
    """Keep ``fn``'s generated source (atomically; a cache that cannot be written only costs the next run time);
    False when the source is not of the shape :func:`_function` accepts (then the reader would refuse it)."""
    from harness.io import atomic_write_text

    try:
        source = inspect.getsource(fn)
    except (OSError, TypeError):
        return False
    if _function(source) is None:
        return False
    try:
        compiled_dir().mkdir(parents=True, exist_ok=True)
        atomic_write_text(_path(key), json.dumps({"source": source, "sha256": _sha(source)}))
    except OSError:
        pass
    return True


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def _load(key: str, modules, printer: type):
    """The function kept under ``key``, or None (absent, damaged, or not of the accepted shape: then removed)."""
    path = _path(key)
    try:
        doc = json.loads(path.read_text())
    except OSError:
        return None
    except ValueError:
        path.unlink(missing_ok=True)
        return None
    source = doc.get("source") if isinstance(doc, dict) else None
    tree = _function(source) if isinstance(source, str) and doc.get("sha256") == _sha(source) else None
    if tree is None:
        path.unlink(missing_ok=True)
        return None
    filename = f"<lambdifygenerated-kept-{key[:16]}>"
    namespace = dict(_namespace(modules, printer))
    exec(compile(tree, filename, "exec"), namespace)  # noqa: S102 - arithmetic only: see _function
    linecache.cache[filename] = (len(source), None, source.splitlines(True), filename)  # as lambdify does
    return namespace[tree.body[0].name]


def _namespace(modules, printer: type) -> dict:
    """The globals ``lambdify`` gives a function of ``modules`` (the functions and constants its code calls)."""
    key = (repr(modules), printer)
    if key not in _NAMESPACES:
        namespace = sp.lambdify([], 0, modules=modules, printer=_printer(printer)).__globals__
        namespace.setdefault("reduce", functools.reduce)  # imported by lambdify when the code has Min/Max
        _NAMESPACES[key] = namespace
    return _NAMESPACES[key]


_NAMESPACES: dict = {}

ALLOWED = frozenset({*_known_functions_numpy.values(), *_known_constants_numpy.values(),
                     *_known_functions_math.values(), *_known_constants_math.values(), *_known_functions.values(),
                     "array", "select", "equal", "not_equal", "less", "less_equal", "greater", "greater_equal",
                     "logical_and", "logical_or", "logical_not", "amax", "amin", "abs", "float", "heaviside",
                     "isnan", "where", "reduce", "maximum", "minimum", "copysign"})
"""The names of the module namespace a kept function may use: the functions and constants SymPy's NumPy and math
printers write (its tables of known functions and constants, the matrix ``array``, ``Piecewise``'s ``select``, the
relations and logic, ``Min``/``Max`` (``reduce`` of ``maximum``), ``Heaviside``). None of them reads or writes a file or runs code."""

_NODES = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Call, ast.Name, ast.Constant, ast.List, ast.Tuple,
          ast.IfExp, ast.Compare, ast.BoolOp, ast.keyword, ast.Load, ast.Subscript, ast.Slice,
          ast.operator, ast.unaryop, ast.cmpop, ast.boolop)


def _function(source) -> ast.Module | None:
    """``source`` parsed, when it is one function of the shape :func:`sympy.lambdify` writes whose expressions are
    arithmetic on its own names and :data:`ALLOWED` (the module docstring); else None."""
    try:
        tree = ast.parse(source)
    except (SyntaxError, ValueError, TypeError):
        return None
    if len(tree.body) != 1 or not isinstance(tree.body[0], ast.FunctionDef):
        return None
    fn = tree.body[0]
    a = fn.args
    if fn.decorator_list or fn.returns or a.vararg or a.kwarg or a.kwonlyargs or a.posonlyargs or a.defaults:
        return None
    local = {arg.arg for arg in a.args}
    for i, statement in enumerate(fn.body):
        if isinstance(statement, ast.Expr) and i == 0 and isinstance(statement.value, ast.Constant) \
                and isinstance(statement.value.value, str):
            continue  # a docstring
        if isinstance(statement, ast.Return) and i == len(fn.body) - 1 and statement.value is not None:
            return tree if _expression(statement.value, local) else None
        if not isinstance(statement, ast.Assign) or len(statement.targets) != 1:
            return None
        if not _expression(statement.value, local):
            return None
        target = statement.targets[0]
        names = target.elts if isinstance(target, (ast.List, ast.Tuple)) else [target]
        if not all(isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store) and not n.id.startswith("__")
                   for n in names):
            return None
        local |= {n.id for n in names}
    return None


def _expression(node: ast.AST, local: set) -> bool:
    for child in ast.walk(node):
        if not isinstance(child, _NODES):
            return False
        if isinstance(child, ast.Name) and not (child.id in local or child.id in ALLOWED):
            return False
        if isinstance(child, ast.Call):
            if not (isinstance(child.func, ast.Name) and child.func.id in ALLOWED):
                return False
            if any(k.arg not in ("axis", "default") for k in child.keywords):
                return False
        if isinstance(child, ast.Subscript) and not isinstance(child.value, ast.Name):
            return False
        if isinstance(child, ast.Constant) and isinstance(child.value, (str, bytes)) \
                and child.value not in ("nan", "inf", "-inf"):
            return False
    return True
