"""Cable pulley system, Exercise A.9 (Figure A.17), solution (A.87)-(A.96): the smooth part.

A load ``L`` (mass ``m_L``) is pulled up an incline of angle ``alpha`` by a massless rope wound on the inner
radius ``r_2`` of the pulley ``R_1`` (mass ``m_1``, moment of inertia ``I_1`` about its fixed, frictionless axis,
outer radius ``r_1``). A second rope, wound on the outer radius ``r_1`` of ``R_1``, carries the movable pulley
``R_2`` (mass ``m_2``, moment of inertia ``I_2``, radius ``r_2``) in a loop whose other end is fixed (the pulley
system of Fig. 3.17); a constant external force ``f`` pulls ``R_2`` vertically down. The only degree of freedom
is the position ``s`` of the load along the incline, uphill positive, ``s(t_0) = 0``. The ropes give
(A.89)-(A.91): ``omega_R1 = s_dot / r_2``, ``v_2 = r_1 omega_R1``, ``v_R2 = v_2 / 2 = s_dot r_1/(2 r_2)``,
``omega_R2 = v_R2 / r_2``; as the load moves up by ``s``, ``R_2`` moves down by ``s r_1/(2 r_2)`` (A.92), (A.93).

Frames and signs: the plane of the drawing is ``x`` (horizontal, towards ``R_1``), ``y`` (up); gravity acts in
``-y``. Heights are measured so that every body is at height 0 at ``s = 0`` (the lecture's choice
``V(t_0) = 0``, (A.92)): the axis of ``R_1`` is the origin, the load starts at ``[-1, 0, 0]`` m, ``R_2`` hangs below
the rope leaving ``R_1`` at ``x = r_1``, its centre at ``x = r_1 + r_2``, and starts at height 0. ``R_1`` turns
clockwise (about ``-z``) as the load moves up, ``R_2`` counter-clockwise (about ``+z``; its left strand comes from
``R_1``, its right strand is fixed). Horizontal positions do not enter the dynamics (they only change the
engines' round-off: Pinocchio's C of the spinning ``R_2`` loses precision with its distance from the origin).

Tree and map theta = phi(q) (three rope connections, five tree joints for one coordinate): the load moves on
two prismatic joints ``x_L`` (axis ``x``, ``theta = s cos(alpha)``) and ``y_L`` (axis ``y``, ``theta = s sin(alpha)``);
``R_1`` turns on ``phi_R1`` (axis ``-z``, ``theta = s / r_2``); ``R_2`` moves down on ``s_R2`` (axis ``-y``,
``theta = s r_1/(2 r_2)``) and turns on ``phi_R2`` (axis ``z``, ``theta = s r_1/(2 r_2²)``). The force ``f`` is a
force ``[0, -f, 0]`` at the centre of ``R_2``, generalized force ``f r_1/(2 r_2)`` (A.93). The load is a point mass
(it only translates); the lecture gives ``I_1``, ``I_2`` about the pulleys' axes only, the transverse moments
never enter and are set equal to them (a physical tensor).

Dry friction (not in this model): between the load and the incline acts Coulomb friction with the normal
force ``f_n = m_L g cos(alpha)`` (A.94) and the tangential force ``f_t = mu_c f_n`` opposing the sliding velocity
``s_dot`` (A.95): generalized force ``-mu_c m_L g cos(alpha) sign(s_dot)`` on ``s`` while sliding (and, at
``s_dot = 0``, sticking while the other forces stay below ``mu_c f_n``, as in Section 3.5.2). It is
non-smooth; it comes with the scenes. ``mu_c`` is declared here so that the scene can use it by name; it
enters none of M, C, g. The data of the task, ``s_1``, ``v_0``, ``v_1``, belong to the scene as well.

Constraint forces: the map's four constraints are the incline (its normal force ``f_n`` on the load), rope 1 between
the load and ``R_1``'s inner radius (``f_S1``, at its tangent point above the rope's line), rope 2 between ``R_1``'s
outer radius and ``R_2``'s left rim (``f_S2``) and rope 2's fixed strand at ``R_2``'s right rim (``f_S3``); the normal
force (A.94) is claimed against ``f_n`` (the force the load exerts on the incline is its reaction).

Not transcribed as claims: (A.95)-(A.96) (they contain the friction); (A.96), the force ``f`` that accelerates
the load from ``v_0`` to ``v_1`` over ``s_1``, is the energy balance (A.87) of (A.88), (A.92), (A.93) and (A.95),
which are claims here except (A.95).
"""

from sympy import cos, diff, sin

from harness.modeling import (WORLD, Claim, Constant, ConstraintForce, Coordinate, Gravity, Inertia, Input, Joint, Link,
                              Parameter, Point, PointForce, Scene, System, standard_gravity)

m_L = Parameter("m_L", 10.0, "kg", "mass of the load")
m_1 = Parameter("m_1", 4.0, "kg", "mass of the pulley R_1 (fixed axis)")
I_1 = Parameter("I_1", 0.08, "kg m^2", "moment of inertia of R_1 about its axis of rotation")
r_1 = Parameter("r_1", 0.2, "m", "outer radius of R_1")
r_2 = Parameter("r_2", 0.1, "m", "inner radius of R_1 and radius of R_2")
m_2 = Parameter("m_2", 2.0, "kg", "mass of the movable pulley R_2")
I_2 = Parameter("I_2", 0.01, "kg m^2", "moment of inertia of R_2 about its axis of rotation")
alpha = Parameter("alpha", 0.5, "rad", "angle of the incline")
mu_c = Parameter("mu_c", 0.3, "1", "coefficient of dry friction load-incline (A.95); used by the friction "
                 "scene, enters none of M, C, g", assumption="nonnegative")
g = standard_gravity()

