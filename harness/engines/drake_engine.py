"""Drake, loading our URDF into a continuous ``MultibodyPlant`` (``time_step = 0``: forward dynamics by the
articulated-body algorithm, no joint limits). Every number comes from a named Drake call:

* ``M = CalcMassMatrix`` (rotor inertia included: a URDF has none, so each joint with armature gets a
  ``JointActuator`` with that rotor inertia and gear ratio 1, whose reflected inertia Drake adds to ``M``);
* ``C θ̇ = CalcBiasTerm`` (Coriolis, centrifugal, gyroscopic: no gravity);
* ``g = −CalcGravityGeneralizedForces`` (Drake returns the gravity force on the right-hand side);
* the Christoffel ``C`` by polarization of ``CalcBiasTerm``, which is exactly quadratic in ``v``
  (:func:`~harness.engines.base.polarization`);
* springs, dampers, inputs and external loads from Drake's own kinematics like the Pinocchio adapter does
  (:func:`~harness.engines.base.spring_damper_forces`, :func:`~harness.engines.base.input_forces`): point positions
  ``CalcPointsPositions``, Jacobians ``CalcJacobianTranslationalVelocity`` / ``CalcJacobianAngularVelocity``, link
  rotations ``CalcRelativeRotationMatrix``. The URDF's joint damping, which Drake would apply itself, is zeroed:
  the dampers are formed from the engine's Jacobians like every other force;
* ``θ̈`` from the generalized-acceleration output port with the applied generalized force (inputs + springs +
  dampers) on its input port.

Joints are mapped by name (``position_start``, ``velocity_start``): Drake orders the joints of a branched tree
differently from Pinocchio. The parser is strict: a warning about our URDF is an error, never console output."""

from __future__ import annotations

import numpy as np
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import BodyIndex, JacobianWrtVariable

from harness.engines.base import Base, TreeEngine, TreeQuantities, input_forces, polarization, spring_damper_forces
from harness.errors import EngineError
from harness.export.numeric import NumericTree
from harness.export.urdf import exported_urdf

_V = JacobianWrtVariable.kV


