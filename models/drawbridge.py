"""Drawbridge, Exercise A.1 (Figures A.1-A.3), solution (A.1)-(A.9).

The bridge (mass ``m_B``, centre of gravity ``S_B`` at ``l_B`` from its bearing ``B``) turns about ``B``; the girder
(mass ``m_T``, centre of gravity ``S_T`` at ``l_T`` from its bearing ``A``) turns about ``A``. Rope 1 joins them at
``l_s`` from each bearing (equal arms) and keeps them parallel, so one coordinate describes both: ``phi_B``, the angle of the
bridge (and the girder) above the horizontal, positive when the bridge is raised. The counterweight ``m`` sits at
``l_m`` on the other side of ``A``. Rope 2 winds on the girder's cylinder (radius ``R``) about ``A`` and pulls with
the force ``f_S2``: a torque ``R f_S2`` on the girder in the sense of ``phi_B`` (the sense (A.6) gives it). Gravity
acts in ``-e_y``. The ropes are massless and the bearings frictionless.

The torque balances (A.2), (A.6) are read off the free-body diagrams with lever arms ``l cos(phi_B)``: the bridge's
weight and rope 1 about ``B``, the girder's weight, the counterweight, rope 1 and rope 2 about ``A``. In the model the
three bodies are a tree of three joints at ``B`` and ``A`` (bridge, girder, counterweight on an arm of the girder),
each turned by ``phi_B``: the map ``theta = phi(q)`` holds rope 1 and the rigid girder. Where ``A`` lies above ``B``
does not enter (``h_A``). The bridge is a plate of length ``2 l_B``, the girder a bar of length ``2 l_T``: their
inertias enter the motion of the scene only, not the balances the lecture prints.

Only rope 2's force is an input of the equations of motion. Rope 2 pulls the girder's cylinder down at radius ``R``:
the torque ``R f_S2`` and the force ``-f_S2 e_y`` at ``A`` (together the rope's pull on its line). The bearing forces
and rope 1's force are constraint forces: rope 1 (``f_S1``, at ``l_s`` from each bearing, vertical: up on the bridge,
down on the girder, (A.1b), (A.5b)) and the counterweight's arm (a torque that keeps the counterweight on the girder)
are the two constraints of the map; ``f_B`` is the force of the joint at ``B`` on the bridge, ``f_A`` the force of
the two joints at ``A`` on the girder and the counterweight. The balances (A.1)-(A.8) are claimed at rest, held by
rope 2 (``f_S2`` from the equations of motion at each drawn ``phi_B``). Not claimed: (A.9), the counterweight for
which rope 2 is slack (a parameter solved from a derived quantity).
"""

from sympy import Matrix, cos

from harness.derivation.bodies import joint_force
from harness.modeling import (WORLD, BodyTorque, Claim, Constant, ConstraintForce, Coordinate, Gravity, Inertia, Input,
                              Joint, Link, Parameter, Point, PointForce, Printed, Scene, System, printed_matrix,
                              standard_gravity)

m_B = Parameter("m_B", 1000.0, "kg", "mass of the bridge")
m_T = Parameter("m_T", 500.0, "kg", "mass of the girder")
m = Parameter("m", 800.0, "kg", "counterweight on the girder")
l_B = Parameter("l_B", 5.0, "m", "bearing B to the bridge's centre of gravity S_B")
l_T = Parameter("l_T", 2.0, "m", "bearing A to the girder's centre of gravity S_T")
l_m = Parameter("l_m", 3.0, "m", "bearing A to the counterweight")
R = Parameter("R", 0.5, "m", "radius of the girder's cylinder that rope 2 winds on")
l_s = Parameter("l_s", 4.0, "m", "bearing to rope 1 on the bridge and on the girder (equal arms)")
h_A = Parameter("h_A", 6.0, "m", "height of bearing A above bearing B (does not enter)")
I_B = Parameter("I_B", 1000.0 * 10.0**2 / 12, "kg m^2", "inertia of the bridge about S_B (plate of length 2 l_B)")
I_T = Parameter("I_T", 500.0 * 4.0**2 / 12, "kg m^2", "inertia of the girder about S_T (bar of length 2 l_T)")
g = standard_gravity()

phi_B = Coordinate("phi_B", "rad", "angle of the bridge and the girder above the horizontal")
f_S2 = Input("f_S2", "N", "tensile force in rope 2, on the girder's cylinder of radius R")


def _plate(inertia):
    """A plate or bar turning about z: its inertia about z (the one that enters), small about its own axis x."""
    return Inertia(inertia / 100, inertia, inertia)


