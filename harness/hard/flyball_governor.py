"""Stiff flyball governor: problem A05 of the IFToMM library of computational benchmark problems for multibody
dynamics ("Stiff flyball governor", M. González et al., University of A Coruña, 2005; described in
M. González, D. Dopico, U. Lugrís, J. Cuadrado, "A benchmarking system for MBS simulation software: problem
standardization and performance measurement", Multibody System Dynamics, 2006). Not a system of the lecture: it
is modeled with the lecture's vocabulary (chapter 5) as the stiff benchmark of the hard cases (``harness hard``).

It lives here, not in ``models/``: the catalogue steps every exported MJCF for 1 s at MuJoCo's default step
(2 ms, ``Euler``) and the benchmark's dampers (4e4 N s/m between bodies: tendon damping, which ``Euler`` treats
explicitly) make that diverge at t = 4 ms — stiffness is the point of the benchmark, so it is simulated with
step sizes and integrators chosen for it (``harness/hard/stiff.py``). Its conformance (M, C, g, q̈ against
Pinocchio and MuJoCo on random states) passed when it was in the catalogue.

Geometry as published with the benchmark (original parameters). A vertical shaft (square bar ``a × w × w``,
``a = 1 m``, ``w = 0.01 m``, density ``rho = 3000 kg/m³``) turns freely about ``e_z`` by ``phi``; it stands on the
ground (its lower end at the origin, centre of mass at ``[0, 0, a/2]``). A cubic slider (edge ``b = 0.1 m``, the
same density) slides along the shaft, its centre at the height ``s``. Two rods (bars ``a × w × w``) hang from
pins on the shaft at ``[±d_AB/2, 0, a]`` (``d_AB = 0.1 m``) and turn about the pins' horizontal axes (normal to
the plane of shaft and rod) by ``alpha_1``, ``alpha_2``: the angle of each rod *below the horizontal*, so that
rod 1 points along ``[cos alpha_1, 0, -sin alpha_1]`` and rod 2 along ``[-cos alpha_2, 0, -sin alpha_2]`` in the
shaft's frame. A point mass ``m_P = 5 kg`` sits at the free end of each rod. In the benchmark the coupler rods
between slider and rods are replaced by spring-damper elements (stiffness ``K = 8e5 N/m``, damping
``C = 4e4 N s/m``, rest length ``s_0 = 0.5 m``) from the slider's side points ``[±b/2, 0, 0]`` to the rods'
mid points: this is what makes the problem stiff. Gravity ``g`` acts in ``-e_z``.

Initial state of the benchmark: ``s = 0.5 m``, ``alpha = 30°`` (the springs are then exactly relaxed:
``|[a/2 cos 30°, 0, a - a/2 sin 30° - s]| = 0.5``), everything at rest relative to the shaft, and the shaft turning
at ``2 pi rad/s`` (an initial angular velocity: the shaft is not driven). What is measured: the slider position
``s(t)`` (harness/hard states the horizon and the error measure).

Tree (identity map, ``q = [phi, s, alpha_1, alpha_2]``): joint ``phi`` revolute about ``z`` from the world to
the shaft; joint ``s`` prismatic along ``z`` from the shaft to the slider; joints ``alpha_1``, ``alpha_2``
revolute about the pins' ``y`` axes from the shaft to the rods (rod 2's pin frame is turned by ``pi`` about
``z``, so that both rods turn *down* with increasing angle). Each rod and its point mass are one rigid body:
mass ``m_R + m_P`` (``m_R = rho a w²``), centre of mass and inertia tensor by Steiner's theorem (3.133).

Drawn states: ``s`` in ``[0.3, 0.7] m`` and ``alpha_1``, ``alpha_2`` in ``[0.2, 0.8] rad`` keep the springs'
lengths above 0.2 m (a spring of zero length has no direction).
"""

import sympy as sp

from harness.modeling.system import (WORLD, Coordinate, Damper, Gravity, Inertia, Joint, Link, Parameter, Point, Spring,
                                     System, steiner)

