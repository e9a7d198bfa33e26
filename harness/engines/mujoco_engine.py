"""MuJoCo, loading our MJCF. Every number comes from a named MuJoCo call or ``MjData`` field:
``mj_fullM`` (the dense mass matrix; MuJoCo 4 no longer keeps it in ``MjData.qM``), ``qfrc_bias``
(at zero velocity: gravity alone), ``qfrc_spring``, ``qfrc_damper`` (tendons and joints), ``qacc``.

MuJoCo has no Coriolis matrix. The Christoffel ``C = ½ ∂(C θ̇)/∂θ̇`` is obtained from ``qfrc_bias`` by
polarization (:func:`~harness.engines.base.polarization`: ``qfrc_bias(v) − qfrc_bias(0)`` is exactly quadratic
in ``v``).

A scene's engine configuration is a list of **spec transforms** handed to :class:`MujocoModel`, each an edit of
the exported ``MjSpec`` before it is compiled: :class:`Options` (time step, integrator, the effects switched on,
friction cone), :class:`JointCoupling` and :class:`ClosureGuide` (equality constraints of closed chains and
couplings), :class:`DryFriction` (joint ``frictionloss``), :class:`ContactSphere` (a sphere on a plane in
contact). MuJoCo's own time stepping is one loop, :meth:`MujocoModel.rollout`, with hooks for what changes
from step to step (inputs, loads, mode switches) and for sampling."""

from __future__ import annotations

import contextlib
import warnings
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from harness.engines import warnings_log
from harness.engines.base import (FREE_JOINT, Base, TreeEngine, TreeQuantities, captured_output, one_line,
                                  polarization, polarization_step)
from harness.errors import EngineError, ModelError
from harness.export.mjcf import exported_inertia, exported_mjcf, mjcf_spec, rpy_quat
from harness.modeling.system import WORLD
from harness.export.numeric import MUJOCO_POINT_MASS_INERTIA, NumericTree

VERSION = mujoco.__version__

WARNINGS = {
    mujoco.mjtWarning.mjWARN_INERTIA: "inertia matrix too close to singular",
    mujoco.mjtWarning.mjWARN_CONTACTFULL: "too many contacts",
    mujoco.mjtWarning.mjWARN_CNSTRFULL: "too many constraints",
    mujoco.mjtWarning.mjWARN_BADQPOS: "NaN, inf or huge value in qpos (the simulation is unstable)",
    mujoco.mjtWarning.mjWARN_BADQVEL: "NaN, inf or huge value in qvel (the simulation is unstable)",
    mujoco.mjtWarning.mjWARN_BADQACC: "NaN, inf or huge value in qacc (the simulation is unstable)",
    mujoco.mjtWarning.mjWARN_BADCTRL: "NaN, inf or huge value in ctrl",
}
"""MuJoCo does not fail on these: it counts them in ``MjData.warning`` (and on bad qpos/qvel/qacc resets the
state and carries on), so without a check a run returns silently wrong numbers. Its warning texts go to
:mod:`harness.engines.warnings_log`, never to the console."""



def _turns(m: mujoco.MjModel, body: int) -> bool:
    """Whether ``body`` can turn: a joint that is not a slide on it or on a body between it and the world."""
    while body > 0:
        start, count = m.body_jntadr[body], m.body_jntnum[body]
        if any(m.jnt_type[j] != mujoco.mjtJoint.mjJNT_SLIDE for j in range(start, start + count)):
            return True
        body = m.body_parentid[body]
    return False


def check_warnings(model: mujoco.MjModel, data: mujoco.MjData, what: str) -> None:
    """After ``mj_step``: raise :class:`EngineError` if any MuJoCo warning counter of ``data`` is non-zero.
    ``mj_step`` checks qpos and qvel of the state it steps *from*, so the final state of a run is checked here
    (``mj_checkPos``, ``mj_checkVel``; they reset ``data`` on a failure). After ``mj_forward`` use
    :func:`check_state`."""
    mujoco.mj_checkPos(model, data)
    mujoco.mj_checkVel(model, data)
    if not data.warning.number[_COUNTERS].any():  # the clean case, at every step of a simulation: one array read
        return
    found = [f"{text} ({data.warning[w].number}x, last index {data.warning[w].lastinfo}){_which(model, w, data)}"
             for w, text in WARNINGS.items() if data.warning[w].number > 0]
    clear_warnings(data)  # counted once: the next evaluation with the same data starts clean
    raise EngineError(f"{what}: MuJoCo warning at t={data.time:g} s: " + "; ".join(found))


def _which(model: mujoco.MjModel, warning, data: mujoco.MjData) -> str:
    """What a warning's index names: for a singular inertia matrix, the joint of the dof whose pivot in the
    factorization vanished (its motion moves no mass or inertia the other joints do not: a point mass turning on a
    pin of its own); else nothing."""
    dof = data.warning[warning].lastinfo
    if warning != mujoco.mjtWarning.mjWARN_INERTIA or not 0 <= dof < model.nv:
        return ""
    joint = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, model.dof_jntid[dof])
    return (f": joint {joint} moves no mass or inertia of its own (a point mass turning on a pin of its own: give "
            "its link an inertia, or leave the joint out)")


_COUNTERS = [int(w) for w in WARNINGS]
"""The indices of :data:`WARNINGS` in ``MjData.warning.number``, the counters as one writable array (a view):
reading them one ``data.warning[w]`` at a time costs ~1 µs each, 13 µs a forward dynamics checked and cleared."""


def clear_warnings(data: mujoco.MjData) -> None:
    """The counters of :data:`WARNINGS` set to 0."""
    data.warning.number[_COUNTERS] = 0


def check_state(model: mujoco.MjModel, data: mujoco.MjData, what: str) -> None:
    """MuJoCo's checks of ``mj_step`` (``mj_checkAcc``, then ``mj_checkPos``, ``mj_checkVel`` in
    :func:`check_warnings`) on a state computed by ``mj_forward``, which skips them. Resets ``data`` on a
    failure."""
    mujoco.mj_checkAcc(model, data)
    check_warnings(model, data, what)


def compile_text(text: str | None, source: str, path: Path | None = None,
                 bound: float | None = None, edit=None, tree=None, accepted: list | None = None) -> mujoco.MjModel:
    """An MJCF or URDF of other origin compiled by MuJoCo (from ``path`` when the model refers to files, else
    from ``text``); ``bound`` sets ``compiler.boundmass``/``boundinertia``; ``edit(spec)`` changes the spec before
    compiling (e.g. :func:`add_free_joint`). A refusal or a compiler warning is a :class:`ModelError` (what
    MuJoCo prints is captured) — but for a file we exported from ``tree``: a warning
    :func:`~harness.engines.warnings_log.explain` explains for that tree is accepted as the conformance run accepts
    it, and ``(message, reason)`` appended to ``accepted``."""
    with captured_output(), warnings.catch_warnings(record=True) as warned:
        warnings.simplefilter("always")
        try:
            spec = mujoco.MjSpec.from_file(str(path)) if path is not None else mujoco.MjSpec.from_string(text)
            if bound is not None:
                spec.compiler.boundmass = bound
                spec.compiler.boundinertia = bound
            if edit is not None:
                edit(spec)
            model = spec.compile()
        except (ValueError, RuntimeError) as exc:
            raise ModelError(f"{source}: MuJoCo refused the model: {one_line(exc)}") from None
    for warning in warned:  # e.g. "Inertia matrix is too close to singular": a model MuJoCo only half accepts
        message = str(warning.message)
        explained, reason = warnings_log.explain("mujoco", message, tree) if tree is not None else (False, "")
        if not explained:
            raise ModelError(f"{source}: MuJoCo warned while compiling: {one_line(message)}")
        if accepted is not None:
            accepted.append((one_line(message), reason))
    return model


def add_free_joint(spec) -> None:
    """Edit of an imported URDF (:func:`compile_text`): the root link on a free joint named
    :data:`~harness.engines.base.FREE_JOINT` (MuJoCo's URDF importer welds the root link to the world)."""
    roots = list(spec.worldbody.bodies)
    if len(roots) != 1:
        raise ModelError(f"a floating base needs one root body under the world, the import has {len(roots)}")
    roots[0].add_freejoint(name=FREE_JOINT)


