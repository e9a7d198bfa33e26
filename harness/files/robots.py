"""``harness robots``: every URDF of the pinned example-robot-data package, loaded in every engine and compared.

For each robot (a URDF of the package, named by its file stem; the two ``anymal.urdf`` by package too):

1. **Reference**: Pinocchio reads the URDF (:func:`harness.engines.pinocchio_engine.load_urdf`), on a free-flyer
   joint for a floating-base robot (:data:`FLOATING`: the legged, humanoid and flying robots, as the package's
   own loaders build them). What urdfdom prints while reading is a finding, not a refusal.
2. **Every other engine of** :data:`ENGINES` (data: an engine is added by name and loader) loads the same
   file, without ``<visual>``/``<collision>`` (``package://`` mesh URIs, ``.dae``; the dynamics do not depend on
   geometry): MuJoCo through its own URDF importer, the root link on a free joint named like Pinocchio's
   (:func:`harness.engines.mujoco_engine.add_free_joint`) for a floating base; Drake through its URDF parser
   (:func:`harness.engines.drake_engine.load_urdf_plant`, a ``QuaternionFloatingJoint`` of that name).
3. **Comparison** (:func:`harness.files.importer.compare`, the one comparison of an import with a reference):
   ``M``, the bias, ``C q̇`` (bias without gravity), ``g`` and the forward dynamics ``q̈`` (zero inputs) at
   ``states`` random states (seeded), joints matched **by name**, a floating base in Pinocchio's free-flyer
   coordinates (MuJoCo's free joint mapped explicitly: :meth:`harness.engines.mujoco_engine.MujocoModel.terms`), plus mass,
   first moment and inertia of what each joint moves. Tolerance: the importer's round-off bound (1e-12 of
   each quantity's scale; ``q̈`` times κ(M)), the conformance policy. What a URDF says and one engine applies
   in forward dynamics while the other does not (``<dynamics damping>``: MuJoCo's joint damping; Pinocchio
   stores it but ``aba`` ignores it) is switched off for the comparison and listed as a finding.
4. **Stepping** (Menagerie's rule): MuJoCo steps the model as imported (damping kept, gravity on, no contact:
   no geometry) for :data:`STEP_SECONDS` with small seeded noise as joint torques; every MuJoCo warning is
   recorded.
5. **Findings** from the file and from what each engine built: mimic joints, continuous joints, fixed links
   merged, links without an inertial (with or without meshes), zero-mass links, inertias that are not
   physical, joint damping/friction, geometry removed.

6. **Our exporter** (:data:`EXPORT`, fixed-base robots with at most :data:`EXPORT_MAX_DOF` moving DoF and no
   ``<mimic>``: :func:`export_scope`): :func:`harness.files.from_urdf.from_urdf` on the file (nothing locked),
   ``instantiate`` at the file's masses, our MJCF (:mod:`harness.export.mjcf`: the file's lumped numbers, no
   boundmass/boundinertia, no balanceinertia) loaded by MuJoCo through
   :class:`~harness.engines.mujoco_engine.MujocoModel`, compared like the other pairs. What our pipeline refuses
   (``ModelError``: e.g. a tensor that is not physical) is "not compared", the reason a finding. Its cause finder
   (:func:`explain_export`): the quarter turns from_urdf snaps (:func:`snapped_angles`), proven by the same export
   with the file's decimals taken literally.
7. **Our symbolic derivation** (:data:`SYMBOLIC`, only when asked: ``harness robots --symbolic``, :data:`ON_REQUEST`;
   the trees of :func:`export_scope`: :func:`symbolic_scope`): :func:`our_system` (from_urdf, as for the exporter)
   derived by :mod:`harness.derivation` (``M`` (5.21), the Christoffel ``C`` (5.95), (5.97) and ``g`` (5.96); body by
   body from 6 DoF on), compiled and evaluated at the same states, ``q̈`` solved numerically
   (:class:`harness.engines.symbolic.SymbolicTree`, joints by name), compared like the other pairs with the same
   bound (:func:`load_symbolic`). A fourth source independent of the engines' recursive algorithms. The derivation is
   cached on disk by the model's hash (``HARNESS_CACHE_DIR``). Its cause finder is the exporter's
   (:func:`explain_export`: the quarter turns from_urdf snaps, proven by the derivation of the file taken literally).
8. **Causes** (:func:`explain`, :func:`explain_refusal`): a pair that disagrees, is refused, or agrees above
   :data:`MARGIN` of the bound gets its cause from the file (:class:`LinkInertia`: each link's stated inertia) and
   from what the engine reported, reproduced (:attr:`Engine.treatment`, :attr:`Engine.repair`) and proven: the
   reference given the engine's changes must agree with it within :data:`MARGIN`. No robot name decides a verdict.

``robots.json`` (schema ``robots/1``; the pair ``pinocchio-symbolic`` only with ``--symbolic``) and ``robots.md``
(one table over all robots, each robot linked to its page ``robots/<robot>.html``, which ``harness report`` writes:
:func:`harness.report.site.robot_pages`) are written by ``harness robots --out DIR``.
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Callable

import numpy as np

from harness.engines.base import FREE_JOINT
from harness.engines.mujoco_engine import VERSION as MUJOCO_VERSION, MujocoModel, add_free_joint, balanced, compile_text
from harness.engines.pinocchio_engine import (VERSION as PINOCCHIO_VERSION, PinocchioModel, load_urdf,
                                              moving_joints)
from harness.errors import EngineError, InputError, ModelError
from harness.files import importer

SCHEMA = "robots/1"
STATES = 10
SEED = 0
STEP_SECONDS = 1.0
NOISE = 0.05
"""Standard deviation of the noise torques while stepping, as a fraction of each joint's gravity torque at the
reference configuration plus 0.1 N·m (small controls)."""

FLOATING = frozenset({
    "a1", "alex_nub_hands", "alex_psyonic_hands", "alex_sake_hands", "alexander_v1.lowerBodyOnly",
    "anymal_b_simple_anymal", "anymal-kinova", "anymal_c_simple_anymal", "b1", "b1-z1", "bolt",
    "borinot_flying_arm_2", "centauro", "g1_29dof_rev_1_0", "g1_29dof_with_hand_rev_1_0", "go1", "go2",
    "quadrotor_base", "hextilt_flying_arm_5", "human", "hyq_no_sensors", "icub", "icub_reduced", "iris",
    "iris_simple", "laikago", "quadruped", "romeo", "romeo_laas_small", "romeo_small", "simple_humanoid",
    "simple_humanoid_classical", "solo", "solo12", "talos_full_v2", "talos_full_v2_box", "talos_reduced",
    "talos_reduced_box", "talos_reduced_corrected"})
"""Robots with a floating base: legged, humanoid and flying robots (the package's loaders put these on a
free-flyer joint; ``talos_left_arm`` is the arm alone, fixed). Every other URDF is a fixed-base robot."""


def package_dir() -> Path | None:
    """The ``robots`` folder of the installed example-robot-data package (None when it is not installed)."""
    urdfs = importer.public_urdfs()
    if urdfs:
        return urdfs[0].parents[2]
    return None


def available() -> dict[str, Path]:
    """Every URDF of the package by robot name (file stem; a stem shared by two packages is prefixed by the
    package: ``anymal_b_simple_anymal``)."""
    root = package_dir()
    if root is None:
        return {}
    paths = sorted(root.glob("*/*/*.urdf"))
    stems: dict[str, int] = {}
    for p in paths:
        stems[p.stem] = stems.get(p.stem, 0) + 1
    out = {}
    for p in paths:
        name = p.stem if stems[p.stem] == 1 else f"{p.parts[-3].removesuffix('_description')}_{p.stem}"
        out[name] = p
    return out


def select(names=None) -> dict[str, Path]:
    """The robots named (every one by default); an unknown name is one InputError line listing the known."""
    robots = available()
    if not robots:
        raise InputError("the pinned example-robot-data package is not installed (pip install -e .)")
    if not names:
        return robots
    unknown = [n for n in names if n not in robots]
    if unknown:
        raise InputError(f"unknown robot(s) {', '.join(unknown)}; known: {', '.join(robots)}")
    return {n: robots[n] for n in names}


# ------------------------------------------------------------------------------------------------ the robot
@dataclass(frozen=True)
class Robot:
    name: str
    path: Path
    text: str
    floating: bool

    @property
    def urdf(self) -> str:
        parts = self.path.parts
        return str(Path(*parts[parts.index("example-robot-data"):])) if "example-robot-data" in parts \
            else str(self.path)


def load_robot(name: str, path: Path) -> Robot:
    return Robot(name, Path(path), Path(path).read_text(), name in FLOATING)


# ------------------------------------------------------------------------------------------------ engines
@dataclass(frozen=True)
class Engine:
    """One engine of the sweep: its name, its label in reports, and how it loads a robot as an engine adapter
    seen through the reference's joints (``loaded``: ``terms``, ``subtree_parts``, ``mass_and_bias``,
    ``body_names``, ``gravity``), matched by joint name. ``load(robot, reference, facts, findings)`` returns
    ``(view, bound)``: ``bound`` is a lower bound the engine put on masses and inertias (0 if none).
    ``importer``: the engine reads the URDF with its own importer, whose treatment of the file the findings
    describe (:func:`file_findings`)."""

    name: str
    label: str
    load: Callable
    importer: bool = False
    treatment: Callable | None = None
    """``treatment(robot, view, facts, bound)``: what the engine did to the file's inertias, derived from the file
    and what the engine reported while loading it: ``{link: (mass, tensor, what it did)}``
    (:func:`explain` loads the reference with those inertias to prove a disagreement's cause)."""
    repair: Callable | None = None
    """``repair(robot, error)``: for a file the engine refuses, the cause found in the file and the file with it
    repaired for both engines, ``(cause, text, who is right)``, or None."""
    scope: Callable | None = None
    """``scope(robot, reference)``: why the engine is not compared on this robot (a sentence), or None when it is."""
    explain: Callable | None = None
    """``explain(engine, robot, reference, view, bound, facts, states, seed)``: the engine's own cause finder, in
    place of :func:`explain` (which reproduces changed inertias)."""


@dataclass
class Reference:
    """The reference engine's load of a robot: its view, the joints by name, the prismatic ones, the model, and
    ``memo``: the values of the views compared with it at the compared states, its own for each engine compared
    with it, an engine's for its cause finder (:func:`importer.compare`)."""

    view: object
    joints: list[str]
    prismatic: set[str]
    model: object
    memo: dict = field(default_factory=dict)


def load_pinocchio(robot: Robot, facts: dict, findings: list[dict]) -> Reference:
    said: list[str] = []
    model = load_urdf(robot.text, robot.urdf, robot.floating, said)
    for text in said:
        findings.append(_finding("urdfdom message", "", f"urdfdom printed while Pinocchio read the file: {text}"))
    free = FREE_JOINT if robot.floating else None
    joints = moving_joints(model, free)
    view = PinocchioModel.loaded(model, joints, free)
    facts.update(view.loaded_facts())
    return Reference(view, joints, view.prismatic, model)


MUJOCO_PASSIVE_OFF = "dof_damping, jnt_stiffness, dof_armature set to 0 for the comparison"


def load_mujoco(robot: Robot, reference: Reference, facts: dict, findings: list[dict]):
    """MuJoCo's own URDF importer, geometry removed (see the module docstring); stepped as imported
    (:meth:`~harness.engines.mujoco_engine.MujocoModel.noisy_steps`), then passive forces off for the comparison."""
    text, source = importer.without_geometry(robot.text, robot.urdf), f"{robot.urdf} (MuJoCo's URDF importer)"
    edit = add_free_joint if robot.floating else None
    try:
        model, refused, bound = importer.load_import(text, source, edit)
    except ModelError as exc:
        if not any(k in str(exc) for k in BALANCE_ERRORS):
            raise
        refused = str(exc).split("MuJoCo refused the model: ", 1)[-1]
        model = compile_text(text, source, bound=importer.IMPORT_BOUND, edit=balanced(edit))
        bound = importer.IMPORT_BOUND
        facts["adjusted"] = BALANCE_NOTE
        findings.append(_finding("refused as is", "", f"MuJoCo refused the import ({refused}); loaded with "
                                 f"{BALANCE_NOTE}: it changes those inertias, so the engines must differ"))
    else:
        if refused:
            findings.append(_finding("refused as is", "", f"MuJoCo refused the import as is ({refused}); loaded "
                                     f"with {importer.BOUND_NOTE}"))
    free = FREE_JOINT if robot.floating else None
    view = MujocoModel.loaded(model, reference.joints, free)
    view.set_gravity(reference.view.gravity)
    facts.update({**view.loaded_facts(), "refused as is": bool(refused)})
    facts["step"] = view.noisy_steps(STEP_SECONDS, NOISE, SEED)
    damped = view.damped_joints()
    if damped:
        findings.append(_finding(
            "joint damping/friction", ", ".join(damped[:6]) + (" …" if len(damped) > 6 else ""),
            f"{len(damped)} joint(s) with URDF <dynamics damping/friction>: MuJoCo imports them as joint damping "
            "and frictionloss (they act in its forward dynamics); Pinocchio stores them (model.damping, "
            "model.friction) but aba ignores them; damping off in MuJoCo for the comparison"))
    view.passive_off()
    if view.dofs != reference.view.dofs:
        findings.append(_finding("dof count", "", f"MuJoCo has {view.dofs} dofs, Pinocchio {reference.view.dofs}"))
    return view, bound


BALANCE_ERRORS = ("balanceinertia", "inertia must have positive eigenvalues")
BALANCE_NOTE = (f"compiler balanceinertia (MuJoCo's own fix of inertias violating A + B >= C) and boundmass = "
                f"boundinertia = {importer.IMPORT_BOUND:g}")




# ------------------------------------------------------------------------------------------------ inertias
MJMINVAL = 1e-15
"""MuJoCo's mjMINVAL: FuseStatic adds a fixed link's mass and inertia to its parent only when its mass is at least
this (``body->mass >= mjMINVAL``); a lighter one is dropped, inertia tensor and all."""
MARGIN = 0.1
"""A check on a round-off bound must stay at or below this fraction of it (the margin policy of the README): an
agreement closer to the bound than this is explained like a disagreement."""


@dataclass(frozen=True)
class LinkInertia:
    """One link's ``<inertial>`` as the file states it: mass, the tensor about the centre of mass in the link's
    axes (the inertial's rpy applied), its principal moments (ascending) and whether the link hangs on a fixed
    joint (engines merge such a link into its parent)."""

    link: str
    mass: float
    xyz: tuple
    tensor: np.ndarray
    moments: np.ndarray
    fixed: bool

    def issues(self) -> list[str]:
        """What is not physical about it (to the round-off of the eigenvalues)."""
        a, b, c = self.moments
        tol = 1e-12 * max(abs(self.moments).max(), 1e-300)   # eigvalsh's round-off
        out = []
        if self.mass <= 0 and np.any(self.tensor):
            out.append("mass 0 with a non-zero inertia tensor")
        if a < -tol:
            out.append("not positive semi-definite")
        elif a <= tol and np.any(self.tensor):
            out.append("singular: a principal moment 0" + (" (rank 1)" if b <= tol else ""))
        if a >= -tol and max(a, 0) + max(b, 0) < c - tol:
            out.append("principal moments violate A + B >= C")
        return out

    def describe(self) -> str:
        return (f"{self.link} (mass {self.mass:g} kg, principal moments "
                + ", ".join(f"{m:.3g}" for m in self.moments) + " kg m²): " + "; ".join(self.issues()))


def link_inertias(text: str, source: str = "URDF") -> list[LinkInertia]:
    """Every link with a complete ``<inertial>`` (mass and inertia), as the file states it (read once per text
    for the last texts: a robot's treatments, repairs and causes read the same file, 62 calls for 20 texts in the
    sweep)."""
    return list(_link_inertias(text, source))


@lru_cache(maxsize=16)
def _link_inertias(text: str, source: str) -> tuple[LinkInertia, ...]:
    from harness.compare.roundtrip import rpy_matrix
    from harness.files.untrusted import parse_xml

    root = parse_xml(text, source)
    fixed = {j.find("child").get("link") for j in root.findall("joint")
             if j.get("type") == "fixed" and j.find("child") is not None}
    out = []
    for link in root.findall("link"):
        inertial = link.find("inertial")
        if inertial is None or inertial.find("mass") is None or inertial.find("inertia") is None:
            continue
        v = {k: float(inertial.find("inertia").get(k, "0")) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
        tensor = np.array([[v["ixx"], v["ixy"], v["ixz"]], [v["ixy"], v["iyy"], v["iyz"]],
                           [v["ixz"], v["iyz"], v["izz"]]])
        origin = inertial.find("origin")
        rpy = [float(t) for t in origin.get("rpy", "0 0 0").split()] if origin is not None else [0, 0, 0]
        xyz = tuple(float(t) for t in origin.get("xyz", "0 0 0").split()) if origin is not None else (0, 0, 0)
        R = rpy_matrix(np.array(rpy))
        tensor = R @ tensor @ R.T
        out.append(LinkInertia(link.get("name"), float(inertial.find("mass").get("value")), xyz, tensor,
                               np.linalg.eigvalsh(tensor), link.get("name") in fixed))
    return tuple(out)


def with_inertias(text: str, source: str, new: dict[str, tuple[float, np.ndarray]]) -> str:
    """The file with the ``<inertial>`` of each link of ``new`` replaced by ``(mass, tensor in link axes)``
    (centre of mass kept, rpy 0)."""
    from lxml import etree

    from harness.files.untrusted import parse_xml

    root = parse_xml(text, source)
    for link in root.findall("link"):
        if link.get("name") not in new:
            continue
        mass, tensor = new[link.get("name")]
        inertial = link.find("inertial")
        origin = inertial.find("origin")
        if origin is not None:
            origin.set("rpy", "0 0 0")
        inertial.find("mass").set("value", repr(float(mass)))
        el = inertial.find("inertia")
        for k, (i, j) in {"ixx": (0, 0), "ixy": (0, 1), "ixz": (0, 2), "iyy": (1, 1), "iyz": (1, 2),
                          "izz": (2, 2)}.items():
            el.set(k, repr(float(tensor[i, j])))
    return etree.tostring(root, encoding="unicode")


def mujoco_inertias(inertias: list[LinkInertia], bound: float, balance: bool, fused: set[str]) -> dict:
    """What MuJoCo's compiler makes of each link's inertia (``user_objects.cc``, ``mjCBody::Compile`` then
    ``mjCModel::FuseStatic``), for the links it changes: mass and principal moments raised to ``bound``
    (``boundmass``, ``boundinertia``); with ``balance`` (``balanceinertia``) principal moments violating
    A + B >= C replaced by their mean; a link of ``fused`` (a fixed link MuJoCo merged into its parent) lighter
    than :data:`MJMINVAL` dropped, tensor and all. ``{link: (mass, tensor, what MuJoCo did)}``."""
    out = {}
    for li in inertias:
        mass = max(li.mass, bound)
        moments, axes = np.linalg.eigh(li.tensor)
        did = []
        if np.any(moments < bound):
            moments = np.maximum(moments, bound)
            did.append(f"principal moments raised to boundinertia {bound:g}")
        if mass != li.mass:
            did.append(f"mass raised to boundmass {bound:g}")
        a, b, c = np.sort(moments)
        if balance and a + b < c:
            moments = np.full(3, moments.sum() / 3)
            did.append(f"balanceinertia: the three principal moments replaced by their mean {moments[0]:.3g}")
        tensor = axes @ np.diag(moments) @ axes.T
        if li.link in fused and mass < MJMINVAL:
            tensor, did = np.zeros((3, 3)), [f"dropped when fused into its parent (mass {mass:g} < mjMINVAL), "
                                             "inertia tensor and all"] if np.any(li.tensor) else []
        if did:
            out[li.link] = (mass, tensor, "; ".join(did))
    return out


def mujoco_treatment(robot: Robot, view, facts: dict, bound: float) -> dict:
    """MuJoCo's compiler on the file's inertias (:func:`mujoco_inertias`): the bound it loaded with, balanceinertia
    when it was switched on, the fixed links it fused (those that are no MuJoCo body)."""
    inertias = link_inertias(robot.text, robot.urdf)
    bodies = set(view.body_names())
    fused = {li.link for li in inertias if li.fixed and li.link not in bodies}
    return mujoco_inertias(inertias, bound, facts.get("adjusted") == BALANCE_NOTE, fused)


def mujoco_repair(robot: Robot, error: str):
    """MuJoCo refuses a tensor that is not positive semi-definite ("inertia must have positive eigenvalues";
    balanceinertia does not apply to it): those links' tensors with their negative principal moments set to 0
    (MuJoCo's bound and balance then apply as to any other link)."""
    if "positive eigenvalues" not in error:
        return None
    bad = [li for li in link_inertias(robot.text, robot.urdf) if "not positive semi-definite" in li.issues()]
    if not bad:
        return None
    new = {}
    for li in bad:
        moments, axes = np.linalg.eigh(li.tensor)
        new[li.link] = (li.mass, axes @ np.diag(np.maximum(moments, 0)) @ axes.T)
    cause = ("inertia tensor not positive semi-definite: " + "; ".join(li.describe() for li in bad)
             + ". MuJoCo refuses it (its compiler requires positive principal moments), Pinocchio computes with "
             "it as written")
    right = ("MuJoCo is right to refuse: no rigid body has a negative principal moment (M may even be indefinite "
             "in Pinocchio); the file is at fault")
    return cause, with_inertias(robot.text, robot.urdf, new), right, [li.link for li in bad]


def drake_treatment(robot: Robot, view, facts: dict, bound: float) -> dict:
    """Drake's parser on the file's inertias: each link it warned about (``facts['substituted']``, from the line
    of its warning) replaced by :func:`~harness.engines.drake_engine.drake_dummy_inertia`."""
    from harness.engines.drake_engine import drake_dummy_inertia

    out = {}
    by_link = {li.link: li for li in link_inertias(robot.text, robot.urdf)}
    for link in facts.get("substituted", []):
        if link in by_link:
            mass, tensor = drake_dummy_inertia(by_link[link].mass)
            out[link] = (mass, tensor, f"replaced by a solid sphere of density 1000 kg/m³ and mass {mass:g} kg")
    return out


def drake_repair(robot: Robot, error: str):
    """Drake's parser refuses references Pinocchio never reads (it ignores ``<mimic>``, buildModel's default, and
    ``<transmission>``): a ``<mimic>`` on a joint without degrees of freedom ("which has 0 DOF cannot mimic"), a
    ``<mimic>`` or ``<transmission>`` naming a joint the file does not hold ("which does not exist"). The file
    without those elements: Pinocchio's model is unchanged by it."""
    from lxml import etree

    from harness.files.untrusted import parse_xml

    root = parse_xml(robot.text, robot.urdf)
    joints = {j.get("name") for j in root.findall("joint")}
    removed, why = [], ""
    if "cannot mimic" in error:
        why = "a <mimic> on a fixed joint (a joint without degrees of freedom cannot follow another)"
        for j in root.findall("joint"):
            if j.get("type") == "fixed" and j.find("mimic") is not None:
                j.remove(j.find("mimic"))
                removed.append(f"<mimic> of {j.get('name')}")
    elif "mimic element specifies joint" in error and "does not exist" in error:
        why = "a <mimic> naming a joint the file does not hold"
        for j in root.findall("joint"):
            m = j.find("mimic")
            if m is not None and m.get("joint") not in joints:
                j.remove(m)
                removed.append(f"<mimic> of {j.get('name')} (joint {m.get('joint')!r})")
    elif "Transmission specifies joint" in error and "does not exist" in error:
        why = "a <transmission> naming a joint the file does not hold"
        for t in root.findall("transmission"):
            named = {j.get("name") for j in t.findall("joint")}
            if named - joints:
                root.remove(t)
                removed.append(f"<transmission> {t.get('name')} (joint {', '.join(sorted(named - joints))})")
    if not removed:
        return None
    cause = (f"{why}: {len(removed)} element(s), {', '.join(removed[:3])}{' …' if len(removed) > 3 else ''}. "
             "Drake's parser refuses the file; Pinocchio ignores these elements")
    right = ("Drake is right to refuse: the file is inconsistent there; Pinocchio's model is that of the file "
             "without these elements")
    return cause, etree.tostring(root, encoding="unicode"), right, removed


DRAKE_KINDS = {
    "inertia substituted": re.compile(r"While (parsing inertia matrix|re-expressing as central inertia)"),
    "mimic ignored": re.compile(r"mimic|coupler", re.I),
    "joint friction unsupported": re.compile(r"'friction' attribute"),
    "transmission ignored": re.compile(r"transmission|mechanicalReduction", re.I),
    "tag ignored": re.compile(r"unsupported and will be ignored"),
}


def load_drake(robot: Robot, reference: Reference, facts: dict, findings: list[dict]):
    """Drake's own URDF parser (:func:`harness.engines.drake_engine.load_urdf_plant`), geometry removed like for
    MuJoCo, the root on a floating joint named like Pinocchio's for a floating base; what the parser warns is
    recorded: an inertia it replaced (:func:`drake_treatment`) by the link its warning's line lies in."""
    from harness.engines.drake_engine import DrakeImport, load_urdf_plant
    from harness.files.untrusted import parse_xml

    text = importer.without_geometry(robot.text, robot.urdf)
    free = FREE_JOINT if robot.floating else None
    plant, said = load_urdf_plant(text, f"{robot.urdf} (Drake's URDF parser)", free, reference.view.gravity)
    view = DrakeImport(plant, reference.joints, free)
    facts.update(view.loaded_facts())
    links = sorted((el.sourceline, el.get("name")) for el in parse_xml(text, robot.urdf).findall("link"))
    substituted, kinds = [], {}
    for message in said:
        kind = next((k for k, rx in DRAKE_KINDS.items() if rx.search(message)), "other")
        kinds.setdefault(kind, []).append(" ".join(message.split()))
        line = re.search(r"\.urdf:(\d+):", message)
        if kind == "inertia substituted" and line:
            inside = [name for start, name in links if start <= int(line.group(1))]
            if inside:
                substituted.append(inside[-1])
    facts["substituted"] = substituted
    facts["warnings"] = {k: len(v) for k, v in kinds.items()}
    for kind, messages in kinds.items():
        where = ", ".join(substituted[:6]) if kind == "inertia substituted" else ""
        findings.append(_finding(f"Drake: {kind}", where, f"{len(messages)} parser warning(s), e.g. "
                                 f"{messages[0][:300]}"))
    if view.dofs != reference.view.dofs:
        findings.append(_finding("dof count", "", f"Drake has {view.dofs} dofs, Pinocchio {reference.view.dofs}"))
    return view, 0.0


# ------------------------------------------------------------------------------------------------ our exporter
EXPORT = "mujoco (our export)"
EXPORT_MAX_DOF = 7
"""Our exporter is compared on fixed-base robots with at most this many moving DoF (the 7-DoF Panda of the
catalogue is built the same way) and no ``<mimic>``: :func:`export_scope`."""


class NotCompared(ModelError):
    """Our pipeline refuses the file (``from_urdf`` or ``instantiate``): the pair is not compared, the reason is a
    finding (a refusal with its reason is not a wrong number)."""


def export_scope(robot: Robot, reference: Reference, pair: str = "the exporter pair") -> str | None:
    """Why our exporter (or, with ``pair``, our other pipeline of the same trees: :func:`symbolic_scope`) is not
    compared on ``robot`` (None when it is): a floating base, more than :data:`EXPORT_MAX_DOF` moving DoF, or
    ``<mimic>`` joints (from the file and the reference's model)."""
    from harness.files.untrusted import parse_xml

    if robot.floating:
        return "floating base: from_urdf builds fixed-base trees (the root link is the world)"
    dof = int(reference.model.nv)
    if dof > EXPORT_MAX_DOF:
        return f"{dof} moving DoF > {EXPORT_MAX_DOF}: out of {pair}'s scope"
    mimic = [j.get("name") for j in parse_xml(robot.text, robot.urdf).findall("joint") if j.find("mimic") is not None]
    if mimic:
        return (f"{len(mimic)} <mimic> joint(s) ({', '.join(mimic[:4])}{' …' if len(mimic) > 4 else ''}): out of "
                f"{pair}'s scope (Pinocchio makes them independent joints, from_urdf couples them)")
    return None


def our_system(robot: Robot, quarter_turns: bool = True):
    """Our :class:`~harness.modeling.system.System` of the file (:func:`harness.files.from_urdf.from_urdf` on its
    text, nothing locked; ``quarter_turns=False``: every angle as the file writes it). Built once per text and
    process for the last 8: a robot's exporter pair and symbolic pair (and the literal loads of their cause finder)
    read the same file into the same frozen System."""
    try:
        return _our_system(robot.text, robot.name, robot.urdf, quarter_turns)
    except ModelError as exc:
        raise NotCompared(f"our from_urdf refuses the file: {exc}") from None


@lru_cache(maxsize=8)
def _our_system(text: str, name: str, urdf: str, quarter_turns: bool):
    from harness.files.from_urdf import from_urdf

    return from_urdf(text, name=re.sub(r"\W", "_", name), title=name, lecture=f"example-robot-data {urdf}",
                     quarter_turns=quarter_turns)


def export_system(robot: Robot, quarter_turns: bool = True):
    """:func:`our_system` and its numbers at the file's masses (:func:`harness.export.numeric.instantiate`)."""
    from harness.export.numeric import instantiate

    system = our_system(robot, quarter_turns)
    try:
        return system, instantiate(system, system.default_parameters())
    except ModelError as exc:
        raise NotCompared(f"our from_urdf/instantiate refuses the file: {exc}") from None


def load_export(robot: Robot, reference: Reference, facts: dict, findings: list[dict], quarter_turns: bool = True):
    """Our pipeline: :func:`export_system`, exported by our MJCF exporter (:func:`harness.export.mjcf.mjcf_string`,
    through :class:`~harness.engines.mujoco_engine.MujocoModel`) and loaded by MuJoCo, seen through the reference's
    joints by name, gravity the reference's. ``bound``: the stand-in inertia our exporter gives a point mass
    (:data:`~harness.export.numeric.MUJOCO_POINT_MASS_INERTIA`) when the tree has one, else 0. The exporter writes
    the file's (lumped) numbers: no boundmass/boundinertia, no balanceinertia (:func:`harness.export.mjcf.mjcf_spec`);
    what is not physical ``instantiate`` refuses before."""
    from harness.export.mjcf import exported_inertia
    from harness.export.numeric import MUJOCO_POINT_MASS_INERTIA

    system, tree = export_system(robot, quarter_turns)
    try:
        exported = MujocoModel(tree)
    except ValueError as exc:   # MjSpec.compile / from_xml_string refusing our export: open, not a scope matter
        raise EngineError(f"MuJoCo refused our export of {robot.urdf}: {' '.join(str(exc).split())}") from None
    view = MujocoModel.loaded(exported.model, reference.joints)
    view.set_gravity(reference.view.gravity)
    facts.update({**view.loaded_facts(), "links": len(tree.links), "quarter_turns": quarter_turns,
                  "snapped": [f"{j} {a}" for j, a, _ in snapped_angles(robot.text, robot.urdf)]})
    if view.dofs != reference.view.dofs:
        findings.append(_finding("dof count", EXPORT, f"our export has {view.dofs} dofs, Pinocchio "
                                 f"{reference.view.dofs}"))
    point = any(link.mass > 0 and exported_inertia(link.inertia) is not None for link in tree.links)
    return view, MUJOCO_POINT_MASS_INERTIA if point else 0.0


def snapped_angles(text: str, source: str = "URDF") -> list[tuple[str, str, float]]:
    """The joint ``origin rpy`` angles of the file that :func:`harness.files.from_urdf.exact_angle` takes as an
    exact multiple of π/2 although their decimals are not its float: ``(joint, decimals, offset rad)``."""
    import math

    from harness.files.from_urdf import QUARTER_TURN_SNAP
    from harness.files.untrusted import parse_xml

    out = []
    for j in parse_xml(text, source).findall("joint"):
        origin = j.find("origin")
        for t in (origin.get("rpy", "").split() if origin is not None else []):
            value = float(t)
            k = round(value / (math.pi / 2))
            offset = value - k * math.pi / 2
            if 0 < abs(offset) <= QUARTER_TURN_SNAP:
                out.append((j.get("name"), t, offset))
    return out


def explain_export(engine: Engine, robot: Robot, reference: Reference, view, bound: float, facts: dict,
                   states: int, seed: int) -> dict | None:
    """Why our export (or our symbolic derivation: ``engine`` is either, both built by ``from_urdf``) does not agree
    with the reference (or agrees closer to the bound than :data:`MARGIN`): the quarter turns ``from_urdf`` makes
    exact (:func:`snapped_angles`: decimals such as ``1.57079632679``, π/2 − 4.9e-12, written as π/2; a documented
    modelling choice, see :mod:`harness.files.from_urdf`). **Proven** when the engine's load of the same file with
    every angle taken literally (``engine.load(..., quarter_turns=False)``) agrees with the reference within
    :data:`MARGIN` of the bound at the same states. None when the file has no such angle."""
    snapped = snapped_angles(robot.text, robot.urdf)
    if not snapped:
        return None
    joints = sorted({j for j, _, _ in snapped})
    largest = max(abs(o) for _, _, o in snapped)
    what = (f"{len(snapped)} rpy angle(s) of {len(joints)} joint(s) ({', '.join(joints[:4])}"
            f"{' …' if len(joints) > 4 else ''}) within {largest:.2g} rad of a multiple of π/2, e.g. "
            f"{snapped[0][1]} (off by {snapped[0][2]:.2g} rad)")
    try:
        literal, literal_bound = engine.load(robot, reference, {}, [], quarter_turns=False)
        checks = importer.compare(literal, reference.view, reference.joints, reference.prismatic, states, seed,
                                  literal_bound, forward=True, memo=reference.memo)
    except (ModelError, EngineError) as exc:
        return {"cause": f"from_urdf snaps {what}; not proven: the literal load failed ({exc})", "right": "",
                "links": [], "proven": False, "after": None}
    after = _ratio(checks)
    proven = all(c["passed"] for c in checks) and after <= MARGIN
    snap = ("from_urdf takes a moving joint's rpy (composed with the fixed joints above it) within 1e-9 rad of a "
            "multiple of π/2 as that exact multiple (its documented snap)")
    cause = (f"the file writes {what}; {snap}. With the file's decimals taken literally {engine.label} agrees with "
             f"Pinocchio: worst ratio {after:.2g} ≤ {MARGIN:g}" if proven else
             f"the file writes {what}; {snap}, but with the decimals taken literally {engine.label} still differs "
             f"(worst ratio {after:.2g}): the cause is elsewhere")
    right = "" if not proven else (
        "both: Pinocchio computes the file's decimals as written, our from_urdf the quarter turn they denote "
        f"(rotations differ by at most {largest:.2g} rad)")
    return {"cause": cause, "right": right, "links": [], "proven": proven, "after": after}


# ------------------------------------------------------------------------------------------------ our derivation
SYMBOLIC = "symbolic"


def symbolic_scope(robot: Robot, reference: Reference) -> str | None:
    """The trees of :func:`export_scope` (the same from_urdf model): fixed base, at most :data:`EXPORT_MAX_DOF`
    moving DoF, no ``<mimic>``."""
    return export_scope(robot, reference, "the symbolic pair")


def load_symbolic(robot: Robot, reference: Reference, facts: dict, findings: list[dict], quarter_turns: bool = True):
    """Our symbolic derivation (:mod:`harness.derivation`) of :func:`our_system`: ``M``, the Christoffel ``C q̇``
    and ``g`` derived from the model's kinematics (body by body from 6 DoF on), compiled, evaluated at the reference's
    states, joints matched by name (:class:`harness.engines.symbolic.SymbolicTree`); the derivation is cached on
    disk by the model's hash (``HARNESS_CACHE_DIR``). Nothing is bounded: ``bound`` 0. ``facts`` receive whether the
    derivation came from the cache and the seconds of deriving and of compiling (the derivation's cost)."""
    from harness.derivation.derive import derive
    from harness.engines.symbolic import SymbolicTree

    system = our_system(robot, quarter_turns)
    start = time.perf_counter()
    derivation = derive(system)
    middle = time.perf_counter()
    view = SymbolicTree(system, reference.joints, reference.view.gravity, derivation)
    view.terms(np.zeros(view.dofs), np.zeros(view.dofs))   # compiles the terms' function
    facts.update({**view.loaded_facts(), "quarter_turns": quarter_turns,
                  "derive or load s": round(middle - start, 2),
                  "compile s": round(time.perf_counter() - middle, 2)})
    return view, 0.0


ENGINES: dict[str, Engine] = {
    MujocoModel.name: Engine(MujocoModel.name, "MuJoCo (URDF importer)", load_mujoco, importer=True,
                             treatment=mujoco_treatment, repair=mujoco_repair),
    "drake": Engine("drake", "Drake (URDF parser)", load_drake, treatment=drake_treatment, repair=drake_repair),
    EXPORT: Engine(EXPORT, "MuJoCo (our export)", load_export, scope=export_scope, explain=explain_export),
    SYMBOLIC: Engine(SYMBOLIC, "our symbolic derivation", load_symbolic, scope=symbolic_scope,
                     explain=explain_export),
}
"""The engines compared with the reference, by name."""
ON_REQUEST = frozenset({SYMBOLIC})
"""Engines compared only when asked (``harness robots --symbolic``): on the 18 trees of the package the symbolic
derivation adds ~110 s of CPU to the sweep with an empty derivation cache and ~35 s with a full one (measured with
``--jobs 2``; the whole sweep without it: ~27 s), mostly SymPy's common-subexpression elimination when compiling and
the cache's reading and writing of the expression graphs."""


def engines(symbolic: bool = False) -> list[Engine]:
    """The engines of one sweep: every engine of :data:`ENGINES`, those of :data:`ON_REQUEST` when asked."""
    return [e for e in ENGINES.values() if symbolic or e.name not in ON_REQUEST]
REFERENCE = Engine(PinocchioModel.name, "Pinocchio", load_pinocchio)


# ------------------------------------------------------------------------------------------------ findings
def _finding(kind: str, where: str, text: str) -> dict:
    return {"kind": kind, "where": where, "text": text}


def file_findings(robot: Robot, reference: Reference | None, imported) -> list[dict]:
    """What the file holds that engines may treat differently, and what each did (when loaded; ``imported``:
    MuJoCo's import, a :class:`~harness.engines.mujoco_engine.MujocoModel`, or None)."""
    from harness.export.numeric import check_inertia
    from harness.compare.roundtrip import rpy_matrix
    from harness.files.untrusted import parse_xml

    root = parse_xml(robot.text, robot.urdf)
    out = []
    links = root.findall("link")
    joints = root.findall("joint")
    mj = imported

    mimic = [(j.get("name"), j.find("mimic")) for j in joints if j.find("mimic") is not None]
    if mimic:
        eq = []
        if mj is not None:
            eq = mj.joint_equalities()
        coupled = [n for n, _ in mimic if any(n in pair for pair in eq)]
        names = ", ".join(f"{n} = {m.get('multiplier', '1')}·{m.get('joint')} + {m.get('offset', '0')}"
                          for n, m in mimic)
        out.append(_finding("mimic joints", names, (
            f"{len(mimic)} mimic joint(s): Pinocchio (buildModel, mimic=False, its default) makes each an "
            f"independent joint; MuJoCo's importer "
            + (f"adds a joint equality constraint for {len(coupled)} of them (forward dynamics with constraints "
               "would couple them; M, bias and the unconstrained q̈ compared here are those of independent joints)"
               if coupled else "makes each an independent hinge too (no equality constraint)"))))
    continuous = [j.get("name") for j in joints if j.get("type") == "continuous"]
    if continuous:
        limited = [n for n in continuous if mj is not None and mj.joint_limited(n)]
        out.append(_finding("continuous joints", ", ".join(continuous[:6]) + (" …" if len(continuous) > 6 else ""), (
            f"{len(continuous)} continuous joint(s): Pinocchio gives each two coordinates (cos θ, sin θ; nq = 2, "
            "nv = 1), MuJoCo a hinge " + (f"with a range on {len(limited)}" if limited else "without range")
            + "; compared through θ")))
    fixed = [j for j in joints if j.get("type") == "fixed"]
    if fixed:
        text = (f"{len(fixed)} fixed joint(s) of {len(joints)}: {len(links)} links. Pinocchio keeps each fixed link "
                "as a frame and adds its inertia to the body of the moving joint it hangs on")
        if mj is not None:
            text += (f"; MuJoCo fuses them (compiler fusestatic): {mj.bodies} bodies"
                     + (" (the root link welded to the world and fused into it)" if not robot.floating else ""))
        out.append(_finding("fixed links merged", "", text + "; the subtree checks show whether mass and inertia "
                            "survived the merge"))
    no_inertial, mesh_only, zero_mass, zero_mass_inertia, non_physical = [], [], [], [], []
    for link in links:
        name = link.get("name")
        inertial = link.find("inertial")
        if inertial is None:
            (mesh_only if link.find("visual/geometry/mesh") is not None
             or link.find("collision/geometry/mesh") is not None else no_inertial).append(name)
            continue
        mass_el, inertia_el = inertial.find("mass"), inertial.find("inertia")
        if mass_el is None or inertia_el is None:
            non_physical.append(f"{name}: <inertial> without <mass> or <inertia> (urdfdom drops it)")
            continue
        mass = float(mass_el.get("value"))
        if mass == 0:
            values = [float(inertia_el.get(k, "0")) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")]
            (zero_mass_inertia if any(values) else zero_mass).append(name)
            continue
        v = {k: float(inertia_el.get(k, "0")) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
        tensor = np.array([[v["ixx"], v["ixy"], v["ixz"]], [v["ixy"], v["iyy"], v["iyz"]],
                           [v["ixz"], v["iyz"], v["izz"]]])
        origin = inertial.find("origin")
        rpy = [float(t) for t in origin.get("rpy", "0 0 0").split()] if origin is not None else [0, 0, 0]
        R = rpy_matrix(np.array(rpy))
        try:
            check_inertia(name, mass, R @ tensor @ R.T)
        except ModelError as exc:
            non_physical.append(str(exc))
    engines_did = ("urdfdom gives it zero mass and inertia (Pinocchio: a massless body); MuJoCo, geometry "
                   "removed, the same (a massless moving body MuJoCo refuses as is: see 'refused as is')")
    if mesh_only:
        out.append(_finding("meshes without inertials", ", ".join(mesh_only[:8]) + (" …" if len(mesh_only) > 8 else ""),
                            f"{len(mesh_only)} link(s) with a mesh but no <inertial>: {engines_did}. With its "
                            "geometry MuJoCo's default (compiler inertiafromgeom='auto') would give such a link the "
                            "mass of its geoms at density 1000: a different robot"))
    if no_inertial:
        out.append(_finding("links without inertials", ", ".join(no_inertial[:8]) + (" …" if len(no_inertial) > 8 else ""),
                            f"{len(no_inertial)} link(s) without <inertial> (frames, sensors): {engines_did}"))
    if zero_mass:
        out.append(_finding("zero-mass links", ", ".join(zero_mass[:8]) + (" …" if len(zero_mass) > 8 else ""),
                            f"{len(zero_mass)} link(s) with <mass value=0>: both engines read zero"))
    if zero_mass_inertia:
        out.append(_finding("zero mass with inertia", ", ".join(zero_mass_inertia[:8]), (
            f"{len(zero_mass_inertia)} link(s) with mass 0 but a non-zero inertia tensor (not physical: a massless "
            "body has no rotational inertia). Pinocchio adds the tensor to the body it is fixed to; MuJoCo drops a "
            "fixed link lighter than mjMINVAL when fusing it, tensor and all (the importer probe 'fixed link "
            "lighter than mjMINVAL'): the engines differ by that tensor")))
    for text in non_physical:
        out.append(_finding("non-physical inertia", text.split(":")[0], text + "; Pinocchio takes it as is"
                            + ("; MuJoCo: see 'refused as is'" if mj is not None else "")))
    geometry = root.xpath("//link/visual | //link/collision")
    if geometry:
        formats = sorted({Path(m.get("filename", "")).suffix.lower() or "?" for m in root.xpath("//geometry/mesh")})
        out.append(_finding("geometry removed", "", (
            f"{len(geometry)} <visual>/<collision> element(s) removed for MuJoCo's importer (package:// URIs it "
            f"cannot resolve; mesh formats {', '.join(formats) or 'none'}): dynamics do not depend on geometry; "
            "no contact while stepping")))
    return out


# ------------------------------------------------------------------------------------------------ one robot
def _worst(checks: list[dict]) -> dict | None:
    if not checks:
        return None
    c = max(checks, key=lambda c: c["ratio"])
    return {"quantity": c["quantity"], "item": c["item"], "max_error": c["max_error"],
            "bound": c["max_error"] / c["ratio"] if c["ratio"] not in (0, float("inf")) else c["tolerance"],
            "ratio": c["ratio"]}


def sweep_robot(job: tuple) -> dict:
    """One robot: ``job = (name, path, states, seed[, mujoco_text[, symbolic]])`` (``mujoco_text``: what the other
    engines read instead of the file, for tests of the matching by name; ``symbolic``: compare our symbolic
    derivation too, :data:`ON_REQUEST`). The record of robots.json. NumPy's BLAS on one thread meanwhile
    (:func:`harness.blas.one_thread`: the matrices are at most a robot's M)."""
    from harness.blas import one_thread

    with one_thread():
        return _sweep_robot(job)


def _sweep_robot(job: tuple) -> dict:
    from lxml import etree

    from harness.files.untrusted import parse_xml

    name, path, states, seed, *rest = job
    start = time.perf_counter()
    robot = load_robot(name, path)
    record = {"robot": name, "urdf": robot.urdf, "floating": robot.floating,
              "base": "floating" if robot.floating else "fixed", "dof": None, "engines": {}, "pairs": [],
              "findings": [], "error": None, "seconds": None}
    if rest and rest[0] is not None:
        robot = Robot(robot.name, robot.path, rest[0], robot.floating)
    root = parse_xml(robot.text, robot.urdf)
    if root.tag == "robot" and root.get("name") is None and root.find("link") is not None:
        root.set("name", name)
        robot = Robot(robot.name, robot.path, etree.tostring(root, encoding="unicode"), robot.floating)
        record["findings"].append(_finding("robot without name", "<robot>", (
            "the <robot> element has no name: urdfdom (Pinocchio) refuses the file (\"No name given for the "
            f"robot\"), MuJoCo's importer does not need it; both read it with name=\"{name}\"")))
    facts: dict = {}
    imported = None
    try:
        reference = REFERENCE.load(robot, facts, record["findings"])
        record["dof"] = int(reference.model.nv)
    except (ModelError, EngineError) as exc:
        reference = None
        record["error"] = f"{REFERENCE.label}: {exc}"
        if root.find("link") is None:
            record["error"] = f"the file holds no <link> (an empty <robot>): nothing to compare ({record['error']})"
    record["engines"][REFERENCE.name] = facts
    for engine in engines(len(rest) > 1 and rest[1]):
        facts = {}
        record["engines"][engine.name] = facts
        pair = {"pair": f"{REFERENCE.name}-{engine.name}", "verdict": NOT_COMPARED, "worst": None,
                "checks": [], "error": None, "cause": None}
        record["pairs"].append(pair)
        if reference is None:
            pair["error"] = record["error"]
            pair["cause"] = no_robot(root, record["error"])
            pair["verdict"] = NOT_COMPARED if pair["cause"] else NOT_COMPARED_OPEN
            continue
        reason = engine.scope(robot, reference) if engine.scope else None
        if reason:
            pair["error"], pair["out_of_scope"] = reason, True
            continue
        try:
            view, bound = engine.load(robot, reference, facts, record["findings"])
            imported = view if engine.importer else imported
            notes: list[str] = []
            checks = importer.compare(view, reference.view, reference.joints, reference.prismatic, states, seed,
                                      bound, forward=True, notes=notes, memo=reference.memo)
            record["findings"] += [_finding("singular mass matrix", engine.name, n) for n in notes]
            record["findings"] += [_finding(f"{engine.label}: forward dynamics refused", "", (
                f"{m} (at the states where the reference's M is singular too: q̈ not compared there)"))
                for m in sorted(getattr(view, "refusals", ()))[:3]]
        except NotCompared as exc:
            pair["error"] = str(exc)
            record["findings"].append(_finding("not compared", engine.label, str(exc)))
            continue
        except (ModelError, EngineError) as exc:
            pair["error"] = str(exc)
            pair["cause"] = explain_refusal(engine, robot, str(exc), states, seed)
            pair["verdict"] = (DISAGREE_EXPLAINED if pair["cause"] and pair["cause"]["proven"]
                               else NOT_COMPARED_OPEN)
            continue
        pair["checks"] = checks
        pair["worst"] = _worst(checks)
        passed = all(c["passed"] for c in checks)
        if passed and pair["worst"]["ratio"] <= MARGIN:
            pair["verdict"] = AGREE
            continue
        pair["cause"] = (engine.explain or explain)(engine, robot, reference, view, bound, facts, states, seed)
        proven = bool(pair["cause"] and pair["cause"]["proven"])
        pair["verdict"] = (AGREE if passed and proven else AGREE_NEAR_BOUND_OPEN if passed
                           else DISAGREE_EXPLAINED if proven else DISAGREE_OPEN)
    try:
        record["findings"] += file_findings(robot, reference, imported)
    except ModelError as exc:
        record["findings"].append(_finding("file", "", str(exc)))
    record["seconds"] = round(time.perf_counter() - start, 2)
    return record


AGREE, DISAGREE_EXPLAINED, DISAGREE_OPEN = "agree", "disagree-explained", "disagree-open"
NOT_COMPARED, NOT_COMPARED_OPEN = "not compared", "not compared-open"
AGREE_NEAR_BOUND_OPEN = "agree-near-bound-open"
VERDICTS = (AGREE, DISAGREE_EXPLAINED, DISAGREE_OPEN, NOT_COMPARED, NOT_COMPARED_OPEN, AGREE_NEAR_BOUND_OPEN)
OPEN_VERDICTS = frozenset({DISAGREE_OPEN, NOT_COMPARED_OPEN, AGREE_NEAR_BOUND_OPEN})
"""A pair is open when the engines disagree (or one refuses the file, or they agree closer to the bound than
:data:`MARGIN`) and no cause was proven: ``harness robots`` then exits 1."""


def _ratio(checks: list[dict]) -> float:
    return max((c["ratio"] for c in checks), default=0.0)


def explain(engine: Engine, robot: Robot, reference: Reference, view, bound: float, facts: dict, states: int,
            seed: int) -> dict | None:
    """Why the engine does not agree with the reference on ``robot`` (or agrees closer to the bound than
    :data:`MARGIN`): the inertias the engine changed (:attr:`Engine.treatment`, derived from the file and what the
    engine reported), given to the reference too; the cause is **proven** when the reference then agrees with the
    engine within :data:`MARGIN` of the bound, at the same states. None when the engine changed nothing."""
    changed = engine.treatment(robot, view, facts, bound) if engine.treatment else {}
    if not changed:
        return None
    by_link = {li.link: li for li in link_inertias(robot.text, robot.urdf)}
    text = with_inertias(robot.text, robot.urdf, {k: v[:2] for k, v in changed.items()})
    try:
        ref = REFERENCE.load(Robot(robot.name, robot.path, text, robot.floating), {}, [])
        checks = importer.compare(view, ref.view, reference.joints, reference.prismatic, states, seed, bound,
                                  forward=True, memo=reference.memo)   # the engine's values of its pair are kept
    except (ModelError, EngineError) as exc:
        return {"cause": f"not proven: the reference refused the emulated file ({exc})", "right": "", "links": [],
                "proven": False, "after": None}
    links = sorted(({"link": k, "issues": by_link[k].issues() if k in by_link else [], "did": v[2]}
                    for k, v in changed.items()), key=lambda x: not x["issues"])   # the non-physical first
    unphysical = [x for x in links if x["issues"]]
    after = _ratio(checks)
    proven = all(c["passed"] for c in checks) and after <= MARGIN
    what = "; ".join(f"{x['link']}: {', '.join(x['issues']) or 'physical'} → {x['did']}" for x in links[:6])
    what += f" (and {len(links) - 6} more)" if len(links) > 6 else ""
    cause = (f"{engine.label} changes the inertia of {len(links)} link(s) the file states "
             f"({len(unphysical)} of them not physical): {what}. With the same changes Pinocchio agrees with it: "
             f"worst ratio {after:.2g} ≤ {MARGIN:g}" if proven else
             f"{engine.label} changes the inertia of {len(links)} link(s) ({what}), but with the same changes the "
             f"engines still differ (worst ratio {after:.2g}): the cause is elsewhere")
    substituted = [x for x in links if not x["did"].startswith(("principal moments raised", "mass raised"))]
    right = "" if not proven else (
        "the file is at fault (no rigid body has these inertias): Pinocchio computes the file as written, "
        f"{engine.label} a physical body in its place (its documented treatment); neither engine errs"
        if substituted else
        f"both, to the bound: Pinocchio computes the file as written, {engine.label} raised the principal moments "
        f"below its lower bound {bound:g} kg m² to it (a documented treatment; a principal moment 0 is the limit "
        "of an infinitely thin body, which MuJoCo does not accept as is)")
    return {"cause": cause, "right": right, "links": links, "proven": proven, "after": after}


REPAIRS = 4
"""Refusals repaired one after the other at most (:func:`explain_refusal`)."""


def explain_refusal(engine: Engine, robot: Robot, error: str, states: int, seed: int) -> dict | None:
    """Why the engine refuses a file Pinocchio reads: the cause found in the file (:attr:`Engine.repair`), proven
    when, with that cause repaired for both engines, they agree (the engine's own treatment of the rest explained
    by :func:`explain`)."""
    found = engine.repair(Robot(robot.name, robot.path, robot.text, robot.floating), error) if engine.repair else None
    if not found:
        return None
    cause, text, right, links = found
    for _ in range(REPAIRS):  # one refusal at a time: a repaired file may show the engine's next one
        repaired = Robot(robot.name, robot.path, text, robot.floating)
        try:
            ref = REFERENCE.load(repaired, {}, [])
            facts: dict = {}
            view, bound = engine.load(repaired, ref, facts, [])
            checks = importer.compare(view, ref.view, ref.joints, ref.prismatic, states, seed, bound, forward=True)
            break
        except (ModelError, EngineError) as exc:
            more = engine.repair(repaired, str(exc))
            if not more:
                return {"cause": cause + f"; not proven: the repaired file fails too ({exc})", "right": right,
                        "links": links, "proven": False, "after": None}
            cause, text, links = f"{cause}; then {more[0]}", more[1], links + more[3]
            right = right if more[2] in right else f"{right}; {more[2]}"
    else:
        return {"cause": cause + "; not proven: still refused", "right": right, "links": links, "proven": False,
                "after": None}
    after = _ratio(checks)
    proven = all(c["passed"] for c in checks) and after <= MARGIN
    rest = None
    if not proven:
        rest = explain(engine, repaired, ref, view, bound, facts, states, seed)
        proven = bool(rest and rest["proven"])
        after = rest["after"] if rest else after
    cause += (f". With it repaired in the file both engines read, they agree (worst ratio {after:.2g}"
              + (f", after: {rest['cause']}" if rest else "") + ")") if proven else \
        f". With it repaired they still differ (worst ratio {after:.2g}): the cause is elsewhere"
    return {"cause": cause, "right": right, "links": links, "proven": proven, "after": after}


def no_robot(root, error: str) -> dict | None:
    """The reference cannot load the file: explained when the file holds no link (no robot to compare)."""
    if root.find("link") is None:
        return {"cause": "the file holds no <link> (an unexpanded xacro stub): no robot; no engine can load it",
                "right": "every engine: there is nothing to compare", "links": [], "proven": True, "after": None}
    return None


def lost(job: tuple, reason: str) -> dict:
    name, path, symbolic = job[0], job[1], len(job) > 5 and job[5]
    return {"robot": name, "urdf": str(path), "floating": name in FLOATING, "base": "floating" if name in FLOATING
            else "fixed", "dof": None, "engines": {}, "findings": [], "error": reason, "seconds": None,
            "pairs": [{"pair": f"{REFERENCE.name}-{e}", "verdict": NOT_COMPARED_OPEN, "worst": None, "checks": [],
                       "error": reason, "cause": None} for e in (x.name for x in engines(symbolic))]}


# ------------------------------------------------------------------------------------------------ documents
def document(records: list[dict], states: int, seed: int, seconds: float, jobs: int, command: str,
             symbolic: bool = False) -> dict:
    compared = engines(symbolic or any(p["pair"].endswith(f"-{SYMBOLIC}") for r in records for p in r["pairs"]))
    pairs = [f"{REFERENCE.name}-{e.name}" for e in compared]
    summary = {p: dict.fromkeys(VERDICTS, 0) for p in pairs}
    for r in records:
        for p in r["pairs"]:
            summary[p["pair"]][p["verdict"]] += 1
    open_pairs = [f"{r['robot']} {p['pair']}" for r in records for p in r["pairs"] if p["verdict"] in OPEN_VERDICTS]
    return {"schema": SCHEMA, "command": command,
            "versions": {"mujoco": MUJOCO_VERSION, "pinocchio": PINOCCHIO_VERSION, "drake": _drake_version(),
                         "example-robot-data": _package_version()},
            "seed": seed, "states": states, "tolerance": importer.TOLERANCE,
            "tolerance_reason": importer.TOLERANCE_REASON + "; qdd times kappa(M)",
            "reference": REFERENCE.name, "engines": {e.name: e.label for e in [REFERENCE, *compared]},
            "pairs": pairs, "summary": summary, "open": open_pairs, "margin": MARGIN,
            "seconds": round(seconds, 1), "jobs": jobs,
            "robots": records}


def _package_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("example-robot-data")
    except PackageNotFoundError:
        return "?"


def _drake_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("drake")
    except PackageNotFoundError:
        return "?"


def verdict_cell(pair: dict) -> str:
    """The verdict; a pair out of its engine's scope says so briefly (the reason is in robots.json)."""
    return f"{pair['verdict']} (out of scope)" if pair.get("out_of_scope") else pair["verdict"]


def cause_cell(pair: dict) -> str:
    """Why a pair does not simply agree: the cause and who is right (empty when it agrees within the margin, and
    for a pair out of its engine's scope: its verdict cell says so)."""
    c = pair.get("cause")
    if not c:
        return f"{pair['error']}" if pair.get("error") and not pair.get("out_of_scope") else ""
    return c["cause"] + (f" Right: {c['right']}." if c.get("right") else "")


def worst_cell(pair: dict) -> str:
    w = pair.get("worst")
    if not w:
        return "–"
    item = "" if w["item"] == w["quantity"] else f" ({w['item']})"
    return f"{w['quantity']}{item} {w['max_error']:.1e} / {w['bound']:.0e} = {w['ratio']:.2g}"


def warnings_cell(record: dict) -> str:
    step = next((facts["step"] for facts in record["engines"].values() if facts.get("step")), None)
    if not step:
        return "–"
    return "; ".join(step["warnings"]) if step["warnings"] else "none"


def line(record: dict) -> str:
    """One console line per robot."""
    pairs = ", ".join(f"{p['pair']} {p['verdict']}"
                      + (f" (worst {worst_cell(p)})" if p.get("worst") else "")
                      + (f": {p['error']}" if p.get("error") and p["verdict"] in OPEN_VERDICTS else "")
                      for p in record["pairs"])
    kinds = sorted({f["kind"] for f in record["findings"]})
    return (f"{record['robot']}: {record['dof'] if record['dof'] is not None else '?'} dof, {record['base']}; "
            f"{pairs}; warnings: {warnings_cell(record)}; findings: {', '.join(kinds) or 'none'}; "
            f"{record['seconds']} s")


def page(robot: str) -> str:
    """The robot's own page of the report, relative to robots.md/robots.html (written by ``harness report``)."""
    return "robots/" + re.sub(r"[^\w.-]", "_", robot) + ".html"


def _cell(text: str) -> str:
    return re.sub(r"\s+", " ", str(text)).replace("|", "\\|")


def markdown(doc: dict) -> str:
    labels = doc["engines"]
    out = [f"# Every robot of example-robot-data {doc['versions']['example-robot-data']}, across the engines", "",
           f"MuJoCo {doc['versions']['mujoco']} (its own URDF importer) and Drake {doc['versions'].get('drake', '?')} "
           "(its URDF parser, a continuous MultibodyPlant), geometry removed, and our own pipeline (from_urdf, "
           "our MJCF exporter, loaded by MuJoCo: \"MuJoCo (our export)\", on fixed-base robots with at most "
           f"{EXPORT_MAX_DOF} moving DoF and no mimic joints; elsewhere not compared, the reason given)"
           + (", and our symbolic derivation of the same from_urdf trees (M (5.21), C·q̇ from the Christoffel "
              "symbols (5.95), body by body from 6 DoF on, g (5.96), compiled and evaluated in float64; q̈ solved "
              "numerically: \"our symbolic derivation\", `harness robots --symbolic`)" if SYMBOLIC in labels else "")
           + ", each against Pinocchio "
           f"{doc['versions']['pinocchio']} (reference) reading the same URDF: M, bias, C·q̇, g and forward "
           f"dynamics q̈ at {doc['states']} random states (seed {doc['seed']}), joints matched by name, floating "
           "bases in Pinocchio's free-flyer coordinates (MuJoCo's free joint and Drake's QuaternionFloatingJoint: "
           "velocities in world axes, mapped); mass, first moment and inertia of what each joint moves. Tolerance "
           f"{doc['tolerance']:.0e} of each quantity's scale ({doc['tolerance_reason']}). Worst: the check with the "
           "largest ratio error / bound. Verdicts: agree (within the bound and within "
           f"{doc.get('margin', MARGIN):g} of it); disagree-explained (the cause detected in the file and proven: "
           "the reference given the engine's changes agrees with it); disagree-open, not compared-open, "
           "agree-near-bound-open (no cause proven: the command fails). Warnings: MuJoCo stepping each robot 1 s "
           "with small noise torques. "
           f"Generated by `{doc['command']}` in {doc['seconds']} s with {doc['jobs']} process(es).", ""]
    for pair, s in doc["summary"].items():
        ref, other = pair.split("-", 1)
        out.append(f"- {labels[ref]} – {labels[other]}: " + ", ".join(f"{n} {v}" for v, n in s.items() if n))
    out.append(f"- open: {', '.join(doc.get('open', [])) or 'none'}")
    header = ["robot", "DoF", "base"] + [f"{labels[p.split('-', 1)[0]]}–{labels[p.split('-', 1)[1]]}"
                                         for p in doc["pairs"]] + ["worst (error / bound = ratio)",
                                                                   "why (cause; who is right)", "time s",
                                                                   "MuJoCo warnings", "findings"]
    out += ["", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in doc["robots"]:
        kinds = sorted({f["kind"] for f in r["findings"]})
        cells = [f"[{r['robot']}]({page(r['robot'])})", r["dof"] if r["dof"] is not None else "?", r["base"]]
        cells += [verdict_cell(p) for p in r["pairs"]]
        cells += ["; ".join(worst_cell(p) for p in r["pairs"]),
                  " ".join(f"{p['pair']}: {cause_cell(p)}" for p in r["pairs"] if cause_cell(p)) or "–",
                  r["seconds"], warnings_cell(r), ", ".join(kinds)]
        out.append("| " + " | ".join(_cell(c) for c in cells) + " |")
    out += ["", "## Per robot", ""]
    for r in doc["robots"]:
        out.append(f"### {r['robot']} ({r['urdf']})")
        out.append("")
        if r["error"]:
            out.append(f"- not loaded: {_cell(r['error'])}")
        for p in r["pairs"]:
            out.append(f"- {p['pair']}: {p['verdict']}" + (f" — {_cell(p['error'])}" if p["error"] else "")
                       + (f" (why: {_cell(cause_cell(p))})" if p.get("cause") else ""))
            for c in p["checks"]:
                if not c["passed"]:
                    out.append(f"  - {importer.finding(c)} at {_cell(c['worst_state'])}")
        for f in r["findings"]:
            out.append(f"- {f['kind']}" + (f" ({_cell(f['where'])})" if f["where"] else "") + f": {_cell(f['text'])}")
        out.append("")
    return "\n".join(out) + "\n"


COUNTEREXAMPLE_KEYS = ("worst_state", "imported", "reference")


def recorded(checks: list[dict]) -> list[dict]:
    """What robots.json keeps of a pair's checks: every failing check with its counterexample (the state where it is
    worst and both values there), and the worst passing check of each quantity without them. Every check was
    judged; robots.md lists them all, ``harness robots NAME`` recomputes them (the whole package: 33 MB → 1.6 MB)."""
    failing = [c for c in checks if not c["passed"]]
    worst: dict[str, dict] = {}
    for c in checks:
        if c["passed"] and c["ratio"] >= worst.get(c["quantity"], {"ratio": -1.0})["ratio"]:
            worst[c["quantity"]] = c
    return failing + [{k: v for k, v in c.items() if k not in COUNTEREXAMPLE_KEYS} for c in worst.values()]


def write(doc: dict, out: Path) -> list[Path]:
    import json

    from harness.checks import json_clean
    from harness.io import atomic_write_text

    paths = [Path(out) / "robots.json", Path(out) / "robots.md"]
    lean = {**doc, "robots": [{**r, "pairs": [{**p, "checks": recorded(p["checks"])} for p in r["pairs"]]}
                              for r in doc["robots"]]}
    atomic_write_text(paths[0], json.dumps(json_clean(lean), separators=(",", ":")) + "\n")
    atomic_write_text(paths[1], markdown(doc))
    return paths