s = Coordinate("s", "m", "position of the load along the incline, uphill positive")
f = Input("f", "N", "constant vertical force pulling R_2 down")

SYSTEM = System(
    name="cable_pulley",
    title="Cable pulley system",
    lecture="Exercise A.9; (A.88)-(A.93)",
    status="smooth part; Coulomb friction on the incline left to the scenes",
    parameters=(mu_c,),  # the friction scene's
    coordinates=(s,),
    links=(
        Link("load_x", description="massless frame of the load's horizontal motion (merged in MuJoCo)"),
        Link("load", m_L, (0, 0, 0), description="the load (point mass, only translates)"),
        Link("R1", m_1, (0, 0, 0), Inertia(I_1, I_1, I_1), description="pulley R_1 on a fixed axis"),
        Link("R2_centre", description="massless frame at the centre of R_2 (merged in MuJoCo)"),
        Link("R2", m_2, (0, 0, 0), Inertia(I_2, I_2, I_2), description="movable pulley R_2"),
    ),
    joints=(
        Joint("x_L", "prismatic", WORLD, "load_x", axis="x", origin=(-1, 0, 0), phi=s * cos(alpha)),
        Joint("y_L", "prismatic", "load_x", "load", axis="y", phi=s * sin(alpha)),
        Joint("phi_R1", "revolute", WORLD, "R1", axis=(0, 0, -1), phi=s / r_2),
        Joint("s_R2", "prismatic", WORLD, "R2_centre", axis=(0, -1, 0), origin=(r_1 + r_2, 0, 0),
              phi=s * r_1 / (2 * r_2)),
        Joint("phi_R2", "revolute", "R2_centre", "R2", axis="z", phi=s * r_1 / (2 * r_2**2)),
    ),
    gravity=Gravity(g, (0, -1, 0)),
    forces=(PointForce("force_f", Point("R2", (0, 0, 0), "R2_axis"), (0, -f, 0)),),
    constraint_forces=(   # the map's four constraints, their forces (the ropes are straight and massless)
        ConstraintForce("f_n", forces=(("load", Point("load"), (-sin(alpha), cos(alpha), 0)),)),
        ConstraintForce("f_S1", forces=(("load", Point("load"), (cos(alpha), sin(alpha), 0)),
                                        ("R1", Point(WORLD, (-r_2 * sin(alpha), r_2 * cos(alpha), 0)),
                                         (-cos(alpha), -sin(alpha), 0)))),
        ConstraintForce("f_S2", forces=(("R1", Point(WORLD, (r_1, 0, 0)), (0, -1, 0)),
                                        ("R2", Point("R2_centre", (-r_2, 0, 0)), (0, 1, 0)))),
        ConstraintForce("f_S3", forces=(("R2", Point("R2_centre", (r_2, 0, 0)), (0, 1, 0)),)),
    ),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
v = s.rate
omega_R1 = v / r_2                     # (A.89)
v_R2 = v * r_1 / (2 * r_2)             # (A.91)
omega_R2 = v * r_1 / (2 * r_2**2)      # (A.91)
_v = "v read as s_dot"
CLAIMS = [
    Claim("(A.89)", "parameter", omega_R1, "angular velocity of R_1, omega_R1 = v / r_2",
          reference=diff(SYSTEM.joint("phi_R1").phi, s.symbol) * v, note=_v),
    Claim("(A.90)", "parameter", v * r_1 / r_2, "exit velocity of the rope from R_1, v_2 = r_1 omega_R1 = v r_1/r_2",
          reference=r_1 * diff(SYSTEM.joint("phi_R1").phi, s.symbol) * v,
          note=_v + "; reference: r_1 times the angular velocity of R_1 from the model's joint map (the rope "
               "leaves R_1 at its outer radius r_1)"),
    Claim("(A.91a)", "parameter", v_R2, "velocity of R_2, v_R2 = v_2/2 = v r_1/(2 r_2)",
          reference=diff(SYSTEM.joint("s_R2").phi, s.symbol) * v, note=_v),
    Claim("(A.91b)", "parameter", omega_R2, "angular velocity of R_2, omega_R2 = v_R2 / r_2 = v r_1/(2 r_2²)",
          reference=diff(SYSTEM.joint("phi_R2").phi, s.symbol) * v, note=_v),
    Claim("(A.88)", "T", m_L * v**2 / 2 + I_1 * omega_R1**2 / 2 + I_2 * omega_R2**2 / 2 + m_2 * v_R2**2 / 2,
          "kinetic energy with (A.89)-(A.91)", note=_v),
    Claim("(A.92)", "V", m_L * g * s * sin(alpha) - m_2 * g * s * r_1 / (2 * r_2),
          "potential energy, V(t_0) = 0 at s(t_0) = 0",
          note="printed for the position s_1 reached at t_1: read as V(s) with s_1 -> s"),
    Claim("(A.93)", "f_np", f * r_1 / (2 * r_2), "generalized force of f",
          note="printed as the work W_F = f s_1 r_1/(2 r_2) of the constant force over s_1; its generalized "
               "force (5.60) is dW_F/ds_1 = f r_1/(2 r_2)"),
    Claim("(A.94)", "constraint:f_n", m_L * g * cos(alpha), "normal force of the load on the incline",
          note="f_n: the incline's force on the load, normal to it (the load's force on the incline is its reaction)"),
]

SCENES = [
    Scene("haul", "Exercise A.9, (A.93): the load moving uphill at v_0 = 0.5 m/s from s_0 = 0 is accelerated by "
          "the constant force f = 60 N on R_2 (the smooth part: dry friction mu_c of (A.95) is not modeled)",
          (0.0,), (0.5,), 2.0, {"gravity", "external"}, inputs={f: Constant(60.0)}),
]
