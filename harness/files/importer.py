"""MuJoCo's own URDF importer, compared with a reference: does ``MjModel.from_xml_string(urdf)`` hold the
same dynamics as the model the URDF describes?

Models and references
---------------------
* every system of the catalogue: MuJoCo's import of our ``urdf/<system>.urdf`` against our own MJCF
  ``urdf/<system>.xml`` (conformant with the derivation and Pinocchio by ``harness check``);
* the test model :data:`FIXTURES` (``harness/files/fixtures/rotated_inertials.urdf``): our exporter writes every
  ``<inertial>`` with ``rpy="0 0 0"`` (the tensor already rotated), so our URDFs cannot show an importer that
  drops an inertial's ``rpy``; this model has rotated inertial frames, full inertia tensors and a rotated
  fixed joint with a moving child (MuJoCo fuses the fixed link into its parent). Its reference is Pinocchio
  loading the same file (Pinocchio's URDF reading is checked against our derivations by ``harness check``).
  It ships with the library (not under ``tests/``) because ``harness importer`` reports on it;
* two public robots of the pinned example-robot-data package (:data:`PUBLIC`: UR5, Panda), against Pinocchio
  reading the same file (their meshes removed for MuJoCo: :func:`without_geometry`).

Compared in the tree coordinates θ (joints matched by name) at :data:`STATES` random states (seeded):
``M`` (``mj_fullM`` / ``pin.crba``), the bias forces ``C θ̇ + g`` (``qfrc_bias`` / ``pin.nonLinearEffects``)
and, per moving joint, everything the joint moves (its subtree, lumped into one body by Steiner's theorem
(3.133)): mass, first moment of mass ``m c`` (mass times centre of mass) and inertia tensor about the centre of
mass, in world axes — independent of how the bodies are cut and framed, so an importer that fuses a body in
the wrong frame or drops a rotation shows up here, while our exporter's fusing of massless links does not.
(``m c`` rather than ``c``: the centre of a subtree of negligible mass is not defined to any accuracy.)

What a URDF cannot say is set on the imported model before comparing (listed per model as
``adjustments``): gravity (a URDF has none; MuJoCo's default is −9.81 z), rotor inertia (armature), and
MuJoCo's lower bound on moving masses and inertias: the importer refuses a point mass (zero inertia) or a
massless moving link as is (``refused`` holds MuJoCo's message); the comparison then uses
``compiler.boundmass``/``boundinertia`` = :data:`IMPORT_BOUND` (1e-14): the treatment our MJCF exporter gives
point masses, at ten times its stand-in :data:`~harness.export.numeric.MUJOCO_POINT_MASS_INERTIA` (mjMINVAL =
1e-15), because the importer fuses static bodies through an eigenvalue test that refuses inertias up to ~5e-15.
Each of the ``n`` bodies of either model may then carry that bound as extra mass and principal inertia up to
``L`` from the origin: an absolute ``allowance`` of ``n·bound`` on mass, ``n·bound·L`` on ``m c``,
``n·bound·max(1, L²)`` on inertia (observed: exactly 1e-14), and on ``M``, the bias and ``q̈`` what those extra
masses and inertias move them by (:func:`bound_allowances`). Without the one on ``M``, the Euler top's import,
which keeps its two massless gimbal links as bodies of the bound's mass and inertia where our MJCF fuses them into
the top, differed in ``M`` by up to 2e-14 (1.7e-11 of its largest entry); and ``harness validate`` called a lab-sized
Furuta pendulum's URDF (slender rods, refused as is) a finding, its ``M`` 2.0e-11 off Pinocchio's: the bound's
own effect, not the file's.

Tolerance: :data:`~harness.compare.conformance.FLOAT64_RTOL` (1e-12) of each quantity's scale — the importer reads
the same shortest-round-trip decimals, so only float64 round-off may remain (principal-axis decomposition,
quaternions: a few ulps). Scales are those of the terms forming a quantity, not of the (possibly cancelling)
result, as in the conformance policy. With ``m`` the largest subtree mass and ``L`` the largest
centre-of-mass coordinate at the state: inertia: ``I_s`` = max(max|I|, ``m L²``), the inertia the masses
create about the origin, which is what enters ``M`` (a point mass's inertia about itself is zero: its 1e-15
stand-in is not compared with itself); ``M``: max(max|M|, ``I_s``) — a body far from its joint contributes
``m |c|²`` and a cancellation of that size to ``M`` (found by the fuzz test: the test model with a centre of
mass 5.7e5 m from its joint gives 7.5e-5 absolute, 9e-5 of max|M| = 0.8, 2e-16 of ``I_s``); bias:
max(max|bias|, that times max(1, max|θ̇|)², ``m |g| L``); mass: ``m``; ``m c``: ``m L``. Non-finite numbers
from either side are an EngineError, not a comparison.

JSON schema of ``importer.json`` (written by ``harness importer --out DIR``)
----------------------------------------------------------------------------
::

    {"schema": "importer/1",
     "command": "harness importer --out reports",
     "versions": {"mujoco": str, "pinocchio": str},
     "seed": int, "states": int, "tolerance": float, "tolerance_reason": str,
     "summary": {"models": int, "agree": int, "differ": int, "refused_as_is": int, "not_loaded": int},
     "models": [{
        "model": str,                   # system name or fixture name
        "kind": "system" | "fixture" | "public",   # public: example-robot-data URDFs (ur5, panda)
        "urdf": str,                    # path relative to the project
        "reference": str,               # "our MJCF urdf/<system>.xml" or "Pinocchio (same URDF)"
        "refused": str | null,          # MuJoCo's message when the URDF does not load as is
        "loaded": bool,                 # loaded (as is or adjusted) and compared
        "error": str | null,            # why it was not compared, when not loaded
        "adjustments": [str],           # what was set on the import before comparing
        "bodies": {"imported": [str], "reference": [str]},   # MuJoCo body names (reference: ours or links)
        "checks": [{"quantity": "M" | "bias" | "mass" | "first moment of mass" | "inertia",
                    "item": str,        # "M", "bias" or the moving joint whose subtree is compared
                    "max_error": float, # relative error |imported - reference| / scale, at worst_state
                    "scale": float, "tolerance": float,
                    "allowance": float, # absolute, from the bound on masses/inertias (0 when loaded as is)
                    "passed": bool,     # at every state: max_error * scale <= tolerance * scale + allowance
                    "worst_state": {"theta": {joint: float}, "theta_dot": {joint: float}},  # largest excess
                    "imported": list, "reference": list}],     # the values at worst_state
        "passed": bool,                 # loaded and every check within tolerance
        "findings": [str]}],            # one line per failed check (empty when it agrees)
     "probes": [{                       # legal edits of the test model, read by both engines
        "probe": str, "model": str, "edit": str, "loaded": bool, "agrees": bool, "error": str | null,
        "max_error": {quantity: float}, "findings": [str]}],
     "controls": [{                     # known importer defects emulated on the fixtures: must be detected
        "defect": str, "model": str, "emulation": str, "detected": bool,
        "max_error": {quantity: float}, "findings": [str]}]}
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache, partial
from pathlib import Path

from typing import TYPE_CHECKING

import numpy as np

from harness.checks import Bound, Check, relative_error, relative_error_rows
from harness.compare.conformance import FLOAT64_RTOL
from harness.engines.base import Base
from harness.engines.mujoco_engine import VERSION as MUJOCO_VERSION, MujocoModel, compile_text
from harness.engines.pinocchio_engine import VERSION as PINOCCHIO_VERSION, PinocchioModel, load_urdf, moving_joints
from harness.errors import EngineError, ModelError
from harness.export.numeric import instantiate, lump_each

PROJECT_ROOT = Path(__file__).resolve().parents[2]
FIXTURES = (Path(__file__).resolve().parent / "fixtures" / "rotated_inertials.urdf",)
PUBLIC = ("ur_description/urdf/ur5_robot.urdf", "panda_description/urdf/panda.urdf")
"""Public robot URDFs of the pinned example-robot-data package, compared like the fixtures."""
STATES = 20
SEED = 0
TOLERANCE = FLOAT64_RTOL
TOLERANCE_REASON = ("float64 round-off of the same decimals (principal axes, quaternions: a few ulps); "
                    "harness.compare.conformance tolerance policy")
if TYPE_CHECKING:
    import mujoco

SCHEMA = "importer/1"
BOUND = Bound("importer round-off", TOLERANCE, TOLERANCE_REASON)
_rel = partial(relative_error, symmetric=False)   # relative to each quantity's scale (≥ the reference's size)
QUANTITIES = ("M", "bias", "mass", "first moment of mass", "inertia")


@lru_cache(maxsize=16)
def without_geometry(urdf_text: str, source: str = "<urdf>") -> str:
    """The URDF without ``<visual>``/``<collision>`` (for MuJoCo's importer: the dynamics do not depend on
    them, and it cannot resolve ``package://`` mesh URIs). Kept for the last texts (a robot's MuJoCo and Drake
    loads strip the same file: 146 calls for 78 texts in ``harness robots``)."""
    from lxml import etree

    from harness.files.untrusted import parse_xml

    root = parse_xml(urdf_text, source)
    for el in root.xpath("//link/visual | //link/collision"):
        el.getparent().remove(el)
    return etree.tostring(root, encoding="unicode")


def public_urdfs() -> list[Path]:
    from importlib.util import find_spec

    spec = find_spec("cmeel")
    if spec is None:
        return []
    share = Path(spec.origin).parent.parent / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
    return [share / rel for rel in PUBLIC if (share / rel).exists()]


# --------------------------------------------------------------------------------- two views of a tree
@dataclass
class Rigid:
    """Everything a moving joint moves (its subtree) lumped into one body at the current state: mass, centre
    of mass, inertia tensor about it (world axes). Independent of how the bodies are cut and framed."""

    mass: float
    com: np.ndarray
    inertia: np.ndarray


def rigid(view, theta, base: Base | None = None) -> dict[str, Rigid]:
    """What each joint of ``view`` (an engine adapter) moves, lumped into one body at ``θ`` (and, with a free
    joint, the base state ``base``; the free joint moves the whole robot): ``(m, c, I_c)`` parts in world axes,
    every joint's at once (:func:`harness.export.numeric.lump_each`)."""
    parts = view.subtree_parts(theta, base) if base is not None else view.subtree_parts(theta)
    return {name: Rigid(*body) for name, body in zip(parts, lump_each(parts.values()))}