SYSTEM = System(
    name="drawbridge",
    title="Drawbridge",
    lecture="Exercise A.1; (A.1)-(A.9)",
    coordinates=(phi_B,),
    links=(
        Link("bridge", m_B, (l_B, 0, 0), _plate(I_B), description="the bridge, S_B at l_B from B"),
        Link("girder", m_T, (l_T, 0, 0), _plate(I_T), description="the girder, S_T at l_T from A"),
        Link("counterweight", m, (-l_m, 0, 0), description="the counterweight m at l_m on the other side of A"),
    ),
    joints=(
        Joint("phi_B", "revolute", WORLD, "bridge", axis="z"),
        Joint("phi_A", "revolute", WORLD, "girder", axis="z", origin=(0, h_A, 0), phi=phi_B),
        Joint("phi_m", "revolute", WORLD, "counterweight", axis="z", origin=(0, h_A, 0), phi=phi_B),
    ),
    gravity=Gravity(g, (0, -1, 0)),
    forces=(BodyTorque("rope_2", "girder", (0, 0, R * f_S2)),
            PointForce("rope_2_pull", Point("girder"), (0, -f_S2, 0))),
    constraint_forces=(
        ConstraintForce("f_S1", forces=(("bridge", Point("bridge", (l_s, 0, 0)), (0, 1, 0)),
                                        ("girder", Point("girder", (l_s, 0, 0)), (0, -1, 0)))),
        ConstraintForce("tau_arm", torques=(("counterweight", (0, 0, 1)), ("girder", (0, 0, -1)))),
    ),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
f_S1_p = Printed("f_S1", "N", "rope 1's force, (A.3)")
f_B_p = printed_matrix("f_B", 2, 1, "N", "the bearing force at B, (A.4)")
f_A_p = printed_matrix("f_A", 2, 1, "N", "the bearing force at A, (A.8)")
_held = "holding:f_S2"


def _f_B():
    """The force of the joint at B on the bridge (a derivation: made when the claim is first compared)."""
    return joint_force(SYSTEM, "phi_B")[:2, 0]


def _f_A():
    """The force of the two joints at A on the girder and the counterweight."""
    return (joint_force(SYSTEM, "phi_A") + joint_force(SYSTEM, "phi_m"))[:2, 0]


_bearing_A = "bearing A carries the girder and the counterweight: the forces of the joints phi_A and phi_m"

CLAIMS = [
    Claim("(A.7)", "holding:f_S2", (m_B * g * l_B + m_T * g * l_T - m * g * l_m * cos(phi_B)) / R * cos(phi_B),
          "tensile force in rope 2 that holds the bridge at phi_B"),
    Claim("(A.3)", "constraint:f_S1", m_B * g * l_B / l_s, "tensile force in rope 1", at=_held, defines=f_S1_p),
    Claim("(A.4)", "parameter", Matrix([0, m_B * g * (1 - l_B / l_s)]), "bearing force at B", at=_held,
          reference=_f_B, defines=f_B_p, note="the force of the joint at B on the bridge"),
    Claim("(A.1a)", "eom", f_B_p[0], "force balance of the bridge in e_x", at=_held, ingredients=("(A.4)",)),
    Claim("(A.1b)", "eom", f_B_p[1] - m_B * g + f_S1_p, "force balance of the bridge in e_y", at=_held,
          ingredients=("(A.3)", "(A.4)")),
    Claim("(A.2)", "eom", -m_B * g * l_B * cos(phi_B) + f_S1_p * l_s * cos(phi_B), "torque balance of the bridge about B",
          at=_held, ingredients=("(A.3)",)),
    Claim("(A.8)", "parameter", Matrix([0, m_B * g * (l_B / l_s + l_B / R * cos(phi_B))
                                        + m_T * g * (1 + l_T / R * cos(phi_B)) - m * g * (1 + l_m / R * cos(phi_B))]),
          "bearing force at A", at=_held, reference=_f_A, defines=f_A_p, note=_bearing_A),
    Claim("(A.5a)", "eom", f_A_p[0], "force balance of the girder in e_x", at=_held, ingredients=("(A.8)",)),
    Claim("(A.5b)", "eom", -m * g - f_S2 + f_A_p[1] - m_T * g - f_S1_p, "force balance of the girder in e_y",
          at=_held, ingredients=("(A.3)", "(A.8)"), note="f_S2: rope 2's force, the input that holds the bridge"),
    Claim("(A.6)", "eom", m * g * l_m * cos(phi_B) + f_S2 * R - m_T * g * l_T * cos(phi_B) - f_S1_p * l_s * cos(phi_B),
          "torque balance of the girder about A", at=_held, ingredients=("(A.3)",),
          note="f_S2: rope 2's force, the input that holds the bridge"),
]

SCENES = [
    Scene("raise", "Exercise A.1: rope 2 pulls with 80 kN (more than the 70.6 kN that hold the bridge horizontal) "
          "and raises it from rest", (0.0,), (0.0,), 3.0, {"gravity", "external"}, inputs={f_S2: Constant(80e3)}),
]
