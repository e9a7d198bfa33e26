"""The modeling vocabulary a model module imports: a lecture system described once, symbolically, with the
equations the lecture prints about it (claims) and the simulations its text describes (scenes, events). It
depends on SymPy and NumPy only: loading the catalogue loads no engine.

* :mod:`harness.modeling.system` — parameters, coordinates and inputs (SymPy symbols carrying their meaning:
  ``m = Parameter("m", 1.0, "kg", "point mass")``, then ``m * l**2 * phi.accel``), bodies, joints, force
  elements, closures, the map ``θ = φ(q)``, and :class:`System`, which collects its parameters and validates;
* :mod:`harness.modeling.solids` — homogeneous solids (cuboid, cylinder, ball) a body is made of;
* :mod:`harness.modeling.claims` — :class:`Claim`, a printed equation;
* :mod:`harness.modeling.scenes` — :class:`Scene` and the input signals ``u(t)``;
* :mod:`harness.modeling.events` — structural changes: stick-slip, rolling or slipping, lift-off.
"""

from harness.modeling.claims import Claim, Printed, printed_matrix
from harness.modeling.events import LiftOff, RollSlip, StickSlip
from harness.modeling.scenes import Bump, Constant, Scene, Sine, Step
from harness.modeling.solids import Ball, Box, Cylinder
from harness.modeling.system import (WORLD, BodyTorque, Closure, ConstraintForce, Coordinate, Damper, Gravity,
                                     Inertia, Input, Joint, JointDamper, JointInput, JointSpring, Link, Parameter, Point,
                                     PointForce, Spring, System, standard_gravity, steiner)

__all__ = ["WORLD", "Ball", "BodyTorque", "Box", "Bump", "Claim", "Closure", "Constant", "ConstraintForce",
           "Coordinate", "Cylinder", "Damper", "Gravity", "Inertia", "Input", "Joint", "JointDamper", "JointInput",
           "JointSpring", "LiftOff", "Link", "Parameter", "Point", "PointForce", "Printed", "printed_matrix",
           "RollSlip", "Scene", "Sine", "Spring", "Step", "StickSlip", "System", "standard_gravity", "steiner"]
