"""MuJoCo, loading our MJCF. Every number comes from a named MuJoCo call or ``MjData`` field:
``mj_fullM`` (the dense mass matrix; MuJoCo 4 no longer keeps it in ``MjData.qM``), ``qfrc_bias``
(at zero velocity: gravity alone), ``qfrc_spring``, ``qfrc_damper`` (tendons and joints), ``qacc``.

MuJoCo has no Coriolis matrix. The Christoffel ``C = ½ ∂(C θ̇)/∂θ̇`` is obtained from ``qfrc_bias`` by
polarization: ``b(v) = qfrc_bias(v) − qfrc_bias(0)`` is exactly quadratic in ``v``, so
``C e_j = (b(v + s e_j) − b(v − s e_j)) / (4 s)`` holds for any step ``s`` with no truncation error, only
round-off (not a finite-difference approximation)."""

from __future__ import annotations

import mujoco
import numpy as np

from harness.engines import warnings_log
from harness.engines.base import State, TreeQuantities, to_lecture
from harness.errors import EngineError
from harness.export.mjcf import mjcf_string
from harness.modeling.system import WORLD
from harness.export.numeric import NumericTree

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



def check_warnings(model: mujoco.MjModel, data: mujoco.MjData, what: str) -> None:
    """After ``mj_step``: raise :class:`EngineError` if any MuJoCo warning counter of ``data`` is non-zero.
    ``mj_step`` checks qpos and qvel of the state it steps *from*, so the final state of a run is checked here
    (``mj_checkPos``, ``mj_checkVel``; they reset ``data`` on a failure). After ``mj_forward`` use
    :func:`check_state`."""
    mujoco.mj_checkPos(model, data)
    mujoco.mj_checkVel(model, data)
    found = [f"{text} ({data.warning[w].number}x, last index {data.warning[w].lastinfo})"
             for w, text in WARNINGS.items() if data.warning[w].number > 0]
    for w in WARNINGS:  # counted once: the next evaluation with the same data starts clean
        data.warning[w].number = 0
    if found:
        raise EngineError(f"{what}: MuJoCo warning at t={data.time:g} s: " + "; ".join(found))


def check_state(model: mujoco.MjModel, data: mujoco.MjData, what: str) -> None:
    """MuJoCo's checks of ``mj_step`` (``mj_checkAcc``, then ``mj_checkPos``, ``mj_checkVel`` in
    :func:`check_warnings`) on a state computed by ``mj_forward``, which skips them. Resets ``data`` on a
    failure."""
    mujoco.mj_checkAcc(model, data)
    check_warnings(model, data, what)


