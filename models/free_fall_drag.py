"""Free fall with altitude-dependent air drag, Exercise 3.9.

A body of mass ``m`` (cross-section ``A``, drag coefficient ``c_W``) at altitude ``h`` above ground, gravity in
``-e_z``; air density ``rho(h) = rho_0 exp(-h/k)``. The drag force opposes the velocity,
``f_D = -c_W A rho(h) v |v| / 2`` (3.9's solution writes ``+ c_W A rho v²/2``, which is the same while the body
falls, ``v <= 0``, and points the wrong way for ``v > 0``: the claim records that convention).

Engine treatment: the drag is an external force on the body computed from the drag law at the state and
applied by each engine through its own Jacobian (``mj_applyFT``; Pinocchio's frame Jacobian). The engines
therefore check mass, gravity and how the force enters the dynamics, *not* the drag law itself.
The drawn altitudes cover the exercise's fall from 39 km.
"""

import sympy as sp

from harness.modeling.claims import Claim
from harness.modeling.system import Coordinate, Gravity, Joint, Link, Parameter, Point, PointForce, System, WORLD

m = Parameter("m", 100.0, "kg", "mass of the falling body")
A = Parameter("A", 0.5, "m^2", "cross-sectional area")
c_W = Parameter("c_W", 0.5, "1", "drag coefficient")
rho_0 = Parameter("rho_0", 1.2, "kg/m^3", "air density at h = 0")
k = Parameter("k", 9100.0, "m", "scale height of the atmosphere")
g = Parameter("g", 9.81, "m/s^2", "acceleration due to gravity")
h = Coordinate("h", "m", "altitude above ground", range=(0.0, 40000.0))

_rho = rho_0.symbol * sp.exp(-h.symbol / k.symbol)

SYSTEM = System(
    name="free_fall_drag",
    title="Free fall with altitude-dependent drag",
    lecture="Exercise 3.9",
    status="engines: drag applied as an external force from the model's law; mass and gravity checked",
    parameters=(m, A, c_W, rho_0, k, g),
    coordinates=(h,),
    links=(Link("body", m.symbol),),
    joints=(Joint("h", "prismatic", WORLD, "body", axis="z"),),
    gravity=Gravity(g.symbol, (0, 0, -1)),
    forces=(PointForce("drag", Point("body", (0, 0, 0), "body_centre"),
                       (0, 0, -c_W.symbol * A.symbol * _rho * h.rate * sp.Abs(h.rate) / 2)),),
    doc=__doc__,
)

CLAIMS = [
    Claim("Solution of Exercise 3.9", "eom",
          m.symbol * h.accel - (-m.symbol * g.symbol + c_W.symbol * A.symbol * _rho * h.rate**2 / 2),
          "m v' = -m g + c_W A rho_0 exp(-h/k) v²/2",
          conventions={"drag written for the falling body (v <= 0): v² = -v|v|": {h.rate**2: -h.rate * sp.Abs(h.rate)}}),
]

from harness.modeling.scenes import Scene  # noqa: E402

SCENES = [
    Scene("stratosphere", "Exercise 3.9: the exercise's fall from rest at h(0) = 39 km with its parameters; "
          "gravity and the thin air's drag rho(h) = rho_0 exp(-h/k) (first 5 s)", (39000.0,), (0.0,), 5.0,
          frozenset({"gravity", "external"})),
    Scene("dense_air", "Exercise 3.9: the same body at 2 km, falling at 60 m/s in dense air, accelerates "
          "towards its terminal velocity (about 90 m/s there; it reaches 78 m/s in 5 s) as the drag grows",
          (2000.0,), (-60.0,), 5.0, frozenset({"gravity", "external"})),
]
