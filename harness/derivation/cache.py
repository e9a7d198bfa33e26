"""On-disk cache of symbolic derivations, keyed by a hash of the model, and of other symbolic results that are
functions of their inputs (:func:`remembered`).

An entry is computed once across processes (:func:`once`): two test workers, or two commands run at the same time,
that need the same missing entry do not both compute it; the second waits for the first and reads what it stored.

Entries are JSON files of ``srepr`` strings with a SHA-256 checksum of their content. An entry that does
not parse or whose checksum does not match is not trusted: it is discarded and the derivation rebuilt.
A derivation whose expressions are small graphs but huge trees (the per-body derivation of
:func:`harness.derivation.derive.derive`) is stored as a graph (``graph=True``): its common subexpressions as numbered
replacements, each written once, and rebuilt in order with ``xreplace`` (``srepr`` of the trees would not end).
Set ``HARNESS_CACHE_DIR`` to move the cache (default: ``.cache/derivations`` in the project); what else a run keeps
(:mod:`harness.kept`) goes beside it, into its parent folder: name a ``derivations`` folder inside an empty one.

Nothing read from the cache can run code. The checksum detects damage, not tampering (anyone who can write an
entry can recompute it), so an entry is read by a parser that accepts only what ``srepr`` writes: calls of SymPy
expression classes (``Add``, ``Symbol``, ``sin``, the dense matrix classes …) whose arguments are such calls,
lists, integers and the few named constants; a string only as the name of a ``Symbol`` (printable text) or the
digits of a ``Float``; keyword arguments only with ``True``/``False``/integer values. Anything else — an
attribute, a subscript, any other name, a string where SymPy would ``sympify`` it — rejects the entry, which is
then rebuilt. The accepted syntax tree is evaluated without builtins.
"""

from __future__ import annotations

import ast
import functools
import hashlib
import json
import os
import re
import threading
from collections.abc import Mapping
from contextlib import contextmanager, nullcontext
from dataclasses import dataclass
from pathlib import Path

import sympy as sp
from sympy.core.parameters import distribute

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


_holding = threading.local()


@contextmanager
def once(key: str):
    """Hold the lock of entry ``key`` (an advisory ``flock`` on ``<key>.lock`` beside it) while it is looked up
    again and computed: a process that finds the entry missing and another that is computing it waits for that
    one, then reads the entry. A process already computing an entry does not wait for another's lock (an entry
    computed within another's computation is computed there without it), so two processes never wait for each
    other; a cache folder that takes no lock file is used without one. The lock file is removed when the entry is
    stored (a process that opens a new one after that finds the entry), so none are left behind."""
    if getattr(_holding, "key", None) is not None:
        yield
        return
    import fcntl

    lock = cache_dir() / f"{key}.lock"
    try:
        cache_dir().mkdir(parents=True, exist_ok=True)
        handle = os.open(lock, os.O_CREAT | os.O_RDWR, 0o644)
    except OSError:
        yield
        return
    try:
        fcntl.flock(handle, fcntl.LOCK_EX)
        _holding.key = key
        yield
    finally:
        _holding.key = None
        try:
            lock.unlink(missing_ok=True)
        except OSError:
            pass
        os.close(handle)   # releases the lock


def checksum(entries: dict) -> str:
    """SHA-256 of a JSON document (keys sorted): what an entry kept on disk is checked against when read."""
    return hashlib.sha256(json.dumps(entries, sort_keys=True).encode()).hexdigest()


def load(key: str, as_computed: bool = False) -> dict | None:
    """The stored values of ``key`` (None when absent or not trusted); ``as_computed``: see :func:`_read`."""
    loaded = load_graph(key, as_computed)
    return None if loaded is None else loaded[0]


def load_graph(key: str, as_computed: bool = False) -> tuple[dict, Graph | None] | None:
    """``(values, graph)`` of ``key``: the stored values, and for an entry stored as a graph the same in its
    stored form (:class:`Graph`), else None; None when absent or not trusted."""
    path = cache_dir() / f"{key}.json"
    if not path.exists():
        return None
    try:
        doc = json.loads(path.read_text())
        entries = doc["entries"]
        replacements = doc.get("replacements", [])
        if doc["sha256"] != checksum({"entries": entries, "replacements": replacements} if replacements
                                      else entries):
            raise ValueError("checksum mismatch")
        return _read(entries, replacements, as_computed)
    except Exception:  # noqa: BLE001 - any damage means: do not trust, rebuild
        path.unlink(missing_ok=True)
        return None