class DrakeModel(TreeEngine):
    """A Drake ``MultibodyPlant`` of one :class:`NumericTree` with the index maps to our joint order."""

    name, reads = "drake", "URDF"

    def __init__(self, tree: NumericTree, urdf: str | None = None):
        self.tree = tree
        self.plant = plant = MultibodyPlant(time_step=0.0)
        parser = Parser(plant)
        parser.SetStrictParsing()
        try:
            parser.AddModelsFromString(urdf if urdf is not None else exported_urdf(tree), "urdf")
        except RuntimeError as exc:
            raise EngineError(f"{tree.system}: Drake refused the URDF: {exc}") from None
        plant.mutable_gravity_field().set_gravity_vector(np.asarray(tree.gravity, dtype=float))
        self.joints = [j.name for j in tree.joints]
        for j in tree.joints:
            if not plant.HasJointNamed(j.name):
                raise EngineError(f"{tree.system}: joint {j.name} missing in the Drake model")
            joint = plant.GetMutableJointByName(j.name)
            joint.set_default_damping(0.0)   # dampers come from Drake's Jacobians (tree.joint_damping)
            if j.armature:                    # rotor inertia: a URDF has none
                rotor = plant.AddJointActuator(f"{j.name}_rotor", joint)
                rotor.set_default_rotor_inertia(j.armature)
                rotor.set_default_gear_ratio(1.0)
        plant.Finalize()
        if plant.num_positions() != plant.num_velocities():
            raise EngineError(f"{tree.system}: Drake model has nq != nv")
        self.context = plant.CreateDefaultContext()
        self.context_bias = plant.CreateDefaultContext()   # the polarization's states
        joints = [plant.GetJointByName(name) for name in self.joints]
        self.q_index = {j.name(): j.position_start() for j in joints}
        self.v_index = {j.name(): j.velocity_start() for j in joints}
        self.iq, self.iv = [self.q_index[n] for n in self.joints], [self.v_index[n] for n in self.joints]
        self.world = plant.world_frame()
        self.frames = {p.name: plant.GetBodyByName(p.name).body_frame() for p in tree.points}

    # ----- coordinates
    def to_q(self, theta):
        q = np.zeros(self.plant.num_positions())
        q[self.iq] = theta
        return q

    def to_v(self, theta_dot):
        v = np.zeros(self.plant.num_velocities())
        v[self.iv] = theta_dot
        return v

    def from_v(self, x):
        return np.asarray(x)[self.iv]

    def _set(self, context, theta, theta_dot):
        q, v = self.to_q(theta), self.to_v(theta_dot)
        self.plant.SetPositions(context, q)
        self.plant.SetVelocities(context, v)
        return q, v

    # ----- Drake's kinematics
    def _position(self, point: str) -> np.ndarray:
        return self.plant.CalcPointsPositions(self.context, self.frames[point], np.zeros(3), self.world).ravel()

    def _jacobian(self, frame) -> np.ndarray:
        return self.plant.CalcJacobianTranslationalVelocity(self.context, _V, frame, np.zeros(3), self.world,
                                                            self.world)

    def _angular(self, link: str) -> np.ndarray:
        frame = self.plant.GetBodyByName(link).body_frame()
        return self.plant.CalcJacobianAngularVelocity(self.context, _V, frame, self.world, self.world)

    def _rotation(self, link: str) -> np.ndarray:
        frame = self.plant.GetBodyByName(link).body_frame()
        return self.plant.CalcRelativeRotationMatrix(self.context, self.world, frame).matrix()

    def _forces(self, q, v, u: dict, loads):
        """``(f_spring, f_damper, τ_input)`` in Drake's order, at the state of ``self.context``."""
        nv = self.plant.num_velocities()
        f_spring, f_damper = spring_damper_forces(self.tree, nv, q, v, self._position,
                                                  lambda p: self._jacobian(self.frames[p]), self.q_index,
                                                  self.v_index)
        tau_input = input_forces(self.tree, nv, u, loads, self.v_index, self._rotation,
                                 lambda p: self._jacobian(self.frames[p]), self._angular)
        return f_spring, f_damper, tau_input

    def _acceleration(self, tau) -> np.ndarray:
        """``θ̈`` (Drake's order) from the generalized-acceleration output port with ``τ`` applied."""
        self.plant.get_applied_generalized_force_input_port().FixValue(self.context, tau)
        return np.asarray(self.plant.get_generalized_acceleration_output_port().Eval(self.context)).copy()

    def _bias(self, theta, theta_dot) -> np.ndarray:
        self._set(self.context_bias, theta, theta_dot)
        return self.from_v(self.plant.CalcBiasTerm(self.context_bias))

    def forward_dynamics(self, theta, theta_dot, u: dict, loads=()) -> np.ndarray:
        q, v = self._set(self.context, theta, theta_dot)
        f_spring, f_damper, tau_input = self._forces(q, v, u, loads)
        return self.from_v(self._acceleration(tau_input + f_spring + f_damper))

    def quantities(self, theta, theta_dot, u: dict, loads=(), christoffel: bool = True) -> TreeQuantities:
        plant, context = self.plant, self.context
        q, v = self._set(context, theta, theta_dot)
        M = plant.CalcMassMatrix(context)
        Cqd = plant.CalcBiasTerm(context)
        g_gravity = -plant.CalcGravityGeneralizedForces(context)
        f_spring, f_damper, tau_input = self._forces(q, v, u, loads)
        qdd = self._acceleration(tau_input + f_spring + f_damper)
        C = polarization(lambda w: self._bias(theta, w), theta_dot) if christoffel else None
        return TreeQuantities(
            M=np.asarray(M)[np.ix_(self.iv, self.iv)], Cqd=self.from_v(Cqd), g_gravity=self.from_v(g_gravity),
            g_spring=-self.from_v(f_spring), f_damper=self.from_v(f_damper), tau_input=self.from_v(tau_input),
            qdd=self.from_v(qdd), C=C,
            calls={"M": "CalcMassMatrix", "Cqd": "CalcBiasTerm",
                   "g": "-CalcGravityGeneralizedForces + springs from CalcPointsPositions, "
                        "CalcJacobianTranslationalVelocity",
                   "C": "polarization of CalcBiasTerm(v ± s e_j) / 4s",
                   "f_damper": "dampers from CalcJacobianTranslationalVelocity",
                   "qdd": "generalized acceleration output port (applied generalized force = inputs + springs + "
                          "dampers)"})

    # ----- the benchmarks' symbolic peer (harness.bench.lightweight_robot)
    def symbolic_terms(self) -> dict:
        """Drake's own symbolic path: ``MultibodyPlant.ToSymbolic()`` at symbolic ``q``, ``v`` (``MakeVectorVariable``),
        ``M = CalcMassMatrix``, ``C θ̇ = CalcBiasTerm``, ``τ_g = CalcGravityGeneralizedForces`` as Drake expressions in
        our joint order, with ``at(θ, θ̇)`` evaluating them (``pydrake.symbolic.Evaluate``) to ``(M, C θ̇, g = −τ_g)``."""
        from pydrake.symbolic import Evaluate, MakeVectorVariable

        plant = self.plant.ToSymbolic()
        context = plant.CreateDefaultContext()
        n = plant.num_velocities()
        qs, vs = MakeVectorVariable(n, "q"), MakeVectorVariable(n, "v")
        plant.SetPositions(context, qs)
        plant.SetVelocities(context, vs)
        M = plant.CalcMassMatrix(context)[np.ix_(self.iv, self.iv)]
        Cqd = plant.CalcBiasTerm(context)[self.iv]
        tau_g = plant.CalcGravityGeneralizedForces(context)[self.iv]   # the gravity force: -g

        def at(theta, theta_dot):
            env = {qs[i]: x for i, x in zip(self.iq, theta)} | {vs[i]: x for i, x in zip(self.iv, theta_dot)}
            return (Evaluate(M, env), Evaluate(Cqd.reshape(-1, 1), env).ravel(),
                    -Evaluate(tau_g.reshape(-1, 1), env).ravel())

        return {"M": M, "Cqd": Cqd, "tau_g": tau_g, "at": at}

    # ----- the export round trip (harness.compare.roundtrip): the URDF as loaded
    @property
    def dofs(self) -> int:
        return self.plant.num_velocities()

    def _inboard(self, body):
        """The joint whose child is ``body`` (None for the world body)."""
        plant = self.plant
        for index in plant.GetJointIndices():
            joint = plant.get_joint(index)
            if joint.child_body().index() == body.index():
                return joint
        return None

    def _carrier(self, body) -> str | None:
        """The moving joint that carries ``body`` (through welds; None: the world)."""
        joint = self._inboard(body)
        while joint is not None and joint.num_velocities() == 0:
            joint = self._inboard(joint.parent_body())
        return None if joint is None else joint.name()

    def link_as_loaded(self, name: str) -> dict | None:
        """A link's moving joint, its frame relative to the joint's frame on it (3 x 4), mass, centre of mass and
        inertia tensor about it in the link frame (``default_spatial_inertia`` shifted to the centre of mass)."""
        if not self.plant.HasBodyNamed(name):
            return None
        body = self.plant.GetBodyByName(name)
        joint = self._inboard(body)
        frame = np.eye(4)[:3] if joint is None else \
            joint.frame_on_child().GetFixedPoseInBodyFrame().inverse().GetAsMatrix34()
        com = body.default_com()
        kept = body.default_spatial_inertia()   # about the body origin (a unit inertia times the mass)
        return {"joint": self._carrier(body), "frame": frame, "mass": body.default_mass(),
                "inertia": kept.Shift(com).CalcRotationalInertia().CopyToFullMatrix3(), "com": com,
                "inertia_about_origin": kept.CalcRotationalInertia().CopyToFullMatrix3()}

    def joint_as_loaded(self, name: str) -> dict | None:
        """A joint's parent joint, type, axis, placement in the parent link (``frame_on_parent``)."""
        if not self.plant.HasJointNamed(name):
            return None
        joint = self.plant.GetJointByName(name)
        kind = joint.type_name()
        axis = joint.revolute_axis() if kind == "revolute" else \
            joint.translation_axis() if kind == "prismatic" else []
        pose = joint.frame_on_parent().GetFixedPoseInBodyFrame()
        return {"parent": self._carrier(joint.parent_body()), "type": kind, "axis": axis,
                "origin": pose.translation(), "rotation": pose.rotation().matrix()}

    def point_as_loaded(self, name: str) -> dict | None:
        """A point (a body welded to its link): its moving joint and its position in the link frame."""
        if not self.plant.HasBodyNamed(name):
            return None
        body = self.plant.GetBodyByName(name)
        weld = self._inboard(body)
        if weld is None:
            return None
        pose = weld.frame_on_parent().GetFixedPoseInBodyFrame().multiply(
            weld.frame_on_child().GetFixedPoseInBodyFrame().inverse())
        return {"joint": self._carrier(body), "position": pose.translation()}


