"""Pulley system with two masses, Example 3.6 (Figure 3.17); (3.45)-(3.49).

Two point masses ``m_1`` and ``m_2`` hang on a massless rope over frictionless, massless pulleys: ``m_1`` on
the movable pulley (two rope segments, ``f_S1``, ``f_S2``), ``m_2`` on the free end of the rope (``f_S3``).
The vertical ``z`` axis points *downward*, in the direction of gravity: (3.45) writes ``m_i z̈_i = m_i g − …``,
so ``e_g = +e_z``. ``z_1``, ``z_2`` are the positions of the masses (origin at the ceiling; their horizontal
positions never change and do not enter, both masses are placed on the ``z`` axis).

The lecture coordinate is ``Delta_z_2`` (``Δz_2``), the displacement of ``m_2`` from its position ``z_20`` at
``t = 0``. The rope couples the masses (3.47): ``z_2 = z_20 + Δz_2`` and ``z_1 = z_10 − Δz_2/2``. The model
has one prismatic tree joint per mass (along ``z``) and this map ``theta = phi(q)``: two tree joints, one
lecture coordinate; the engines' quantities are brought to ``Δz_2`` by ``J = ∂phi/∂q = [−1/2, 1]ᵀ``. The
rope force ``f_S`` is the constraint force of that map, declared as one: the rope pulls ``m_1`` up with two
segments (``2 f_S``, (3.45a) with (3.46)) and ``m_2`` up with one (``f_S``). The momentum balances (3.45), (3.48)
are claimed with ``f_S`` from (3.49b); ``z̈_1``, ``z̈_2`` are written in ``Δz̈_2`` by (3.47) and the single rope
force ``f_S`` of (3.46) stands for ``f_S1``, ``f_S2``, ``f_S3`` (the model's rope is one force: (3.46) is an
assumption of the model, not checked).
"""

from harness.modeling import (WORLD, Claim, ConstraintForce, Coordinate, Gravity, Joint, Link, Parameter, Point, Printed,
                              Scene, System, standard_gravity)

m_1 = Parameter("m_1", 2.0, "kg", "mass on the movable pulley")
m_2 = Parameter("m_2", 1.5, "kg", "mass on the free end of the rope")
z_10 = Parameter("z_10", 1.0, "m", "position of m_1 at t = 0 (downward from the ceiling)", assumption="real")
z_20 = Parameter("z_20", 1.5, "m", "position of m_2 at t = 0 (downward from the ceiling)", assumption="real")
g = standard_gravity()

Delta_z_2 = Coordinate("Delta_z_2", "m", "displacement of m_2 from z_20 (downward)")

SYSTEM = System(
    name="pulley",
    title="Pulley system with two masses",
    lecture="Example 3.6; (3.45)-(3.49)",
    coordinates=(Delta_z_2,),
    links=(
        Link("mass_1", m_1, description="point mass m_1 on the movable pulley"),
        Link("mass_2", m_2, description="point mass m_2 on the free end of the rope"),
    ),
    joints=(
        Joint("z_1", "prismatic", WORLD, "mass_1", axis="z", phi=z_10 - Delta_z_2 / 2),  # (3.47)
        Joint("z_2", "prismatic", WORLD, "mass_2", axis="z", phi=z_20 + Delta_z_2),      # (3.47)
    ),
    gravity=Gravity(g, (0, 0, 1)),  # z points downward
    constraint_forces=(ConstraintForce("f_S", forces=(("mass_1", Point("mass_1"), (0, 0, -2)),
                                                      ("mass_2", Point("mass_2"), (0, 0, -1)))),),
    doc=__doc__,
)

f_S_p = Printed("f_S", "N", "the rope force, (3.49b)")
_notation = "z_1_ddot = -Delta_z_2_ddot/2, z_2_ddot = Delta_z_2_ddot by (3.47); f_S1 = f_S2 = f_S3 = f_S (3.46)"

CLAIMS = [
    Claim("(3.47a)", "position:mass_2", z_20 + Delta_z_2, "z_2 = z_20 + Δz_2", index=(2,)),
    Claim("(3.47b)", "position:mass_1", z_10 - Delta_z_2 / 2, "z_1 = z_10 − Δz_2/2", index=(2,)),
    Claim("(3.49a)", "eom", Delta_z_2.accel - 2 * g * (2 * m_2 - m_1) / (m_1 + 4 * m_2),
          "d²/dt² Δz_2 = 2 g (2 m_2 − m_1)/(m_1 + 4 m_2)"),
    Claim("(3.49b)", "constraint:f_S", 3 * m_1 * m_2 * g / (4 * m_2 + m_1),
          "rope force f_S = 3 m_1 m_2 g/(4 m_2 + m_1)", defines=f_S_p),
    Claim("(3.45a)", "eom", m_1 * (-Delta_z_2.accel / 2) - (m_1 * g - f_S_p - f_S_p), "momentum balance of m_1",
          ingredients=("(3.49b)",), note=_notation),
    Claim("(3.45b)", "eom", m_2 * Delta_z_2.accel - (m_2 * g - f_S_p), "momentum balance of m_2",
          ingredients=("(3.49b)",), note=_notation),
    Claim("(3.48a)", "eom", -m_1 / 2 * Delta_z_2.accel - (m_1 * g - 2 * f_S_p), "(3.45a) with (3.46), (3.47)",
          ingredients=("(3.49b)",)),
    Claim("(3.48b)", "eom", m_2 * Delta_z_2.accel - (m_2 * g - f_S_p), "(3.45b) with (3.46), (3.47)",
          ingredients=("(3.49b)",)),
]

SCENES = [
    Scene("release", "Example 3.6, (3.49): both masses released from rest, gravity only; m_2 (1.5 kg) sinks and "
          "lifts m_1 (2 kg) on the movable pulley, uniform acceleration (conservative)", (0.0,), (0.0,), 2.0,
          {"gravity"}),
]