def _read(entries: dict, replacements: list, as_computed: bool = False) -> tuple[dict, Graph | None]:
    """The values of an entry's texts (and its :class:`Graph` when it has replacements); an entry stored as a graph
    gives its values as :class:`Trees`, each built when first read. ``as_computed`` (an entry without replacements):
    evaluated as SymPy builds a tree but without distributing a number over a sum, which gives back the tree
    ``srepr`` wrote (``factor_terms``' ``Mul(1/8, Add(…))`` stays factored; evaluation off altogether would keep
    ``srepr``'s ``Mul(-1, 2, c)`` for ``−2 c``); the derivations are read evaluated, as they always were."""
    names: set = set()     # the replacement symbols defined so far (each text refers to earlier ones only)
    codes = []
    for symbol, text in replacements:
        codes.append((symbol, _code(text, names)))
        names.add(symbol)
    entry_codes = {name: _code(text, names) for name, text in entries.items()}
    if not replacements:
        with distribute(False) if as_computed else nullcontext():
            return {name: _evaluate(code, {}) for name, code in entry_codes.items()}, None
    symbols = {symbol: sp.Symbol(symbol) for symbol in names}
    reduced = {name: _evaluate(code, symbols) for name, code in entry_codes.items()}
    return Trees(entry_codes, codes), Graph(tuple(codes), reduced,
                                            hashlib.sha256(json.dumps(replacements).encode()).hexdigest())


class Trees(Mapping):
    """The values of an entry stored as a graph, each built when first read: its stored form with every
    replacement symbol standing for that replacement's tree, the replacements built in stored order, each once.
    A compiler takes the stored form (:class:`Graph`); only what reads a tree (a claim, the report's equations)
    pays for building them: SymPy's evaluation of the trees was 2.8 s of each load of a 6-DoF arm (example-robot-data's
    kinova, loaded twice by ``harness robots --symbolic``: 7.3 → 1.7 s), where ``θ = φ(q)`` needs none of them."""

    def __init__(self, entries: dict, replacements: list):
        self._entries, self._replacements = entries, replacements
        self._shared: dict = {}   # a replacement symbol's name -> its tree
        self._values: dict = {}

    def __getitem__(self, name: str):
        if name not in self._values:
            code = self._entries[name]
            names = set(code.co_names)
            used = [k for k, (symbol, _) in enumerate(self._replacements) if symbol in names]
            for symbol, text in self._replacements[len(self._shared):max(used, default=-1) + 1]:
                self._shared[symbol] = _evaluate(text, self._shared)
            self._values[name] = _evaluate(code, self._shared)
        return self._values[name]

    def __contains__(self, name) -> bool:  # without building the tree (Mapping's would read it)
        return name in self._entries

    def __iter__(self):
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)


@dataclass(frozen=True, eq=False)
class Graph:
    """Values stored as a graph (``store(..., graph=True)``), in the form a compiler takes them: :attr:`replacements`
    ``((symbol, value), …)``, each value in the symbols of earlier ones, and each entry ``reduced`` in those symbols.
    Compiling the values themselves would search the huge trees for their common subexpressions once more
    (SymPy's ``cse`` comparing equal sub-trees node by node: 10 s of the 6-DoF so101's 17)."""

    codes: tuple               # ``(symbol name, compiled text)`` of each stored replacement, checked (:func:`_code`)
    reduced: dict
    digest: str | None = None  # SHA-256 of the stored replacements' texts (keys the compiled code of this graph)

    @functools.cached_property
    def replacements(self) -> tuple:
        """The replacements' values, built when a compiler first needs them: a function whose generated code is
        kept on disk (:mod:`harness.derivation.lambdified`, keyed by the reduced entries and :attr:`digest`)
        needs none of them. Building them at every load cost ``harness robots --symbolic`` about 2 CPU s, every
        function read from disk (three runs each, alternating, one process: its robots' "derive or load" seconds
        summed 3.3–4.5 s built, 2.0–2.1 s not; user time 16.1–19.9 s against 14.2–18.0 s)."""
        symbols = {name: sp.Symbol(name) for name, _ in self.codes}
        return tuple((symbols[name], _evaluate(code, symbols)) for name, code in self.codes)

    def __reduce__(self):  # code objects do not pickle: a copy sent to another process carries the values
        return _built_graph, (self.replacements, self.reduced, self.digest)

    @property
    def cse(self):
        """``lambdify``'s ``cse`` of expressions in this graph's symbols (:meth:`needed`), with the graph's digest as its
        ``cache_key`` (:mod:`harness.derivation.lambdified`)."""
        def cse(exprs):
            return self.needed(exprs)
        cse.cache_key = None if self.digest is None else f"graph {self.digest}"
        return cse

    def needed(self, exprs):
        """The replacements expressions in this graph's symbols need, in order, and the expressions as they are."""
        needed = set().union(*(getattr(e, "free_symbols", ()) for e in exprs))
        kept = []
        for symbol, value in reversed(self.replacements):
            if symbol in needed:
                kept.append((symbol, value))
                needed |= value.free_symbols
        return kept[::-1], exprs