class MujocoModel:
    def __init__(self, tree: NumericTree, xml: str | None = None, spec: mujoco.MjSpec | None = None):
        self.tree = tree
        if spec is not None:  # a scene's engine configuration (contact, dry friction) on top of the export
            self.model = warnings_log.compile_spec(spec, tree, "MjSpec.compile (scene)")
        else:  # MuJoCo loads the MJCF text we export (the same text as urdf/<system>.xml for default parameters)
            xml = xml if xml is not None else mjcf_string(tree)
            with warnings_log.capture("mujoco", "MjModel.from_xml_string", tree):
                self.model = mujoco.MjModel.from_xml_string(xml)
        self.data = mujoco.MjData(self.model)
        self.data_rest = mujoco.MjData(self.model)
        self.qpos_index, self.dof_index = [], []
        for j in tree.joints:
            jid = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_JOINT, j.name)
            if jid < 0:
                raise EngineError(f"{tree.system}: joint {j.name} missing in the MuJoCo model")
            self.qpos_index.append(self.model.jnt_qposadr[jid])
            self.dof_index.append(self.model.jnt_dofadr[jid])
        self.actuators = {name: mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_ACTUATOR, name)
                          for name, _ in tree.actuators}

    def _bias(self, theta, velocity):
        """``qfrc_bias`` (Coriolis, centrifugal and gravity) at one state, from ``mj_forward``."""
        d = self.data_rest
        d.qpos[self.qpos_index] = theta
        d.qvel[:] = 0.0
        d.qvel[self.dof_index] = velocity
        mujoco.mj_forward(self.model, d)
        return self._pick(d.qfrc_bias)

    def christoffel(self, theta, theta_dot):
        n = len(theta_dot)
        step = max(1.0, float(np.max(np.abs(theta_dot))) if n else 1.0)
        C = np.zeros((n, n))
        for j in range(n):
            e = np.zeros(n)
            e[j] = step
            C[:, j] = (self._bias(theta, theta_dot + e) - self._bias(theta, theta_dot - e)) / (4 * step)
        return C

    def _pick(self, vec):
        return np.asarray(vec)[self.dof_index].copy()

    def applied(self, loads) -> np.ndarray:
        """External forces/torques as ``qfrc_applied``, by ``mj_applyFT`` at the current kinematics."""
        m, d = self.model, self.data
        qfrc = np.zeros(m.nv)
        for load in loads:
            R = np.eye(3)
            if load.frame != WORLD:
                R = d.xmat[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, load.frame)].reshape(3, 3)
            vector, zero = R @ load.vector, np.zeros(3)
            if load.kind == "force":
                site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, load.where)
                body, point = m.site_bodyid[site], d.site_xpos[site].copy()
                mujoco.mj_applyFT(m, d, vector, zero, point, body, qfrc)
            else:
                body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, load.where)
                mujoco.mj_applyFT(m, d, zero, vector, d.xpos[body].copy(), body, qfrc)
        return qfrc

    def quantities(self, theta, theta_dot, u: dict, loads=(), christoffel: bool = True) -> TreeQuantities:
        m, d, d0 = self.model, self.data, self.data_rest
        for data, vel in ((d, theta_dot), (d0, np.zeros_like(theta_dot))):
            data.qpos[self.qpos_index] = theta
            data.qvel[self.dof_index] = vel
            data.ctrl[:] = 0.0
            data.qfrc_applied[:] = 0.0
            for name, aid in self.actuators.items():
                data.ctrl[aid] = u[name]
            mujoco.mj_kinematics(m, data)
            mujoco.mj_comPos(m, data)
            if data is d:
                data.qfrc_applied[:] = self.applied(loads)
            mujoco.mj_forward(m, data)
        M = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, M)
        gravity = self._pick(d0.qfrc_bias)
        C = self.christoffel(theta, theta_dot) if christoffel else None  # reuses data_rest
        tau_input = np.zeros(m.nv)
        tau_input[:] = d.qfrc_actuator + d.qfrc_applied
        check_state(m, d, self.tree.system)
        if C is not None and not np.all(np.isfinite(C)):
            raise EngineError(f"{self.tree.system}: MuJoCo's qfrc_bias is not finite at this velocity")
        return TreeQuantities(
            M=M[np.ix_(self.dof_index, self.dof_index)], Cqd=self._pick(d.qfrc_bias) - gravity,
            g_gravity=gravity, g_spring=-self._pick(d.qfrc_spring),
            f_damper=self._pick(d.qfrc_damper), tau_input=self._pick(tau_input), qdd=self._pick(d.qacc), C=C,
            calls={"C": "polarization of qfrc_bias(qvel ± s e_j) / 4s", "M": "mj_fullM", "Cqd": "qfrc_bias(qvel) - qfrc_bias(qvel=0)", "g": "qfrc_bias(qvel=0) - qfrc_spring",
                   "f_damper": "qfrc_damper", "qdd": "mj_forward -> qacc"})


def evaluate(state: State, model: MujocoModel | None = None):
    model = model or MujocoModel(state.tree)
    return to_lecture("mujoco", state, model.quantities(state.theta, state.theta_dot, state.u, state.loads))
