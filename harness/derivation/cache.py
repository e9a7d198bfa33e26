"""On-disk cache of symbolic derivations, keyed by a hash of the model.

Entries are JSON files of ``srepr`` strings with a SHA-256 checksum of their content. An entry that does
not parse or whose checksum does not match is not trusted: it is discarded and the derivation rebuilt.
A derivation whose expressions are small graphs but huge trees (the per-body derivation of
:func:`harness.derivation.derive.derive`) is stored as a graph (``graph=True``): its common subexpressions as numbered
replacements, each written once, and rebuilt in order with ``xreplace`` (``srepr`` of the trees would not end).
Set ``HARNESS_CACHE_DIR`` to move the cache (default: ``.cache/derivations`` in the project).

Nothing read from the cache can run code. The checksum detects damage, not tampering (anyone who can write an
entry can recompute it), so an entry is read by a parser that accepts only what ``srepr`` writes: calls of SymPy
expression classes (``Add``, ``Symbol``, ``sin``, the dense matrix classes …) whose arguments are such calls,
lists, integers and the few named constants; a string only as the name of a ``Symbol`` (an identifier) or the
digits of a ``Float``; keyword arguments only with ``True``/``False``/integer values. Anything else — an
attribute, a subscript, any other name, a string where SymPy would ``sympify`` it — rejects the entry, which is
then rebuilt. The accepted syntax tree is evaluated without builtins.
"""

from __future__ import annotations

import ast
import hashlib
import json
import os
import re
from dataclasses import dataclass
from pathlib import Path

import sympy as sp

from harness.errors import OutputError
from harness.io import atomic_write_text

PROJECT_ROOT = Path(__file__).resolve().parents[2]


# The derivation's source is part of the cache key: a changed derivation never reads old entries.
_DERIVATION_SOURCES = ("modeling/system.py", "derivation/kinematics.py", "derivation/derive.py", "derivation/cache.py")


def code_version() -> str:
    digest = hashlib.sha256()
    for name in _DERIVATION_SOURCES:
        digest.update((Path(__file__).parents[1] / name).read_bytes())
    return digest.hexdigest()[:12]


def cache_dir() -> Path:
    return Path(os.environ.get("HARNESS_CACHE_DIR", PROJECT_ROOT / ".cache" / "derivations"))


def _checksum(entries: dict[str, str]) -> str:
    return hashlib.sha256(json.dumps(entries, sort_keys=True).encode()).hexdigest()


def load(key: str) -> dict | None:
    """The stored values of ``key`` (None when absent or not trusted)."""
    loaded = load_graph(key)
    return None if loaded is None else loaded[0]


def load_graph(key: str) -> tuple[dict, Graph | None] | None:
    """``(values, graph)`` of ``key``: the stored values, and for an entry stored as a graph the same in its
    stored form (:class:`Graph`), else None; None when absent or not trusted."""
    path = cache_dir() / f"{key}.json"
    if not path.exists():
        return None
    try:
        doc = json.loads(path.read_text())
        entries = doc["entries"]
        replacements = doc.get("replacements", [])
        if doc["sha256"] != _checksum({"entries": entries, "replacements": replacements} if replacements
                                      else entries):
            raise ValueError("checksum mismatch")
        return _read(entries, replacements)
    except Exception:  # noqa: BLE001 - any damage means: do not trust, rebuild
        path.unlink(missing_ok=True)
        return None


def _read(entries: dict, replacements: list) -> tuple[dict, Graph | None]:
    """The values of an entry's texts (and its :class:`Graph` when it has replacements)."""
    shared: dict = {}      # a replacement symbol's name -> its expression, built once
    symbols: dict = {}     # a replacement symbol's name -> the symbol
    reduced_replacements = []
    for symbol, text in replacements:  # in order: each refers to earlier ones only
        code = _code(text, shared)
        shared[symbol] = _evaluate(code, shared)
        reduced_replacements.append((sp.Symbol(symbol), _evaluate(code, symbols)))
        symbols[symbol] = sp.Symbol(symbol)
    codes = {name: _code(text, shared) for name, text in entries.items()}
    values = {name: _evaluate(code, shared) for name, code in codes.items()}
    if not replacements:
        return values, None
    reduced = {name: _evaluate(code, symbols) for name, code in codes.items()}
    return values, Graph(tuple(reduced_replacements), reduced)


@dataclass(frozen=True, eq=False)
class Graph:
    """Values stored as a graph (``store(..., graph=True)``), in the form a compiler takes them: ``replacements``
    ``((symbol, value), …)``, each value in the symbols of earlier ones, and each entry ``reduced`` in those symbols.
    Compiling the values themselves would search the huge trees for their common subexpressions once more
    (SymPy's ``cse`` comparing equal sub-trees node by node: 10 s of the 6-DoF so101's 17)."""

    replacements: tuple
    reduced: dict

    def cse(self, exprs):
        """``lambdify``'s ``cse`` of expressions in this graph's symbols: the replacements they need, in order,
        and the expressions as they are."""
        needed = set().union(*(getattr(e, "free_symbols", ()) for e in exprs))
        kept = []
        for symbol, value in reversed(self.replacements):
            if symbol in needed:
                kept.append((symbol, value))
                needed |= value.free_symbols
        return kept[::-1], exprs