def balanced(edit=None):
    """An edit (:func:`compile_text`) switching on ``compiler.balanceinertia`` (MuJoCo's own fix of inertias
    violating A + B >= C), then applying ``edit``."""
    def apply(spec) -> None:
        spec.compiler.balanceinertia = True
        if edit is not None:
            edit(spec)
    return apply


class MujocoModel(TreeEngine):
    """A MuJoCo model of one :class:`NumericTree` (our MJCF text; with ``transforms``, the exported ``MjSpec``
    edited by each transform and compiled, its warnings recorded under ``where``) with the index maps to our
    joint order."""

    name, reads = "mujoco", "MJCF"
    integrators = ("Euler", "RK4", "implicit", "implicitfast")
    natively = frozenset({"stepping", "dry friction", "contact", "soft constraints"})
    free: str | None = None
    """The free joint of a floating base (:meth:`loaded` with ``free``), else None."""

    def __init__(self, tree: NumericTree, xml: str | None = None, transforms=(),
                 where: str = "MjSpec.compile (scene)"):
        self.tree = tree
        if transforms:  # a scene's engine configuration (constraints, contact, dry friction) on top of the export
            spec = mjcf_spec(tree)
            for transform in transforms:
                transform(spec)
            model = warnings_log.compile_spec(spec, tree, where)
        else:  # MuJoCo loads the MJCF text we export (the same text as urdf/<system>.xml for default parameters)
            xml = xml if xml is not None else exported_mjcf(tree)
            with warnings_log.capture("mujoco", "MjModel.from_xml_string", tree):
                model = mujoco.MjModel.from_xml_string(xml)
        self._attach(model, [j.name for j in tree.joints])
        self.actuators = {name: mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_ACTUATOR, name)
                          for name, _ in tree.actuators}
        # bodies our export gave the stand-in inertia ε E (point masses, slender rods: mjcf.exported_inertia) that
        # can turn (a hinge, ball or free joint on their way to the world): on a body that only slides it adds nothing
        self.stand_ins = [bid for link in tree.links if exported_inertia(link.inertia) is not None
                          and (bid := mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, link.name)) > 0
                          and _turns(self.model, bid)]
        self._jacr, self._jacr_dot = np.zeros((3, self.model.nv)), np.zeros((3, self.model.nv))   # stand_in's
        # (input, actuator id) of the external loads MuJoCo applies as actuators (LoadActuators)
        self.load_actuators = [(input_name, mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_ACTUATOR, name))
                               for t in transforms if isinstance(t, LoadActuators)
                               for name, input_name, _, _ in t.entries]

    @property
    def driven(self) -> list[str]:
        """The inputs that set a ``ctrl`` (:meth:`set_inputs`): of the actuators on joints, then of the loads
        MuJoCo applies as actuators (:class:`LoadActuators`)."""
        return list(dict.fromkeys([*self.actuators, *(name for name, _ in self.load_actuators)]))

    @classmethod
    def loaded(cls, model: mujoco.MjModel, joints: list[str], free: str | None = None) -> "MujocoModel":
        """A model MuJoCo has compiled (a file of other origin), seen through ``joints`` (hinge, slide) and, with
        ``free``, a free joint of that name, reported in Pinocchio's free-flyer convention
        (:class:`~harness.engines.base.Base`; see :meth:`terms`)."""
        self = cls.__new__(cls)
        self._attach(model, list(joints))
        self.actuators, self.load_actuators, self.stand_ins = {}, [], []
        self._base = Base.rest()
        if free is not None:
            fid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, free)
            if fid < 0 or model.jnt_type[fid] != mujoco.mjtJoint.mjJNT_FREE:
                raise EngineError(f"free joint {free!r} missing in the MuJoCo model")
            self.free, self.free_id = free, fid
            self.free_qpos, self.free_dof = int(model.jnt_qposadr[fid]), int(model.jnt_dofadr[fid])
        return self

    def _attach(self, model: mujoco.MjModel, joints: list[str]) -> None:
        self.model, self.joints = model, joints
        self._subtrees_of: dict | None = None   # :meth:`_subtrees`
        self.data = mujoco.MjData(model)  # one: an MjData costs 0.35 ms to make (the bindings' views), a fifth of
        # a small model's load; quantities() evaluates the rest state and the polarization on it first
        self.jids, self.qpos_index, self.dof_index = [], [], []
        for name in joints:
            jid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
            if jid < 0:
                raise EngineError(f"{self.label + ': ' if self.tree else ''}joint {name} missing in the MuJoCo model")
            self.jids.append(jid)
            self.qpos_index.append(model.jnt_qposadr[jid])
            self.dof_index.append(model.jnt_dofadr[jid])
        # index arrays, not lists: NumPy picks by an array in a sixth of the time (0.12 µs, a list 0.78 µs), and a
        # run of MuJoCo's own reads θ, θ̇ at every sample (planar_manipulator/swing: 1.0 ms of a 10.5 ms run)
        self.qpos_index = np.array(self.qpos_index, dtype=np.intp)
        self.dof_index = np.array(self.dof_index, dtype=np.intp)

    def _bias(self, theta, velocity):
        """``qfrc_bias`` (Coriolis, centrifugal and gravity) at one state, from ``mj_forward``, less the stand-in
        inertia's (:meth:`stand_in`)."""
        d = self.data
        d.qpos[self.qpos_index] = theta
        d.qvel[:] = 0.0
        d.qvel[self.dof_index] = velocity
        mujoco.mj_forward(self.model, d)
        return self._pick(d.qfrc_bias - self.stand_in(d)[1]) if self.stand_ins else self._pick(d.qfrc_bias)

    def stand_in(self, d) -> tuple[np.ndarray, np.ndarray]:
        """``(ΔM, Δb)``: the terms the stand-in inertia ``ε E`` of our export (a point mass's, a slender rod's:
        :func:`~harness.export.mjcf.exported_inertia`) adds to ``mj_fullM`` and ``qfrc_bias`` at the state of ``d``
        (after its forward): ``ΔM = ε Σ J_ωᵀ J_ω`` and ``Δb = ε Σ J_ωᵀ J̇_ω q̇`` over those bodies, their angular
        Jacobians ``mj_jacBody`` and its rate ``mj_jacDot`` in world axes (an isotropic inertia turns with no
        gyroscopic term). MuJoCo needs it (mjMINVAL); the model we compare is without it: on a lab-sized Furuta
        pendulum (arm 85 mm, pendulum 24 g) it put MuJoCo's M off ours by 20 times the tolerance."""
        nv = self.model.nv
        delta_M, delta_b = np.zeros((nv, nv)), np.zeros(nv)
        for jacr, rate in self._turning(d):
            delta_M += jacr.T @ jacr
            delta_b += jacr.T @ rate
        return MUJOCO_POINT_MASS_INERTIA * delta_M, MUJOCO_POINT_MASS_INERTIA * delta_b

    def _turning(self, d):
        """``(J_ω, J̇_ω q̇)`` of each body with the stand-in inertia at the state of ``d`` (``mj_jacBody``,
        ``mj_jacDot``; ``J_ω`` a buffer, read before the next)."""
        m = self.model
        for body in self.stand_ins:
            mujoco.mj_jacBody(m, d, None, self._jacr, body)
            mujoco.mj_jacDot(m, d, None, self._jacr_dot, d.xipos[body], body)
            yield self._jacr, self._jacr_dot @ d.qvel

    def _qacc(self, d) -> np.ndarray:
        """``qacc`` of ``d``'s forward, the stand-in inertia's terms taken out (:meth:`stand_in`): from
        ``(M + ΔM) qacc = τ − b − Δb``, ``q̈ = qacc + (M + ΔM)⁻¹ (ΔM q̈ + Δb)``, taken as ``qacc + (M + ΔM)⁻¹ ε Σ J_ωᵀ
        (J_ω qacc + J̇_ω q̇)`` with MuJoCo's own factor of ``M + ΔM`` from the forward (``mj_solveM``): off the exact
        one by ``ε² / λ_min(M)²`` relative, and neither ``mj_fullM`` nor ``ΔM`` formed on the path a simulation calls
        (a ``mj_fullM`` and a NumPy solve made the pendulum's forward dynamics 8.6 → 28.2 µs a call; this, 8.5 → 17.5
        µs; the governor's two arms 9.3 → 23.1 µs; forming ``ΔM`` here cost 3.5 µs more). The one q̈ of
        :meth:`forward_dynamics`, :meth:`quantities` and :meth:`mass_and_forces`."""
        m = self.model
        force = np.zeros(m.nv)
        for jacr, rate in self._turning(d):
            force += jacr.T @ (jacr @ d.qacc + rate)
        correction = np.zeros((1, m.nv))
        mujoco.mj_solveM(m, d, correction, (MUJOCO_POINT_MASS_INERTIA * force)[None])
        return d.qacc + correction[0]

    def christoffel(self, theta, theta_dot):
        return polarization(lambda v: self._bias(theta, v), theta_dot)

    def _pick(self, vec):
        return np.asarray(vec)[self.dof_index].copy()

    def applied(self, loads) -> np.ndarray:
        """External forces/torques as ``qfrc_applied``, by ``mj_applyFT`` at the current kinematics."""
        m, d = self.model, self.data
        qfrc = np.zeros(m.nv)
        zero = np.zeros(3)
        for load in loads:
            vector = load.vector
            if load.frame != WORLD:
                vector = d.xmat[self._id(mujoco.mjtObj.mjOBJ_BODY, load.frame)].reshape(3, 3) @ vector
            if load.kind == "force":
                site = self._id(mujoco.mjtObj.mjOBJ_SITE, load.where)
                body, point = m.site_bodyid[site], d.site_xpos[site].copy()
                mujoco.mj_applyFT(m, d, vector, zero, point, body, qfrc)
            else:
                body = self._id(mujoco.mjtObj.mjOBJ_BODY, load.where)
                mujoco.mj_applyFT(m, d, zero, vector, d.xpos[body].copy(), body, qfrc)
        return qfrc

    def _forward(self, data, theta, theta_dot, u: dict, loads) -> None:
        """``mj_forward`` of ``data`` at the state with inputs as ``ctrl`` and loads as ``qfrc_applied``."""
        m = self.model
        data.qpos[self.qpos_index] = theta
        data.qvel[self.dof_index] = theta_dot
        data.ctrl[:] = 0.0
        data.qfrc_applied[:] = 0.0
        data.xfrc_applied[:] = 0.0   # what a rollout held (hold_loads)
        for name, aid in self.actuators.items():
            data.ctrl[aid] = u[name]
        mujoco.mj_kinematics(m, data)
        mujoco.mj_comPos(m, data)
        if loads is not None:
            data.qfrc_applied[:] = self.applied(loads)
        mujoco.mj_forward(m, data)

    def forward_dynamics(self, theta, theta_dot, u: dict, loads=()) -> np.ndarray:
        """``θ̈`` alone: ``mj_forward → qacc`` (checked as :meth:`quantities` does; the stand-in inertia's terms
        taken out, :meth:`_own`)."""
        self._forward(self.data, theta, theta_dot, u, loads)
        check_state(self.model, self.data, self.tree.system)
        return self._pick(self._qacc(self.data) if self.stand_ins else self.data.qacc)

    def mass_and_forces(self, theta, theta_dot, u: dict, loads=(), acceleration=None) -> tuple[np.ndarray, np.ndarray]:
        """``(M, h)`` from one ``mj_forward``: ``mj_fullM`` and ``h = qfrc_actuator + qfrc_applied + qfrc_spring +
        qfrc_damper − qfrc_bias`` (:meth:`quantities` takes a second forward to split gravity off ``qfrc_bias``; the
        stand-in inertia's terms taken out, :meth:`_own`); with ``acceleration`` ``a``, ``h − M a``
        (:meth:`TreeEngine.mass_and_forces`)."""
        m, d = self.model, self.data
        self._forward(d, theta, theta_dot, u, loads)
        check_state(m, d, self.tree.system)
        M, bias, _ = self._own(d)
        h = d.qfrc_actuator + d.qfrc_applied + d.qfrc_spring + d.qfrc_damper - bias
        M, h = M[np.ix_(self.dof_index, self.dof_index)], self._pick(h)
        return M, h if acceleration is None else h - M @ acceleration

    def _own(self, d) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(M, qfrc_bias, qacc)`` of ``d``'s forward (``mj_fullM``), the stand-in inertia's terms taken out
        (:meth:`stand_in`, :meth:`_qacc`)."""
        m = self.model
        M = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, M)
        bias, qacc = d.qfrc_bias.copy(), d.qacc.copy()
        if self.stand_ins:
            delta_M, delta_b = self.stand_in(d)
            M, bias, qacc = M - delta_M, bias - delta_b, self._qacc(d)
        return M, bias, qacc

    def quantities(self, theta, theta_dot, u: dict, loads=(), christoffel: bool = True) -> TreeQuantities:
        m, d = self.model, self.data
        warmstart = d.qacc_warmstart.copy()  # the state's forward starts from the previous state's, as before
        self._forward(d, theta, np.zeros_like(theta_dot), u, None)
        gravity = self._pick(d.qfrc_bias)
        C = self.christoffel(theta, theta_dot) if christoffel else None
        d.qacc_warmstart[:] = warmstart
        clear_warnings(d)  # what is checked below is the state's forward, as with a data of its own
        self._forward(d, theta, theta_dot, u, loads)  # last: the data holds the state's own forward afterwards
        M, bias, qacc = self._own(d)
        calls = {"C": "polarization of qfrc_bias(qvel ± s e_j) / 4s", "M": "mj_fullM",
                 "Cqd": "qfrc_bias(qvel) - qfrc_bias(qvel=0)", "g": "qfrc_bias(qvel=0) - qfrc_spring",
                 "f_damper": "qfrc_damper", "qdd": "mj_forward -> qacc"}
        if self.stand_ins:  # what each call's number is less (_own, stand_in)
            for k in ("C", "M", "Cqd"):
                calls[k] += " (less the stand-in inertia's terms, MujocoModel.stand_in)"
            calls["qdd"] += ", + mj_solveM(ΔM qacc + Δb) for the stand-in inertia (MujocoModel._qacc)"
        tau_input = np.zeros(m.nv)
        tau_input[:] = d.qfrc_actuator + d.qfrc_applied
        check_state(m, d, self.tree.system)
        if C is not None and not np.all(np.isfinite(C)):
            raise EngineError(f"{self.tree.system}: MuJoCo's qfrc_bias is not finite at this velocity")
        return TreeQuantities(
            M=M[np.ix_(self.dof_index, self.dof_index)], Cqd=self._pick(bias) - gravity,
            g_gravity=gravity, g_spring=-self._pick(d.qfrc_spring),
            f_damper=self._pick(d.qfrc_damper), tau_input=self._pick(tau_input), qdd=self._pick(qacc), C=C,
            extra={"Cqd_subtracted": float(np.abs(gravity).max(initial=0.0)),
                   "C_subtracted": np.abs(gravity) / polarization_step(theta_dot)},
            calls=calls)

    # ----- MuJoCo's own time stepping
    def configure(self, options: "Options") -> None:
        """``<option>`` settings on the compiled model (time step, integrator of :meth:`rollout`)."""
        options.set(self.model.opt)

    def reset(self) -> None:
        mujoco.mj_resetData(self.model, self.data)

    def set_state(self, theta, theta_dot) -> None:
        self.data.qpos[self.qpos_index] = theta
        self.data.qvel[self.dof_index] = theta_dot

    def theta(self) -> np.ndarray:
        return self.data.qpos[self.qpos_index].copy()

    def theta_dot(self) -> np.ndarray:
        return self.data.qvel[self.dof_index].copy()

    @property
    def time(self) -> float:
        return self.data.time

    def address(self, joint: str) -> tuple[int, int]:
        """``(qpos address, dof address)`` of a joint of the compiled model (also one of a transform's)."""
        jid = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_JOINT, joint)
        return int(self.model.jnt_qposadr[jid]), int(self.model.jnt_dofadr[jid])

    def joint_state(self, address: tuple[int, int]):
        """``(position, velocity)`` of the joint at ``address`` (:meth:`address`)."""
        return self.data.qpos[address[0]], self.data.qvel[address[1]]

    def set_joint(self, address: tuple[int, int], position: float, velocity: float) -> None:
        self.data.qpos[address[0]], self.data.qvel[address[1]] = position, velocity

    def set_inputs(self, values: dict) -> None:
        """``ctrl`` of each actuator (an input on a joint, a load applied as an actuator) from ``values`` by input
        name (:attr:`driven`)."""
        for name, aid in self.actuators.items():
            self.data.ctrl[aid] = values[name]
        for name, aid in self.load_actuators:
            self.data.ctrl[aid] = values[name]

    def apply_loads(self, loads) -> None:
        """``qfrc_applied`` of the external loads at the current kinematics (between ``mj_step1`` and ``mj_step2``)."""
        self.data.qfrc_applied[:] = self.applied(loads)

    def holds(self, kind: str, where: str, frame: str) -> bool:
        """Whether a load (:class:`~harness.engines.base.Load`'s ``kind``, ``where``, ``frame``) of constant
        components is a constant ``xfrc_applied`` (:meth:`hold_loads`): a torque in world axes, or a force in world
        axes at its body's centre of mass, where MuJoCo applies ``xfrc_applied`` (elsewhere its moment about the
        centre of mass turns with the body; in a link's axes the vector does)."""
        if frame != WORLD:
            return False
        if kind == "torque":
            return True
        site = self._id(mujoco.mjtObj.mjOBJ_SITE, where)
        centre = self.model.body_ipos[self.model.site_bodyid[site]]
        return bool(np.array_equal(self.model.site_pos[site], centre))

    def hold_loads(self, loads) -> None:
        """The external loads as ``xfrc_applied`` (forces and torques in world axes at the bodies' centres of mass),
        which MuJoCo applies through each stage's Jacobian of every step until they are set again: loads of constant
        components held over steps without a Python call per step (each must be one :meth:`holds`)."""
        m = self.model
        xfrc = np.zeros((m.nbody, 6))
        for load in loads:
            if not self.holds(load.kind, load.where, load.frame):
                raise ValueError(f"the load at {load.where} ({load.kind} in {load.frame} axes) is not a constant "
                                 "xfrc_applied: it needs a Python call per step (apply_loads)")
            if load.kind == "force":
                xfrc[m.site_bodyid[self._id(mujoco.mjtObj.mjOBJ_SITE, load.where)], :3] += load.vector
            else:
                xfrc[self._id(mujoco.mjtObj.mjOBJ_BODY, load.where), 3:] += load.vector
        self.data.xfrc_applied[:] = xfrc

    @contextlib.contextmanager
    def loads_at_each_stage(self, loads_at, integrator: str):
        """Within it, MuJoCo's control callback (``mjcb_control``: called in every ``mj_forward`` of a step, after
        the stage's kinematics and before its actuation; ``actuation`` must not be disabled) sets ``qfrc_applied``
        to :meth:`applied` of ``loads_at(k, θ, θ̇)`` at the stage's state, ``k`` the step (the callback's calls
        counted, :data:`STAGES` of ``integrator`` per step): loads that read the state, exact at every stage of
        RK4 (evaluated at a step's start and held they would make it first order). Yields the list holding the
        count of calls, which the caller checks against its steps (a count off would hold a wrong step's inputs).
        The callback is MuJoCo's, one per process: the one before is put back."""
        stages, calls = STAGES[integrator], [0]

        def control(m, d) -> None:
            k = calls[0] // stages
            calls[0] += 1
            d.qfrc_applied[:] = self.applied(loads_at(k, d.qpos[self.qpos_index], d.qvel[self.dof_index]))
        before = mujoco.get_mjcb_control()
        mujoco.set_mjcb_control(control)
        try:
            yield calls
        finally:
            mujoco.set_mjcb_control(before)

    def set_frictionloss(self, address: tuple[int, int], value: float) -> None:
        self.model.dof_frictionloss[address[1]] = value

    def friction_holds(self, address: tuple[int, int]) -> bool:
        """Whether the joint's dry friction held it over the last step: its ``frictionloss`` row's ``efc_state``
        is ``mjCNSTRSTATE_QUADRATIC``, its force within ``frictionloss`` (sticking), not at it (sliding)."""
        d = self.data
        rows = (d.efc_type[:d.nefc] == mujoco.mjtConstraint.mjCNSTR_FRICTION_DOF) & (d.efc_id[:d.nefc] == address[1])
        return bool(np.any(d.efc_state[:d.nefc][rows] == mujoco.mjtConstraintState.mjCNSTRSTATE_QUADRATIC))

    def forward(self) -> None:
        mujoco.mj_forward(self.model, self.data)

    def pose(self, theta) -> None:
        """The tree at ``theta``, positions only (``mj_kinematics``, ``mj_comPos``, ``mj_tendon``): for pictures."""
        self.data.qpos[self.qpos_index] = theta
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_comPos(self.model, self.data)
        mujoco.mj_tendon(self.model, self.data)

    def rollout(self, steps: int, every: int = 1, sample=None, before=None, between=None,
                check: str | None = None, changes=None) -> list:
        """MuJoCo's own stepping from the current state, the one loop that calls Python (:meth:`recorded`: none):
        ``steps`` calls of ``mj_step`` (split into ``mj_step1``, ``between(k)``, ``mj_step2`` when ``between`` is
        given: forces that depend on the step's kinematics), ``before(k)`` ahead of step ``k`` (inputs, mode
        switches), ``sample(k)`` at ``k = 0, every, …`` up to ``steps`` (the samples returned); without ``before``
        and ``between`` the steps between two samples are one ``mj_step(m, d, nstep)`` (MuJoCo's loop in C: the
        same steps, no Python call per step).
        ``changes``: the steps (sorted, from 0) at which ``before`` has something new to set, what it set held in
        between (piecewise-constant inputs, :func:`harness.scenes.simulate.input_setter`): ``before`` runs there
        only and MuJoCo steps in its own loop to the next change or sample; None: ``before`` runs at every step.
        With ``check`` (a description), MuJoCo's warning counters are checked at the end
        (:func:`check_warnings`): an unstable run is a failure, not a trajectory."""
        m, d = self.model, self.data
        out, k = [], 0
        segments = between is None and (before is None or changes is not None)   # MuJoCo's loop in C between
        pending = list(changes or ())[::-1]   # the next change last
        while True:
            if sample is not None and k % every == 0:
                out.append(sample(k))
            if k == steps:
                break
            if segments:  # to the next sample, change or the end
                while pending and pending[-1] <= k:
                    if pending.pop() == k:
                        before(k)
                n = min(every - k % every if sample is not None else steps, steps - k,
                        pending[-1] - k if pending else steps)
                mujoco.mj_step(m, d, nstep=n)
                k += n
                continue
            if before is not None:
                before(k)
            if between is None:
                mujoco.mj_step(m, d)
            else:
                mujoco.mj_step1(m, d)
                between(k)
                mujoco.mj_step2(m, d)
            k += 1
        if check is not None:
            check_warnings(m, d, check)
        return out

    def recorded(self, steps: int, every: int = 1, before=None, changes=None,
                 check: str | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(t, θ, θ̇)`` at steps ``k = 0, every, …`` up to ``steps`` of MuJoCo's own stepping from the current
        state, the steps :meth:`rollout` takes, bit for bit, but stepped **and recorded** in MuJoCo's C loop
        (``mujoco.rollout``: the physics state after every step, the inputs ``ctrl``, ``qfrc_applied`` and
        ``xfrc_applied`` held as set), ``before(k)`` run ahead of each step of ``changes`` (sorted, from 0; None:
        no change) and nothing of Python between them; the samples are picked from the records afterwards. Where
        :meth:`rollout` stops at every sample to read the state, a run costs a Python call per sample: 201 samples
        took a quarter of tower_crane/slew's 200 steps of RK4 (1.67 ms against 1.26 ms), time a comparison of
        MuJoCo's runs with others would have counted as MuJoCo's."""
        from mujoco import rollout as c_rollout

        m, d = self.model, self.data
        size, inputs = mujoco.mj_stateSize(m, _STATE), mujoco.mj_stateSize(m, _INPUTS)
        states = np.empty((steps + 1, size))
        mujoco.mj_getState(m, d, states[0], _STATE)
        starts = sorted({0, *(k for k in (changes or ()) if k < steps)})
        for start, end in zip(starts, starts[1:] + [steps]):
            if before is not None and start in (changes or ()):
                before(start)
            if end == start:
                continue
            state, held = np.empty((1, size)), np.empty(inputs)
            mujoco.mj_getState(m, d, state[0], _STATE)        # what before(start) left, as the loop would step it
            mujoco.mj_getState(m, d, held, _INPUTS)
            c_rollout.rollout([m], [d], state, np.tile(held, (1, end - start, 1)),
                              control_spec=_INPUTS, nstep=end - start, state=states[start + 1:end + 1][None],
                              initial_warmstart=d.qacc_warmstart[None].copy(), skip_checks=True)
        if check is not None:
            check_warnings(m, d, check)
        picked = states[::every]
        nq = m.nq
        return picked[:, 0], picked[:, 1 + self.qpos_index], picked[:, 1 + nq + self.dof_index]

    # ----- a tree of other origin (harness.files.importer): M, bias, what each joint moves
    # MuJoCo's free joint: ``qpos = [x, y, z, qw, qx, qy, qz]`` (quaternion scalar first), ``qvel`` = linear
    # velocity of the body's origin **in world axes**, then angular velocity **in the body's axes** (MuJoCo
    # issue #691; the agreement of ``M`` with Pinocchio checks it). With ``R`` the base orientation and
    # ``T = diag(R, I)`` (``qvel_base = T v``, ``v`` Pinocchio's local velocity), the quantities are brought to
    # Pinocchio's coordinates by the virtual-work map of DESIGN.md: ``M_v = Tᵀ M T``,
    # ``(C v)_v = Tᵀ (M Ṫ v + C qvel)`` with ``Ṫ v = (R (ω × v_lin), 0)``, ``g_v = Tᵀ g``, and the
    # acceleration ``v̇ = T⁻¹ (qacc − Ṫ v)``.
    def _set(self, theta, theta_dot, base: Base | None = None) -> None:
        d = self.data
        d.qpos[:] = self.model.qpos0
        d.qvel[:] = 0
        d.qpos[self.qpos_index] = theta
        d.qvel[self.dof_index] = theta_dot
        if self.free:
            self._base = base = base or Base.rest()
            a, b = self.free_qpos, self.free_dof
            d.qpos[a:a + 3] = base.position
            d.qpos[a + 3:a + 7] = np.roll(base.quat_xyzw, 1)  # (x, y, z, w) -> MuJoCo's (w, x, y, z)
            d.qvel[b:b + 3] = _quat_matrix(np.roll(base.quat_xyzw, 1)) @ base.velocity[:3]
            d.qvel[b + 3:b + 6] = base.velocity[3:]
        mujoco.mj_forward(self.model, d)

    @property
    def view_dofs(self) -> list[int]:
        """MuJoCo's dof indices in the order of the views' vectors: the free joint's six, then ``joints``."""
        return (list(range(self.free_dof, self.free_dof + 6)) if self.free else []) + list(self.dof_index)

    def _map(self):
        """``T`` (the rotation ``R`` of the base in its linear block) and ``Ṫ v`` of the free joint at the
        current state (identity and zero without one), over :attr:`view_dofs`."""
        n = len(self.view_dofs)
        T, Tdot_v = np.eye(n), np.zeros(n)
        if self.free:
            R = _quat_matrix(np.roll(self._base.quat_xyzw, 1))
            T[:3, :3] = R
            Tdot_v[:3] = R @ np.cross(self._base.velocity[3:], self._base.velocity[:3])
        return T, Tdot_v

    def terms(self, theta, theta_dot, base: Base | None = None, forward: bool = True) -> dict:
        """``M`` (``mj_fullM``) and the bias ``C v + g`` (``qfrc_bias``); with ``forward`` also ``Cqd``, ``g``
        and the forward dynamics ``qdd`` with zero inputs (``qacc_smooth``: no constraint, no passive force), in
        the views' coordinates (a free joint mapped to Pinocchio's free flyer: see above)."""
        self._set(theta, theta_dot, base)
        m, d, idx = self.model, self.data, self.view_dofs
        M = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, M)
        M = M[np.ix_(idx, idx)]
        if not self.free:  # exactly MuJoCo's numbers
            out = {"M": M, "bias": d.qfrc_bias[idx].copy()}
        else:
            T, Tdot_v = self._map()
            out = {"M": T.T @ M @ T, "bias": T.T @ (d.qfrc_bias[idx] + M @ Tdot_v)}
        if not forward:
            return out
        if np.any(d.qfrc_passive[idx]):
            raise EngineError("MuJoCo's passive forces are not zero (damping, springs): qacc_smooth is not the "
                              "forward dynamics with zero inputs")
        T, Tdot_v = self._map()
        out["qdd"] = np.linalg.solve(T, d.qacc_smooth[idx] - Tdot_v)
        self._set(theta, np.zeros(len(theta)), self._base.at_rest() if self.free else None)
        out["g"] = T.T @ d.qfrc_bias[idx]
        out["Cqd"] = out["bias"] - out["g"]
        return out

    def mass_and_bias(self, theta, theta_dot, base: Base | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``M`` (``mj_fullM``) and the bias ``C θ̇ + g`` (``qfrc_bias``) at ``θ`` (other joints at ``qpos0``)."""
        t = self.terms(theta, theta_dot, base, forward=False)
        return t["M"], t["bias"]

    def subtree_parts(self, theta, base: Base | None = None) -> dict[str, list]:
        """Per joint (and the free joint), the ``(mass, centre of mass, inertia tensor about it)`` of every body
        it moves, world axes (``xipos``, ``ximat``, ``body_inertia``)."""
        self._set(theta, np.zeros(len(theta)), base)
        m, d = self.model, self.data
        world = {}
        for b in range(m.nbody):
            R = d.ximat[b].reshape(3, 3)
            world[b] = (m.body_mass[b], d.xipos[b].copy(), R @ np.diag(m.body_inertia[b]) @ R.T)
        return {name: [world[b] for b in subtree] for name, subtree in self._subtrees().items()}

    def _subtrees(self) -> dict[str, list[int]]:
        """Per joint (and the free joint), the bodies it moves (``body_parentid``, ``jnt_bodyid``: the compiled
        tree, the same at every state; found once per model)."""
        if self._subtrees_of is not None:
            return self._subtrees_of
        m = self.model
        children: dict[int, list[int]] = {}
        for c in range(1, m.nbody):  # once, not per joint: a chain of n links costs n², not n³
            children.setdefault(int(m.body_parentid[c]), []).append(c)
        out = {}
        named = list(zip(self.joints, self.jids)) + ([(self.free, self.free_id)] if self.free else [])
        for name, jid in named:
            subtree, stack = [], [int(m.jnt_bodyid[jid])]
            while stack:
                b = stack.pop()
                subtree.append(b)
                stack += children.get(b, [])
            out[name] = subtree
        self._subtrees_of = out
        return out

    # ----- what the robots sweep (harness.files.robots) reads of an import
    def loaded_facts(self) -> dict:
        """What MuJoCo built from a file of other origin: bodies, nq, nv, equality constraints, total mass."""
        m = self.model
        return {"bodies": m.nbody - 1, "nq": m.nq, "nv": m.nv, "equalities": m.neq,
                "mass": round(float(m.body_mass.sum()), 9)}

    def damped_joints(self) -> list[str]:
        """The joints with damping or friction loss (``dof_damping``, ``dof_frictionloss``)."""
        m = self.model
        return [m.joint(j).name for j in range(m.njnt)
                if m.dof_damping[m.jnt_dofadr[j]] or m.dof_frictionloss[m.jnt_dofadr[j]]]

    def passive_off(self) -> None:
        """``dof_damping``, ``jnt_stiffness``, ``dof_armature`` set to 0 (forward dynamics without passive
        forces, as Pinocchio's ``aba``)."""
        self.model.dof_damping[:] = 0
        self.model.jnt_stiffness[:] = 0
        self.model.dof_armature[:] = 0

    def joint_equalities(self) -> list[tuple[str, str]]:
        """The joint pairs coupled by a joint equality constraint (``mjEQ_JOINT``), e.g. an imported mimic."""
        m = self.model
        return [(m.joint(int(m.eq_obj1id[e])).name, m.joint(int(m.eq_obj2id[e])).name)
                for e in range(m.neq) if m.eq_type[e] == mujoco.mjtEq.mjEQ_JOINT]

    def joint_limited(self, name: str) -> bool | None:
        """Whether joint ``name`` has a range (None: no such joint)."""
        jid = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_JOINT, name)
        return None if jid < 0 else bool(self.model.jnt_limited[jid])

    @property
    def bodies(self) -> int:
        """Bodies besides the world."""
        return self.model.nbody - 1

    def noisy_steps(self, seconds: float, noise: float, seed: int) -> dict:
        """``mj_step`` from ``qpos0`` at rest for ``seconds`` with seeded noise torques on the joints (not a free
        joint): standard deviation ``noise`` times each joint's gravity torque at ``qpos0`` plus 0.1 N·m. The
        steps, the time, every warning (MuJoCo's warning counters and its warning handler's texts)."""
        model, data = self.model, self.data
        mujoco.mj_resetData(model, data)  # from qpos0 at rest
        mujoco.mj_forward(model, data)
        joints = [d for d in range(model.nv) if model.jnt_type[model.dof_jntid[d]] != mujoco.mjtJoint.mjJNT_FREE]
        sigma = noise * (np.abs(data.qfrc_bias[joints]) + 0.1)
        rng = np.random.default_rng(seed)
        steps = int(round(seconds / model.opt.timestep))
        start, found = warnings_log.mark(), []

        noise = rng.normal(0.0, sigma, size=(steps, len(joints)))   # drawn at once: the same numbers, in order

        def torques(k):
            data.qfrc_applied[joints] = noise[k]

        self.rollout(steps, before=torques)  # the one stepping loop
        try:
            check_warnings(model, data, f"{steps} x mj_step with noise torques")
        except EngineError as exc:
            found.append(str(exc))
        found += [t.strip() for t in warnings_log.texts_since(start)]
        if not (np.all(np.isfinite(data.qpos)) and np.all(np.isfinite(data.qvel))):
            found.append("state not finite after stepping")
        data.qfrc_applied[:] = 0  # the adapter's other calls see no leftover torques
        return {"steps": steps, "time": round(float(data.time), 6), "timestep": float(model.opt.timestep),
                "warnings": found}

    def body_names(self) -> list[str]:
        return [self.model.body(i).name for i in range(self.model.nbody)]

    @property
    def gravity(self) -> np.ndarray:
        return np.asarray(self.model.opt.gravity)

    def set_gravity(self, gravity) -> None:
        self.model.opt.gravity[:] = gravity

    @property
    def armature(self) -> np.ndarray:
        return self.model.dof_armature[self.dof_index]

    def set_armature(self, values) -> None:
        self.model.dof_armature[self.dof_index] = values

    def facts(self) -> dict:
        """What ``harness validate`` reports of a loaded model."""
        m = self.model
        return {"bodies": m.nbody - 1, "dof": m.nv, "actuators": m.nu,
                "moving mass": f"{float(m.body_mass[m.body_weldid != 0].sum()):.6g} kg"}

    # ----- the export round trip (harness.compare.roundtrip): the MJCF as loaded
    @property
    def dofs(self) -> int:
        return self.model.nv

    def _id(self, kind, name) -> int:
        """The id of a named object of the compiled model, looked up once (its names do not change; the loads
        of a scene are applied by name at every step)."""
        ids = self.__dict__.setdefault("_ids", {})
        if (kind, name) not in ids:
            ids[kind, name] = mujoco.mj_name2id(self.model, kind, name)
        return ids[kind, name]

    def collision_pairs(self) -> list[tuple[int, int]]:
        """The geom pairs MuJoCo's collision detection considers, by its own filter: ``contype``/``conaffinity``
        compatible, not in one weld body, not parent and child unless one of them is welded to the world."""
        m = self.model
        weld = m.body_weldid[m.geom_bodyid]
        parent = m.body_weldid[m.body_parentid[weld]]
        out = []
        for a in range(m.ngeom):
            for b in range(a + 1, m.ngeom):
                if not (m.geom_contype[a] & m.geom_conaffinity[b] or m.geom_contype[b] & m.geom_conaffinity[a]):
                    continue
                if weld[a] == weld[b] or (weld[a] and weld[b] and (weld[a] == parent[b] or weld[b] == parent[a])):
                    continue
                out.append((a, b))
        return out

    def clearance(self, pairs, distmax: float) -> tuple[np.ndarray, np.ndarray]:
        """At the current state (after :meth:`forward`), per pair: the signed distance of its geoms less their
        contact margin (``mj_geomDistance``, capped at ``distmax``: MuJoCo makes a contact only below it) and a bound
        of the rate at which it can shrink, the sum over its two geoms of ``|v| + |ω| r`` (``mj_objectVelocity``
        at the geom's centre, ``r`` its bounding radius ``geom_rbound``; 0 for a geom welded to the world)."""
        m, d = self.model, self.data
        speed = np.zeros(m.ngeom)
        v = np.zeros(6)
        for g in {g for pair in pairs for g in pair}:
            if m.body_weldid[m.geom_bodyid[g]]:
                mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_GEOM, g, v, 0)
                speed[g] = np.linalg.norm(v[3:]) + np.linalg.norm(v[:3]) * m.geom_rbound[g]
        gaps = np.array([mujoco.mj_geomDistance(m, d, a, b, distmax, None) - max(m.geom_margin[a], m.geom_margin[b])
                         for a, b in pairs])
        return gaps, np.array([speed[a] + speed[b] for a, b in pairs])

    def geom_name(self, gid) -> str:
        """A geom's name (its id where it has none)."""
        return mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_GEOM, int(gid)) or f"geom {int(gid)}"

    def _body_name(self, bid) -> str:
        return mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_BODY, bid)

    def body_as_loaded(self, name: str) -> dict | None:
        """A body's mass, inertia tensor about its centre of mass in the body frame (``R diag(body_inertia) Rᵀ``,
        ``R`` from ``body_iquat``) and centre of mass ``body_ipos``."""
        bid = self._id(mujoco.mjtObj.mjOBJ_BODY, name)
        if bid < 0:
            return None
        m = self.model
        R = _quat_matrix(m.body_iquat[bid])
        return {"mass": m.body_mass[bid], "inertia": R @ np.diag(m.body_inertia[bid]) @ R.T, "com": m.body_ipos[bid]}

    def joint_as_loaded(self, name: str) -> dict | None:
        """A joint's bodies (parent, its own), type, axis ``jnt_axis`` and anchor ``jnt_pos`` in its body, and
        its body's placement in the parent (``body_pos``, ``body_quat``)."""
        jid = self._id(mujoco.mjtObj.mjOBJ_JOINT, name)
        if jid < 0:
            return None
        m = self.model
        bid = m.jnt_bodyid[jid]
        kind = _MJ_TYPE.get(mujoco.mjtJoint(m.jnt_type[jid]), str(mujoco.mjtJoint(m.jnt_type[jid])))
        return {"bodies": [self._body_name(m.body_parentid[bid]), self._body_name(bid)], "type": kind,
                "axis": m.jnt_axis[jid], "anchor": m.jnt_pos[jid], "origin": m.body_pos[bid],
                "rotation": _quat_matrix(m.body_quat[bid])}

    def point_as_loaded(self, name: str) -> dict | None:
        """A point (site): its body and position ``site_pos`` in it."""
        sid = self._id(mujoco.mjtObj.mjOBJ_SITE, name)
        if sid < 0:
            return None
        return {"link": self._body_name(self.model.site_bodyid[sid]), "position": self.model.site_pos[sid]}

    # ----- what a benchmark times: the raw calls at one state
    def kernels(self, theta, theta_dot) -> dict:
        """Zero-argument calls at ``(θ, θ̇)``: ``mj_fwdPosition + mj_fullM`` (M), ``mj_fwdPosition +
        mj_fwdVelocity`` (``qfrc_bias`` = C θ̇ + g), ``mj_forward`` (θ̈)."""
        m, d = self.model, self.data
        d.qpos[self.qpos_index], d.qvel[self.dof_index] = theta, theta_dot
        dense = np.zeros((m.nv, m.nv))

        def mass():
            mujoco.mj_fwdPosition(m, d)
            mujoco.mj_fullM(m, d, dense)

        def bias():
            mujoco.mj_fwdPosition(m, d)
            mujoco.mj_fwdVelocity(m, d)

        return {"M": mass, "bias": bias, "qdd": lambda: mujoco.mj_forward(m, d)}


