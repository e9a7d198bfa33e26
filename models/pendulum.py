"""Mathematical pendulum, Example 3.12 (Figure 3.31).

A point mass ``m`` on a massless rigid rod of length ``l`` swings about the ``e_x`` axis; gravity acts in
``-e_z``. The angle ``phi`` is measured from the downward vertical, so that the mass is at
``y = l sin(phi)``, ``z = -l cos(phi)`` (3.109). Equation of motion (3.111): ``m l² phi'' = -m g l sin(phi)``.
"""

from harness.modeling.system import Coordinate, Gravity, Joint, Link, Parameter, System

m = Parameter("m", 1.0, "kg", "point mass")
l = Parameter("l", 1.0, "m", "length of the massless rod")
g = Parameter("g", 9.81, "m/s^2", "acceleration due to gravity")

SYSTEM = System(
    name="pendulum",
    title="Mathematical pendulum",
    lecture="Example 3.12; (3.109), (3.111), (3.112)",
    parameters=(m, l, g),
    coordinates=(Coordinate("phi", "rad", "angle from the downward vertical"),),
    links=(Link("bob", mass=m.symbol, com=(0, 0, -l.symbol), description="point mass m at the rod's end"),),
    joints=(Joint("phi", "revolute", "world", "bob", axis="x"),),
    gravity=Gravity(g.symbol, (0, 0, -1)),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
from harness.modeling.claims import Claim  # noqa: E402
import sympy as _sp  # noqa: E402

_phi = SYSTEM.coordinates[0]
CLAIMS = [
    Claim("(3.109)", "position:bob", _sp.Matrix([0, l.symbol * _sp.sin(_phi.symbol), -l.symbol * _sp.cos(_phi.symbol)]),
          "position of the mass: y = l sin(phi), z = -l cos(phi)"),
    Claim("(3.111)", "eom", m.symbol * l.symbol**2 * _phi.accel + m.symbol * g.symbol * l.symbol * _sp.sin(_phi.symbol),
          "m l² phi'' = -m g l sin(phi)"),
]

# ----------------------------------------------------------------------------- scenes
from harness.modeling.scenes import Scene  # noqa: E402

SCENES = [
    Scene("swing", "Example 3.12: released at 60° from rest, gravity only (conservative)", (1.0472,), (0.0,), 4.0,
          frozenset({"gravity"})),
]