# --------------------------------------------------------------------------------- comparison
@dataclass
class _Worst:
    """The state where one quantity's error exceeds what is allowed there by the most; its verdict is a
    :class:`harness.checks.Check` (relative error against :data:`TOLERANCE` plus the allowance at that state)."""

    quantity: str
    item: str
    max_error: float = 0.0
    scale: float = 0.0
    allowance: float = 0.0
    worst: dict | None = None
    imported: list | None = None
    reference: list | None = None
    excess: float = -math.inf
    amplification: float = 1.0

    def update(self, error, scale, state, imported, reference, allowance=0.0, amplification=1.0):
        """Keep the state where the error exceeds what is allowed there by the most (``amplification``: of the
        tolerance at that state, κ(M) for forward dynamics as in the conformance policy)."""
        excess = error - self._allowed(scale, allowance, amplification)
        if excess > self.excess:
            self.max_error, self.scale, self.allowance, self.worst = float(error), float(scale), allowance, state
            self.imported, self.reference = np.asarray(imported).tolist(), np.asarray(reference).tolist()
            self.excess, self.amplification = excess, float(amplification)

    @staticmethod
    def _allowed(scale, allowance, amplification=1.0) -> float:
        return TOLERANCE * amplification + (allowance / scale if scale > 0 else allowance)

    def check(self) -> Check:
        bound = self._allowed(self.scale, self.allowance, self.amplification)
        return Check(self.quantity, "mujoco import", self.max_error, bound, BOUND.name, self.item)

    def record(self) -> dict:
        out = {"quantity": self.quantity, "item": self.item, "max_error": self.max_error, "scale": self.scale,
               "tolerance": TOLERANCE * self.amplification, "allowance": self.allowance,
               "passed": self.check().passed, "ratio": self.check().ratio,
               "worst_state": self.worst, "imported": self.imported, "reference": self.reference}
        if self.amplification != 1.0:
            out["amplification"] = self.amplification
        return out


