"""Toggle press, Exercise A.10 (Figure A.18), solution (A.97)-(A.107).

Two legs move in the x-y plane; gravity acts in ``-e_y`` (exercise text, (A.105)). Leg 1 (length ``L_1``)
turns about the fixed pivot at the origin by ``phi_1 = q`` (A.97), counter-clockwise from ``e_x``; the knee is
at ``L_1 [cos q, sin q, 0]``. Leg 2 (length ``L_2``) runs from the knee to the slide, in the direction
``[cos phi_2, -sin phi_2, 0]`` (A.98), i.e. its absolute angle is ``-phi_2``. The massless slide keeps the
leg's end point on the x-axis (A.99), which closes the chain and gives the nonlinear map (A.100)
``phi_2(q) = arcsin(L_1/L_2 sin q)``. Centres of gravity in the middle of the legs (A.101); ``I_1``, ``I_2``
are the moments of inertia about ``z`` through the centres of gravity (A.104).

Tree and map: world -(joint ``phi_1``: revolute z, ``theta = q``)-> leg 1 -(joint ``theta_2``: revolute z at
``[L_1, 0, 0]``, relative angle ``theta = -phi_2(q) - q``)-> leg 2; the slide needs no body (it is
massless). One lecture coordinate, two tree joints: the closed chain is the map.

Return spring: the lecture's potential (A.106) ``c_F/2 (x_e - s_F0)²`` with the relaxed length ``s_F0`` is a
spring of length ``x_e`` along the x-axis, modeled as a spring between the frame at the origin and the end
point ``e`` of leg 2 (its length ``|p_0^e| = x_e`` because the chain keeps ``y_e = 0`` and ``x_e > 0``). The
knee force ``f`` acts on the knee in ``-e_y``, the load force ``f_L`` on the slide in ``-e_x`` (A.107).

Singular points and drawn states: ``d phi_2/dq = L_1 cos q / (L_2 cos phi_2)`` blows up where leg 2 stands
perpendicular to the slide guide, ``L_1 |sin q| = L_2`` (``cos phi_2 = 0``). Full extension ``q = 0`` is *not*
such a point (there ``d phi_2/dq = L_1/L_2``; it is the dead point of the slide, ``d x_e/dq = 0``). Random
parameters are drawn in ``[default/2, 2 default]``, so ``L_1/L_2 ≤ 4 · 0.4/0.6 = 8/3``; with the drawn range
``|q| ≤ 0.3`` this keeps ``L_1/L_2 |sin q| ≤ 0.79`` (``cos phi_2 ≥ 0.61``) and ``cos q > 0``, hence
``x_e > 0`` (the spring never reaches zero length).

Inertia tensors: slender legs with their long axis along ``x_k``; only ``I_1``, ``I_2`` (about ``z``) enter the
planar motion, ``I_xx1``, ``I_yy1``, ``I_xx2``, ``I_yy2`` complete physical tensors for the engines.
"""

from sympy import Matrix, asin, cos, diff, sin

from harness.modeling import (Printed, WORLD, Claim, Closure, Coordinate, Gravity, Inertia, Input, Joint, Link, Parameter, Point,
                              PointForce, Scene, Spring, System, standard_gravity)

m_1 = Parameter("m_1", 2.0, "kg", "mass of leg 1")
m_2 = Parameter("m_2", 3.0, "kg", "mass of leg 2")
L_1 = Parameter("L_1", 0.4, "m", "length of leg 1 (pivot to knee)")
L_2 = Parameter("L_2", 0.6, "m", "length of leg 2 (knee to slide)")
I_xx1 = Parameter("I_xx1", 0.000533, "kg m^2", "inertia of leg 1 about its long axis x_1 through s1")
I_yy1 = Parameter("I_yy1", 0.02693, "kg m^2", "inertia of leg 1 about y_1 through s1")
I_1 = Parameter("I_1", 0.02693, "kg m^2", "moment of inertia of leg 1 about z through its centre of gravity")
I_xx2 = Parameter("I_xx2", 0.0008, "kg m^2", "inertia of leg 2 about its long axis x_2 through s2")
I_yy2 = Parameter("I_yy2", 0.0904, "kg m^2", "inertia of leg 2 about y_2 through s2")
I_2 = Parameter("I_2", 0.0904, "kg m^2", "moment of inertia of leg 2 about z through its centre of gravity")
c_F = Parameter("c_F", 500.0, "N/m", "spring constant of the return spring")
s_F0 = Parameter("s_F0", 1.2, "m", "relaxed length of the return spring")
g = standard_gravity()

q = Coordinate("q", "rad", "angle phi_1 of leg 1 against e_x (A.97); kept in |q| <= 0.3 (see above)",
               range=(-0.3, 0.3))
f = Input("f", "N", "force on the knee, acting in -e_y")
f_L = Input("f_L", "N", "load force on the slide, acting in -e_x")

phi_2 = asin(L_1 / L_2 * sin(q))  # (A.100)

knee = Point("leg_1", (L_1, 0, 0), "knee")
end_point = Point("leg_2", (L_2, 0, 0), "e")
origin = Point(WORLD, (0, 0, 0), "O")

