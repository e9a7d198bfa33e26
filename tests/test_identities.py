"""identically_zero, the proof behind a printed equation's symbolic decision and a scene's idle constraint rows: a
yes is exact, a no is said only where it is proved, and no answer depends on the machine's speed."""

import sympy as sp

from harness.derivation.identities import identically_zero

a, b, x = sp.symbols("a b x", real=True)


def test_identities_of_sines_and_cosines_are_proved():
    """Sums and multiples of angles, powers of s² + c², tangents, a rational function, a root of equal radicands:
    each vanishes, proved."""
    assert identically_zero(sp.sin(a + b) - sp.sin(a) * sp.cos(b) - sp.cos(a) * sp.sin(b)) is True
    assert identically_zero(sp.sin(2 * a) - 2 * sp.sin(a) * sp.cos(a)) is True
    assert identically_zero((sp.sin(3 * a) * sp.cos(b) - 3 * sp.sin(a) * sp.cos(b) + 4 * sp.sin(a) ** 3 * sp.cos(b))
                            / (2 + sp.cos(a))) is True
    assert identically_zero((sp.sin(a) ** 2 + sp.cos(a) ** 2) ** 3 - 1) is True
    assert identically_zero(sp.tan(a) * sp.cos(a) - sp.sin(a)) is True
    assert identically_zero(1 / (1 + sp.cos(a)) - (1 - sp.cos(a)) / sp.sin(a) ** 2) is True
    assert identically_zero(sp.sqrt(x ** 2 + sp.sin(a) ** 2) - sp.sqrt(x ** 2 + 1 - sp.cos(a) ** 2)) is True


def test_what_is_not_zero_is_no_where_proved_and_undecided_elsewhere():
    """A polynomial in sines, cosines and symbols that is not 0 is proved not to be (False); where other functions
    remain (an arcsine) or angles are not independent (a half angle beside the whole one), a remainder proves
    nothing (None). A term float arithmetic would round away (1 − 1e-30 is 1.0 in floats) is kept: the floats are
    made exact first."""
    assert identically_zero(sp.sin(a) ** 2 - sp.cos(a) ** 2) is False
    assert identically_zero(sp.sin(a) ** 2 + sp.cos(a) ** 2) is False
    tiny = sp.Add(x * (sp.sin(a) ** 2 + sp.cos(a) ** 2), -x, sp.Float(1e-30) * x, evaluate=False)
    assert identically_zero(tiny) is False
    assert identically_zero(sp.asin(sp.sin(a)) - a) is None
    assert identically_zero(sp.sin(a) - 2 * sp.sin(a / 2) * sp.cos(a / 2)) is None


def test_a_numerator_beyond_the_bound_of_terms_is_not_decided():
    """The bound is counted before expanding, so it is the same on every machine (no CPU-time budget): 3⁶ terms
    are decided under the default bound and not under a bound of 1 000 (the expansion and the product: 1 458)."""
    big = sp.prod([sp.sin(y) + sp.cos(y) + 1 for y in sp.symbols("y0:6")])
    assert identically_zero(big - sp.expand(big)) is True
    assert identically_zero(big - sp.expand(big), limit=1000) is None