def _finite(what: str, state: dict, **values) -> None:
    bad = [name for name, v in values.items() if not np.all(np.isfinite(v))]
    if bad:
        raise EngineError(f"{what}: {', '.join(bad)} not finite at θ = {list(state['theta'].values())}")


@dataclass(frozen=True)
class _ReferenceState:
    """What :func:`compare` takes from the reference at one state (θ, θ̇, base): what each joint moves, the terms,
    and the scales they give (length ``L``, largest subtree mass, inertia, ``M`` and bias scales, ``max|M⁻¹|``,
    the acceleration scale and κ(M)). Read only: kept in ``compare``'s memo for the reference's next
    comparison at the same state."""

    rigid: dict
    terms: dict
    length: float
    mass: float
    i_scale: float
    m_scale: float
    b_scale: float
    inverse_max: float | None = None
    a_scale: float | None = None
    kappa: float | None = None

    @classmethod
    def of(cls, r_r: dict, t_r: dict, qdd: bool, theta_dot, base: Base | None, gravity) -> "_ReferenceState":
        """``qdd``: the forward dynamics is compared at this state (``M⁻¹``, κ(M) and the acceleration scale)."""
        M_r, b_r = t_r["M"], t_r["bias"]
        length = max(1e-300, max(float(np.max(np.abs(r.com))) for r in r_r.values()))
        mass = max(r.mass for r in r_r.values())
        i_scale = max(mass * length**2, max(float(np.max(np.abs(r.inertia))) for r in r_r.values()))
        m_scale = max(float(np.max(np.abs(M_r))), i_scale)
        speed = max([1.0, float(np.max(np.abs(theta_dot), initial=0.0))]
                    + ([float(np.max(np.abs(base.velocity)))] if base is not None else []))
        b_scale = max(float(np.max(np.abs(b_r))), m_scale * speed ** 2,
                      mass * float(np.linalg.norm(gravity)) * length)
        if not qdd:
            return cls(r_r, t_r, length, mass, i_scale, m_scale, b_scale)
        inverse_max = float(np.max(np.abs(np.linalg.inv(M_r))))
        return cls(r_r, t_r, length, mass, i_scale, m_scale, b_scale, inverse_max,
                   max(inverse_max * b_scale, speed ** 2), float(np.linalg.cond(M_r)))


def random_base(rng) -> Base:
    """A floating base state: position in (−1, 1) m, orientation uniform on SO(3), local velocity in (−2, 2)."""
    quat = rng.normal(size=4)
    return Base(rng.uniform(-1, 1, 3), quat / np.linalg.norm(quat), rng.uniform(-2, 2, 6))


