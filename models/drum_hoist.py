"""Drum hoist, Exercise A.8 (Figures A.15, A.16), solution (A.70)-(A.86).

A drum (mass ``m_T``, moment of inertia ``I_T`` about its axis through its centre ``S``) rolls without slipping
on a horizontal surface with its outer radius ``r_a``. A massless rope leaves the drum's inner radius ``r_i``
horizontally at the top (lever arm ``r_i + r_a`` about the contact point, (A.77)), runs over a massless,
frictionless pulley and carries a block of mass ``m_B``. A linear spring (stiffness ``c``, unstretched length
``s_f0``) pulls the drum's centre back, ``f_f = c (x_T - s_f0)`` (A.85). Gravity acts on the block and the drum.

Frames and signs, as the lecture's balances read: ``x`` horizontal towards the pulley, ``y`` pointing *down*
(the weight ``m_B g`` of the block acts in ``+y``, (A.80)), hence ``z = x × y`` into the drawing plane and
gravity ``e_g = [0, 1, 0]``. The degree of freedom is the position ``x_T`` of the drum's centre (A.78)-(A.79):
rolling gives the drum's rotation ``phi = x_T / r_a`` (positive about ``z``, clockwise in the drawing) and the
block's descent ``y_B = x_T + r_i phi = (r_i + r_a)/r_a x_T``.

Tree and map theta = phi(q) (rolling and rope are constraints, three tree joints for one coordinate): the
prismatic joint ``x_T`` (axis ``x``, the drum's centre at height ``r_a`` above the ground, i.e. at ``y = -r_a``)
carries a massless frame, the revolute joint ``phi`` (axis ``z``) the drum, ``theta_phi = x_T / r_a``; the block
hangs on the prismatic joint ``y_B`` (axis ``y``) below the pulley, ``theta_yB = (r_i + r_a)/r_a x_T``, with
``y_B = 0`` at ``x_T = 0``. The spring is a spring on the joint ``x_T`` with rest position ``s_f0``.
Inertia: the lecture gives only ``I_T`` about the drum's axis; the transverse moments never enter (the drum
turns about ``z`` only) and are set equal to ``I_T``, which is a physical tensor. The block is a point mass
(it only translates).

The spring force at rest (A.76), ``f_f = (r_i + r_a)/r_a m_B g``, is claimed as the equilibrium it
implies with ``f_f = c (x_T - s_f0)`` (A.85): ``x_T* = s_f0 + (r_i + r_a) m_B g / (r_a c)``.

Constraint forces (the cutting forces of Figure A.16): the rope's force ``f_S`` pulls the drum at the top of its inner
radius towards the pulley (``+x``) and the block up (``-y``); the rolling contact's tangential force ``f_t`` acts
on the drum at its contact point in ``-x`` (the sense (A.73) gives it). The normal force ``f_n`` is the force of
the joint ``x_T`` on the drum (``-y``, up). The lecture writes ``f_S``, ``f_t`` both for the static forces
(A.70)-(A.77) and for the forces in motion (A.80)-(A.85) and notes that they differ: the claims name the latter
``f_S_dyn``, ``f_t_dyn``. ``omega = phi_dot`` (the lecture's definition) with (A.78) and ``v_B = y_B_dot`` with
(A.79) are written in ``x_T``. Not claimed: the pulley's bearing forces (A.71a-b) (the massless pulley is no body of
the model).
"""

from harness.derivation.bodies import joint_force
from harness.modeling import (WORLD, Claim, ConstraintForce, Coordinate, Gravity, Inertia, Joint, JointSpring, Link,
                              Parameter, Point, Printed, Scene, System, standard_gravity)

m_T = Parameter("m_T", 20.0, "kg", "mass of the drum")
I_T = Parameter("I_T", 0.4, "kg m^2", "moment of inertia of the drum about its axis (through S)")
r_a = Parameter("r_a", 0.2, "m", "outer radius of the drum (rolls on the surface)")
r_i = Parameter("r_i", 0.1, "m", "inner radius of the drum (carries the rope)")
m_B = Parameter("m_B", 10.0, "kg", "mass of the block")
c = Parameter("c", 500.0, "N/m", "stiffness of the spring at the drum's centre")
s_f0 = Parameter("s_f0", 0.5, "m", "unstretched length of the spring")
g = standard_gravity()

x_T = Coordinate("x_T", "m", "position of the drum's centre")

SYSTEM = System(
    name="drum_hoist",
    title="Drum hoist",
    lecture="Exercise A.8; (A.70)-(A.86)",
    coordinates=(x_T,),
    links=(
        Link("drum_centre", description="massless frame at the drum's centre S (merged with the drum in MuJoCo)"),
        Link("drum", m_T, (0, 0, 0), Inertia(I_T, I_T, I_T), description="the drum, centre of mass on its axis"),
        Link("block", m_B, (0, 0, 0), description="the block (point mass, only translates)"),
    ),
    joints=(
        Joint("x_T", "prismatic", WORLD, "drum_centre", axis="x", origin=(0, -r_a, 0)),
        Joint("phi", "revolute", "drum_centre", "drum", axis="z", phi=x_T / r_a),
        Joint("y_B", "prismatic", WORLD, "block", axis="y", origin=(2, 0, 0), phi=(r_i + r_a) / r_a * x_T),
    ),
    gravity=Gravity(g, (0, 1, 0)),
    forces=(JointSpring("spring_f", "x_T", c, s_f0),),
    constraint_forces=(
        ConstraintForce("f_S", forces=(("drum", Point("drum_centre", (0, -r_i, 0)), (1, 0, 0)),
                                       ("block", Point("block"), (0, -1, 0)))),
        ConstraintForce("f_t", forces=(("drum", Point("drum_centre", (0, r_a, 0)), (-1, 0, 0)),)),
    ),
    doc=__doc__,
)