_MJ_TYPE = {mujoco.mjtJoint.mjJNT_HINGE: "revolute", mujoco.mjtJoint.mjJNT_SLIDE: "prismatic"}


def _quat_matrix(quat) -> np.ndarray:
    """Rotation matrix of a unit quaternion in MuJoCo's order (w, x, y, z) (``mju_quat2Mat``; Pinocchio's
    (x, y, z, w) reordered by ``np.roll(q, 1)``)."""
    mat = np.zeros(9)
    mujoco.mju_quat2Mat(mat, np.asarray(quat, dtype=float))
    return mat.reshape(3, 3)


# --------------------------------------------------------------------------------------------- spec transforms
_FLAGS = {"equality": mujoco.mjtDisableBit.mjDSBL_EQUALITY, "constraint": mujoco.mjtDisableBit.mjDSBL_CONSTRAINT,
          "frictionloss": mujoco.mjtDisableBit.mjDSBL_FRICTIONLOSS, "contact": mujoco.mjtDisableBit.mjDSBL_CONTACT,
          "gravity": mujoco.mjtDisableBit.mjDSBL_GRAVITY, "spring": mujoco.mjtDisableBit.mjDSBL_SPRING,
          "damper": mujoco.mjtDisableBit.mjDSBL_DAMPER, "actuation": mujoco.mjtDisableBit.mjDSBL_ACTUATION}