rho = Parameter("rho", 3000.0, "kg/m^3", "density of shaft, slider and rods")
a = Parameter("a", 1.0, "m", "length of the shaft and of each rod")
w = Parameter("w", 0.01, "m", "width and height of the shaft's and rods' square cross-section")
b = Parameter("b", 0.1, "m", "edge of the cubic slider")
d_AB = Parameter("d_AB", 0.1, "m", "distance between the rods' pins A and B on the shaft")
m_P = Parameter("m_P", 5.0, "kg", "point mass at the free end of each rod")
K = Parameter("K", 8.0e5, "N/m", "stiffness of each spring-damper element")
C = Parameter("C", 4.0e4, "N s/m", "damping of each spring-damper element")
s_0 = Parameter("s_0", 0.5, "m", "rest length of the springs")
g = Parameter("g", 9.81, "m/s^2", "acceleration due to gravity")

phi = Coordinate("phi", "rad", "angle of the shaft about e_z")
s = Coordinate("s", "m", "height of the slider's centre above the shaft's lower end", range=(0.3, 0.7))
alpha_1 = Coordinate("alpha_1", "rad", "angle of rod 1 below the horizontal", range=(0.2, 0.8))
alpha_2 = Coordinate("alpha_2", "rad", "angle of rod 2 below the horizontal", range=(0.2, 0.8))

_rho, _a, _w, _b, _mP = rho.symbol, a.symbol, w.symbol, b.symbol, m_P.symbol
m_bar = _rho * _a * _w**2                  # shaft, rod: square bars a × w × w
m_slider = _rho * _b**3
m_rod = m_bar + _mP                        # rod and its point mass: one rigid body
x_rod = (m_bar * _a / 2 + _mP * _a) / m_rod  # its centre of mass along the rod


# the rod and its point mass about their common centre of mass, by Steiner's term (3.126), (3.133)
_I_rod = (Inertia.cuboid(m_bar, _a, _w, _w).matrix + steiner(m_bar, sp.Matrix([_a / 2 - x_rod, 0, 0]))
          + steiner(_mP, sp.Matrix([_a - x_rod, 0, 0])))
ROD_INERTIA = Inertia(sp.simplify(_I_rod[0, 0]), sp.simplify(_I_rod[1, 1]), sp.simplify(_I_rod[2, 2]))


def _rod(name: str, description: str) -> Link:
    return Link(name, m_rod, (x_rod, 0, 0), ROD_INERTIA, description=description)


SYSTEM = System(
    name="flyball_governor",
    title="Stiff flyball governor (IFToMM benchmark A05)",
    lecture="not in the lecture: IFToMM multibody benchmark A05, modeled with chapter 5",
    parameters=(rho, a, w, b, d_AB, m_P, K, C, s_0, g),
    coordinates=(phi, s, alpha_1, alpha_2),
    links=(
        Link("shaft", m_bar, (0, 0, _a / 2), Inertia.cuboid(m_bar, _w, _w, _a), description="vertical square bar"),
        Link("slider", m_slider, (0, 0, 0), Inertia.cuboid(m_slider, _b, _b, _b), description="cubic slider"),
        _rod("rod_1", "rod 1 with its point mass at the free end"),
        _rod("rod_2", "rod 2 with its point mass at the free end"),
    ),
    joints=(
        Joint("phi", "revolute", WORLD, "shaft", axis="z"),
        Joint("s", "prismatic", "shaft", "slider", axis="z"),
        Joint("alpha_1", "revolute", "shaft", "rod_1", axis="y", origin=(d_AB.symbol / 2, 0, _a)),
        Joint("alpha_2", "revolute", "shaft", "rod_2", axis="y", origin=(-d_AB.symbol / 2, 0, _a), rpy=(0, 0, sp.pi)),
    ),
    gravity=Gravity(g.symbol, (0, 0, -1)),
    forces=(
        Spring("spring_1", Point("slider", (_b / 2, 0, 0), "E"), Point("rod_1", (_a / 2, 0, 0), "C_1"), K.symbol,
               s_0.symbol),
        Spring("spring_2", Point("slider", (-_b / 2, 0, 0), "F"), Point("rod_2", (_a / 2, 0, 0), "D_2"), K.symbol,
               s_0.symbol),
        Damper("damper_1", Point("slider", (_b / 2, 0, 0), "E"), Point("rod_1", (_a / 2, 0, 0), "C_1"), C.symbol),
        Damper("damper_2", Point("slider", (-_b / 2, 0, 0), "F"), Point("rod_2", (_a / 2, 0, 0), "D_2"), C.symbol),
    ),
    doc=__doc__,
)