f_S_p = Printed("f_S", "N", "the rope force at rest, (A.70)")
f_t_p = Printed("f_t", "N", "the tangential force at the contact at rest, (A.75)")
f_S_dyn = Printed("f_S_dyn", "N", "the rope force in motion, (A.81) (printed f_S)")
f_t_dyn = Printed("f_t_dyn", "N", "the tangential force in motion, (A.84) (printed f_t)")

CLAIMS = [
    Claim("(A.78)", "parameter", x_T / r_a, "rolling: angle of the drum phi = x_T / r_a",
          reference=SYSTEM.joint("phi").phi),
    Claim("(A.79)", "position:block", (r_i + r_a) / r_a * x_T, "descent of the block y_B = (r_i + r_a)/r_a x_T",
          index=(1,)),
    Claim("(A.86)", "eom", x_T.accel - ((r_i + r_a) * m_B * g * r_a - c * (x_T - s_f0) * r_a**2)
          / ((r_i + r_a)**2 * m_B + I_T + m_T * r_a**2), "equation of motion solved for the acceleration",
          note="printed for v_T_dot with v_T = x_T_dot: read as x_T_ddot"),
    Claim("(A.76)", "equilibrium", s_f0 + (1 + r_i / r_a) * m_B * g / c,
          "spring force at rest f_f = (1 + r_i/r_a) m_B g",
          note="printed as the spring force f_f; with f_f = c (x_T - s_f0) (A.85) the rest position is "
               "x_T* = s_f0 + f_f / c"),
    # ---- at rest (A.70)-(A.77): the forces of the cut-free bodies at the equilibrium
    Claim("(A.70)", "constraint:f_S", m_B * g, "rope force at rest f_S = f_gB = m_B g", at="equilibrium",
          defines=f_S_p),
    Claim("(A.72)", "parameter", m_T * g, "normal force on the drum at rest f_n = f_gT = m_T g", at="equilibrium",
          reference=lambda: -joint_force(SYSTEM, "x_T")[1],
          note="f_n acts on the drum in -e_y (up): the force of the joint x_T on the drum, its -y component"),
    Claim("(A.73)", "eom", f_S_p - c * (x_T - s_f0) - f_t_p, "force balance of the drum in x at rest",
          at="equilibrium", ingredients=("(A.70)", "(A.75) f_t"),
          note="f_f = c (x_T - s_f0), the lecture's spring force"),
    Claim("(A.74)", "eom", f_S_p * r_i + f_t_p * r_a, "torque balance of the drum about S at rest",
          at="equilibrium", ingredients=("(A.70)", "(A.75) f_t")),
    Claim("(A.75)", "constraint:f_t", -r_i / r_a * Printed("F_S", "N", "printed in (A.75)"),
          "tangential force at rest f_t = -(r_i/r_a) F_S", at="equilibrium"),
    Claim("(A.75) f_t", "constraint:f_t", -r_i / r_a * m_B * g, "tangential force at rest f_t = -(r_i/r_a) m_B g",
          at="equilibrium", defines=f_t_p),
    Claim("(A.77)", "eom", Printed("f_s", "N", "printed in (A.77)") * (r_i + r_a) - c * (x_T - s_f0) * r_a,
          "torque balance of the drum about the contact point M at rest", at="equilibrium",
          note="f_f = c (x_T - s_f0), the lecture's spring force"),
    # ---- in motion (A.80)-(A.85)
    Claim("(A.80)", "eom", m_B * (r_i + r_a) / r_a * x_T.accel - (m_B * g - f_S_dyn),
          "momentum balance of the block", ingredients=("(A.81)",),
          note="v_B = y_B_dot with (A.79): d/dt v_B = (r_i + r_a)/r_a x_T_ddot"),
    Claim("(A.81)", "constraint:f_S", m_B * (g - (r_i + r_a) / r_a * x_T.accel), "rope force in motion",
          defines=f_S_dyn, note="printed for v_T_dot with v_T = x_T_dot: read as x_T_ddot"),
    Claim("(A.82)", "eom", I_T * x_T.accel / r_a - (f_S_dyn * r_i + f_t_dyn * r_a),
          "angular momentum balance of the drum about S", ingredients=("(A.81)", "(A.84)"),
          note="omega = phi_dot with (A.78): d/dt omega = x_T_ddot / r_a"),
    Claim("(A.83)", "constraint:f_t", (I_T * x_T.accel / r_a - f_S_dyn * r_i) / r_a, "tangential force in motion",
          ingredients=("(A.81)",), note="omega = phi_dot with (A.78): d/dt omega = x_T_ddot / r_a"),
    Claim("(A.84)", "constraint:f_t", (r_i * (r_i + r_a) * m_B + I_T) * x_T.accel / r_a**2 - r_i / r_a * m_B * g,
          "tangential force in motion with (A.81), (A.78)", defines=f_t_dyn,
          note="printed for v_T_dot with v_T = x_T_dot: read as x_T_ddot"),
    Claim("(A.85)", "eom", m_T * x_T.accel - (f_S_dyn - c * (x_T - s_f0) - f_t_dyn),
          "momentum balance of the drum in x", ingredients=("(A.81)", "(A.84)"),
          note="printed for v_T_dot with v_T = x_T_dot: read as x_T_ddot"),
]

SCENES = [
    Scene("release", "Exercise A.8, (A.86): released from rest with the spring relaxed (x_T = s_f0); the block "
          "sinks, the drum rolls and oscillates about the rest position x_T* = 0.794 m of (A.76), (A.85) "
          "(conservative)", (0.5,), (0.0,), 3.0, {"gravity", "springs"}),
]
