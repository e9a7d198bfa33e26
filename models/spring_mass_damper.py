"""Spring-mass-damper system with three masses, Example 3.10 (Figure 3.29); (3.91)-(3.95).

Three point masses ``m_1``, ``m_2``, ``m_3`` move vertically; ``s_1``, ``s_2``, ``s_3`` are their heights, counted
upward: gravity acts in ``-e_z`` (``−m_i g`` in (3.91)). ``m_1`` and ``m_2`` stand side by side on the ground, each
on a linear spring (``c_11``, relaxed length ``s_011``; ``c_22``, ``s_022``) and a linear damper (``d_11``;
``d_22``) whose foot points are fixed to the ground at height 0 directly below the mass, so that those
springs have the length ``s_1`` and ``s_2``. ``m_3`` lies on top of both: the spring ``c_13`` (``s_013``) and the
damper ``d_13`` connect ``m_1`` and ``m_3``, the spring ``c_23`` (``s_023``) connects ``m_2`` and ``m_3``; their
attachment points on ``m_3`` lie vertically above ``m_1`` and ``m_2``, so these lengths are ``s_3 − s_1`` and
``s_3 − s_2``. The load ``f_L`` pushes ``m_3`` down (``−f_L`` in (3.91c), ``b = [0, 0, −1]ᵀ`` (3.95)). Every
element is vertical, so the springs and dampers between points (axial elements, (3.84), (3.88)) give
exactly the linear forces of (3.91). The horizontal positions (``m_1`` at ``x = −0.5 m``, ``m_2`` at
``x = +0.5 m``, ``m_3`` between them) never change and do not enter the dynamics.

Each mass has a prismatic tree joint along ``z`` from the ground (identity map, ``q = [s_1, s_2, s_3]ᵀ``).

Ranges: a spring or damper between two points is singular at zero length (its direction is undefined)
and (3.91) describes it only while its length is positive. The drawn states keep every element at least
0.2 m long: ``s_1, s_2 ∈ [0.2, 0.8] m`` and ``s_3 ∈ [1.1, 1.9] m``.
"""

from sympy import Matrix, diag

from harness.modeling import (WORLD, Claim, Coordinate, Damper, Gravity, Input, Joint, Link, Parameter, Point,
                              PointForce, Scene, Spring, Step, System, standard_gravity)

m_1 = Parameter("m_1", 1.0, "kg", "mass 1 (on the ground, left)")
m_2 = Parameter("m_2", 1.5, "kg", "mass 2 (on the ground, right)")
m_3 = Parameter("m_3", 2.0, "kg", "mass 3 (on top of masses 1 and 2)")
c_11 = Parameter("c_11", 800.0, "N/m", "spring ground - m_1")
c_22 = Parameter("c_22", 600.0, "N/m", "spring ground - m_2")
c_13 = Parameter("c_13", 400.0, "N/m", "spring m_1 - m_3")
c_23 = Parameter("c_23", 500.0, "N/m", "spring m_2 - m_3")
s_011 = Parameter("s_011", 0.5, "m", "relaxed length of spring c_11")
s_022 = Parameter("s_022", 0.5, "m", "relaxed length of spring c_22")
s_013 = Parameter("s_013", 0.8, "m", "relaxed length of spring c_13")
s_023 = Parameter("s_023", 0.8, "m", "relaxed length of spring c_23")
d_11 = Parameter("d_11", 5.0, "N s/m", "damper ground - m_1")
d_22 = Parameter("d_22", 4.0, "N s/m", "damper ground - m_2")
d_13 = Parameter("d_13", 3.0, "N s/m", "damper m_1 - m_3")
g = standard_gravity()

f_L = Input("f_L", "N", "load force on m_3, pointing down")

s_1 = Coordinate("s_1", "m", "height of m_1 above the ground", range=(0.2, 0.8))
s_2 = Coordinate("s_2", "m", "height of m_2 above the ground", range=(0.2, 0.8))
s_3 = Coordinate("s_3", "m", "height of m_3 above the ground", range=(1.1, 1.9))

# attachment points (every element vertical): ground feet below m_1 and m_2, and the two points on m_3
ground_1 = Point(WORLD, (-0.5, 0, 0), "ground_1")
ground_2 = Point(WORLD, (0.5, 0, 0), "ground_2")
point_1 = Point("mass_1", (0, 0, 0), "P1")
point_2 = Point("mass_2", (0, 0, 0), "P2")
point_31 = Point("mass_3", (-0.5, 0, 0), "P31")
point_32 = Point("mass_3", (0.5, 0, 0), "P32")
point_3 = Point("mass_3", (0, 0, 0), "P3")

