"""Drive train, Example 3.16 (Figure 3.37); (3.136)-(3.142). Variant with the motor's rotor as a body.

A motor (rotor inertia ``I_m``, torque ``tau_m``) drives a body with moment of inertia ``I_1`` through a lossless
gear with ratio ``i_g`` (input speed / output speed), ``φ̇_1 = φ̇_m / i_g`` (3.136); a linear torsion spring
``c`` and a rotational damper ``d`` connect it with a second body ``I_2``, on which the load torque ``tau_l``
acts against the positive sense of rotation (``−tau_l`` in (3.138c), ``b_e = [0, −1]ᵀ`` (3.142)). All bodies
turn about parallel ``z`` axes, counter-clockwise positive, all angles counted from the relaxed spring;
there is no gravity (it does not enter (3.138)). The lecture coordinates are ``q = [phi_1, phi_2]ᵀ``, the
absolute angles of the two bodies (3.141).

Tree and map ``theta = phi(q)`` (three tree joints, two lecture coordinates; the gear is a constraint):

* ``phi_m`` – the rotor, a body with axial moment of inertia ``I_m`` on a revolute joint to the world, at
  ``phi_m = i_g phi_1`` (3.136 integrated, both sides counted from zero; the gear does not reverse the sense
  of rotation, as in (3.136)). The motor torque ``tau_m`` acts in this joint (against the housing).
* ``phi_1`` – body 1 (``I_1``) on a revolute joint to the world (identity map).
* ``phi_21`` – body 2 (``I_2``) on a revolute joint on body 1 (same axis), at the shaft's twist
  ``phi_21 = phi_2 − phi_1``; the torsion spring ``c`` and the damper ``d`` act in this joint,
  ``V = c/2 (phi_1 − phi_2)²`` and ``−d (φ̇_2 − φ̇_1)``, as in (3.138b, c).

The rotor's kinetic energy ``½ I_m φ̇_m² = ½ i_g² I_m φ̇_1²`` is where the reflected rotor inertia of (3.140a)
comes from: ``M_q = Jᵀ M_θ J`` with ``J = ∂phi/∂q`` puts ``i_g² I_m`` onto ``phi_1``, and the motor torque
in ``phi_m`` becomes ``i_g tau_m`` on ``phi_1`` (``b_u = [i_g, 0]ᵀ``). The companion model
``drive_train_armature`` gives the same equations without a rotor body: it puts ``i_g² I_m`` as engine
armature (rotor inertia) on the joint ``phi_1`` and the motor torque ``i_g tau_m`` directly on body 1; both
models must agree with each other, with (3.140)-(3.142) and with both engines.

The lecture gives only the moments of inertia about the axes of rotation. The bodies' masses (centres of
mass on their axes) and their transverse moments of inertia never enter the dynamics (the bodies only
turn about ``z``); they are set to a stated mass and to ``3/4`` of the axial moment (a physical tensor: a
solid cylinder of length ``√1.5`` times its radius). Nor does where along the common axis each body sits: they
are placed one after the other as on a shaft (body 1 0.6 m from the rotor, body 2 1 m beyond body 1), so that a
picture seen across the axis shows each of them.

The gear cut open (3.137) is the map's constraint: the torque ``tau_1`` on body 1 and ``tau_1^(m) = tau_1 / i_g``
against the rotor, declared as one constraint force of magnitude ``tau_1``; (3.139) is claimed as it. Not claimed:
(3.137) and (3.138a), which name ``tau_1^(m)``, a value the lecture does not print.
"""

from sympy import Matrix, diag, diff

from harness.modeling import (WORLD, BodyTorque, Claim, Constant, ConstraintForce, Coordinate, Inertia, Input, Joint,
                              JointDamper, JointInput, JointSpring, Link, Parameter, Printed, Scene, Step, System)

I_m = Parameter("I_m", 0.002, "kg m^2", "moment of inertia of the motor's rotor")
I_1 = Parameter("I_1", 0.5, "kg m^2", "moment of inertia of body 1 (gear output side)")
I_2 = Parameter("I_2", 0.8, "kg m^2", "moment of inertia of body 2 (load side)")
i_g = Parameter("i_g", 10.0, "1", "gear ratio (input speed / output speed)")
c = Parameter("c", 200.0, "N m/rad", "stiffness of the torsion spring between bodies 1 and 2")
d = Parameter("d", 1.5, "N m s/rad", "damping constant of the rotational damper between bodies 1 and 2")
m_m = Parameter("m_m", 0.5, "kg", "mass of the rotor (centre of mass on its axis; does not enter)")
m_1 = Parameter("m_1", 5.0, "kg", "mass of body 1 (centre of mass on its axis; does not enter)")
m_2 = Parameter("m_2", 8.0, "kg", "mass of body 2 (centre of mass on its axis; does not enter)")

tau_m = Input("tau_m", "N m", "motor torque")
tau_l = Input("tau_l", "N m", "load torque on body 2")

phi_1 = Coordinate("phi_1", "rad", "angle of body 1")
phi_2 = Coordinate("phi_2", "rad", "angle of body 2")


BODY_1_AT = (0, 0, 0.6)
"""Where body 1's joint sits on the axis, from the rotor's (m): behind the gear."""
SHAFT = (0, 0, 1.0)
"""Where body 2's joint sits on the axis, from body 1's (m): the shaft with the torsion spring and the damper."""


def disc_inertia(I):
    """Axial moment ``I`` about ``z``; transverse moments ``3/4 I`` (never enter, see the docstring)."""
    return Inertia(3 * I / 4, 3 * I / 4, I)