EFFECT_FLAGS = {"gravity": ("gravity",), "springs": ("spring",), "dampers": ("damper",), "inputs": ("actuation",),
                "friction": ("frictionloss",), "contact": ("contact",), "external": ()}
"""The disable flags of each scene effect (:data:`harness.modeling.scenes.EFFECTS`): what switches it off in
MuJoCo. External loads are ours (``qfrc_applied``): pruned, they are not evaluated at all."""


def effect_flags(effects) -> tuple:
    """The disable flags of ``effects`` (sorted, without repetition)."""
    return tuple(sorted({flag for e in effects for flag in EFFECT_FLAGS[e]}))


STIFF_SOLIMP = [0.9999, 0.9999, 0.001, 0.5, 2.0]   # MuJoCo's impedance at its hardest

_STATE = mujoco.mjtState.mjSTATE_FULLPHYSICS    # what MujocoModel.recorded keeps of each step: time, qpos, qvel, …
_INPUTS = (mujoco.mjtState.mjSTATE_CTRL | mujoco.mjtState.mjSTATE_QFRC_APPLIED
           | mujoco.mjtState.mjSTATE_XFRC_APPLIED)   # what it holds over a stretch between input changes
STAGES = {"Euler": 1, "implicitfast": 1, "implicit": 1, "RK4": 4}   # mj_forward calls of one mj_step


