"""Pinocchio, loading our URDF. Every number comes from a named Pinocchio call; springs, dampers and
inputs are evaluated from Pinocchio's own frames and Jacobians (``computeJointJacobians``,
``updateFramePlacements``, ``getFrameJacobian``), never from the symbolic model. Closed chains and couplings are
rows of the constraint Jacobian of Pinocchio's KKT forward dynamics (:class:`Constraints`)."""

from __future__ import annotations

import re

import numpy as np
import pinocchio as pin

from harness.engines.base import (FREE_JOINT, Base, State, TreeEngine, TreeQuantities, captured_output,
                                  coriolis_to_lecture, input_forces, one_line, spring_damper_forces, to_lecture)
from harness.errors import EngineError, ModelError
from harness.export.numeric import NumericTree
from harness.export.urdf import exported_urdf

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
VERSION = pin.__version__


def load_urdf(urdf_text: str, source: str, floating: bool = False, said: list | None = None) -> pin.Model:
    """A URDF of other origin in Pinocchio (``floating``: on a free-flyer joint named
    :data:`~harness.engines.base.FREE_JOINT`); a refusal is one :class:`ModelError` line holding Pinocchio's
    message and what urdfdom printed (which names the link: "link 'arm' is not unique"); what urdfdom prints
    without failing (a dropped inertial) is a :class:`ModelError` too, unless ``said`` is given: then it is
    appended there."""
    refused = None
    with captured_output() as out:
        try:
            model = (pin.buildModelFromXML(urdf_text, pin.JointModelFreeFlyer()) if floating
                     else pin.buildModelFromXML(urdf_text))
        except (ValueError, RuntimeError) as exc:
            refused = one_line(exc)
    if refused is not None:
        text = one_line(out[0]) if out and out[0].strip() else ""
        raise ModelError(f"{source}: Pinocchio refused the URDF: {refused}" + (f" (urdfdom: {text})" if text else ""))
    if out and out[0].strip():  # urdfdom complains without failing (e.g. a dropped inertial)
        if said is None:
            raise ModelError(f"{source}: Pinocchio/urdfdom reported: {one_line(out[0])}")
        said.append(one_line(out[0]))
    if floating and model.names[1] != FREE_JOINT:
        raise EngineError(f"{source}: Pinocchio named the free flyer {model.names[1]!r}, not {FREE_JOINT!r}")
    return model


