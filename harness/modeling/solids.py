"""Homogeneous solids in a body-fixed frame: the shapes the lecture builds its bodies from (3.118)-(3.128).

A model may say which solids a link's body is made of (:attr:`harness.modeling.system.Link.solids`, pairs of a solid
and its density): the pictures then show those solids instead of the solid equivalent to its inertia tensor, and a
test integrates their mass, centre of mass and inertia tensor over their volumes
(:func:`harness.derivation.bodies.solid_inertia`) and finds the link's. The integrals themselves live there.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp


@dataclass(frozen=True)
class Box:
    """A homogeneous cuboid ``x0 ≤ x ≤ x1``, ``y0 ≤ y ≤ y1``, ``z0 ≤ z ≤ z1`` in a body-fixed frame."""

    x: tuple
    y: tuple
    z: tuple

    @staticmethod
    def around(centre, edges) -> "Box":
        """The cuboid with edges ``(a, b, c)`` along x, y, z centred at ``centre``."""
        return Box(*[(sp.sympify(c) - sp.sympify(e) / 2, sp.sympify(c) + sp.sympify(e) / 2)
                     for c, e in zip(centre, edges)])


@dataclass(frozen=True)
class Cylinder:
    """A homogeneous solid cylinder of ``radius`` about the frame's z axis, ``0 ≤ z ≤ length``."""

    radius: object
    length: object


@dataclass(frozen=True)
class Ball:
    """A homogeneous solid ball of ``radius`` centred at the frame's origin."""

    radius: object


SOLIDS = (Box, Cylinder, Ball)