@dataclass(frozen=True)
class Options:
    """``<option>``: the time step, the integrator (``Euler``, ``RK4``, ``implicit``, ``implicitfast``), the
    effects switched on (``enable``: their disable flags cleared) and off (``disable``: set; a scene's pruned
    effects, :func:`effect_flags`) — ``equality``, ``constraint``, ``frictionloss``, ``contact``, ``gravity``,
    ``spring``, ``damper``, ``actuation`` —, an elliptic friction cone, noslip iterations. A spec
    transform, or set on a compiled model (:meth:`MujocoModel.configure`)."""

    timestep: float | None = None
    integrator: str | None = None
    enable: tuple = ()
    elliptic: bool = False
    noslip_iterations: int | None = None
    disable: tuple = ()

    def __call__(self, spec) -> None:
        self.set(spec.option)

    def set(self, option) -> None:
        if self.enable:
            bits = 0
            for flag in self.enable:
                bits |= _FLAGS[flag]
            option.disableflags &= ~int(bits)
        if self.disable:
            bits = 0
            for flag in self.disable:
                bits |= _FLAGS[flag]
            option.disableflags |= int(bits)
        if self.elliptic:
            option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
        if self.timestep is not None:
            option.timestep = self.timestep
        if self.integrator is not None:
            option.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{self.integrator.upper()}")
        if self.noslip_iterations is not None:
            option.noslip_iterations = self.noslip_iterations