def check_moves_mass(pmodel: pin.Model, source: str, seed: int, states: int = 3) -> None:
    """Every moving joint moves mass: a joint whose whole subtree (the links it moves) has neither mass nor
    inertia, or a mass matrix singular at random states (a massless link on a prismatic joint, a URDF without
    any ``<inertial>``), makes the model invalid; the message names the link."""
    from harness.derivation.compile import regular_spectrum

    def child_link(jid):
        for f in pmodel.frames:
            if f.type == pin.FrameType.BODY and f.parentJoint == jid:
                return f.name
        return pmodel.names[jid]

    for jid in range(1, pmodel.njoints):
        if pmodel.joints[jid].nv == 0:
            continue
        subtree = pmodel.subtrees[jid]
        mass = sum(pmodel.inertias[k].mass for k in subtree)
        inertia = max(float(np.abs(np.array(pmodel.inertias[k].inertia)).max()) for k in subtree)
        if mass == 0 and inertia == 0:
            raise ModelError(f"{source}: link {child_link(jid)!r} (moved by joint {pmodel.names[jid]!r}) and "
                             "everything it carries have no mass and no inertia: the mass matrix is singular "
                             "(give the link an <inertial>)")
    data = pmodel.createData()
    rng = np.random.default_rng(seed)
    singular = None
    for _ in range(states):
        q = pin.randomConfiguration(pmodel, -np.ones(pmodel.nq), np.ones(pmodel.nq)) if pmodel.nq else pin.neutral(pmodel)
        q = np.where(np.isfinite(q), q, rng.uniform(-1, 1, pmodel.nq))
        M = pin.crba(pmodel, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        w, v = np.linalg.eigh(M)
        if regular_spectrum(w):
            return
        singular = v[:, 0]
    if singular is not None:
        idx = int(np.argmax(np.abs(singular)))
        jid = next(j for j in range(1, pmodel.njoints)
                   if pmodel.joints[j].idx_v <= idx < pmodel.joints[j].idx_v + pmodel.joints[j].nv)
        raise ModelError(f"{source}: the mass matrix is singular at {states} random states: a motion of joint "
                         f"{pmodel.names[jid]!r} (link {child_link(jid)!r}) moves no mass (give it an <inertial> "
                         "with mass and inertia)")


def moving_joints(model: pin.Model, free: str | None = None) -> list[str]:
    """Names of the 1-dof joints (revolute, continuous, prismatic) of a Pinocchio model, in tree order, the
    free-flyer joint ``free`` left out (a :class:`ModelError` for any other joint: only 1-dof joints are
    compared)."""
    names = []
    for jid in range(1, model.njoints):
        if free is not None and model.names[jid] == free:
            continue
        if model.joints[jid].nv != 1:
            raise ModelError(f"joint {model.names[jid]}: only 1-dof joints are compared "
                             f"({model.joints[jid].shortname()})")
        names.append(model.names[jid])
    return names


def _read_only(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a


MIRRORED_ONE_BY_ONE = 10   # lower-triangle elements of M that _crba mirrors one by one (nv <= 5), else by indexing


class PinocchioModel(TreeEngine):
    """A Pinocchio model of one :class:`NumericTree` with the index maps to our joint order."""

    name, reads = "pinocchio", "URDF"
    natively = frozenset({"kkt constraints"})
    free: str | None = None
    """The free-flyer joint of a floating base (:meth:`loaded` with ``free``), else None."""
    springs_or_dampers = False
    """Whether the tree has a spring or a damper (a tendon, a joint spring or damper) to evaluate."""
    dampers = False
    """Whether the tree has a damper (of a tendon, of a joint): without one ``f_damper`` stays 0, not added to ``τ``."""
    force_free = False
    """Whether the tree has no force element (spring, damper, input) to evaluate: ``τ`` is 0 without loads."""

    def __init__(self, tree: NumericTree, urdf: str | None = None):
        self.tree = tree
        model = pin.buildModelFromXML(urdf if urdf is not None else exported_urdf(tree))
        model.gravity.linear = np.asarray(tree.gravity, dtype=float)
        for j in tree.joints:  # URDF has no rotor inertia: Pinocchio's armature is set from the model
            if j.armature:
                model.armature[model.joints[model.getJointId(j.name)].idx_v] = j.armature
        if model.nq != model.nv:
            raise EngineError(f"{tree.system}: Pinocchio model has nq != nv (continuous joints?)")
        self._attach(model, [j.name for j in tree.joints])
        self.frames = {p.name: model.getFrameId(p.name) for p in tree.points}
        # a point on no joint (the world's): its placement is its frame's own and its Jacobian zero, read once
        pin.framesForwardKinematics(model, self.data, pin.neutral(model))
        self._fixed = {name: (_read_only(self.data.oMf[f].translation.copy()), _read_only(np.zeros((3, model.nv))))
                       for name, f in self.frames.items() if model.frames[f].parentJoint == 0}
        self.springs_or_dampers = bool(tree.tendons or tree.joint_stiffness or tree.joint_damping)
        self.dampers = bool(tree.joint_damping) or any(t[5] is not None for t in tree.tendons)
        self.force_free = not (self.springs_or_dampers or tree.actuators)

    @classmethod
    def loaded(cls, model: pin.Model, joints: list[str], free: str | None = None) -> "PinocchioModel":
        """A model Pinocchio has loaded (a URDF of other origin), seen through ``joints`` (revolute, prismatic;
        continuous as cos/sin) and, with ``free``, its free-flyer joint of that name: the views' vectors are
        then the free flyer's six velocities (Pinocchio's own convention, a :class:`~harness.engines.base.Base`)
        followed by ``joints``."""
        self = cls.__new__(cls)
        self._attach(model, list(joints))
        self.frames, self._fixed = {}, {}
        if free is not None:
            if not model.existJointName(free):
                raise EngineError(f"joint {free} missing in the Pinocchio model")
            self.free_id = model.getJointId(free)
            if model.joints[self.free_id].shortname() != "JointModelFreeFlyer":
                raise EngineError(f"joint {free!r} of the Pinocchio model is not a free flyer")
            self.free = free
        return self

    def _attach(self, model: pin.Model, joints: list[str]) -> None:
        self.model, self.joints = model, joints
        self._subtrees_of: dict | None = None   # :meth:`_subtrees`
        self._link_frames: dict = {}            # :meth:`_frame_of`
        self.data = model.createData()
        self.model_no_gravity = model.copy()
        self.model_no_gravity.gravity.linear = np.zeros(3)
        self.data_no_gravity = self.model_no_gravity.createData()
        self.jids = []
        for name in joints:
            if not model.existJointName(name):
                raise EngineError(f"{self.label + ': ' if self.tree else ''}joint {name} missing in the Pinocchio "
                                  "model")
            self.jids.append(model.getJointId(name))
        self.index = [model.joints[jid].idx_v for jid in self.jids]
        self._index_grid = np.ix_(self.index, self.index)   # from_pin_matrix's rows and columns
        self._lower = np.tril_indices(model.nv, -1)         # what _crba mirrors from the upper triangle
        # ... one element at a time where that is cheaper than fancy indexing (1.6 µs; an element 0.1 µs)
        self._lower_pairs = tuple(zip(*self._lower)) if model.nv * (model.nv - 1) // 2 <= MIRRORED_ONE_BY_ONE else None
        self.v_index = dict(zip(joints, self.index))
        self.continuous = any(model.joints[jid].nq == 2 for jid in self.jids)
        # Pinocchio's configuration and velocity hold our θ, θ̇ in their order: to_pin and from_pin copy, no scatter
        self._in_order = self.index == list(range(model.nv)) and model.nq == model.nv

    # ----- coordinates
    def to_pin(self, theta):
        """Pinocchio's vector (``q`` without continuous joints, ``v``, ``τ``) of ours, for Pinocchio to read: ours
        as it is where the order is the same (``_in_order``), else scattered into zeros (0.9 µs a call)."""
        if self._in_order:
            return np.asarray(theta, dtype=float)
        v = np.zeros(self.model.nv)
        v[self.index] = theta
        return v

    def to_q(self, theta):
        """The configuration of ``θ``: :meth:`to_pin`, a continuous joint as ``(cos θ, sin θ)``."""
        if not self.continuous:
            return self.to_pin(theta)
        q = pin.neutral(self.model)
        for jid, th in zip(self.jids, theta):
            jm = self.model.joints[jid]
            if jm.nq == 2:
                q[jm.idx_q:jm.idx_q + 2] = np.cos(th), np.sin(th)
            else:
                q[jm.idx_q] = th
        return q

    def from_pin(self, v):
        """Ours of Pinocchio's vector: always a copy (``pin.aba`` returns a view of its ``data.ddq``)."""
        return np.array(v, dtype=float) if self._in_order else np.asarray(v)[self.index]

    def from_pin_matrix(self, A):
        """Ours of Pinocchio's matrix: a copy, its rows and columns in our order."""
        return np.array(A, dtype=float) if self._in_order else np.asarray(A)[self._index_grid]

    def frame_jacobian(self, frame: int) -> np.ndarray:
        """``6 x nv`` frame Jacobian (LOCAL_WORLD_ALIGNED); eigenpy hands a ``6 x 1`` matrix back as a 1-D array."""
        return np.asarray(pin.getFrameJacobian(self.model, self.data, frame, LWA)).reshape(6, self.model.nv)

    # ----- forces from Pinocchio's frames and Jacobians
    def _frames(self, q) -> None:
        """The frames' placements and Jacobians at ``q`` (``computeJointJacobians``, which places the joints, then
        ``updateFramePlacements``): what a force acting at a point needs, a tendon or an external load."""
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)

    def point_forces(self, q, v):
        """Generalized forces of tendons (springs/dampers between points) and joint springs/dampers,
        from Pinocchio's frame placements and frame Jacobians: ``Σ J_bᵀ f − J_aᵀ f``. The frames are computed
        only for a tree with tendons (joint springs and dampers act on ``q``, ``v`` alone)."""
        model, data = self.model, self.data
        if not self.springs_or_dampers:
            zero = np.zeros(model.nv)   # no spring or damper in the tree (a pruned one): nothing to evaluate
            return zero, zero
        if self.tree.tendons:
            self._frames(q)
        return spring_damper_forces(self.tree, model.nv, q, v, self._position, self._point_jacobian, self.v_index,
                                    self.v_index)

    def _position(self, point: str) -> np.ndarray:
        """A point's position in world axes (after :meth:`_frames`); a point of the world's, read once."""
        fixed = self._fixed.get(point)
        return fixed[0] if fixed is not None else self.data.oMf[self.frames[point]].translation

    def _point_jacobian(self, point: str) -> np.ndarray:
        """A point's ``3 x nv`` translational Jacobian (LOCAL_WORLD_ALIGNED, after :meth:`_frames`); 0 for a point of
        the world's."""
        fixed = self._fixed.get(point)
        return fixed[1] if fixed is not None else self.frame_jacobian(self.frames[point])[:3]

    def input_forces(self, q, u: dict, loads=()):
        """Inputs on joints, and external forces/torques by (5.73) with Pinocchio's frame Jacobians
        (call after :meth:`point_forces`, which computes the frames at ``q`` of a tree with tendons)."""
        model, data = self.model, self.data
        if loads and not self.tree.tendons:
            self._frames(q)
        return input_forces(self.tree, model.nv, u, loads, self.v_index,
                            lambda link: data.oMf[self._frame_of(link)].rotation, self._point_jacobian,
                            lambda link: self.frame_jacobian(self._frame_of(link))[3:])

    def _frame_of(self, link: str) -> int:
        """The id of a link's body frame, looked up once (``model.getFrameId`` searches the names)."""
        if link not in self._link_frames:
            self._link_frames[link] = self.model.getFrameId(link)
        return self._link_frames[link]

    def _applied(self, q, v, u: dict, loads=()) -> tuple:
        """``(f_spring, f_damper, τ_input)`` in Pinocchio's order: the force elements' generalized forces
        (:meth:`point_forces`, then :meth:`input_forces`, which reuses the frames the first computed); zeros,
        nothing evaluated, for a tree without force elements and loads (:attr:`force_free`: a pruned one)."""
        if self.force_free and not loads:
            zero = np.zeros(self.model.nv)
            return zero, zero, zero
        f_spring, f_damper = self.point_forces(q, v)
        return f_spring, f_damper, self.input_forces(q, u, loads)

    def _aba(self, q, v, u: dict, loads=()) -> tuple:
        """``(θ̈, f_spring, f_damper, τ_input)`` in Pinocchio's order: ``pin.aba`` with ``τ`` = inputs + springs +
        dampers (:meth:`_applied`, :meth:`_tau`). ``θ̈`` is a view of Pinocchio's ``data.ddq``, which the next
        ``pin.aba`` overwrites: both callers take it through :meth:`from_pin`, which copies, before any other call."""
        f_spring, f_damper, tau_input = self._applied(q, v, u, loads)
        return pin.aba(self.model, self.data, q, v, self._tau(f_spring, f_damper, tau_input)), f_spring, f_damper, \
            tau_input

    def _tau(self, f_spring, f_damper, tau_input):
        """``τ`` = inputs + springs + dampers; the inputs and loads alone, no sum of zeros formed, in a tree without
        springs and dampers (:attr:`springs_or_dampers`: a pruned one; ``τ`` = 0 itself where :attr:`force_free`),
        no damper's where the tree has none (:attr:`dampers`). The same ``τ`` bit for bit (``x + 0 = x``)."""
        if not self.springs_or_dampers:
            return tau_input
        return tau_input + f_spring + f_damper if self.dampers else tau_input + f_spring

    def forward_dynamics(self, theta, theta_dot, u: dict, loads=()) -> np.ndarray:
        """``θ̈`` alone, the call a simulation makes (:meth:`_aba`)."""
        return self.from_pin(self._aba(self.to_pin(theta), self.to_pin(theta_dot), u, loads)[0])

    def mass_and_forces(self, theta, theta_dot, u: dict, loads=(), acceleration=None) -> tuple[np.ndarray, np.ndarray]:
        """``(M, h)``: ``pin.crba`` and ``h`` = inputs + springs + dampers − ``pin.nonLinearEffects`` (``C θ̇ + g``),
        the two calls a map with more tree joints than lecture coordinates needs (no ``pin.aba``, no gravity
        apart); with ``acceleration`` ``a``, ``h − M a`` (:meth:`TreeEngine.mass_and_forces`) by ``pin.rnea``
        (``M a + C θ̇ + g``) in place of ``pin.nonLinearEffects``. Both arrays are this call's own (no copy)."""
        q, v = self.to_pin(theta), self.to_pin(theta_dot)
        M = self._crba(q)
        f_spring, f_damper, tau_input = self._applied(q, v, u, loads)
        bias = pin.nonLinearEffects(self.model, self.data, q, v) if acceleration is None else \
            pin.rnea(self.model, self.data, q, v, self.to_pin(acceleration))
        h = self._tau(f_spring, f_damper, tau_input) - bias
        return (M, h) if self._in_order else (M[self._index_grid], h[self.index])

    def _crba(self, q) -> np.ndarray:
        """``pin.crba`` fills the upper triangle: the symmetric ``M`` in Pinocchio's order."""
        M = np.array(pin.crba(self.model, self.data, q))
        if self._lower_pairs is None:
            M[self._lower] = M.T[self._lower]
        else:
            for i, j in self._lower_pairs:
                M[i, j] = M[j, i]
        return M

    def quantities(self, theta, theta_dot, u: dict, loads=(), christoffel: bool = True) -> TreeQuantities:
        """Everything in tree coordinates; ``christoffel=False`` skips the two Coriolis matrices (for
        simulation, where only the forward dynamics is needed)."""
        model, data = self.model, self.data
        q, v = self.to_pin(theta), self.to_pin(theta_dot)
        M = self._crba(q)
        g_gravity = pin.computeGeneralizedGravity(model, data, q).copy()
        Cqd = pin.nonLinearEffects(model, data, q, v) - g_gravity
        extra, C_christoffel = {"Cqd_subtracted": float(np.abs(g_gravity).max(initial=0.0))}, None
        if christoffel:
            extra["C_coriolis_matrix"] = self.from_pin_matrix(pin.computeCoriolisMatrix(model, data, q, v))
            _, dtau_dv, _ = pin.computeRNEADerivatives(self.model_no_gravity, self.data_no_gravity, q, v,
                                                       np.zeros(model.nv))
            C_christoffel = self.from_pin_matrix(0.5 * np.asarray(dtau_dv))
        qdd, f_spring, f_damper, tau_input = self._aba(q, v, u, loads)
        return TreeQuantities(
            M=self.from_pin_matrix(M), Cqd=self.from_pin(Cqd), g_gravity=self.from_pin(g_gravity),
            g_spring=-self.from_pin(f_spring), f_damper=self.from_pin(f_damper),
            tau_input=self.from_pin(tau_input), qdd=self.from_pin(qdd),
            C=C_christoffel, extra=extra,
            calls={"M": "pin.crba", "Cqd": "pin.nonLinearEffects - pin.computeGeneralizedGravity",
                   "g": "pin.computeGeneralizedGravity + frame-Jacobian springs",
                   "C": "0.5 * pin.computeRNEADerivatives(g=0, a=0).dtau_dv",
                   "C_coriolis_matrix": "pin.computeCoriolisMatrix",
                   "f_damper": "frame-Jacobian dampers (pin.computeJointJacobians), joint dampers",
                   "qdd": "pin.aba(tau = inputs + springs + dampers)"})

    def evaluate(self, state: State):
        t = self.quantities(state.theta, state.theta_dot, state.u, state.loads)
        evaluation = to_lecture(self.name, state, t)
        evaluation.extra["C_coriolis_matrix"] = coriolis_to_lecture(state, t.M, t.extra["C_coriolis_matrix"])
        return evaluation

    # ----- a tree of other origin (harness.files.importer): M, bias, what each joint moves
    @property
    def view_index(self) -> list[int]:
        """Pinocchio's velocity indices in the order of the views' vectors: the free flyer's six, then joints."""
        head = []
        if self.free:
            iv = self.model.joints[self.free_id].idx_v
            head = list(range(iv, iv + 6))
        return head + list(self.index)

    def _q_v(self, theta, theta_dot, base: Base | None = None):
        """Pinocchio's ``(q, v)`` at ``θ``, ``θ̇`` (other joints at their neutral position) and, with a free
        flyer, the base state ``base`` (at rest at the origin when None)."""
        if not self.free:
            return self.to_q(theta), self.to_pin(theta_dot)
        q, v = pin.neutral(self.model), np.zeros(self.model.nv)
        for jid, th, thd in zip(self.jids, theta, theta_dot):
            jm = self.model.joints[jid]
            if jm.nq == 2:
                q[jm.idx_q:jm.idx_q + 2] = np.cos(th), np.sin(th)
            else:
                q[jm.idx_q] = th
            v[jm.idx_v] = thd
        base = base or Base.rest()
        jm = self.model.joints[self.free_id]
        q[jm.idx_q:jm.idx_q + 7] = np.concatenate([base.position, base.quat_xyzw])
        v[jm.idx_v:jm.idx_v + 6] = base.velocity
        return q, v

    def terms(self, theta, theta_dot, base: Base | None = None, forward: bool = True) -> dict:
        """``M`` (``pin.crba``), the bias ``C θ̇ + g`` (``pin.nonLinearEffects``); with ``forward`` also ``g``
        (``pin.computeGeneralizedGravity``), ``Cqd`` = bias − g and ``qdd`` (``pin.aba`` with zero torque), in
        the views' order (:attr:`view_index`)."""
        model, data = self.model, self.data
        q, v = self._q_v(theta, theta_dot, base)
        idx = self.view_index
        out = {"M": self._crba(q)[np.ix_(idx, idx)], "bias": np.asarray(pin.nonLinearEffects(model, data, q, v))[idx]}
        if forward:
            out["g"] = np.asarray(pin.computeGeneralizedGravity(model, data, q))[idx]
            out["Cqd"] = out["bias"] - out["g"]
            out["qdd"] = np.asarray(pin.aba(model, data, q, v, np.zeros(model.nv)))[idx]
        return out

    def mass_and_bias(self, theta, theta_dot, base: Base | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``M`` (``pin.crba``) and the bias ``C θ̇ + g`` (``pin.nonLinearEffects``) at ``θ`` (other joints at
        their neutral position), in the order of ``joints`` (after the free flyer's six, with one)."""
        t = self.terms(theta, theta_dot, base, forward=False)
        return t["M"], t["bias"]

    def subtree_parts(self, theta, base: Base | None = None) -> dict[str, list]:
        """Per joint (and the free flyer), the ``(mass, centre of mass, inertia tensor about it)`` of every body
        it moves, world axes (``pin.forwardKinematics``, ``model.subtrees``)."""
        q, _ = self._q_v(theta, np.zeros(len(theta)), base)
        pin.forwardKinematics(self.model, self.data, q)
        subtrees = self._subtrees()
        world = {}   # each body once, not per joint that moves it: a chain of n bodies costs n, not n²
        for k in sorted({k for bodies in subtrees.values() for k in bodies}):
            placed = self.data.oMi[k].act(self.model.inertias[k])
            R = self.data.oMi[k].rotation
            world[k] = (float(placed.mass), np.array(placed.lever), R @ np.array(self.model.inertias[k].inertia) @ R.T)
        return {name: [world[k] for k in bodies] for name, bodies in subtrees.items()}

    def _subtrees(self) -> dict[str, list[int]]:
        """Per joint (and the free flyer), the bodies it moves (``model.subtrees``: the same at every state; read
        once per model)."""
        if self._subtrees_of is None:
            named = list(zip(self.joints, self.jids)) + ([(self.free, self.free_id)] if self.free else [])
            self._subtrees_of = {name: [int(k) for k in self.model.subtrees[jid]] for name, jid in named}
        return self._subtrees_of

    def loaded_facts(self) -> dict:
        """What Pinocchio built from a URDF of other origin: joints, nq, nv, body frames, total mass."""
        m = self.model
        return {"joints": m.njoints - 1, "nq": m.nq, "nv": m.nv,
                "bodies (frames)": sum(f.type == pin.FrameType.BODY for f in m.frames),
                "mass": round(sum(m.inertias[i].mass for i in range(m.njoints)), 9)}

    def body_names(self) -> list[str]:
        return [f.name for f in self.model.frames if f.type == pin.FrameType.BODY]

    @property
    def prismatic(self) -> set[str]:
        """The names of the prismatic joints among :attr:`joints` (their positions are lengths, not angles)."""
        return {name for name, jid in zip(self.joints, self.jids)
                if self.model.joints[jid].shortname().startswith("JointModelP")}

    def facts(self) -> dict:
        """What Pinocchio loaded: joints, degrees of freedom and the moving mass."""
        m = self.model
        return {"joints": m.njoints - 1, "dof": m.nv,
                "moving mass": f"{sum(m.inertias[i].mass for i in range(1, m.njoints)):.6g} kg"}

    @property
    def gravity(self) -> np.ndarray:
        return np.asarray(self.model.gravity.linear)

    # ----- the export round trip (harness.compare.roundtrip): the URDF as loaded
    @property
    def dofs(self) -> int:
        return self.model.nv

    def _joint_name(self, jid: int) -> str | None:
        return None if jid == 0 else self.model.names[jid]

    def _body_frame(self, name):
        m = self.model
        return m.frames[m.getFrameId(name, pin.FrameType.BODY)] if m.existFrame(name, pin.FrameType.BODY) else None

    def link_as_loaded(self, name: str) -> dict | None:
        """A link's moving joint (None: the world), its frame relative to the joint frame (3 x 4), mass, centre
        of mass and inertia tensor about it in the link frame: ``model.inertias`` of the joint, which in our trees
        carries exactly that one link."""
        frame = self._body_frame(name)
        if frame is None:
            return None
        inertia = self.model.inertias[frame.parentJoint]
        return {"joint": self._joint_name(frame.parentJoint), "frame": frame.placement.homogeneous[:3],
                "mass": inertia.mass, "inertia": inertia.inertia, "com": inertia.lever}

    def joint_as_loaded(self, name: str) -> dict | None:
        """A joint's parent joint, type, axis (joint frame), placement in the parent joint's frame."""
        m = self.model
        if not m.existJointName(name):
            return None
        jid = m.getJointId(name)
        kind, axis = _joint_axis(m.joints[jid])
        placement = m.jointPlacements[jid]
        return {"parent": self._joint_name(m.parents[jid]), "type": kind, "axis": axis,
                "origin": placement.translation, "rotation": placement.rotation}

    def point_as_loaded(self, name: str) -> dict | None:
        """A point's moving joint and its position in that joint's (= its link's) frame."""
        frame = self._body_frame(name)
        if frame is None:
            return None
        return {"joint": self._joint_name(frame.parentJoint), "position": frame.placement.translation}

    # ----- what a benchmark times: the raw calls at one state
    def kernels(self, theta, theta_dot) -> dict:
        """Zero-argument calls at ``(θ, θ̇)``: ``crba`` (M), ``nonLinearEffects`` (C θ̇ + g),
        ``computeGeneralizedGravity`` (g), ``aba`` (θ̈ with τ = 0); each returns the engine's own array."""
        model, data = self.model, self.data
        q, v, tau = self.to_pin(theta), self.to_pin(theta_dot), np.zeros(self.model.nv)
        return {"M": lambda: pin.crba(model, data, q), "nle": lambda: pin.nonLinearEffects(model, data, q, v),
                "g": lambda: pin.computeGeneralizedGravity(model, data, q),
                "qdd": lambda: pin.aba(model, data, q, v, tau)}

    # ----- closed chains and couplings (harness.scenes.phenomena.closures)
    def constraints(self, couplings, closures) -> "Constraints":
        return Constraints(self, couplings, closures)


_PIN_ALIGNED = re.compile(r"JointModel([RP])([XYZ])")
_PIN_UNALIGNED = {"JointModelRevoluteUnaligned": "revolute", "JointModelPrismaticUnaligned": "prismatic"}


def _joint_axis(joint) -> tuple[str, list]:
    """(type, axis) of a Pinocchio joint: axis-aligned joints (``JointModelRZ``, ``JointModelPX``) carry the
    axis in their type, unaligned ones (URDF axes that are not +x/+y/+z, e.g. -z) in ``.axis``. Any other
    joint model (e.g. ``JointModelRUBZ`` for a continuous joint) is reported by its name, without axis."""
    name = joint.shortname()
    if match := _PIN_ALIGNED.fullmatch(name):
        return ("revolute" if match[1] == "R" else "prismatic"), np.eye(3)["XYZ".index(match[2])].tolist()
    if name in _PIN_UNALIGNED:
        return _PIN_UNALIGNED[name], np.asarray(joint.extract().axis, dtype=float).tolist()
    return name, []


class Constraints:
    """Couplings ``θ_d = offset + ratio θ_i`` (``(dependent, independent, offset, ratio)``) and closures (a point
    held on a plane, ``(point, normal, value)``: ``nᵀ p = value``) as rows of the constraint Jacobian of
    Pinocchio's KKT forward dynamics ``pin.forwardDynamics(model, data, q, v, τ, J, γ)``
    (``M a + b = τ + Jᵀλ``, ``J a + γ = 0``). A closure's row is ``nᵀ J_point`` of the point's frame Jacobian, its
    drift ``nᵀ a_point(q, v, 0)`` from ``pin.getFrameClassicalAcceleration``: Pinocchio's own kinematics."""

    def __init__(self, pm: PinocchioModel, couplings, closures):
        self.pm = pm
        model = pm.model
        self.rows = []
        for dependent, independent, offset, ratio in couplings:
            row = np.zeros(model.nv)
            row[pm.v_index[dependent]], row[pm.v_index[independent]] = 1.0, -ratio
            self.rows.append((row, offset))
        self.closures = [(model.getFrameId(point), np.array(normal, dtype=float), value)
                         for point, normal, value in closures]

    def residual(self, q, v):
        """``c``, ``J`` and ``J̇ v`` at the Pinocchio state (kinematics computed here), in Pinocchio's order."""
        pm = self.pm
        model, data = pm.model, pm.data
        c, J, drift = [], [], []
        for row, offset in self.rows:
            c.append(row @ q - offset)
            J.append(row)
            drift.append(0.0)
        if self.closures:
            pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
            pin.computeJointJacobians(model, data, q)
            pin.updateFramePlacements(model, data)
            for fid, n, value in self.closures:
                c.append(n @ data.oMf[fid].translation - value)
                J.append(n @ pm.frame_jacobian(fid)[:3])
                drift.append(n @ pin.getFrameClassicalAcceleration(model, data, fid, LWA).linear)
        return np.array(c), np.array(J).reshape(len(c), model.nv), np.array(drift)

    def forward_dynamics(self, theta, theta_dot, u: dict, loads, omega: float) -> np.ndarray:
        """``θ̈`` of the constrained tree with Baumgarte stabilization ``γ = J̇ v + 2 ω ċ + ω² c``; without rows
        (the open tree, its constraints proved inactive) ``pin.aba``."""
        pm = self.pm
        q, v = pm.to_pin(theta), pm.to_pin(theta_dot)
        f_spring, f_damper = pm.point_forces(q, v)
        tau = pm.input_forces(q, u, loads) + f_spring + f_damper
        if not self.rows and not self.closures:  # the open tree: no rows, Pinocchio's ABA
            return pm.from_pin(pin.aba(pm.model, pm.data, q, v, tau))
        c, J, drift = self.residual(q, v)
        gamma = drift + 2 * omega * (J @ v) + omega * omega * c
        return pm.from_pin(pin.forwardDynamics(pm.model, pm.data, q, v, tau, J, gamma))

    def violation(self, theta, theta_dot, theta_scale) -> tuple[np.ndarray, np.ndarray]:
        """``|c|`` and the scale of the terms forming each constraint, ``Σ_j |∂c/∂θ_j| theta_scale_j``."""
        pm = self.pm
        c, J, _ = self.residual(pm.to_pin(theta), pm.to_pin(theta_dot))
        return np.abs(c), np.abs(J) @ pm.to_pin(theta_scale)
