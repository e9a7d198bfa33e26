"""Quarter-car vertical model, Exercise A.4 (Figures A.8, A.9); (A.38)-(A.42).

Wheel mass ``m_R`` at height ``x_R`` and body mass ``m_A`` at height ``x_A`` move along ``e_z``; gravity acts in
``-e_z``. All springs are unstretched for ``x_A = x_R = x_U = 0``. The suspension (spring ``c_A``, damper
``d_A``) acts between wheel and body, the tyre (spring ``c_R``, damper ``d_R``) between the road at ``x_U(t)``
and the wheel (A.38).

Tree: the wheel slides on a prismatic joint from the world (``theta = x_R``), the body on a prismatic joint
from the wheel (``theta = x_A - x_R``: a linear map). The suspension spring and damper are a joint spring and
damper of that relative joint. The road moves: with the inputs ``x_U`` and ``v_U = ẋ_U`` the tyre force
``c_R (x_U - x_R) + d_R (v_U - ẋ_R)`` splits exactly into a spring ``c_R`` and a damper ``d_R`` on the wheel's
joint (the parts in ``x_R``, ``ẋ_R``) and an external force ``c_R x_U + d_R v_U`` on the wheel (the road's part),
which each engine applies through its own Jacobian.

The lecture allows a velocity-dependent suspension damping ``d_A(v_RA)``; the model uses a constant ``d_A``
(the engines' joint damping is linear). A nonlinear damper law belongs to the scenes.

The heights put the body 0.2 m below the wheel at rest (A.42); the picture draws it 0.5 m higher, above the wheel
where a vehicle has it (``drawn_at``: the picture's offset only, the model is unchanged).
"""

from sympy import Matrix

from harness.modeling import (WORLD, Bump, Claim, Coordinate, Gravity, Input, Joint, JointDamper, JointSpring, Link,
                              Parameter, Point, PointForce, Scene, System, standard_gravity)

m_A = Parameter("m_A", 400.0, "kg", "quarter of the vehicle body mass")
m_R = Parameter("m_R", 40.0, "kg", "wheel mass")
c_A = Parameter("c_A", 2.0e4, "N/m", "suspension spring stiffness")
d_A = Parameter("d_A", 1.5e3, "N s/m", "suspension damping (constant, see docstring)")
c_R = Parameter("c_R", 2.0e5, "N/m", "tyre stiffness")
d_R = Parameter("d_R", 1.0e2, "N s/m", "tyre damping")
g = standard_gravity()

x_U = Input("x_U", "m", "road displacement x_U(t)")
v_U = Input("v_U", "m/s", "road velocity dx_U/dt")
x_R = Coordinate("x_R", "m", "height of the wheel")
x_A = Coordinate("x_A", "m", "height of the vehicle body")

SYSTEM = System(
    name="quarter_car",
    title="Quarter-car vertical model",
    lecture="Exercise A.4; (A.38)-(A.42)",
    coordinates=(x_R, x_A),
    links=(Link("wheel", m_R, description="lumped wheel mass"),
           Link("body", m_A, description="lumped body mass", drawn_at=(0, 0, 0.5))),
    joints=(Joint("wheel_z", "prismatic", WORLD, "wheel", axis="z", phi=x_R),
            Joint("suspension", "prismatic", "wheel", "body", axis="z", phi=x_A - x_R)),
    gravity=Gravity(g, (0, 0, -1)),
    forces=(
        JointSpring("tyre_spring", "wheel_z", c_R),
        JointDamper("tyre_damper", "wheel_z", d_R),
        PointForce("road", Point("wheel", (0, 0, 0), "wheel_centre"), (0, 0, c_R * x_U + d_R * v_U)),
        JointSpring("suspension_spring", "suspension", c_A),
        JointDamper("suspension_damper", "suspension", d_A),
    ),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
f_cA = c_A * (x_R - x_A)
f_dA = d_A * (x_R.rate - x_A.rate)
f_cR = c_R * (x_U - x_R)
f_dR = d_R * (v_U - x_R.rate)
mass_g = (m_A + m_R) * g
CLAIMS = [
    Claim("(A.39a)", "eom", m_A * x_A.accel - (f_cA + f_dA - m_A * g), "body", index=(1,)),
    Claim("(A.39b)", "eom", m_R * x_R.accel - (f_cR + f_dR - f_cA - f_dA - m_R * g), "wheel", index=(0,)),
    Claim("(A.40a)", "eom", f_cA - m_A * g, "static balance of the body, x_U = 0", index=(1,), at="equilibrium",
          note="0 = f_cA - m_A g written as the residual f_cA - m_A g"),
    Claim("(A.40b)", "eom", f_cR - f_cA - m_R * g, "static balance of the wheel, x_U = 0", index=(0,),
          at="equilibrium", note="0 = f_cR - f_cA - m_R g written as the residual"),
    Claim("(A.41), (A.42)", "equilibrium",
          Matrix([-mass_g / c_R, -mass_g / c_R - m_A * g / c_A]), "static deflections for x_U = 0"),
]

_rest = (-(400.0 + 40.0) * 9.81 / 2.0e5, -(400.0 + 40.0) * 9.81 / 2.0e5 - 400.0 * 9.81 / 2.0e4)  # (A.41), (A.42)
SCENES = [
    Scene("bump", "Exercise A.4: from the static deflection over a 5 cm road bump of 0.2 s", _rest, (0.0, 0.0), 2.0,
          {"gravity", "springs", "dampers", "external"},
          inputs={x_U: Bump(0.05, 0.3, 0.2), v_U: Bump(0.05, 0.3, 0.2, rate=True)}),
    Scene("smooth_road", "Exercise A.4 on a smooth road (x_U = v_U = 0) with the tyre damper d_R = 0: the body "
          "released 2 cm above its static deflection (A.42) bounces on the suspension; the road's force "
          "c_R x_U + d_R v_U is idle and left out", (_rest[0], _rest[1] + 0.02), (0.0, 0.0), 2.0,
          {"gravity", "springs", "dampers"}, params={d_R: 0.0}),
]
