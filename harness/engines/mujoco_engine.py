"""MuJoCo, loading our MJCF. Every number comes from a named MuJoCo call or ``MjData`` field:
``mj_fullM`` (the dense mass matrix; MuJoCo 4 no longer keeps it in ``MjData.qM``), ``qfrc_bias``
(at zero velocity: gravity alone), ``qfrc_spring``, ``qfrc_damper`` (tendons and joints), ``qacc``."""

from __future__ import annotations

import mujoco
import numpy as np

from harness.engines.base import State, TreeQuantities, to_lecture
from harness.errors import EngineError
from harness.export.mjcf import mjcf_spec
from harness.export.numeric import NumericTree


class MujocoModel:
    def __init__(self, tree: NumericTree, xml: str | None = None):
        self.tree = tree
        self.model = mujoco.MjModel.from_xml_string(xml) if xml is not None else mjcf_spec(tree).compile()
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

    def _pick(self, vec):
        return np.asarray(vec)[self.dof_index].copy()

    def quantities(self, theta, theta_dot, u: dict) -> TreeQuantities:
        m, d, d0 = self.model, self.data, self.data_rest
        for data, vel in ((d, theta_dot), (d0, np.zeros_like(theta_dot))):
            data.qpos[self.qpos_index] = theta
            data.qvel[self.dof_index] = vel
            data.ctrl[:] = 0.0
            for name, aid in self.actuators.items():
                data.ctrl[aid] = u[name]
            mujoco.mj_forward(m, data)
        M = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, M)
        tau_input = np.zeros(m.nv)
        tau_input[:] = d.qfrc_actuator
        if d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0:
            raise EngineError(f"{self.tree.system}: MuJoCo reported a bad qacc")
        return TreeQuantities(
            M=M[np.ix_(self.dof_index, self.dof_index)], Cqd=self._pick(d.qfrc_bias - d0.qfrc_bias),
            g_gravity=self._pick(d0.qfrc_bias), g_spring=-self._pick(d.qfrc_spring),
            f_damper=self._pick(d.qfrc_damper), tau_input=self._pick(tau_input), qdd=self._pick(d.qacc),
            calls={"M": "mj_fullM", "Cqd": "qfrc_bias(qvel) - qfrc_bias(qvel=0)", "g": "qfrc_bias(qvel=0) - qfrc_spring",
                   "f_damper": "qfrc_damper", "qdd": "mj_forward -> qacc"})


def evaluate(state: State, model: MujocoModel | None = None):
    model = model or MujocoModel(state.tree)
    return to_lecture("mujoco", state, model.quantities(state.theta, state.theta_dot, state.u))