# ------------------------------------------------------------------------------ a URDF of other origin
DUMMY_DENSITY = 1000.0
"""Drake's parser (``multibody/parsing/detail_common.cc``, ``ParseSpatialInertia``) replaces an inertia that fails
``CouldBePhysicallyValid()`` (a negative principal moment, moments violating A + B >= C) or that it cannot
re-express about the centre of mass (mass 0 with a non-zero tensor) by a solid sphere of this density (water)
about the inertial's origin, of the link's mass (1 kg when that is not positive), with a warning."""


def drake_dummy_inertia(mass: float) -> tuple[float, np.ndarray]:
    """The ``(mass, tensor about the centre of mass)`` Drake's parser substitutes (:data:`DUMMY_DENSITY`)."""
    m = mass if np.isfinite(mass) and mass > 0 else 1.0
    radius = np.cbrt(3.0 / (4.0 * np.pi) * m / DUMMY_DENSITY)
    return m, np.eye(3) * 0.4 * m * radius**2


class _Collect:
    """A ``logging.Handler`` stand-in collecting what pydrake's ``drake`` logger receives (parser warnings)."""

    def __init__(self):
        import logging

        self.records: list[str] = []
        self.handler = logging.Handler()
        self.handler.emit = lambda record: self.records.append(record.getMessage())

    def __enter__(self):
        import logging

        self.logger = logging.getLogger("drake")
        self.propagate = self.logger.propagate
        self.logger.addHandler(self.handler)
        self.logger.propagate = False
        return self.records

    def __exit__(self, *exc):
        self.logger.removeHandler(self.handler)
        self.logger.propagate = self.propagate
        return False