GRAPH_SYMBOLS = "_cse_"  # names of the stored replacements (no model symbol starts with an underscore)
_REPLACEMENT = re.compile(r"Symbol\('(" + GRAPH_SYMBOLS + r"\d+)'\)")
_CLASSES = {name: obj for name in dir(sp) if not name.startswith("_")
            for obj in [getattr(sp, name)]
            if isinstance(obj, type) and issubclass(obj, (sp.Basic, sp.MatrixBase))}
_CONSTANTS = {name: getattr(sp, name) for name in ("pi", "E", "I", "oo", "zoo", "nan", "true", "false")}
_NAMED_BY_STRING = {"Symbol", "Dummy", "Wild", "Function", "Float"}
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_FLOAT = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\Z")


class UnsafeEntry(ValueError):
    """A cache entry holding something ``srepr`` does not write."""


def _validate(node: ast.AST, shared: dict) -> None:
    """Accept only the syntax ``srepr`` produces (see the module docstring); raise :class:`UnsafeEntry`."""
    if isinstance(node, ast.Expression):
        return _validate(node.body, shared)
    if isinstance(node, ast.Call):
        if not isinstance(node.func, ast.Name) or node.func.id not in _CLASSES:
            raise UnsafeEntry(f"call of {ast.dump(node.func)[:60]}")
        for k, arg in enumerate(node.args):
            if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
                pattern = _FLOAT if node.func.id == "Float" else _IDENTIFIER
                if k != 0 or node.func.id not in _NAMED_BY_STRING or not pattern.match(arg.value):
                    raise UnsafeEntry(f"string {arg.value[:40]!r} in {node.func.id}")
            else:
                _validate(arg, shared)
        for kw in node.keywords:
            if kw.arg is None or not (isinstance(kw.value, ast.Constant) and type(kw.value.value) in (bool, int)):
                raise UnsafeEntry(f"keyword {kw.arg} of {node.func.id}")
        return None
    if isinstance(node, (ast.List, ast.Tuple)):
        for item in node.elts:
            _validate(item, shared)
        return None
    if isinstance(node, ast.Constant) and type(node.value) in (int, bool):
        return None
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub) and isinstance(node.operand, ast.Constant) \
            and type(node.operand.value) is int:
        return None
    if isinstance(node, ast.Name) and (node.id in _CONSTANTS or node.id in shared):
        return None
    raise UnsafeEntry(f"{type(node).__name__} node")


def _code(text: str, shared: dict):
    """The compiled expression of an ``srepr`` text whose replacement symbols are the names in ``shared``: its
    syntax tree is checked (:func:`_validate`) first. Evaluated by :func:`_evaluate` without builtins in a namespace
    of SymPy's expression classes — faster than ``sympify``, whose tokenizer was 3.8 of the 6.2 s of the 7-DoF arm's
    entry, and with no way to reach anything but those classes."""
    tree = ast.parse(_REPLACEMENT.sub(r"\1", text), mode="eval")
    _validate(tree, shared)
    return compile(tree, "<cache entry>", "eval")


_GLOBALS = {"__builtins__": {}, **_CLASSES, **_CONSTANTS}


def _evaluate(code, shared: dict):
    """The expression of :func:`_code`'s ``code``, its replacement symbols standing for the values in ``shared``."""
    return eval(code, _GLOBALS, shared)  # noqa: S307


def store(key: str, values: dict, graph: bool = False) -> tuple[dict, Graph | None]:
    """Store ``values`` under ``key`` (as a graph: their common subexpressions written once) and return them as
    every later :func:`load_graph` reads them. The texts do not always read back to the same trees (``srepr`` of
    ``factor_terms``' ``Mul(1/8, Add(…))`` reads back distributed, as SymPy evaluates it): a run that derives and
    one that loads compile the same expressions, so that their results are the same to the last bit."""
    if graph:
        reduced_names = list(values)
        replacements, reduced = sp.cse([values[name] for name in reduced_names], order="none",
                                       symbols=sp.numbered_symbols(GRAPH_SYMBOLS))
        entries = {name: sp.srepr(value) for name, value in zip(reduced_names, reduced)}
        pairs = [[symbol.name, sp.srepr(expr)] for symbol, expr in replacements]
        doc = {"sha256": _checksum({"entries": entries, "replacements": pairs}), "entries": entries,
               "replacements": pairs}
    else:
        entries, pairs = {name: sp.srepr(value) for name, value in values.items()}, []
        doc = {"sha256": _checksum(entries), "entries": entries}
    try:
        atomic_write_text(cache_dir() / f"{key}.json", json.dumps(doc))
    except OutputError:  # a full disk or a folder gone read-only: the derivation in memory is still good
        pass
    return _read(entries, pairs)