def compare(imported, reference, joints: list[str], prismatic: set[str], states: int = STATES,
            seed: int = SEED, bound: float = 0.0, forward: bool = False, notes: list | None = None,
            memo: dict | None = None) -> list[dict]:
    """Worst relative differences of ``imported`` against ``reference`` (both tree views) over random
    states: θ uniform in (−π, π) for rotations, (−1, 1) m for slides; θ̇ uniform in (−2, 2). ``bound``: the
    lower bound MuJoCo put on each body's mass and principal inertias of the import (0 when loaded as is);
    each body of either model may then carry that much extra mass (and inertia) at up to ``L`` from the
    origin: an absolute ``allowance`` of ``n·bound`` on mass, ``n·bound·L`` on the first moment of mass,
    ``n·bound·max(1, L²)`` on inertia (``n`` bodies of both models). Non-finite numbers: EngineError.

    Views with a free joint (``reference.free``) are compared at a random :class:`Base` per state too
    (:func:`random_base`), in Pinocchio's free-flyer coordinates; the whole robot (what the free joint moves)
    is one more item of the mass checks. ``forward``: also ``Cqd`` (bias without gravity) and ``g`` at the
    scale of the bias, and the forward dynamics ``qdd`` at the scale of the accelerations the terms cause
    (``max|M⁻¹|`` times the bias scale, at least ``v²``) with the tolerance times κ(M), the conformance policy
    (:mod:`harness.compare.conformance`). Where the reference's ``M`` is singular (a joint that moves no mass:
    its ``q̈`` is not finite) ``q̈`` is not compared at that state; ``notes`` receives how often.

    ``memo``: a dict the caller keeps while neither view changes: what each view gives at a state (the reference's
    :class:`_ReferenceState`, the import's subtrees and terms), kept by the view and the state's exact bits for the
    next comparison at the same states (a robot's pairs: every engine is compared with the same reference; a cause
    finder compares the same engine with an emulated reference)."""
    rng = np.random.default_rng(seed)
    undefined = 0
    free = reference.free
    checks: dict[tuple, _Worst] = {}
    n_bound = (len(imported.body_names()) + len(reference.body_names())) * bound

    def check(quantity, item):
        return checks.setdefault((quantity, item), _Worst(quantity, item))

    def remembered(view, what: str, key: tuple, compute=None):
        """What ``compute()`` gave for ``view`` at this state, kept in ``memo`` (without ``compute``: what was kept,
        or None)."""
        entry = memo.get((id(view), what, key)) if memo is not None else None
        if entry is not None and entry[0] is view:   # the view is kept with its values: its id is not reused
            return entry[1]
        if compute is None:
            return None
        value = compute()
        if memo is not None:
            memo[id(view), what, key] = (view, value)
        return value

    for _ in range(states):
        theta = np.array([rng.uniform(-1, 1) if j in prismatic else rng.uniform(-np.pi, np.pi) for j in joints])
        theta_dot = rng.uniform(-2, 2, len(joints))
        state = {"theta": dict(zip(joints, theta.tolist())), "theta_dot": dict(zip(joints, theta_dot.tolist()))}
        kw = {}
        if free:
            kw["base"] = random_base(rng)
            state["base"] = kw["base"].record()
        key = (theta.tobytes(), theta_dot.tobytes(), forward,
               np.concatenate([kw["base"].position, kw["base"].quat_xyzw, kw["base"].velocity]).tobytes()
               if free else None)
        kept = remembered(reference, "reference", key)
        r_i = remembered(imported, "rigid", key, lambda: rigid(imported, theta, **kw))
        r_r = kept.rigid if kept else rigid(reference, theta, **kw)
        t_i = dict(remembered(imported, "terms", key, lambda: imported.terms(theta, theta_dot, forward=True, **kw))) \
            if forward else None
        t_r = (kept.terms if kept else reference.terms(theta, theta_dot, forward=True, **kw)) if forward else None
        terms_r = t_r
        if forward and not np.all(np.isfinite(t_r["qdd"])):  # M singular: no forward dynamics to compare
            undefined += 1
            t_r = {k: v for k, v in t_r.items() if k != "qdd"}   # the reference's own dict is kept whole
            del t_i["qdd"]
        M_i, b_i = (t_i["M"], t_i["bias"]) if forward else \
            remembered(imported, "M and bias", key, lambda: imported.mass_and_bias(theta, theta_dot, **kw))
        if forward:
            M_r, b_r = t_r["M"], t_r["bias"]
        else:
            M_r, b_r = (kept.terms["M"], kept.terms["bias"]) if kept else \
                reference.mass_and_bias(theta, theta_dot, **kw)
            terms_r = {"M": M_r, "bias": b_r}
        _finite(f"{type(imported).__name__} (import)", state, **{"M": M_i, "bias": b_i, **(t_i or {})},
                bodies=[[x.mass, *x.com, *x.inertia.ravel()] for x in r_i.values()])
        if not kept:   # a kept state's reference values were finite
            _finite(f"{type(reference).__name__} (reference)", state, **{"M": M_r, "bias": b_r, **(t_r or {})},
                    bodies=[[x.mass, *x.com, *x.inertia.ravel()] for x in r_r.values()])
            kept = remembered(reference, "reference", key, lambda: _ReferenceState.of(
                r_r, terms_r, bool(forward and "qdd" in t_r), theta_dot, kw.get("base"), reference.gravity))
        length, mass, i_scale, m_scale, b_scale = kept.length, kept.mass, kept.i_scale, kept.m_scale, kept.b_scale
        m_allow, c_allow, g_allow = bound_allowances(n_bound, length, theta_dot, kw.get("base"), reference.gravity)
        check("M", "M").update(_rel(M_i, M_r, m_scale), m_scale, state, M_i, M_r, m_allow)
        check("bias", "bias").update(_rel(b_i, b_r, b_scale), b_scale, state, b_i, b_r, c_allow + g_allow)
        if forward:
            for q, allow in (("Cqd", c_allow), ("g", g_allow)):
                check(q, q).update(_rel(t_i[q], t_r[q], b_scale), b_scale, state, t_i[q], t_r[q], allow)
        if forward and "qdd" in t_r:
            a_scale, kappa = kept.a_scale, kept.kappa
            allowance = kept.inverse_max * (m_allow * float(np.max(np.abs(t_r["qdd"]))) + c_allow + g_allow)
            check("qdd", "qdd").update(_rel(t_i["qdd"], t_r["qdd"], a_scale), a_scale, state, t_i["qdd"],
                                       t_r["qdd"], allowance, kappa)
        moment = mass * length
        m_i, m_r = (np.array([r[j].mass for j in r_r]) for r in (r_i, r_r))
        c_i, c_r = (np.array([r[j].com for j in r_r]).reshape(-1, 3) for r in (r_i, r_r))
        f_i, f_r = m_i[:, None] * c_i, m_r[:, None] * c_r   # first moments m c
        I_i, I_r = (np.array([r[j].inertia for j in r_r]).reshape(-1, 3, 3) for r in (r_i, r_r))
        errors = zip(relative_error_rows(m_i, m_r, mass), relative_error_rows(f_i, f_r, moment),
                     relative_error_rows(I_i, I_r, i_scale))
        for k, (j, (e_mass, e_first, e_inertia)) in enumerate(zip(r_r, errors)):
            check("mass", j).update(e_mass, mass, state, [m_i[k]], [m_r[k]], n_bound)
            check("first moment of mass", j).update(e_first, moment, state, f_i[k], f_r[k], n_bound * length)
            check("inertia", j).update(e_inertia, i_scale, state, I_i[k], I_r[k], n_bound * max(1.0, length**2))
    if undefined and notes is not None:
        notes.append(f"q̈ not compared at {undefined} of {states} states: the reference's M is singular there "
                     "(a joint moves no mass; Pinocchio's aba returns non-finite values)")
    return [c.record() for c in checks.values()]