@dataclass(frozen=True)
class VisualGeomsDropped:
    """The visual-only geoms of our export (group :data:`~harness.export.mjcf.VISUAL_GROUP`, ``contype =
    conaffinity = 0``, no mass: the bodies' inertia is explicit) left out of a model whose run no renderer reads:
    MuJoCo still poses every geom at every stage of a step, and with contact detection on bounds each in its broad
    phase. What they are drawn from changes no number of the dynamics (a pruned run, the same trajectory bit for
    bit)."""

    def __call__(self, spec) -> None:
        from harness.export.mjcf import VISUAL_GROUP

        for geom in list(spec.geoms):
            if geom.group == VISUAL_GROUP and geom.contype == 0 and geom.conaffinity == 0:
                spec.delete(geom)


WHAT_FLAGS = ("mjDSBL_CONSTRAINT", "mjDSBL_EQUALITY", "mjDSBL_FRICTIONLOSS", "mjDSBL_LIMIT", "mjDSBL_CONTACT",
              "mjDSBL_SPRING", "mjDSBL_DAMPER", "mjDSBL_GRAVITY", "mjDSBL_CLAMPCTRL", "mjDSBL_ACTUATION",
              "mjDSBL_SENSOR")
"""The disable flags that switch off what MuJoCo computes for a model's elements and effects. The others say how it
computes a step (the solver's warm start, constraint islands, the collision phases, Euler's damping, the reference
time's safety, the reset of an unstable run): a model pruned of elements computes them as before."""

