"""The numbers of every source at a state, kept within a process while the oracles of a system check it.

The conformance run and every printed equation of a system are checked first on the same states
(:func:`harness.compare.strategies.system_states`), and the numbers at a state do not depend on which oracle asks:
our derivation's quantities with their scales and κ(M) (``"derivation"``), each engine's evaluation (by its name).
Within :func:`sharing` each is computed once: by the conformance run, which evaluates every source at every state,
or by the first claim that needs it. Nothing is kept outside the block; the engines' models must not change within
it (a test that swaps an engine's exported file evaluates outside it)."""

from __future__ import annotations

from contextlib import contextmanager

KEPT = 4096
"""States whose evaluations are kept at most (then all are dropped): a system's 200 states and those its claims put
at rest or at an equilibrium."""

_KEPT: dict = {}
_SHARING = [0]


@contextmanager
def sharing():
    """Within the block (nested blocks share one), :func:`at` keeps what is evaluated at a state; dropped at the
    end of the outermost block."""
    _SHARING[0] += 1
    try:
        yield
    finally:
        _SHARING[0] -= 1
        if not _SHARING[0]:
            _KEPT.clear()


def at(state) -> dict:
    """The evaluations at ``state`` by source, to be read or filled in: kept within :func:`sharing` (each source's
    entry written once, never changed afterwards), else a dict for this call only."""
    if not _SHARING[0]:
        return {"system": state.system}
    kept = _KEPT.get(state.key)
    if kept is not None and kept["system"] is state.system:
        return kept
    if len(_KEPT) >= KEPT:
        _KEPT.clear()
    kept = _KEPT[state.key] = {"system": state.system}
    return kept