def bound_allowances(n_bound: float, length: float, theta_dot, base, gravity) -> tuple[float, float, float]:
    """What the compiler's bound may move ``M``, ``C q̇`` and ``g`` by, absolutely, at a state (``n_bound``: the
    bound times the bodies of both models, each of which may carry that much extra mass and principal inertia at up
    to ``length`` from the origin): a joint's translational column of a body's Jacobian is at most ``max(1, L)``
    long, its rotational one at most 1, so ``|ΔM| ≤ n·bound (max(1, L)² + 1)``; the Christoffel terms of that
    ``ΔM`` at rates summing to ``v`` (the base's too) at most ``3 |ΔM| max(1, v)²`` (``Γ`` of ``½ ∂ΔM/∂q``, a
    derivative of a column at most as long as the column); the bound's weight ``n·bound |g| max(1, L)``."""
    m_allow = n_bound * (max(1.0, length) ** 2 + 1.0)
    v = float(np.sum(np.abs(theta_dot))) + (float(np.sum(np.abs(base.velocity))) if base is not None else 0.0)
    return m_allow, 3.0 * m_allow * max(1.0, v) ** 2, n_bound * float(np.linalg.norm(gravity)) * max(1.0, length)


def finding(c: dict) -> str:
    what = (c["quantity"] if c["item"] in ("M", "bias", "Cqd", "g", "qdd")
            else f"{c['quantity']} of what {c['item']} moves")
    return f"{what}: relative error {c['max_error']:.3g} (tolerance {c['tolerance']:.0e})"


IMPORT_BOUND = 1e-14
"""``compiler.boundmass``/``boundinertia`` of an import MuJoCo refuses as is (see the module docstring)."""
BOUND_NOTE = (f"compiler boundmass = boundinertia = {IMPORT_BOUND:g} (MuJoCo refuses a point mass or "
              "massless moving link as is)")


def load_import(urdf_text: str, source: str, edit=None, tree=None,
                accepted: list | None = None) -> tuple["mujoco.MjModel", str | None, float]:
    """MuJoCo's import, as is or (refused as is: point masses, massless moving links) with the lower bound
    :data:`IMPORT_BOUND` on masses and inertias: the model, MuJoCo's refusal, the bound used. ``edit``, ``tree``,
    ``accepted``: see :func:`~harness.engines.mujoco_engine.compile_text` (e.g. ``add_free_joint``; our own URDF's
    tree, whose explained compiler warnings are accepted)."""
    try:
        return compile_text(urdf_text, source, edit=edit, tree=tree, accepted=accepted), None, 0.0
    except ModelError as exc:
        refused = str(exc).split("MuJoCo refused the model: ", 1)[-1]
        model = compile_text(urdf_text, source, bound=IMPORT_BOUND, edit=edit, tree=tree, accepted=accepted)
        return model, refused, IMPORT_BOUND


