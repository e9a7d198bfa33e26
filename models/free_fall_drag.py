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

from sympy import Abs, exp

from harness.modeling import (WORLD, Claim, Coordinate, Gravity, Joint, Link, Parameter, Point, PointForce, Scene,
                              System, standard_gravity)

m = Parameter("m", 100.0, "kg", "mass of the falling body")
A = Parameter("A", 0.5, "m^2", "cross-sectional area")
c_W = Parameter("c_W", 0.5, "1", "drag coefficient")
rho_0 = Parameter("rho_0", 1.2, "kg/m^3", "air density at h = 0")
k = Parameter("k", 9100.0, "m", "scale height of the atmosphere")
g = standard_gravity()
h = Coordinate("h", "m", "altitude above ground", range=(0.0, 40000.0))
v = h.rate

rho = rho_0 * exp(-h / k)

SYSTEM = System(
    name="free_fall_drag",
    title="Free fall with altitude-dependent drag",
    lecture="Exercise 3.9",
    status="engines: drag applied as an external force from the model's law; mass and gravity checked",
    coordinates=(h,),
    links=(Link("body", m),),
    joints=(Joint("h", "prismatic", WORLD, "body", axis="z"),),
    gravity=Gravity(g, (0, 0, -1)),
    forces=(PointForce("drag", Point("body", (0, 0, 0), "body_centre"), (0, 0, -c_W * A * rho * v * Abs(v) / 2)),),
    doc=__doc__,
)

CLAIMS = [
    Claim("Solution of Exercise 3.9", "eom", m * h.accel - (-m * g + c_W * A * rho * v**2 / 2),
          "m v' = -m g + c_W A rho_0 exp(-h/k) v²/2",
          conventions={"drag written for the falling body (v <= 0): v² = -v|v|": {v**2: -v * Abs(v)}}),
]

SCENES = [
    Scene("stratosphere", "Exercise 3.9: the exercise's fall from rest at h(0) = 39 km with its parameters; "
          "gravity and the thin air's drag rho(h) = rho_0 exp(-h/k) (first 5 s)", (39000.0,), (0.0,), 5.0,
          {"gravity", "external"}),
    Scene("dense_air", "Exercise 3.9: the same body at 2 km, falling at 60 m/s in dense air, accelerates "
          "towards its terminal velocity (about 90 m/s there; it reaches 78 m/s in 5 s) as the drag grows",
          (2000.0,), (-60.0,), 5.0, {"gravity", "external"}),
]