SYSTEM = System(
    name="toggle_press",
    title="Toggle press",
    lecture="Exercise A.10; (A.97)-(A.107)",
    coordinates=(q,),
    links=(
        Link("leg_1", m_1, (L_1 / 2, 0, 0), Inertia(I_xx1, I_yy1, I_1), description="leg 1, pivot to knee along x_1"),
        Link("leg_2", m_2, (L_2 / 2, 0, 0), Inertia(I_xx2, I_yy2, I_2), description="leg 2, knee to slide along x_2"),
    ),
    joints=(
        Joint("phi_1", "revolute", WORLD, "leg_1", axis="z", phi=q),
        Joint("theta_2", "revolute", "leg_1", "leg_2", axis="z", origin=(L_1, 0, 0), phi=-phi_2 - q),
    ),
    gravity=Gravity(g, (0, -1, 0)),
    forces=(
        Spring("spring_F", origin, end_point, c_F, s_F0),
        PointForce("knee_force", knee, (0, -f, 0)),
        PointForce("load_force", end_point, (-f_L, 0, 0)),
    ),
    closures=(Closure("slide", end_point, (0, 1, 0), 0),),  # (A.99): the slide keeps e on the x-axis
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
qd = q.rate
phi_2 = asin(L_1 / L_2 * sin(q))             # (A.100), as printed
dphi2 = diff(phi_2, q)                       # the lecture leaves ∂phi_2/∂q unevaluated
p_e = L_1 * Matrix([cos(q), sin(q), 0]) + L_2 * Matrix([cos(phi_2), -sin(phi_2), 0])
T = (m_1 * L_1**2 * qd**2 / 8
     + m_2 * L_1**2 * qd**2 / 2 + m_2 * L_2**2 * dphi2**2 * qd**2 / 8
     - m_2 * L_1 * L_2 * cos(q + phi_2) * dphi2 * qd**2 / 2
     + I_1 * qd**2 / 2 + I_2 * (dphi2 * qd)**2 / 2)
V_g = m_1 * g * L_1 / 2 * sin(q) + m_2 * g * (L_1 * sin(q) - L_2 / 2 * sin(phi_2))
V_F = c_F * (L_1 * cos(q) + L_2 * cos(phi_2) - s_F0)**2 / 2
f_q_f = -f * L_1 * cos(q)
F_printed = Printed("F", "N", "printed in the force vector of (A.107a)")
f_q_fL = f_L * (L_1 * sin(q) + L_2 * sin(phi_2) * dphi2)
L = T - V_g - V_F
dL_dqd = diff(L, qd)
euler_lagrange = diff(dL_dqd, q) * qd + diff(dL_dqd, qd) * q.accel - diff(L, q) - (f_q_f + f_q_fL)  # d/dt ∂L/∂q̇ ...

CLAIMS = [
    Claim("(A.98), (A.100)", "position:e", p_e, "end point of leg 2 (on the slide), phi_1 = q, phi_2 = phi_2(q)",
          note="phi_1 read as q (A.97); its y-component is the constraint (A.99)"),
    Claim("(A.101a)", "position:leg_1", L_1 / 2 * Matrix([cos(q), sin(q), 0]), "centre of gravity of leg 1"),
    Claim("(A.102a)", "v:leg_1", L_1 / 2 * Matrix([-sin(q), cos(q), 0]) * qd, "velocity of the centre of gravity of leg 1"),
    Claim("(A.102b)", "v:leg_2", L_1 * Matrix([-sin(q), cos(q), 0]) * qd
          + L_2 / 2 * Matrix([-sin(phi_2), -cos(phi_2), 0]) * dphi2 * qd, "velocity of the centre of gravity of leg 2",
          note="the printed ∂phi_2(q)/∂q is the derivative of (A.100), left unevaluated in the text"),
    Claim("(A.103a)", "omega:leg_1", qd, "angular velocity of leg 1 (about e_z)", index=(2,)),
    Claim("(A.103b)", "omega:leg_2", -dphi2 * qd, "angular velocity of leg 2 (about e_z)", index=(2,),
          note="the printed ∂phi_2(q)/∂q is the derivative of (A.100), left unevaluated in the text"),
    Claim("(A.101b)", "position:leg_2",
          L_1 * Matrix([cos(q), sin(q), 0]) + L_2 / 2 * Matrix([cos(phi_2), -sin(phi_2), 0]),
          "centre of gravity of leg 2"),
    Claim("(A.104)", "T", T, "kinetic energy, ∂phi_2/∂q left unevaluated"),
    Claim("(A.105), (A.106)", "V", V_g + V_F, "potential energy V_g + V_F of the weights and the return spring",
          note="the constant V_g,0 read as 0 (reference level y = 0 through the pivot, as the harness uses)"),
    Claim("(A.107a), (A.107b)", "f_np", f_q_f + f_q_fL, "generalized force of the knee force f and the load f_L",
          note="the right-hand sides of (A.107a), (A.107b)"),
    Claim("(A.107a), (A.107b) middle", "f_np",
          (Matrix([[0, -F_printed, 0]]) * Matrix([L_1 * cos(q), L_1 * sin(q), 0]).diff(q))[0]
          + (Matrix([[-f_L, 0, 0]]) * p_e.diff(q))[0],
          "generalized forces as force vector times the Jacobian of the point of application",
          note="the force vector of (A.107a) with F as printed"),
    Claim("(A.104)-(A.107), Euler-Lagrange", "eom", euler_lagrange,
          "d/dt ∂L/∂q̇ - ∂L/∂q = f_q,f + f_q,f_L with L = T - V_g - V_F",
          note="the lecture states the equation of motion only in words after (A.107); the residual is that "
               "Euler-Lagrange equation evaluated symbolically with the printed T, V_g, V_F, f_q,f, f_q,f_L"),
]

SCENES = [
    Scene("return", "Exercise A.10: released near full extension, the return spring pulls the press back "
          "(closed chain through the nonlinear map)", (0.25,), (0.0,), 1.0, {"gravity", "springs"}),
]