def _load_import(urdf_text: str, source: str, record: dict, tree=None,
                 accepted: list | None = None) -> tuple["mujoco.MjModel", float]:
    model, record["refused"], bound = load_import(urdf_text, source, tree=tree, accepted=accepted)
    if record["refused"]:
        record["adjustments"].append(BOUND_NOTE)
    return model, bound


def _record(name, kind, urdf_path, reference) -> dict:
    parts = urdf_path.parts
    if "example-robot-data" in parts:  # a public robot: named within its package
        rel = Path(*parts[parts.index("example-robot-data"):])
    else:
        rel = urdf_path.relative_to(PROJECT_ROOT) if urdf_path.is_relative_to(PROJECT_ROOT) else urdf_path
    return {"model": name, "kind": kind, "urdf": str(rel), "reference": reference, "refused": None,
            "loaded": False, "error": None, "adjustments": [], "bodies": {"imported": [], "reference": []},
            "checks": [], "passed": False, "findings": []}


def _finish(record: dict, checks: list[dict]) -> dict:
    record["checks"] = checks
    record["loaded"] = True
    record["findings"] = [finding(c) for c in checks if not c["passed"]]
    record["passed"] = not record["findings"]
    return record


def compare_system(system, states: int = STATES, seed: int = SEED, folder: Path | None = None) -> dict:
    """MuJoCo's import of our ``<system>.urdf`` against our MJCF of the same system (default parameters), both
    named as exported in ``folder`` (the repository's ``urdf/`` unless given: :func:`harness.run.export_folders`)."""
    from harness.export.files import system_files

    tree, accepted = instantiate(system, system.default_parameters()), []  # the files' tree
    files = system_files(system, tree)
    urdf_text, mjcf_text = files[f"{system.name}.urdf"], files[f"{system.name}.xml"]
    folder = PROJECT_ROOT / "urdf" if folder is None else Path(folder)
    record = _record(system.name, "system", folder / f"{system.name}.urdf", "")
    mjcf_name = str(Path(record["urdf"]).with_suffix(".xml"))
    record["reference"] = f"our MJCF {mjcf_name}"
    try:
        joints = [j.name for j in system.joints]
        prismatic = {j.name for j in system.joints if j.type == "prismatic"}
        ours = compile_text(mjcf_text, mjcf_name, tree=tree, accepted=accepted)
        imported, bound = _load_import(urdf_text, record["urdf"], record, tree, accepted)
        for message, reason in dict.fromkeys(accepted):  # as the conformance run accepts them: explained
            record["adjustments"].append(f"MuJoCo warned while compiling ({message}), explained: {reason}")
        ref, imp = MujocoModel.loaded(ours, joints), MujocoModel.loaded(imported, joints)
        imp.set_gravity(ref.gravity)
        record["adjustments"].append(f"gravity {ref.gravity.tolist()} (a URDF has none)")
        armature = ref.armature
        if np.any(armature):
            imp.set_armature(armature)
            record["adjustments"].append(f"armature {armature.tolist()} (a URDF has no rotor inertia)")
        record["bodies"] = {"imported": imp.body_names(), "reference": ref.body_names()}
        return _finish(record, compare(imp, ref, joints, prismatic, states, seed, bound))
    except (ModelError, EngineError) as exc:
        record["error"] = str(exc)
        return record


def compare_urdf(path: Path, text: str, kind: str = "fixture", states: int = STATES, seed: int = SEED,
                 import_text: str | None = None) -> dict:
    """MuJoCo's import of a URDF against Pinocchio reading the same file (``import_text``: what MuJoCo reads
    instead, for the controls)."""
    record = _record(path.stem, kind, path, "Pinocchio (same URDF)")
    try:
        pmodel = load_urdf(text, str(path))
        ref = PinocchioModel.loaded(pmodel, moving_joints(pmodel))
        joints, prismatic = ref.joints, ref.prismatic
        imported, bound = _load_import(without_geometry(import_text or text, str(path)), str(path), record)
        imp = MujocoModel.loaded(imported, joints)
        imp.set_gravity(ref.gravity)
        record["bodies"] = {"imported": imp.body_names(), "reference": ref.body_names()}
        return _finish(record, compare(imp, ref, joints, prismatic, states, seed, bound))
    except (ModelError, EngineError) as exc:
        record["error"] = str(exc)
        return record


def _drop_rpy(text: str, xpath: str) -> str:
    from lxml import etree

    root = etree.fromstring(text.encode(), etree.XMLParser(resolve_entities=False, no_network=True))
    for el in root.xpath(xpath):
        el.attrib.pop("rpy", None)
    return etree.tostring(root, encoding="unicode")


CONTROLS = {
    "inertial rpy dropped": ("//inertial/origin", "MuJoCo reads the file with every `<inertial><origin rpy>` "
                             "deleted; Pinocchio reads it as is"),
    "static body fused in the wrong frame": ("//joint[@type='fixed']/origin", "MuJoCo reads the file with the "
                                             "rotation (rpy) of every fixed joint deleted, so the fixed link is "
                                             "fused unrotated; Pinocchio reads it as is"),
}
"""Known importer defects, emulated on the fixtures: the comparison must report them (it is not blind)."""


