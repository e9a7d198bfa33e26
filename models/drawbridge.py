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

Only rope 2's force is an input of the equations of motion; the bearing forces (A.4), (A.8) and rope 1's force
(A.3) are constraint forces, which the harness does not derive (they stay in the list of unclaimed equations).
"""

from sympy import cos

from harness.modeling import (WORLD, BodyTorque, Claim, Constant, Coordinate, Gravity, Inertia, Input, Joint, Link,
                              Parameter, Scene, System, standard_gravity)

m_B = Parameter("m_B", 1000.0, "kg", "mass of the bridge")
m_T = Parameter("m_T", 500.0, "kg", "mass of the girder")
m = Parameter("m", 800.0, "kg", "counterweight on the girder")
l_B = Parameter("l_B", 5.0, "m", "bearing B to the bridge's centre of gravity S_B")
l_T = Parameter("l_T", 2.0, "m", "bearing A to the girder's centre of gravity S_T")
l_m = Parameter("l_m", 3.0, "m", "bearing A to the counterweight")
R = Parameter("R", 0.5, "m", "radius of the girder's cylinder that rope 2 winds on")
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
    forces=(BodyTorque("rope_2", "girder", (0, 0, R * f_S2)),),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
CLAIMS = [
    Claim("(A.7)", "holding:f_S2", (m_B * g * l_B + m_T * g * l_T - m * g * l_m * cos(phi_B)) / R * cos(phi_B),
          "tensile force in rope 2 that holds the bridge at phi_B"),
]

SCENES = [
    Scene("raise", "Exercise A.1: rope 2 pulls with 80 kN (more than the 70.6 kN that hold the bridge horizontal) "
          "and raises it from rest", (0.0,), (0.0,), 3.0, {"gravity", "external"}, inputs={f_S2: Constant(80e3)}),
]
