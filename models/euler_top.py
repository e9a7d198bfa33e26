"""Heavy top in Euler angles: a rigid body turning about a fixed point, its orientation parametrized by the Euler
angles of Section 4.2.1 (4.18) and Exercise 4.3 (4.63).

The lecture introduces the Euler angles ``(phi, theta, psi)`` as three successive rotations: about ``z_0`` by
``phi``, about the rotated ``y`` axis by ``theta``, about the rotated ``z`` axis by ``psi`` (4.18). This system
realizes that chain with three revolute joints at one fixed point ``O``: the massless frames ``precession``
(after ``phi``) and ``nutation`` (after ``theta``), and the body ``top`` (after ``psi``), so that its rotation
matrix is (4.18) and its rotational Jacobian the (J_omega)_0^3 of Exercise 4.3. The lecture has no dynamics for
it; the body is a top of mass ``m`` with its centre of gravity at ``s`` on its own ``z`` axis and principal
inertias ``I_xx``, ``I_yy``, ``I_zz`` about it, gravity in ``-e_z``: a heavy top (Lagrange's top when
``I_xx = I_yy``), whose equations of motion the harness derives and compares with the engines like any other.

Singularity: the Euler angles are singular at ``theta = 0`` and ``theta = pi`` (``phi`` and ``psi`` turn about
the same axis; (4.63) loses rank, ``M`` is singular). The drawn states keep ``theta`` in ``[0.2, pi - 0.2]``.

Claims: the elementary rotation about ``z`` (4.9) is the precession frame's ``R_0^1``; the elementary rotation
about ``y`` (4.10a) and its ``S`` (4.47) are the nutation frame's rotation relative to the precession frame (the
chain's second elementary rotation); (4.14) is the nutation frame's ``R_0^2`` (``z`` then the rotated ``y``);
(4.18) the top's ``R_0^3``, (4.46) the precession frame's ``S``, (4.63) the top's (J_omega)_0^3. The rotations
about ``x`` ((4.10b), the second matrix of (4.47), (4.19)) and the other orders ((4.15)-(4.17)) belong to other
chains and stay unclaimed.
"""

from sympy import Matrix, cos, sin

from harness.modeling import (WORLD, Claim, Coordinate, Gravity, Inertia, Joint, Link, Parameter, Scene, System,
                              standard_gravity)

m = Parameter("m", 0.5, "kg", "mass of the top")
s = Parameter("s", 0.04, "m", "fixed point O to the top's centre of gravity, along its own z axis")
I_xx = Parameter("I_xx", 4e-4, "kg m^2", "inertia of the top about its x axis through its centre of gravity")
I_yy = Parameter("I_yy", 5e-4, "kg m^2", "inertia of the top about its y axis through its centre of gravity")
I_zz = Parameter("I_zz", 3e-4, "kg m^2", "inertia of the top about its own z axis through its centre of gravity")
g = standard_gravity()

phi = Coordinate("phi", "rad", "Euler angle 1: rotation about z_0 (precession)")
theta = Coordinate("theta", "rad", "Euler angle 2: rotation about the rotated y axis (nutation)",
                   range=(0.2, 3.141592653589793 - 0.2))
psi = Coordinate("psi", "rad", "Euler angle 3: rotation about the rotated z axis (spin)")

SYSTEM = System(
    name="euler_top",
    title="Heavy top in Euler angles",
    lecture="Section 4.2.1, Exercise 4.3; (4.9), (4.10a), (4.14), (4.18), (4.46), (4.47), (4.63)",
    coordinates=(phi, theta, psi),
    links=(
        Link("precession", description="massless frame after the rotation by phi about z_0"),
        Link("nutation", description="massless frame after the rotation by theta about the rotated y axis"),
        Link("top", m, (0, 0, s), Inertia(I_xx, I_yy, I_zz), description="the top, after psi about its own z axis"),
    ),
    joints=(
        Joint("phi", "revolute", WORLD, "precession", axis="z"),
        Joint("theta", "revolute", "precession", "nutation", axis="y"),
        Joint("psi", "revolute", "nutation", "top", axis="z"),
    ),
    gravity=Gravity(g, (0, 0, -1)),
    forces=(),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
c_p, s_p, c_t, s_t, c_s, s_s = cos(phi), sin(phi), cos(theta), sin(theta), cos(psi), sin(psi)
_angles = "phi, theta, psi of the text are the coordinates phi, theta, psi"

CLAIMS = [
    Claim("(4.9)", "R:precession", Matrix([[c_p, -s_p, 0], [s_p, c_p, 0], [0, 0, 1]]),
          "elementary rotation R_z,phi", note="the precession frame's R_0^1"),
    Claim("(4.10a)", "R:precession/nutation", Matrix([[c_t, 0, s_t], [0, 1, 0], [-s_t, 0, c_t]]),
          "elementary rotation R_y,theta",
          note="printed as R_0^1 of a frame turned about y_0; here the chain's second elementary rotation, the "
               "nutation frame relative to the precession frame"),
    Claim("(4.14)", "R:nutation", Matrix([[c_t * c_p, -s_p, c_p * s_t], [s_p * c_t, c_p, s_p * s_t], [-s_t, 0, c_t]]),
          "R_zy = R_z,phi R_y,theta (z, then the rotated y)", note="the printed product's result; " + _angles),
    Claim("(4.18)", "R:top", Matrix([
        [c_p * c_t * c_s - s_p * s_s, -c_p * c_t * s_s - s_p * c_s, c_p * s_t],
        [s_p * c_t * c_s + c_p * s_s, -s_p * c_t * s_s + c_p * c_s, s_p * s_t],
        [-s_t * c_s, s_t * s_s, c_t]]), "Euler angles: R_0^1 = R_z,phi R_y,theta R_z,psi",
          note="the printed product's result; R_0^1 of the text is the top's R_0^3 here; " + _angles),
    Claim("(4.46)", "S:precession", Matrix([[0, -phi.rate, 0], [phi.rate, 0, 0], [0, 0, 0]]),
          "S_z,phi = R_z,phi' R_z,phi^T"),
    Claim("(4.47) S_y,theta", "S:precession/nutation", Matrix([[0, 0, theta.rate], [0, 0, 0], [-theta.rate, 0, 0]]),
          "S_y,theta = R_y,theta' R_y,theta^T (the first matrix of (4.47); S_x,psi needs a rotation about x)",
          note="of the chain's second elementary rotation, as (4.10a)"),
    Claim("(4.63)", "J_omega:top", Matrix([[0, -s_p, c_p * s_t], [0, c_p, s_p * s_t], [1, 0, c_t]]),
          "(J_omega)_0^3 of the Euler angles", note=_angles),
]

# ----------------------------------------------------------------------------- scenes
SCENES = [
    Scene("spinning", "a heavy top spun at 40 rad/s about its own axis, released at theta = 0.5 rad without "
          "precession: it nutates and precesses under gravity (conservative)", (0.0, 0.5, 0.0), (0.0, 0.0, 40.0),
          1.0, {"gravity"}),
]