def controls(fixtures=FIXTURES, states: int = STATES, seed: int = SEED) -> list[dict]:
    out = []
    for path in fixtures:
        text = path.read_text()
        for defect, (xpath, emulation) in CONTROLS.items():
            r = compare_urdf(path, text, "control", states, seed, import_text=_drop_rpy(text, xpath))
            worst = {}
            for c in r["checks"]:
                worst[c["quantity"]] = max(worst.get(c["quantity"], 0.0), c["max_error"])
            out.append({"defect": defect, "model": path.stem, "emulation": emulation,
                        "detected": r["loaded"] and not r["passed"], "max_error": worst, "findings": r["findings"]})
    return out


PROBES = {
    "fixed link lighter than mjMINVAL, with rotational inertia": (
        '<mass value="0.5"/>', '<mass value="1e-16"/>',
        "link `tool` (on a fixed joint): mass 0.5 -> 1e-16 kg, inertia tensor kept"),
    "inertial origin with rpy only": (
        '<origin xyz="0.3 0.05 -0.02" rpy="0.4 -0.7 1.1"/>', '<origin rpy="0.4 -0.7 1.1"/>',
        "link `link_1`: inertial origin without xyz"),
    "joint axis not of unit length": ('<axis xyz="0 1 0"/>', '<axis xyz="0 2.5 0"/>', "joint `j2`: axis (0, 2.5, 0)"),
    "oblique joint axis": ('<axis xyz="0 0 1"/>\n    <limit effort="100" velocity="100" lower="-10" upper="10"/>\n  '
                           '</joint>\n  <joint name="j2"',
                           '<axis xyz="0.3 0.5 0.8"/>\n    <limit effort="100" velocity="100" lower="-10" '
                           'upper="10"/>\n  </joint>\n  <joint name="j2"', "joint `j1`: axis (0.3, 0.5, 0.8)"),
    "continuous joint": ('<joint name="j1" type="revolute">', '<joint name="j1" type="continuous">',
                         "joint `j1`: continuous instead of revolute"),
}
"""Legal edits of the test model, read by MuJoCo and Pinocchio alike: where does the importer differ?"""


def probes(fixture: Path = FIXTURES[0], states: int = STATES, seed: int = SEED) -> list[dict]:
    text = fixture.read_text()
    out = []
    for probe, (old, new, edit) in PROBES.items():
        if text.count(old) != 1:
            raise ModelError(f"{fixture}: probe {probe!r} does not apply (its text occurs {text.count(old)}x)")
        r = compare_urdf(fixture, text.replace(old, new), "probe", states, seed)
        worst = {}
        for c in r["checks"]:
            worst[c["quantity"]] = max(worst.get(c["quantity"], 0.0), c["max_error"])
        out.append({"probe": probe, "model": fixture.stem, "edit": edit, "loaded": r["loaded"],
                    "agrees": r["passed"], "error": r["error"], "max_error": worst, "findings": r["findings"]})
    return out


def run(systems=(), fixtures=FIXTURES, states: int = STATES, seed: int = SEED, folders: dict | None = None) -> dict:
    """The ``importer.json`` document for ``systems`` (:class:`~harness.modeling.system.System`; the
    application layer passes the catalogue's, and ``folders``, where each is exported) and the fixtures."""
    records = [compare_system(s, states, seed, (folders or {}).get(s.name)) for s in systems]
    records += [compare_urdf(p, p.read_text(), "fixture", states, seed) for p in fixtures]
    records += [compare_urdf(p, p.read_text(), "public", states, seed) for p in public_urdfs()]
    summary = {"models": len(records), "agree": sum(r["passed"] for r in records),
               "differ": sum(r["loaded"] and not r["passed"] for r in records),
               "refused_as_is": sum(r["refused"] is not None for r in records),
               "not_loaded": sum(not r["loaded"] for r in records)}
    return {"schema": SCHEMA, "command": "harness importer --out reports",
            "versions": {"mujoco": MUJOCO_VERSION, "pinocchio": PINOCCHIO_VERSION},
            "seed": seed, "states": states, "tolerance": TOLERANCE, "tolerance_reason": TOLERANCE_REASON,
            "summary": summary, "models": records, "probes": probes(fixtures[0], states, seed),
            "controls": controls(fixtures, states, seed)}