ELEMENTS = {"inputs": ("actuators",), "external": ("actuators",), "springs": ("tendons",), "dampers": ("tendons",),
            "friction": ("tendons",), "contact": ("geoms", "pairs", "excludes")}
"""The kinds of MjSpec element a scene effect may need: an input's or a load's actuator, a point spring's or
damper's spatial tendon (a joint's is a coefficient of its joint), contact's geoms."""


@dataclass(frozen=True)
class ActingTree:
    """The tree with what its acting effects need and no more: every element of the model but its bodies, joints and
    inertias and the elements of the effects in ``acting`` (:data:`ELEMENTS`) deleted (actuators, sensors, tendons,
    equalities, contact pairs and exclusions, geoms, and the sites no kept element joins), and every disable flag of
    what MuJoCo computes (:data:`WHAT_FLAGS`) set but those of the acting effects (:func:`effect_flags`); how it
    computes a step (the other flags) is left as the model has it. ``rows``: a closed chain's constraint rows act,
    its equalities kept with the equality and constraint flags clear.

    What a step of a model that simulates those effects costs at the least in MuJoCo's terms: a model of the same
    tree with more elements or fewer of these flags set computes the same stages and more, and one without an
    acting effect's elements does not simulate the scene, so no pruning of it steps faster
    (:func:`harness.scenes.phenomena.pruning.attainable`). With no acting effect, the bare tree: bodies, joints and
    inertias alone."""

    acting: frozenset = frozenset()
    rows: bool = False

    def __call__(self, spec) -> None:
        kept = {kind for effect in self.acting for kind in ELEMENTS.get(effect, ())}
        kept |= {"equalities"} if self.rows else set()
        for kind in ("actuators", "sensors", "tendons", "equalities", "pairs", "excludes", "geoms"):
            if kind not in kept:
                for element in list(getattr(spec, kind)):
                    spec.delete(element)
        with warnings.catch_warnings():   # a compile to read what joins the sites: the model's own compile says
            warnings.simplefilter("ignore")   # its warnings (MujocoModel, check_warnings)
            joined = _joined_sites(spec.compile())
        for site in list(spec.sites):
            if site.name not in joined:
                spec.delete(site)
        clear = set(effect_flags(self.acting)) | ({"actuation"} if "actuators" in kept else set())
        clear |= {"equality", "constraint"} if self.rows else set()
        for name in WHAT_FLAGS:
            spec.option.disableflags |= int(mujoco.mjtDisableBit.__members__[name])
        for flag in clear:
            spec.option.disableflags &= ~int(_FLAGS[flag])


def _joined_sites(model: mujoco.MjModel) -> set[str]:
    """The sites a tendon's path, an actuator's transmission or reference, or an equality joins."""
    ids = {int(model.wrap_objid[i]) for i in range(model.nwrap) if model.wrap_type[i] == mujoco.mjtWrap.mjWRAP_SITE}
    ids |= {int(i) for k in range(model.nu) if model.actuator_trntype[k] == mujoco.mjtTrn.mjTRN_SITE
            for i in model.actuator_trnid[k]}
    ids |= {int(i) for k in range(model.neq) if model.eq_objtype[k] == mujoco.mjtObj.mjOBJ_SITE
            for i in (model.eq_obj1id[k], model.eq_obj2id[k])}
    return {model.site(i).name for i in ids if i >= 0}


