"""The project's ``lambdify`` (harness.derivation.lambdified): generated code kept on disk, read back only when it is
arithmetic of the shape lambdify writes."""

import json

import numpy as np
import pytest
import sympy as sp

import harness.kept
import models
from harness.derivation import lambdified
from harness.derivation.lambdified import lambdify


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path / "derivations"))
    return tmp_path / "compiled"


def _generated(monkeypatch) -> list:
    """Counts the functions SymPy generates (a kept one is read, not generated)."""
    calls = []
    real = sp.lambdify

    def counting(args, *rest, **options):
        if args != []:  # the namespace of a module set is taken from a function of no arguments
            calls.append(1)
        return real(args, *rest, **options)
    monkeypatch.setattr(lambdified.sp, "lambdify", counting)
    return calls


X, Y = sp.symbols("x y", real=True)
EXPRESSIONS = [  # what the project compiles: matrices, lists, shared subexpressions, Piecewise, Abs, Min/Max, constants
    (sp.Matrix([[sp.sin(X) * Y, sp.sqrt(X**2 + 1)], [sp.pi * X, sp.exp(-Y) / 3]]), {"cse": True}),
    ([sp.cos(X + Y) ** 2 + sp.cos(X + Y), sp.atan2(Y, X), sp.Float(0.014107263642161838) * X], {"cse": True}),
    (sp.Piecewise((X, X > 0), (-Y, True)) + sp.Abs(Y) + sp.Max(X, Y) + sp.sign(X), {}),
    (sp.Matrix([sp.Heaviside(X) * Y, sp.Min(X, 2) - sp.E]), {"docstring_limit": 0}),
]


@pytest.mark.parametrize("modules", ["numpy", "math", None])
@pytest.mark.parametrize("expr, options", EXPRESSIONS)
def test_kept_code_is_read_back_and_computes_the_same(cache, monkeypatch, modules, expr, options):
    if modules == "math" and isinstance(expr, sp.MatrixBase):
        pytest.skip("the math printer writes no matrices")
    generated = _generated(monkeypatch)
    fresh = lambdify([X, Y], expr, modules=modules, **options)
    assert len(generated) == 1 and len(list(cache.glob("*.json"))) == 1
    kept = lambdify([X, Y], expr, modules=modules, **options)
    assert len(generated) == 1, "read from the cache, not generated again"
    for x, y in [(0.3, -1.7), (-2.0, 0.5), (1e-300, 7.0)]:
        a, b = fresh(x, y), kept(x, y)
        assert np.array_equal(np.asarray(a, dtype=float), np.asarray(b, dtype=float))  # bit for bit


def test_the_key_is_what_decides_the_code(cache, monkeypatch):
    generated = _generated(monkeypatch)
    lambdify([X, Y], X * Y, modules="numpy")
    lambdify([X, Y], X * Y, modules="math")          # other modules
    lambdify([Y, X], X * Y, modules="numpy")          # other arguments
    lambdify([X, Y], X * Y + 1, modules="numpy")      # another expression
    lambdify([X, Y], X * Y, modules="numpy", cse=True)  # other options
    assert len(generated) == 5
    lambdify([X, Y], X * Y, modules="numpy", cse=lambda e: sp.cse(e))  # a cse function without a cache_key: not kept
    lambdify([X, Y], X * Y, modules="numpy", cse=lambda e: sp.cse(e))
    assert len(generated) == 7 and len(list(cache.glob("*.json"))) == 5


def _forge(cache, source: str) -> None:
    (entry,) = cache.glob("*.json")
    entry.write_text(json.dumps({"source": source, "sha256": lambdified._sha(source)}))  # the checksum recomputed


