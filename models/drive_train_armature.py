"""Drive train, Example 3.16 (Figure 3.37); (3.136)-(3.142). Variant with the rotor inertia as armature.

The same drive train as ``drive_train`` (motor with rotor inertia ``I_m`` and torque ``tau_m``, lossless gear
with ratio ``i_g`` (3.136), body 1 ``I_1``, torsion spring ``c`` and damper ``d`` to body 2 ``I_2``, load torque
``tau_l`` against the positive sense of rotation; all axes parallel to ``z``, counter-clockwise positive,
angles counted from the relaxed spring, no gravity; ``q = [phi_1, phi_2]ᵀ``), but without a rotor body:
the motor is eliminated as in (3.139), (3.140a).

* ``phi_1`` – body 1 (``I_1``) on a revolute joint to the world (identity map), with the rotor inertia
  reflected through the gear as the joint's **armature** ``i_g² I_m`` (``Joint(armature=...)``: MuJoCo's
  ``dof_armature``, Pinocchio's ``model.armature``, ``+ i_g² I_m`` on ``M_θ[phi_1, phi_1]`` in the derivation).
  The motor torque enters through the gear as the torque ``i_g tau_m`` on body 1 (``b_u = [i_g, 0]ᵀ``, the
  ``tau_m i_g`` of (3.139)), applied as an external torque about ``z``.
* ``phi_21`` – body 2 (``I_2``) on a revolute joint on body 1 (same axis), at ``phi_21 = phi_2 − phi_1``; the
  torsion spring ``c`` and the damper ``d`` act in this joint, as in (3.138b, c).

How the two models relate: in ``drive_train`` the rotor is a body on its own tree joint at
``phi_m = i_g phi_1`` and its kinetic energy ``½ I_m φ̇_m²`` is mapped to ``phi_1`` by ``J = ∂phi/∂q``; here the
engines themselves add the reflected inertia ``i_g² I_m`` as armature. Both must give (3.140)-(3.142):
the same ``M = diag(I_1 + i_g² I_m, I_2)``, ``C = 0``, ``K q``, ``D q̇`` and inputs.

The lecture gives only the moments of inertia about the axes of rotation. The bodies' masses (centres of
mass on their axes) and their transverse moments of inertia never enter the dynamics; they are set to a
stated mass and to ``3/4`` of the axial moment (a physical tensor), and placed along the axis, as in
``drive_train``.
"""

from harness.modeling import WORLD, BodyTorque, Constant, Joint, JointDamper, JointSpring, Link, Scene, Step, System
# the same parameters, inputs, coordinates, bodies and printed equations as the rotor-body model (one place):
# both models must satisfy (3.140)-(3.142), one through the gear map, one through the engines' armature
from models.drive_train import CLAIMS as _CLAIMS
from models.drive_train import (BODY_1_AT, SHAFT, I_1, I_2, I_m, c, d, disc_inertia, i_g, m_1, m_2, phi_1, phi_2,
                                tau_l, tau_m)

# all but the gear: the map (3.136) (its reference is the rotor's tree joint phi_m) and the gear torque tau_1 (3.139)
# with the balance (3.138b) it enters, the gear's constraint force: only drive_train has the gear
CLAIMS = [claim for claim in _CLAIMS if claim.equation not in ("(3.136)", "(3.138b)", "(3.139)")]

__all__ = ["CLAIMS", "SCENES", "SYSTEM"]

SYSTEM = System(
    name="drive_train_armature",
    title="Drive train (rotor inertia as armature)",
    lecture="Example 3.16; (3.136)-(3.142)",
    coordinates=(phi_1, phi_2),
    links=(
        Link("body_1", m_1, inertia=disc_inertia(I_1), description="body 1 on the gear's output side"),
        Link("body_2", m_2, inertia=disc_inertia(I_2), description="body 2 carrying the load torque"),
    ),
    joints=(
        Joint("phi_1", "revolute", WORLD, "body_1", axis="z", origin=BODY_1_AT, armature=i_g**2 * I_m),  # (3.140a)
        Joint("phi_21", "revolute", "body_1", "body_2", axis="z", origin=SHAFT, phi=phi_2 - phi_1),
    ),
    forces=(
        JointSpring("spring_c", "phi_21", c),
        JointDamper("damper_d", "phi_21", d),
        BodyTorque("motor", "body_1", (0, 0, i_g * tau_m)),  # b_u = [i_g, 0] (3.142)
        BodyTorque("load", "body_2", (0, 0, -tau_l)),        # b_e = [0, -1] (3.142)
    ),
    doc=__doc__,
)

SCENES = [
    Scene("spin_up", "Example 3.16, (3.141): the scene spin_up of drive_train with the rotor inertia as "
          "armature: tau_m = 2 N m from rest, load torque tau_l = 5 N m from 1 s", (0.0, 0.0), (0.0, 0.0), 3.0,
          {"springs", "dampers", "external"}, inputs={tau_m: Constant(2.0), tau_l: Step(1.0, 5.0)}),
]
