"""Pinocchio, loading our URDF. Every number comes from a named Pinocchio call; springs, dampers and
inputs are evaluated from Pinocchio's own frames and Jacobians (``framesForwardKinematics``,
``computeFrameJacobian``), never from the symbolic model."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from harness.engines.base import State, TreeQuantities, coriolis_to_lecture, to_lecture
from harness.errors import EngineError
from harness.export.numeric import NumericTree
from harness.export.urdf import urdf_string
from harness.modeling.system import WORLD

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


class PinocchioModel:
    """A Pinocchio model of one :class:`NumericTree` with the index maps to our joint order."""

    def __init__(self, tree: NumericTree, urdf: str | None = None):
        self.tree = tree
        self.model = pin.buildModelFromXML(urdf if urdf is not None else urdf_string(tree))
        self.model.gravity.linear = np.asarray(tree.gravity, dtype=float)
        for j in tree.joints:  # URDF has no rotor inertia: Pinocchio's armature is set from the model
            if j.armature:
                self.model.armature[self.model.joints[self.model.getJointId(j.name)].idx_v] = j.armature
        self.data = self.model.createData()
        self.model_no_gravity = self.model.copy()
        self.model_no_gravity.gravity.linear = np.zeros(3)
        self.data_no_gravity = self.model_no_gravity.createData()
        if self.model.nq != self.model.nv:
            raise EngineError(f"{tree.system}: Pinocchio model has nq != nv (continuous joints?)")
        self.index = []
        for j in tree.joints:
            if not self.model.existJointName(j.name):
                raise EngineError(f"{tree.system}: joint {j.name} missing in the Pinocchio model")
            self.index.append(self.model.joints[self.model.getJointId(j.name)].idx_v)
        self.frames = {p.name: self.model.getFrameId(p.name) for p in tree.points}

    def to_pin(self, theta):
        v = np.zeros(self.model.nv)
        v[self.index] = theta
        return v

    def from_pin(self, v):
        return np.asarray(v)[self.index]

    def from_pin_matrix(self, A):
        return np.asarray(A)[np.ix_(self.index, self.index)]

    def frame_jacobian(self, frame: int) -> np.ndarray:
        """``6 x nv`` frame Jacobian (LOCAL_WORLD_ALIGNED); eigenpy hands a ``6 x 1`` matrix back as a 1-D array."""
        return np.asarray(pin.getFrameJacobian(self.model, self.data, frame, LWA)).reshape(6, self.model.nv)

    def point_forces(self, q, v):
        """Generalized forces of tendons (springs/dampers between points) and joint springs/dampers,
        from Pinocchio's frame placements and frame Jacobians: ``Σ J_bᵀ f − J_aᵀ f``."""
        model, data = self.model, self.data
        pin.computeJointJacobians(model, data, q)
        pin.framesForwardKinematics(model, data, q)
        f_spring = np.zeros(model.nv)
        f_damper = np.zeros(model.nv)
        for name, a, b, stiffness, rest, damping in self.tree.tendons:
            fa, fb = self.frames[a], self.frames[b]
            r = data.oMf[fb].translation - data.oMf[fa].translation
            length = np.linalg.norm(r)
            e = r / length
            J = self.frame_jacobian(fb)[:3] - self.frame_jacobian(fa)[:3]
            length_rate = e @ (J @ v)
            f_spring += J.T @ (-stiffness * (length - rest) * e)
            f_damper += J.T @ (-damping * length_rate * e)
        for joint, (stiffness, rest) in self.tree.joint_stiffness.items():
            k = self.index[[j.name for j in self.tree.joints].index(joint)]
            f_spring[k] += -stiffness * (q[k] - rest)
        for joint, damping in self.tree.joint_damping.items():
            k = self.index[[j.name for j in self.tree.joints].index(joint)]
            f_damper[k] += -damping * v[k]
        return f_spring, f_damper

    def input_forces(self, q, u: dict, loads=()):
        """Inputs on joints, and external forces/torques by (5.73) with Pinocchio's frame Jacobians
        (call after :meth:`point_forces`, which computes the kinematics at ``q``)."""
        model, data = self.model, self.data
        tau = np.zeros(model.nv)
        names = [j.name for j in self.tree.joints]
        for input_name, joint in self.tree.actuators:
            tau[self.index[names.index(joint)]] += u[input_name]
        for load in loads:
            R = np.eye(3) if load.frame == WORLD else data.oMf[model.getFrameId(load.frame)].rotation
            vector = R @ load.vector
            fid = self.frames[load.where] if load.kind == "force" else model.getFrameId(load.where)
            J = self.frame_jacobian(fid)
            tau += (J[:3] if load.kind == "force" else J[3:]).T @ vector
        return tau

    def _aba(self, q, v, u: dict, loads=()) -> tuple:
        """``(θ̈, f_spring, f_damper, τ_input)`` in Pinocchio's order: ``pin.aba`` with ``τ`` = inputs + springs +
        dampers."""
        f_spring, f_damper = self.point_forces(q, v)
        tau_input = self.input_forces(q, u, loads)
        return pin.aba(self.model, self.data, q, v, tau_input + f_spring + f_damper).copy(), f_spring, f_damper, \
            tau_input

    def forward_dynamics(self, theta, theta_dot, u: dict, loads=()) -> np.ndarray:
        """``θ̈`` alone, the call a simulation makes (:meth:`_aba`)."""
        return self.from_pin(self._aba(self.to_pin(theta), self.to_pin(theta_dot), u, loads)[0])

    def quantities(self, theta, theta_dot, u: dict, loads=(), christoffel: bool = True) -> TreeQuantities:
        """Everything in tree coordinates; ``christoffel=False`` skips the two Coriolis matrices (for
        simulation, where only the forward dynamics is needed)."""
        model, data = self.model, self.data
        q, v = self.to_pin(theta), self.to_pin(theta_dot)
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        g_gravity = pin.computeGeneralizedGravity(model, data, q).copy()
        Cqd = pin.nonLinearEffects(model, data, q, v) - g_gravity
        extra, C_christoffel = {}, None
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
                   "qdd": "pin.aba(tau = inputs + springs + dampers)"})


def evaluate(state: State, model: PinocchioModel | None = None):
    model = model or PinocchioModel(state.tree)
    t = model.quantities(state.theta, state.theta_dot, state.u, state.loads)
    evaluation = to_lecture("pinocchio", state, t)
    evaluation.extra["C_coriolis_matrix"] = coriolis_to_lecture(state, t.M, t.extra["C_coriolis_matrix"])
    return evaluation
