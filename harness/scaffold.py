"""``harness new NAME``: a new system module with the shape of a real model and a checklist.

The scaffold is a complete, conformant model (a rod on a revolute joint with gravity, a torsion spring and
viscous friction), so that ``harness check NAME`` is green before the first edit and stays green edit by edit.
``docs/adding-a-system.md`` walks through turning it into a lecture system.
"""

from __future__ import annotations

import keyword
import re
import shutil
from pathlib import Path
from string import Template

from harness.errors import HarnessError, InputError, OutputError
from harness.io import atomic_write_text, existing_folder

_NAME = re.compile(r"[a-z][a-z0-9_]*\Z")

TEMPLATE = Template('''"""TODO title, Example/Exercise X.Y of the lecture (Figure X.Y).

TODO describe the system in the lecture's words: bodies, joints, coordinates and how they are measured, the
direction of gravity, every force element, with the equation numbers used (e.g. (3.128)-(3.135)).

Checklist (delete an item when it is done; `docs/adding-a-system.md` explains each step):

1. [ ] Title and lecture reference in ``SYSTEM`` (``lecture="Example 3.15; (3.128)-(3.135)"``).
2. [ ] Parameters: the lecture's symbols in ASCII (``m_1``, ``l_s1``, ``I_zz2``, ``rho_S``), each with an SI
       default, a unit (``"1"`` if dimensionless), a description and its assumption (positive/nonnegative/real).
       They are SymPy symbols: write ``m_1 * l_1**2`` as the lecture does; ``SYSTEM`` collects them.
3. [ ] Coordinates q: names, units, what they measure, and a ``range`` away from coordinate singularities;
       ``phi_1.rate`` and ``phi_1.accel`` are its velocity and acceleration.
4. [ ] Links: mass, centre of mass in the link frame, inertia tensor about the centre of mass (``Inertia``,
       ``Inertia.cuboid``, ``Inertia.cylinder``; a point mass has none). Inertia must be positive definite and
       satisfy the triangle inequality for the default parameters -- checked when the module is loaded.
5. [ ] Joints: parent -> child, axis, origin/rpy; ``phi=`` when the tree joint is not a lecture coordinate
       (``theta = phi(q)``: gear ratio, rope, absolute angles, closed chain).
6. [ ] Gravity direction and force elements (Spring, Damper, JointSpring, JointDamper, JointInput,
       PointForce, BodyTorque) as the lecture describes them; delete those it does not have.
7. [ ] ``harness check $name`` is green (and ``harness export`` writes urdf/$name.*).
8. [ ] CLAIMS: the equations printed in the lecture, transcribed as printed; ``harness claims $name``.
9. [ ] SCENES: simulations the lecture describes; ``harness scenes $name --run``.
10. [ ] ``harness report`` shows the system; ``make test`` is green.
"""

from harness.modeling import (Coordinate, Gravity, Inertia, Joint, JointDamper, JointSpring, Link, Parameter, System,
                              standard_gravity)

# ----------------------------------------------------------------------------- parameters (symbol, default, unit)
m_1 = Parameter("m_1", 1.0, "kg", "mass of the rod")
l_1 = Parameter("l_1", 0.5, "m", "length of the rod")
b_1 = Parameter("b_1", 0.05, "m", "width of the rod")
h_1 = Parameter("h_1", 0.02, "m", "height of the rod")
c_1 = Parameter("c_1", 2.0, "N m/rad", "stiffness of the torsion spring in the bearing")
d_1 = Parameter("d_1", 0.1, "N m s/rad", "viscous friction in the bearing")
g = standard_gravity()

# ----------------------------------------------------------------------------- coordinates q
phi_1 = Coordinate("phi_1", "rad", "angle of the rod from the downward vertical")

SYSTEM = System(
    name="$name",
    title="TODO title",
    lecture="TODO Example X.Y; (X.1)-(X.2)",
    coordinates=(phi_1,),
    # links: a body-fixed frame each; centre of mass and inertia about it in that frame
    links=(Link("rod", mass=m_1, com=(0, 0, -l_1 / 2), inertia=Inertia.cuboid(m_1, b_1, h_1, l_1),
                description="homogeneous cuboid rod, its long edge along -z_1"),),
    # joints: parent -> child, rotation about the x axis by the lecture coordinate of the same name
    joints=(Joint("phi_1", "revolute", "world", "rod", axis="x"),),
    gravity=Gravity(g, (0, 0, -1)),
    # force elements (delete what the lecture's system does not have); a driven joint: an input declared as
    # tau_1 = Input("tau_1", "N m", "motor torque in joint 1") and JointInput("motor_1", "phi_1", tau_1) here
    forces=(JointSpring("spring_1", "phi_1", c_1, 0), JointDamper("friction_1", "phi_1", d_1)),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
# from harness.modeling import Claim
# from sympy import Matrix, sin
# CLAIMS = [
#     Claim("(X.1)", "M", Matrix([[m_1 * l_1**2 / 3]]), "mass matrix as printed"),
#     Claim("(X.2)", "eom", m_1 * l_1**2 / 3 * phi_1.accel + m_1 * g * l_1 / 2 * sin(phi_1), "as printed"),
# ]
CLAIMS = []

# ----------------------------------------------------------------------------- scenes
# from harness.modeling import Scene
# SCENES = [Scene("swing", "released at 30 deg from rest, gravity only", (0.5236,), (0.0,), 3.0, {"gravity"})]
SCENES = []
''')


def check_name(name: str, catalogue=None) -> None:
    """A new system's name: a lower-case identifier, not a Python keyword, not taken in ``catalogue``."""
    if not _NAME.match(name) or keyword.iskeyword(name):
        raise InputError(f"new: {name!r} is not a valid system name; use a lower-case Python identifier such as "
                         f"my_rod")
    if catalogue is not None and name in catalogue:
        raise InputError(f"new: a system named {name!r} exists already ({catalogue.get(name).lecture})")


def scaffold(name: str, folder: str | Path | None = None, catalogue=None) -> Path:
    """Write ``<folder>/<name>.py`` (default: the catalogue's own folder, else ``models/``) from
    :data:`TEMPLATE`, creating ``folder`` where it does not exist yet; refuses to overwrite and refuses a name
    ``catalogue`` holds."""
    check_name(name, catalogue)
    if folder:
        path = Path(folder)
    elif catalogue is not None:
        path = Path(catalogue.path[0])
    else:
        from harness.catalogue import MODELS_DIR

        path = MODELS_DIR
    target = path / f"{name}.py"
    if target.exists():
        raise InputError(f"new: {target} exists already")
    outermost = None if not folder else _outermost_missing(path)
    if outermost is None:
        existing_folder(path, "new --dir")
    try:
        path.mkdir(parents=True, exist_ok=True)   # a folder of your own models, created with its first module
        atomic_write_text(target, TEMPLATE.substitute(name=name))
    except BaseException as exc:
        if outermost is not None:                 # nothing half-made is left: the folders this call created
            shutil.rmtree(outermost, ignore_errors=True)
        if isinstance(exc, OSError) and not isinstance(exc, HarnessError):
            raise OutputError(f"new --dir {path}: {exc.strerror or exc}") from None
        raise
    target.chmod(0o644)
    return target


def _outermost_missing(path: Path) -> Path | None:
    """The outermost folder of ``path`` that does not exist yet (None: ``path`` exists)."""
    missing = None
    for folder in [path, *path.parents]:
        if folder.exists():
            break
        missing = folder
    return missing