def load_urdf_plant(urdf_text: str, source: str, free: str | None = None,
                    gravity=None) -> tuple[MultibodyPlant, list[str]]:
    """A continuous ``MultibodyPlant`` of a URDF of other origin (lenient parsing: what the parser warns is
    returned, never printed), its root link welded to the world or, with ``free``, on a
    ``QuaternionFloatingJoint`` of that name, ``gravity`` as the reference's; joint damping set to 0 (Pinocchio's ``aba`` has none). A refusal
    is one :class:`EngineError` line."""
    from pydrake.multibody.tree import QuaternionFloatingJoint

    plant = MultibodyPlant(time_step=0.0)
    with _Collect() as said:
        try:
            instance = Parser(plant).AddModelsFromString(urdf_text, "urdf")[0]
            children = {plant.get_joint(j).child_body().index() for j in plant.GetJointIndices()}
            roots = [plant.get_body(b) for b in plant.GetBodyIndices(instance) if b not in children]
            if len(roots) > 1 or (free is not None and not roots):
                raise EngineError(f"{source}: Drake: {len(roots)} root links, one expected")
            if free is not None:
                plant.AddJoint(QuaternionFloatingJoint(free, plant.world_frame(), roots[0].body_frame()))
            elif roots:  # else the file's link "world" is Drake's world, its joint to the root already there
                plant.WeldFrames(plant.world_frame(), roots[0].body_frame())
            for j in plant.GetJointIndices():
                joint = plant.get_mutable_joint(j)
                if joint.num_velocities() == 1:
                    joint.set_default_damping(0.0)
            couplers = plant.GetConstraintIds()
            for cid in couplers:  # a <mimic>: a coupler constraint, which a continuous plant cannot hold
                plant.RemoveConstraint(cid)
            if couplers:
                said.append(f"{len(couplers)} coupler constraint(s) of <mimic> joints removed (a continuous "
                            "MultibodyPlant holds no constraints; Pinocchio's buildModel ignores <mimic> too)")
            if gravity is not None:
                plant.mutable_gravity_field().set_gravity_vector(np.asarray(gravity, dtype=float))
            plant.Finalize()
        except RuntimeError as exc:
            raise EngineError(f"{source}: Drake refused the URDF: {' '.join(str(exc).split())}") from None
    return plant, said