def markdown(doc: dict) -> str:
    s = doc["summary"]
    lines = ["# MuJoCo's URDF importer against our MJCF and Pinocchio", "",
             f"MuJoCo {doc['versions']['mujoco']} loads each URDF directly (`MjModel` from the URDF text); the "
             "import is compared with our MJCF of the same system (for the test model with rotated inertial "
             "frames and two public robots of example-robot-data: with Pinocchio reading the same file) at "
             f"{doc['states']} random states (seed "
             f"{doc['seed']}), joints matched by name. Tolerance {doc['tolerance']:.0e} of each quantity's scale "
             f"({doc['tolerance_reason']}). Generated by `{doc['command']}`.", "",
             f"{s['models']} models: {s['agree']} agree, {s['differ']} differ, {s['not_loaded']} not compared; "
             f"{s['refused_as_is']} refused as is by the importer.", "",
             "Findings: " + _findings_text(doc), "",
             "| model | reference | refused as is | M | bias | mass | first moment m·c | inertia | verdict |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in doc["models"]:
        worst = {}
        for c in r["checks"]:
            worst[c["quantity"]] = max(worst.get(c["quantity"], 0.0), c["max_error"])
        cells = [f"{worst[q]:.1e}" if q in worst else "–" for q in QUANTITIES]
        verdict = "agrees" if r["passed"] else ("differs" if r["loaded"] else "not compared")
        lines.append(f"| {r['model']} | {r['reference']} | {'yes' if r['refused'] else 'no'} | "
                     + " | ".join(cells) + f" | {verdict} |")
    differ = [r for r in doc["models"] if not r["passed"]]
    if differ:
        lines += ["", "## Where the importer differs", ""]
        for r in differ:
            lines.append(f"### {r['model']} ({r['urdf']})")
            lines.append("")
            if r["error"]:
                lines.append(f"- not compared: {r['error']}")
            for c in r["checks"]:
                if not c["passed"]:
                    lines.append(f"- {finding(c)}; imported {_short(c['imported'])}, reference "
                                 f"{_short(c['reference'])} at θ = {_short(list(c['worst_state']['theta'].values()))}")
            lines.append("")
    lines += ["", "## Edge cases: legal edits of the test model, read by MuJoCo and Pinocchio alike", "",
              "| edit | M | bias | inertia | first moment m·c | verdict |", "|---|---|---|---|---|---|"]
    for p in doc.get("probes", []):
        e = p["max_error"]
        verdict = "agrees" if p["agrees"] else ("**differs**" if p["loaded"] else f"not compared: {p['error']}")
        lines.append(f"| {p['probe']}: {p['edit']} | "
                     + " | ".join(f"{e[q]:.2g}" if q in e else "–"
                                  for q in ("M", "bias", "inertia", "first moment of mass"))
                     + f" | {verdict} |")
    lines += ["", "## Controls: known importer defects, emulated", "",
              "The known defects of MuJoCo's URDF importer do not show above; to show that the comparison would see "
              "them, each is emulated on the test model (what MuJoCo reads is altered, the reference is not):", "",
              "| defect | model | emulation | M | bias | inertia | first moment m·c | detected |",
              "|---|---|---|---|---|---|---|---|"]
    for c in doc.get("controls", []):
        e = c["max_error"]
        lines.append(f"| {c['defect']} | {c['model']} | {c['emulation']} | "
                     + " | ".join(f"{e[q]:.2g}" if q in e else "–"
                                  for q in ("M", "bias", "inertia", "first moment of mass"))
                     + f" | {'yes' if c['detected'] else 'NO'} |")
    refused = [r for r in doc["models"] if r["refused"]]
    if refused:
        lines += ["", "## Refused as is (compared with MuJoCo's lower bounds on mass and inertia)", ""]
        lines += [f"- {r['model']}: {r['refused']}" for r in refused]
    return "\n".join(lines) + "\n"


def _findings_text(doc: dict) -> str:
    s = doc["summary"]
    worst = max((c["max_error"] for r in doc["models"] for c in r["checks"] if c["quantity"] in ("M", "bias")),
                default=0.0)
    text = []
    if s["differ"] == 0 and s["not_loaded"] == 0:
        text.append(f"MuJoCo {doc['versions']['mujoco']}'s importer holds the same dynamics as the reference for "
                    f"every model (largest relative difference of M and bias {worst:.1e}), including rotated "
                    "inertial frames and a rotated fixed joint fused into its parent: the known defects "
                    "(dropping an inertial's rpy, fusing static bodies in the wrong frame) do not reproduce; the "
                    "controls below show they would be seen.")
    else:
        text.append(f"{s['differ']} model(s) differ, {s['not_loaded']} not compared (below).")
    differing = [p for p in doc.get("probes", []) if p["loaded"] and not p["agrees"]]
    for p in differing:
        worst_p = max(p["max_error"].get("M", 0.0), p["max_error"].get("inertia", 0.0))
        text.append(f"Where the importer differs from Pinocchio: {p['probe']} ({p['edit']}): relative error "
                    f"{worst_p:.2g} in M/inertia (edge cases below).")
    if s["refused_as_is"]:
        text.append(f"{s['refused_as_is']} URDFs are refused as is: MuJoCo requires every moving body to have mass "
                    "and inertia above mjMINVAL, so a point mass (zero inertia tensor) or a massless intermediate "
                    "link (gimbal, carrier) does not load without `compiler boundmass/boundinertia`; Pinocchio "
                    "and our MJCF (1e-15 stand-in) take them.")
    return " ".join(text)


def _short(values) -> str:
    return np.array2string(np.asarray(values, dtype=float), precision=6, separator=", ",
                           max_line_width=10_000).replace("\n", "")


def write(doc: dict, out: Path) -> list[Path]:
    import json

    from harness.io import atomic_write_text

    paths = [Path(out) / "importer.json", Path(out) / "importer.md"]
    atomic_write_text(paths[0], json.dumps(doc, indent=1) + "\n")
    atomic_write_text(paths[1], markdown(doc))
    return paths
