"""Mass on a rough surface: dry friction and structural change, Section 3.5.2; (3.76)-(3.80).

A mass ``m`` slides along ``e_x`` on a horizontal rough surface under an external force ``f_e``; gravity in
``-e_z`` presses it on the surface (``f_N = m g``, (3.76b)). Coulomb's law: it sticks while ``|f_e| <= mu_H f_N``
and ``ẋ = 0`` (3.80a); otherwise it slides with ``f_C = mu_C f_N sgn(ẋ)`` (3.78), (3.79), (3.80b).

This model is the *sliding* branch (3.80b): the friction force ``-mu_C m g sgn(ẋ)`` is an external force
evaluated from the friction law and applied by each engine through its Jacobian (at ``ẋ = 0`` it vanishes).
Sticking and the switching between the branches are events of the trajectory: the stick-slip scene checks
them (MuJoCo's own dry friction, ``frictionloss``, against the event-located symbolic simulation).
"""

from sympy import sign

from harness.modeling import (WORLD, Claim, Coordinate, Gravity, Input, Joint, JointInput, Link, Parameter, Point,
                              PointForce, Scene, Sine, StickSlip, System, standard_gravity)

m = Parameter("m", 1.0, "kg", "mass")
mu_H = Parameter("mu_H", 0.3, "1", "static friction coefficient")
mu_C = Parameter("mu_C", 0.2, "1", "sliding friction coefficient")
g = standard_gravity()
f_e = Input("f_e", "N", "external horizontal force")
x = Coordinate("x", "m", "position of the mass")

SYSTEM = System(
    name="stick_slip",
    title="Dry friction: sticking and sliding",
    lecture="Section 3.5.2; (3.76)-(3.80)",
    status="sliding branch (3.80b); sticking and switching left to the scenes",
    parameters=(mu_H,),  # sticking: in the scenes only
    coordinates=(x,),
    links=(Link("mass", m),),
    joints=(Joint("x", "prismatic", WORLD, "mass", axis="x"),),
    gravity=Gravity(g, (0, 0, -1)),
    forces=(JointInput("push", "x", f_e),
            PointForce("sliding_friction", Point("mass", (0, 0, 0), "contact"), (-mu_C * m * g * sign(x.rate), 0, 0))),
    doc=__doc__,
)

CLAIMS = [
    Claim("(3.79)", "eom", m * x.accel - (f_e - mu_C * m * g * sign(x.rate)), "m x'' = f_e - mu_C m g sgn(x')"),
    Claim("(3.80b)", "eom", m * x.accel - (f_e - mu_C * m * g * sign(x.rate)),
          "sliding branch: x' = v, m v' = f_e - mu_C m g sgn(v)",
          note="v → x_dot and v' → x_ddot by the first row x' = v of the same system (the state's definition); "
               "the second row is transcribed as its residual"),
]

_amplitude = 1.2 * mu_H.default * m.default * g.default   # 1.2 times the largest force sticking can hold

SCENES = [
    Scene("stick_slip", "Section 3.5.2, (3.80): from rest under f_e = 1.2 mu_H m g sin(pi t); sticks, breaks "
          "away where |f_e| = mu_H m g, slides against mu_C m g, comes to rest and sticks again, in both "
          "directions", (0.0,), (0.0,), 4.0, {"inputs", "external", "friction"},
          inputs={f_e: Sine(_amplitude, 0.5)}, events=(StickSlip(x, mu_H, mu_C, m * g),)),
    Scene("holds", "Section 3.5.2, (3.80a): from rest under f_e = 0.8 mu_H m g sin(pi t), a force sticking can hold "
          "throughout: the friction never switches (a bound over the horizon, harness.scenes.effects), so the "
          "sliding friction, 0 at x' = 0, cannot act; the event-located runs must find no breakaway",
          (0.0,), (0.0,), 4.0, {"inputs", "friction"},
          inputs={f_e: Sine(0.8 * mu_H.default * m.default * g.default, 0.5)},
          events=(StickSlip(x, mu_H, mu_C, m * g),)),
]