class DrakeImport:
    """A Drake plant of a URDF of other origin seen through the reference's joints (by name) and, with ``free``,
    its floating joint reported in Pinocchio's free-flyer convention (:class:`~harness.engines.base.Base`):
    Drake's ``QuaternionFloatingJoint`` has ``q = (w, x, y, z, p)`` and ``v = (ω, v)`` of the body origin in
    world axes, so ``v_drake = T v`` with ``T = [[0, R], [R, 0]]``; the quantities are mapped by virtual work
    like MuJoCo's free joint: ``M_v = Tᵀ M T``, ``bias_v = Tᵀ (bias + M Ṫ v)`` with ``Ṫ v = (0, R (ω × v))``,
    ``v̇ = T⁻¹ (v̇_drake − Ṫ v)``. Every number from a named Drake call: ``CalcMassMatrix``, ``CalcBiasTerm``,
    ``CalcGravityGeneralizedForces``, the generalized-acceleration output port (zero applied force)."""

    name = "drake"

    def __init__(self, plant: MultibodyPlant, joints: list[str], free: str | None = None):
        self.plant, self.joints, self.free = plant, list(joints), free
        self.context = plant.CreateDefaultContext()
        self.refusals: set[str] = set()
        """Drake's refusals of forward dynamics (a non-positive-definite articulated inertia), by message."""
        self._moved_bodies: dict | None = None   # :meth:`_moved`
        self._bodies: dict = {}
        missing = [j for j in joints if not plant.HasJointNamed(j)]
        if missing:
            raise EngineError(f"joint(s) {', '.join(missing)} missing in the Drake model")
        self.jobs = [plant.GetJointByName(j) for j in joints]
        self.iq = [j.position_start() for j in self.jobs]
        self.iv = [j.velocity_start() for j in self.jobs]
        self.base = Base.rest()
        if free is not None:
            fj = plant.GetJointByName(free)
            self.fq, self.fv = fj.position_start(), fj.velocity_start()
            self.free_joint = fj

    @property
    def view_dofs(self) -> list[int]:
        return (list(range(self.fv, self.fv + 6)) if self.free else []) + self.iv

    def _set(self, theta, theta_dot, base: Base | None = None) -> None:
        plant = self.plant
        q = plant.GetDefaultPositions().copy()
        v = np.zeros(plant.num_velocities())
        q[self.iq], v[self.iv] = theta, theta_dot
        if self.free:
            self.base = base = base or Base.rest()
            R = self._R()
            q[self.fq:self.fq + 4] = np.roll(base.quat_xyzw, 1)
            q[self.fq + 4:self.fq + 7] = base.position
            v[self.fv:self.fv + 3] = R @ base.velocity[3:]
            v[self.fv + 3:self.fv + 6] = R @ base.velocity[:3]
        plant.SetPositions(self.context, q)
        plant.SetVelocities(self.context, v)

    def _R(self) -> np.ndarray:
        from pydrake.common.eigen_geometry import Quaternion

        x, y, z, w = self.base.quat_xyzw
        return Quaternion(w, x, y, z).rotation()

    def _map(self):
        n = len(self.view_dofs)
        T, Tdot_v = np.eye(n), np.zeros(n)
        if self.free:
            R = self._R()
            T[:6, :6] = 0
            T[:3, 3:6] = R
            T[3:6, :3] = R
            Tdot_v[3:6] = R @ np.cross(self.base.velocity[3:], self.base.velocity[:3])
        return T, Tdot_v

    def terms(self, theta, theta_dot, base: Base | None = None, forward: bool = True) -> dict:
        try:
            return self._terms(theta, theta_dot, base, forward)
        except RuntimeError as exc:
            raise EngineError(f"Drake: {' '.join(str(exc).split())}") from None

    def _terms(self, theta, theta_dot, base: Base | None = None, forward: bool = True) -> dict:
        plant, context, idx = self.plant, self.context, self.view_dofs
        self._set(theta, theta_dot, base)
        M = np.asarray(plant.CalcMassMatrix(context))[np.ix_(idx, idx)]
        gravity = -np.asarray(plant.CalcGravityGeneralizedForces(context))[idx]
        bias = np.asarray(plant.CalcBiasTerm(context))[idx] + gravity
        T, Tdot_v = self._map()
        out = {"M": T.T @ M @ T, "bias": T.T @ (bias + M @ Tdot_v)}
        if not forward:
            return out
        plant.get_applied_generalized_force_input_port().FixValue(context, np.zeros(plant.num_velocities()))
        try:
            vdot = np.asarray(plant.get_generalized_acceleration_output_port().Eval(context))[idx]
        except RuntimeError as exc:  # a joint that moves no mass: Drake's ABA refuses, Pinocchio's is not finite
            if "is not positive-definite" not in str(exc):
                raise
            self.refusals.add(" ".join(str(exc).split()))
            vdot = np.full(len(idx), np.nan)
        out["qdd"] = np.linalg.solve(T, vdot - Tdot_v)
        out["g"] = T.T @ gravity
        out["Cqd"] = out["bias"] - out["g"]
        return out

    def mass_and_bias(self, theta, theta_dot, base: Base | None = None):
        t = self.terms(theta, theta_dot, base, forward=False)
        return t["M"], t["bias"]

    def subtree_parts(self, theta, base: Base | None = None) -> dict[str, list]:
        """Per joint (and the floating joint), ``(mass, centre of mass, inertia tensor about it)`` of every body
        it moves, world axes (``GetBodiesKinematicallyAffectedBy``, ``EvalBodyPoseInWorld``,
        ``default_spatial_inertia``)."""
        plant, context = self.plant, self.context
        self._set(theta, np.zeros(len(theta)), base)
        moved = self._moved()
        world = {}
        for b, (body, mass, com, I) in self._bodies.items():
            X = plant.EvalBodyPoseInWorld(context, body)
            R = X.rotation().matrix()
            world[b] = (mass, X.multiply(com), R @ I @ R.T)
        return {name: [world[b] for b in bodies] for name, bodies in moved.items()}

    def _moved(self) -> dict[str, list[int]]:
        """Per joint (and the floating joint), the bodies it moves (``GetBodiesKinematicallyAffectedBy``), and
        ``_bodies``: each one's mass, centre of mass and rotational inertia about it in its own frame
        (``default_spatial_inertia``); asked of the plant once: they do not depend on the state."""
        if self._moved_bodies is None:
            plant = self.plant
            named = list(zip(self.joints, self.jobs)) + ([(self.free, self.free_joint)] if self.free else [])
            self._moved_bodies = {name: [int(b) for b in plant.GetBodiesKinematicallyAffectedBy([joint.index()])]
                                  for name, joint in named}
            for b in sorted({b for bodies in self._moved_bodies.values() for b in bodies}):
                body = plant.get_body(BodyIndex(b))
                M = body.default_spatial_inertia()
                com = M.get_com()
                self._bodies[b] = (body, float(M.get_mass()), com,
                                   M.Shift(com).CalcRotationalInertia().CopyToFullMatrix3())
        return self._moved_bodies

    def body_names(self) -> list[str]:
        from pydrake.multibody.tree import BodyIndex

        return [self.plant.get_body(BodyIndex(i)).name() for i in range(1, self.plant.num_bodies())]

    @property
    def gravity(self) -> np.ndarray:
        return np.asarray(self.plant.gravity_field().gravity_vector())

    @property
    def dofs(self) -> int:
        return self.plant.num_velocities()

    def loaded_facts(self) -> dict:
        plant = self.plant
        from pydrake.multibody.tree import BodyIndex

        return {"bodies": plant.num_bodies() - 1, "nq": plant.num_positions(), "nv": plant.num_velocities(),
                "mass": round(sum(plant.get_body(BodyIndex(i)).default_mass() for i in range(1, plant.num_bodies())),
                              9)}