LOADS_REFERENCE = "loads_reference"   # the world site the gear of a load applied as an actuator is in (LoadActuators)


@dataclass(frozen=True)
class LoadActuators:
    """External forces at points in world axes, linear in the inputs with constant directions, ``f = Σᵢ uᵢ dᵢ``, as
    MuJoCo's site actuators: one per input of a load, ``<general site="point" refsite="loads_reference"
    gear="dᵢ 0 0 0">`` with ``ctrl = uᵢ`` (a force ``uᵢ dᵢ`` at the site, ``dᵢ`` in the axes of a site fixed to the
    world). MuJoCo applies them in its own step, where a load evaluated in Python costs a call per step or stage
    (:meth:`MujocoModel.apply_loads`, :meth:`MujocoModel.loads_at_each_stage`); :func:`~harness.scenes.simulate.
    load_actuators` reads them from a system. ``entries``: ``(actuator name, input name, point, dᵢ)``."""

    entries: tuple

    def __call__(self, spec) -> None:
        spec.option.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_ACTUATION)  # off in an export without inputs
        spec.worldbody.add_site(name=LOADS_REFERENCE)
        for name, _, point, direction in self.entries:
            spec.add_actuator(name=name, target=point, trntype=mujoco.mjtTrn.mjTRN_SITE, refsite=LOADS_REFERENCE,
                              gear=[*map(float, direction), 0.0, 0.0, 0.0])


@dataclass(frozen=True)
class JointCoupling:
    """``θ_dependent = offset + ratio θ_independent``: ``<equality><joint polycoef="offset ratio 0 0 0">``."""

    dependent: str
    independent: str
    offset: float
    ratio: float
    solref: tuple
    solimp: tuple = tuple(STIFF_SOLIMP)

    def __call__(self, spec) -> None:
        spec.add_equality(type=mujoco.mjtEq.mjEQ_JOINT, name1=self.dependent, name2=self.independent,
                          data=[self.offset, self.ratio, 0, 0, 0] + [0.0] * 7, solref=list(self.solref),
                          solimp=list(self.solimp))


@dataclass(frozen=True)
class ClosureGuide:
    """A point (site) held on the plane ``nᵀ p = value`` by a guide body on two slide joints spanning the plane,
    joined to the point by ``<equality><connect>``. The guide has ``mass`` (MuJoCo needs a mass on a moving
    body), its weight is compensated (``gravcomp``) and its inertia cancelled step by step
    (:meth:`compensation`)."""

    name: str
    point: str
    normal: tuple
    value: float
    mass: float
    solref: tuple
    solimp: tuple = tuple(STIFF_SOLIMP)

    def __call__(self, spec) -> None:
        n = np.array(self.normal, dtype=float)
        n /= np.linalg.norm(n)
        t1 = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(n, t1)
        guide = spec.worldbody.add_body(name=f"guide_{self.name}", pos=self.value * n)
        guide.explicitinertial = True
        guide.mass = self.mass
        guide.fullinertia = [guide.mass] * 3 + [0.0] * 3  # it only slides: its inertia never acts
        guide.gravcomp = 1.0                                # its weight is compensated (it is massless in the model)
        guide.add_joint(name=f"guide_{self.name}_1", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=t1)
        guide.add_joint(name=f"guide_{self.name}_2", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=t2)
        guide.add_site(name=f"guide_{self.name}")
        spec.add_equality(type=mujoco.mjtEq.mjEQ_CONNECT, objtype=mujoco.mjtObj.mjOBJ_SITE,
                          name1=self.point, name2=f"guide_{self.name}", solref=list(self.solref),
                          solimp=list(self.solimp))

    def place(self, mm: MujocoModel) -> None:
        """The guide where the point is (at the model's current state)."""
        m, d = mm.model, mm.data
        mujoco.mj_kinematics(m, d)
        site = d.site_xpos[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, self.point)]
        body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"guide_{self.name}")
        for k in (1, 2):
            jid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"guide_{self.name}_{k}")
            axis = m.jnt_axis[jid]
            d.qpos[m.jnt_qposadr[jid]] = axis @ (site - m.body_pos[body])

    def compensation(self, mm: MujocoModel):
        """A per-step call (between ``mj_step1`` and ``mj_step2``) cancelling the guide's inertia with its last
        acceleration, ``qfrc_applied = m_guide q̈_guide`` (lag dt)."""
        m, d = mm.model, mm.data
        body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"guide_{self.name}")
        dofs = [(int(m.jnt_dofadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"guide_{self.name}_{k}")]),
                 float(m.body_mass[body])) for k in (1, 2)]

        def compensate():
            for dof, mass in dofs:
                d.qfrc_applied[dof] = mass * d.qacc[dof]
        return compensate


@dataclass(frozen=True)
class DryFriction:
    """Joint ``frictionloss`` (MuJoCo's dry friction, one coefficient: switch it with
    :meth:`MujocoModel.set_frictionloss`), its soft-constraint parameters."""

    joint: str
    frictionloss: float
    solref: tuple
    solimp: tuple = tuple(STIFF_SOLIMP)

    def __call__(self, spec) -> None:
        joint = spec.joint(self.joint)
        joint.solref_friction = list(self.solref)
        joint.solimp_friction = list(self.solimp)
        joint.frictionloss = self.frictionloss


@dataclass(frozen=True)
class ContactSphere:
    """The link as a sphere of ``radius`` in contact with a plane of roll-pitch-yaw ``plane_rpy`` through the
    point ``radius`` below its origin, friction ``mu`` (condim 3); a slide joint ``normal`` (along the link
    frame's z) added first, so the sphere may leave the plane."""

    link: str
    radius: float
    plane_rpy: tuple
    mu: float
    solref: tuple
    solimp: tuple = tuple(STIFF_SOLIMP)

    def __call__(self, spec) -> None:
        body = spec.body(self.link)
        old = [(j.name, j.type, list(j.axis)) for j in body.joints]
        for j in list(body.joints):
            spec.delete(j)
        body.add_joint(name="normal", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, 1])  # free to leave the plane
        for name, kind, axis in old:
            body.add_joint(name=name, type=kind, axis=axis)
        quat = rpy_quat(list(self.plane_rpy))
        normal = np.zeros(3)
        mujoco.mju_rotVecQuat(normal, np.array([0.0, 0.0, 1.0]), quat)
        contact = dict(friction=[self.mu, 0.0, 0.0], condim=3, solref=list(self.solref), solimp=list(self.solimp))
        spec.worldbody.add_geom(name="plane", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1],
                                pos=-self.radius * normal, quat=quat, **contact)
        body.add_geom(name="ball", type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[self.radius, 0, 0], **contact)


@dataclass(frozen=True)
class CollisionMeshes:
    """Collision geometry: each ``(body, shape, pos, quat)`` a geom of that body (``"world"``: the fixed base) that
    collides (``contype = conaffinity = 1``, no mass: the bodies' inertia is explicit); ``shape`` is
    ``("mesh", file)`` or ``("box", half sizes)``. With ``floor`` a plane ``z = floor``. MuJoCo collides a mesh's
    convex hull; parent and child are filtered as usual. Contact detection stays off until enabled
    (``Options(enable=("contact", "constraint"))``)."""

    geoms: tuple
    floor: float | None = None

    def __call__(self, spec) -> None:
        for k, (body, (kind, data), pos, quat) in enumerate(self.geoms):
            parent = spec.worldbody if body == WORLD else spec.body(body)
            common = dict(pos=list(pos), quat=list(quat), contype=1, conaffinity=1, mass=0.0, group=3)
            if kind == "mesh":
                name = f"collision_{k}_{Path(data).stem}"
                spec.add_mesh(name=name, file=str(data))
                parent.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_MESH, meshname=name, **common)
            else:
                parent.add_geom(name=f"collision_{k}_box", type=mujoco.mjtGeom.mjGEOM_BOX, size=list(data), **common)
        if self.floor is not None:
            spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1],
                                    pos=[0.0, 0.0, self.floor], contype=1, conaffinity=1)