def _built_graph(replacements: tuple, reduced: dict, digest: str | None) -> Graph:
    graph = Graph((), reduced, digest)
    graph.__dict__["replacements"] = replacements  # what the cached property would have built
    return graph


GRAPH_SYMBOLS = "_cse_"  # names of the stored replacements (no model symbol starts with an underscore)
_REPLACEMENT = re.compile(r"Symbol\('(" + GRAPH_SYMBOLS + r"\d+)'\)")
_CLASSES = {name: obj for name in dir(sp) if not name.startswith("_")
            for obj in [getattr(sp, name)]
            if isinstance(obj, type) and issubclass(obj, (sp.Basic, sp.MatrixBase))}
_CONSTANTS = {name: getattr(sp, name) for name in ("pi", "E", "I", "oo", "zoo", "nan", "true", "false")}
_NAMED_BY_STRING = {"Symbol", "Dummy", "Wild", "Function", "Float"}
_FLOAT = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\Z")


def _is_name(text: str) -> bool:
    """A symbol's name: printable text (the lecture's ``I_zz^S``); a name is never evaluated, only held."""
    return 0 < len(text) <= 200 and text.isprintable()


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
                valid = _FLOAT.match(arg.value) if node.func.id == "Float" else _is_name(arg.value)
                if k != 0 or node.func.id not in _NAMED_BY_STRING or not valid:
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


def remembered(kind: str, code: tuple[Path, ...], inputs: tuple, compute):
    """The SymPy value of ``compute()``, remembered on disk under a hash of ``kind``, the source of the modules that
    compute it (``code``), SymPy's version and the ``srepr`` of ``inputs``: a symbolic result that is a function of
    these (a reduction of a printed equation to zero, its lecture form) is computed once and read back by later
    runs, as a derivation is. It is read back as computed (``as_computed``, :func:`_read`), and the value returned is
    always the one read back, so a run that computes it and one that reads it give the same result. A computation
    under a CPU-time budget (:func:`harness.limits.cpu_budget`) is remembered as the machine that first ran it
    reached it."""
    digest = hashlib.sha256()
    for part in (kind.encode(), sp.__version__.encode(), *(path.read_bytes() for path in code),
                 *(sp.srepr(x).encode() for x in inputs)):
        digest.update(part + b"\0")
    key = f"{kind}-{digest.hexdigest()[:24]}"
    stored = load(key, as_computed=True)
    if stored is None:
        with once(key):
            stored = load(key, as_computed=True)
            if stored is None:
                stored, _ = store(key, {"value": compute()}, as_computed=True)
    return stored["value"]


def store(key: str, values: dict, graph: bool = False, as_computed: bool = False) -> tuple[dict, Graph | None]:
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
        doc = {"sha256": checksum({"entries": entries, "replacements": pairs}), "entries": entries,
               "replacements": pairs}
    else:
        entries, pairs = {name: sp.srepr(value) for name, value in values.items()}, []
        doc = {"sha256": checksum(entries), "entries": entries}
    try:
        atomic_write_text(cache_dir() / f"{key}.json", json.dumps(doc))
    except OutputError:  # a full disk or a folder gone read-only: the derivation in memory is still good
        pass
    return _read(entries, pairs, as_computed)
