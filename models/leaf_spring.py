"""Two masses with a leaf spring, Example 3.8 (Figure 3.20); (3.71)-(3.74).

Two point masses ``m_1`` and ``m_2`` move along one axis, each held by a linear spring to the ground (``c_1``,
relaxed length ``s_01``; ``c_2``, ``s_02``), and joined by a leaf spring that gives the force
``f_12 = c_12 (z_1 - z_2)`` on a relative displacement, ``f_21 = -f_12`` (the text). The lecture coordinates
are the displacements from the relaxed lengths, ``z_1 = s_1 - s_01`` and ``z_2 = s_2 - s_02``; the potential energy
is 0 at ``z_1 = z_2 = 0``, where the masses are at rest: no gravity acts along the motion (the text's ``V`` holds
the springs only).

Model: ``m_1`` on a prismatic joint ``z_1`` along ``z`` from the ground, with the spring ``c_1`` in it
(``V = c_1 z_1²/2``); ``m_2`` on a prismatic joint on ``m_1``, ``l_12`` above it at rest, at the relative
displacement ``theta = z_2 - z_1`` (the map), with the leaf spring in it (``V = c_12 (z_2 - z_1)²/2``: the text's
``f_12 = c_12 (z_1 - z_2)``; how the leaf bends, which only the figure shows, does not enter); the spring ``c_2``
between a ground point ``s_02`` above ``m_2``'s rest position and ``m_2`` (``V = c_2 z_2²/2`` while its length
``s_02 - z_2`` is positive: the drawn displacements keep it so). ``l_12`` does not enter the dynamics.
"""

from sympy import Matrix

from harness.modeling import (WORLD, Claim, Coordinate, Joint, JointSpring, Link, Parameter, Point, Scene, Spring,
                              System)

m_1 = Parameter("m_1", 1.0, "kg", "mass 1")
m_2 = Parameter("m_2", 2.0, "kg", "mass 2")
c_1 = Parameter("c_1", 100.0, "N/m", "stiffness of the spring between the ground and m_1")
c_2 = Parameter("c_2", 150.0, "N/m", "stiffness of the spring between the ground and m_2")
c_12 = Parameter("c_12", 50.0, "N/m", "stiffness of the leaf spring between m_1 and m_2")
s_02 = Parameter("s_02", 0.5, "m", "relaxed length of the spring c_2")
l_12 = Parameter("l_12", 0.5, "m", "distance of the masses at rest (does not enter)")

z_1 = Coordinate("z_1", "m", "displacement of m_1 from the relaxed length s_01", range=(-0.2, 0.2))
z_2 = Coordinate("z_2", "m", "displacement of m_2 from the relaxed length s_02", range=(-0.2, 0.2))

SYSTEM = System(
    name="leaf_spring",
    title="Two masses with a leaf spring",
    lecture="Example 3.8; (3.71)-(3.74)",
    coordinates=(z_1, z_2),
    links=(Link("mass_1", m_1, description="point mass m_1"),
           Link("mass_2", m_2, description="point mass m_2, l_12 from m_1 at rest")),
    joints=(Joint("z_1", "prismatic", WORLD, "mass_1", axis="z"),
            Joint("z_21", "prismatic", "mass_1", "mass_2", axis="z", origin=(0, 0, l_12), phi=z_2 - z_1)),
    forces=(JointSpring("spring_1", "z_1", c_1),
            JointSpring("leaf_spring", "z_21", c_12),
            Spring("spring_2", Point("mass_2", name="P2"), Point(WORLD, (0, 0, l_12 + s_02), "ground_2"), c_2, s_02)),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
f_F = Matrix([c_1 * z_1 + c_12 * (z_1 - z_2), c_2 * z_2 + c_12 * (z_2 - z_1)])         # (3.71)
K = Matrix([[c_1 + c_12, -c_12], [-c_12, c_2 + c_12]])                                   # (3.74)

CLAIMS = [
    Claim("(3.71)", "g", f_F, "the spring forces f_F(z_1, z_2) by the displacements",
          note="f_F, the forces of the springs combined according to the displacements, is the vector of potential "
               "forces g = ∂V/∂z"),
    Claim("(3.73) ∂f_F1/∂z_2", "K", c_12, "integrability condition: ∂f_F1/∂z_2 = c_12", index=(0, 1)),
    Claim("(3.73) ∂f_F2/∂z_1", "K", c_12, "integrability condition: ∂f_F2/∂z_1 = c_12", index=(1, 0)),
    Claim("(3.74)", "V", (c_1 + c_12) * z_1**2 / 2 + (c_2 + c_12) * z_2**2 / 2 - c_12 * z_1 * z_2,
          "potential energy V = ½ zᵀ K z"),
    Claim("(3.74) K", "K", K, "stiffness matrix K"),
]

SCENES = [
    Scene("release", "Example 3.8: m_1 pulled 5 cm out of its rest position and released, m_2 at rest; the leaf "
          "spring passes the motion on (conservative, springs only)", (0.05, 0.0), (0.0, 0.0), 2.0, {"springs"}),
]