SYSTEM = System(
    name="spring_mass_damper",
    title="Spring-mass-damper system with three masses",
    lecture="Example 3.10; (3.91)-(3.95)",
    coordinates=(s_1, s_2, s_3),
    links=(
        Link("mass_1", m_1, description="point mass m_1"),
        Link("mass_2", m_2, description="point mass m_2"),
        Link("mass_3", m_3, description="point mass m_3 (attachment points 0.5 m to either side)"),
    ),
    joints=(
        Joint("s_1", "prismatic", WORLD, "mass_1", axis="z", origin=(-0.5, 0, 0)),
        Joint("s_2", "prismatic", WORLD, "mass_2", axis="z", origin=(0.5, 0, 0)),
        Joint("s_3", "prismatic", WORLD, "mass_3", axis="z"),
    ),
    gravity=Gravity(g, (0, 0, -1)),
    forces=(
        Spring("spring_11", ground_1, point_1, c_11, s_011),
        Damper("damper_11", ground_1, point_1, d_11),
        Spring("spring_22", ground_2, point_2, c_22, s_022),
        Damper("damper_22", ground_2, point_2, d_22),
        Spring("spring_13", point_1, point_31, c_13, s_013),
        Damper("damper_13", point_1, point_31, d_13),
        Spring("spring_23", point_2, point_32, c_23, s_023),
        PointForce("load_L", point_3, (0, 0, -f_L)),  # b = [0, 0, -1] (3.95)
    ),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
v_1, v_2, v_3 = s_1.rate, s_2.rate, s_3.rate
a_1, a_2, a_3 = s_1.accel, s_2.accel, s_3.accel
q, qd, qdd = Matrix([s_1, s_2, s_3]), Matrix([v_1, v_2, v_3]), Matrix([a_1, a_2, a_3])
M = diag(m_1, m_2, m_3)
D = Matrix([[d_11 + d_13, 0, -d_13], [0, d_22, 0], [-d_13, 0, d_13]])                          # (3.93)
K = Matrix([[c_11 + c_13, 0, -c_13], [0, c_22 + c_23, -c_23], [-c_13, -c_23, c_13 + c_23]])  # (3.94)
k = Matrix([-m_1 * g + c_11 * s_011 - c_13 * s_013,
            -m_2 * g + c_22 * s_022 - c_23 * s_023,
            -m_3 * g + c_13 * s_013 + c_23 * s_023])                                        # (3.95)
b = Matrix([0, 0, -1])                                                                      # (3.95)
q_R = K.inv() * k                                                                           # (3.96)
dq, dqd, dqdd = q - q_R, qd, qdd                                    # Δq = q − q_R (before (3.97)), q_R constant

CLAIMS = [
    Claim("(3.91a)", "eom", m_1 * a_1 - (-m_1 * g - c_11 * (s_1 - s_011) - d_11 * v_1 + c_13 * (s_3 - s_1 - s_013)
                                         - d_13 * (v_1 - v_3)), "momentum balance of m_1", index=(0,)),
    Claim("(3.91b)", "eom", m_2 * a_2 - (-m_2 * g - c_22 * (s_2 - s_022) - d_22 * v_2 + c_23 * (s_3 - s_2 - s_023)),
          "momentum balance of m_2", index=(1,)),
    Claim("(3.91c)", "eom", m_3 * a_3 - (-m_3 * g - c_13 * (s_3 - s_1 - s_013) + d_13 * (v_1 - v_3)
                                         - c_23 * (s_3 - s_2 - s_023) - f_L), "momentum balance of m_3", index=(2,)),
    Claim("(3.92)", "M", M, "mass matrix M = diag(m_1, m_2, m_3)"),
    Claim("(3.92), (3.94), (3.95)", "g", K * q - k, "potential forces K q − k (springs and gravity)",
          note="(3.92) M q̈ + D q̇ + K q = k + b f_L read as g = K q − k, f_np = −D q̇ + b f_L"),
    Claim("(3.92), (3.93), (3.95)", "f_np", -D * qd + b * f_L, "non-potential forces −D q̇ + b f_L",
          note="(3.92) M q̈ + D q̇ + K q = k + b f_L read as g = K q − k, f_np = −D q̇ + b f_L"),
    Claim("(3.92)", "eom", M * qdd + D * qd + K * q - k - b * f_L, "M q̈ + D q̇ + K q = k + b f_L"),
    Claim("(3.96)", "equilibrium", q_R, "equilibrium position q_R = K⁻¹ k (for f_L = 0)",
          note="K (3.94), k (3.95) as printed"),
    Claim("(3.97)", "eom", M * dqdd + D * dqd + K * dq + K * q_R - k - b * f_L,
          "M Δq̈ + D Δq̇ + K Δq + K q_R = k + b f_L about the equilibrium position",
          note="Δq = q − q_R as the text defines it, with q_R = K⁻¹ k of (3.96) (constant: Δq̇ = q̇, Δq̈ = q̈); "
               "K, k of (3.94), (3.95). The underbrace, printed under K Δq + K q_R and labelled k, is not "
               "part of the equation and not transcribed"),
]

SCENES = [
    Scene("released", "Example 3.10, (3.91)-(3.95): the masses released from rest, displaced from their rest "
          "position s = (0.474, 0.462, 1.245) m; gravity, springs and dampers; the load f_L steps to 30 N at 1 s",
          (0.55, 0.40, 1.35), (0.0, 0.0, 0.0), 3.0, {"gravity", "springs", "dampers", "external"},
          inputs={f_L: Step(1.0, 30.0)}),
]