SYSTEM = System(
    name="drive_train",
    title="Drive train (rotor as a body coupled by the gear)",
    lecture="Example 3.16; (3.136)-(3.142)",
    coordinates=(phi_1, phi_2),
    links=(
        Link("rotor", m_m, inertia=disc_inertia(I_m), description="the motor's rotor"),
        Link("body_1", m_1, inertia=disc_inertia(I_1), description="body 1 on the gear's output side"),
        Link("body_2", m_2, inertia=disc_inertia(I_2), description="body 2 carrying the load torque"),
    ),
    joints=(
        Joint("phi_m", "revolute", WORLD, "rotor", axis="z", phi=i_g * phi_1),     # (3.136)
        Joint("phi_1", "revolute", WORLD, "body_1", axis="z", origin=BODY_1_AT),
        Joint("phi_21", "revolute", "body_1", "body_2", axis="z", origin=SHAFT, phi=phi_2 - phi_1),
    ),
    forces=(
        JointSpring("spring_c", "phi_21", c),
        JointDamper("damper_d", "phi_21", d),
        JointInput("motor", "phi_m", tau_m),
        BodyTorque("load", "body_2", (0, 0, -tau_l)),  # b_e = [0, -1] (3.142)
    ),
    # the gear cut open (3.137): tau_1 on body 1, tau_1^(m) = tau_1 / i_g against the rotor
    constraint_forces=(ConstraintForce("tau_1", torques=(("body_1", (0, 0, 1)), ("rotor", (0, 0, -1 / i_g)))),),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
w_1, w_2, a_1, a_2 = phi_1.rate, phi_2.rate, phi_1.accel, phi_2.accel
q, qd, qdd = Matrix([phi_1, phi_2]), Matrix([w_1, w_2]), Matrix([a_1, a_2])
M = diag(I_1 + i_g**2 * I_m, I_2)                  # (3.141)
K = Matrix([[c, -c], [-c, c]])                     # (3.142)
D = Matrix([[d, -d], [-d, d]])                     # (3.142)
b_e, b_u = Matrix([0, -1]), Matrix([i_g, 0])       # (3.142)
_read_as = "(3.141) M q̈ + D q̇ + K q = b_e τ_l + b_u τ_m read as g = K q, f_np = −D q̇ + b_e τ_l + b_u τ_m"

tau_1_p = Printed("tau_1", "N m", "the gear torque on body 1, (3.139)")

CLAIMS = [
    Claim("(3.136)", "parameter", 1 / i_g, "gear: φ̇_1 = (1/i_g) φ̇_m, the printed factor between the rates",
          reference=1 / diff(SYSTEM.joint("phi_m").phi, phi_1.symbol),
          note="φ_m is the rotor's tree joint phi_m; the printed factor 1/i_g = φ̇_1/φ̇_m is compared with the "
               "model's joint map phi_m = i_g phi_1 (reference 1/(∂phi_m/∂phi_1))"),
    Claim("(3.138c)", "eom", I_2 * a_2 - (c * (phi_1 - phi_2) + d * (w_1 - w_2) - tau_l),
          "angular momentum balance of body 2, I_2 φ̈_2 = c (φ_1 − φ_2) + d (φ̇_1 − φ̇_2) − τ_l", index=(1,)),
    Claim("(3.139)", "constraint:tau_1", tau_m * i_g - I_m * i_g**2 * a_1,
          "gear torque on the output side τ_1 = τ_m i_g − I_m i_g² φ̈_1", defines=tau_1_p),
    Claim("(3.138b)", "eom", I_1 * a_1 - (tau_1_p - c * (phi_1 - phi_2) - d * (w_1 - w_2)),
          "angular momentum balance of body 1, I_1 φ̈_1 = τ_1 − c (φ_1 − φ_2) − d (φ̇_1 − φ̇_2)", index=(0,),
          ingredients=("(3.139)",)),
    Claim("(3.140a)", "eom", (I_1 + i_g**2 * I_m) * a_1 - (tau_m * i_g - c * (phi_1 - phi_2) - d * (w_1 - w_2)),
          "(I_1 + i_g² I_m) φ̈_1 = τ_m i_g − c (φ_1 − φ_2) − d (φ̇_1 − φ̇_2)", index=(0,)),
    Claim("(3.140b)", "eom", I_2 * a_2 - (c * (phi_1 - phi_2) + d * (w_1 - w_2) - tau_l),
          "I_2 φ̈_2 = c (φ_1 − φ_2) + d (φ̇_1 − φ̇_2) − τ_l", index=(1,)),
    Claim("(3.141)", "M", M, "M = diag(I_1 + i_g² I_m, I_2)"),
    Claim("(3.141), (3.142)", "g", K * q, "potential forces K q (torsion spring)", note=_read_as),
    Claim("(3.141), (3.142)", "f_np", -D * qd + b_e * tau_l + b_u * tau_m,
          "non-potential forces −D q̇ + b_e τ_l + b_u τ_m", note=_read_as),
    Claim("(3.141)", "eom", M * qdd + D * qd + K * q - b_e * tau_l - b_u * tau_m,
          "M q̈ + D q̇ + K q = b_e τ_l + b_u τ_m"),
]

SCENES = [
    Scene("spin_up", "Example 3.16, (3.141): from rest the motor torque tau_m = 2 N m (i_g tau_m = 20 N m on "
          "body 1) spins the drive train up; the load torque tau_l = 5 N m comes on at 1 s; the shaft twists "
          "and its oscillation is damped by d", (0.0, 0.0), (0.0, 0.0), 3.0,
          {"springs", "dampers", "inputs", "external"}, inputs={tau_m: Constant(2.0), tau_l: Step(1.0, 5.0)}),
]