@pytest.mark.parametrize("body", [
    "    __import__('os').system('touch {marker}')\n    return x",
    "    return open('{marker}', 'w')",
    "    return x.__class__",
    "    return load('{marker}')",                                    # a NumPy function that reads a file
    "    return eval('x')",
    "    return (lambda: open('{marker}', 'w'))()",
    "    return [open('{marker}', 'w') for k in [1]]",
    "    import os\n    return x",
    "    y = builtins.open('{marker}', 'w')\n    return x",
    "    return array([x], dtype='{marker}')",
])
def test_a_forged_entry_runs_no_code(cache, tmp_path, body):
    """An entry rewritten with a recomputed checksum is refused unless it is arithmetic of lambdify's shape: the
    payload never runs, and the function is generated again."""
    marker = tmp_path / "ran"
    lambdify([X, Y], X + Y, modules="numpy")
    _forge(cache, "def _lambdifygenerated(x, y):\n" + body.format(marker=marker) + "\n")
    fn = lambdify([X, Y], X + Y, modules="numpy")
    assert fn(1.0, 2.0) == 3.0 and not marker.exists()
    assert "x + y" in json.loads(next(cache.glob("*.json")).read_text())["source"]  # written again


def test_a_damaged_entry_is_generated_again(cache):
    lambdify([X, Y], X - Y, modules="math")
    (entry,) = cache.glob("*.json")
    doc = json.loads(entry.read_text())
    entry.write_text(json.dumps({**doc, "source": doc["source"].replace("x - y", "x + y")}))  # checksum not fixed
    assert lambdify([X, Y], X - Y, modules="math")(1.0, 2.0) == -1.0
    entry.write_text("{not json")
    assert lambdify([X, Y], X - Y, modules="math")(1.0, 2.0) == -1.0
    assert json.loads(entry.read_text())["source"] == doc["source"]


def test_a_built_expression_is_found_by_its_recipe_without_building_it(cache, monkeypatch):
    """``lambdify_built``: the kept code of what ``build()`` returns is found by the recipe's hash (texts that
    decide the expression) without calling ``build``; another recipe builds; a damaged alias builds and compiles as
    ``lambdify`` does (the same code, read by its key)."""
    built = []

    def build():
        built.append(1)
        return sp.Matrix([sp.Abs(X * Y) + sp.Abs(X)])

    fresh = lambdified.lambdify_built(("terms of x*y + x", sp.srepr(X * Y + X)), [X, Y], build, modules="numpy")
    (alias,) = cache.glob("recipes/*.json")
    assert len(built) == 1 and len(list(cache.glob("*.json"))) == 1
    kept = lambdified.lambdify_built(("terms of x*y + x", sp.srepr(X * Y + X)), [X, Y], build, modules="numpy")
    assert len(built) == 1, "found by its recipe: not built again"
    assert np.array_equal(fresh(-0.3, 2.0), kept(-0.3, 2.0)) and float(kept(-0.3, 2.0)[0, 0]) == 0.3 * 2.0 + 0.3
    lambdified.lambdify_built(("terms of x*y - x", sp.srepr(X * Y - X)), [X, Y], build, modules="numpy")
    assert len(built) == 2   # another recipe: built (the same expression: its code read by its key)
    for damaged in ("{not json", json.dumps({"key": "0" * 64, "sha256": "0"}), None):
        if damaged is None:   # intact, but naming code that is not kept
            harness.kept.keep(alias, "0" * 64)
        else:
            alias.write_text(damaged)
        again = lambdified.lambdify_built(("terms of x*y + x", sp.srepr(X * Y + X)), [X, Y], build, modules="numpy")
        assert np.array_equal(again(-0.3, 2.0), fresh(-0.3, 2.0))
    assert len(built) == 5


@pytest.mark.parametrize("name", ["stick_slip", "free_fall_drag", "quarter_car", "governor", "lightweight_robot"])
def test_what_the_project_compiles_is_kept(cache, name):
    """Every function compiled for a system (its quantities, its terms of (5.93), per-body graphs included) is of
    the accepted shape: nothing the project generates falls outside :data:`ALLOWED` (else it would be generated
    anew in every run)."""
    from harness import profiling
    from harness.derivation.compile import CompiledModel, compiled

    system = models.get(name)
    derivation = compiled(system).derivation

    def counts():
        profiling.enable()
        profiling.reset()
        try:
            CompiledModel(system, derivation).warm()
            return profiling.snapshot()["counts"]
        finally:
            profiling.enable(False)
    first = counts()
    assert first.get("compiled code generated", 0) + first.get("compiled code read from the cache", 0) >= 15
    assert "compiled code not kept (outside the accepted shape)" not in first
    second = counts()
    assert "compiled code generated" not in second and second["compiled code read from the cache"] >= 15
