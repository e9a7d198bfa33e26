"""Contact detection pruned: the lightweight robot's scene ``fall`` in MuJoCo's own RK4 with the Panda's real
collision meshes and a floor, contact detection on (``contact``, ``constraint`` enabled) against the same MJCF with
the collision geometry dropped and ``mjDSBL_CONTACT`` set (:class:`~harness.engines.mujoco_engine.Options`
``disable``) and, as in every pruned MuJoCo run, the visual geoms no one reads in a run dropped
(:class:`~harness.engines.mujoco_engine.VisualGeomsDropped`; with contact detection on, MuJoCo bounds them in its
broad phase too: measured per RK4 step, 3.7 µs of the idle model's 27.8 µs, 0.4 µs of the pruned model's 8.0 µs,
so the ratio is 3.3 × with them in both, 3.5 × pruned, 3.2 × with them in neither): the scene touches nothing
while nothing touches, so every collision test is work for nothing. Whether anything touches is not assumed, it
is bounded: along the pruned run, at every step, each geom pair MuJoCo's collision detection considers has a
clearance ``d`` (``mj_geomDistance`` less the contact margin) and a bound ``r`` of the rate at which it can shrink
(``|v| + |ω| r_bound`` of both geoms); over a step of length ``Δt`` the pair's clearance stays above
``(d_k + d_k+1)/2 − 1.1 max(r_k, r_k+1) Δt/2`` (the distance is Lipschitz with that rate; 1.1 covers the rate's
change within a 0.25 ms step). While that is positive for every pair, no contact can be made, the contact-on run
is the pruned run: contact is inferred idle over that interval (:func:`certified_contact_free`). The run with
contact on also records the first step at which MuJoCo finds a contact (and the pair); the ratio is measured over
the certified interval, where both trajectories must agree, and the whole horizon's disagreement is reported
beside it (a scene whose contact can act cannot be pruned).

Collision geometry: the ``<collision>`` meshes and boxes of ``example-robot-data``'s ``panda.urdf`` (the pinned package), each
on the body it moves with — ``panda_link0`` on the fixed base, ``panda_link1`` … ``panda_link7`` on theirs, the
hand (fixed joints ``panda_joint8``, ``panda_hand_joint``) and the fingers' collision boxes (held at the 1 mm
opening, as the model holds them) on ``panda_link7`` as the model lumps them. MuJoCo collides the meshes' convex
hulls; parent–child pairs are filtered (MuJoCo's default).
"""

from __future__ import annotations

import time

import numpy as np

from harness.scenes.phenomena.pruning import REPEATS

ROBOT, SCENE = "lightweight_robot", "fall"
CONTACT_GOAL = 3.0       # idle / pruned, MuJoCo on the robot with contact detection pruned (issue 17)
STEPS = 2000             # RK4 steps over the 0.5 s horizon (dt = 0.25 ms)
FLOOR = 0.0              # the floor through the base's origin, z = 0
EVERY = 10               # sample every 10 steps (2.5 ms)


def _transform(origin) -> np.ndarray:
    from harness.derivation.kinematics import rpy_rotation

    T = np.eye(4)
    if origin is None:
        return T
    xyz = [float(v) for v in origin.get("xyz", "0 0 0").split()]
    rpy = [float(v) for v in origin.get("rpy", "0 0 0").split()]
    T[:3, :3] = np.array(rpy_rotation(rpy), dtype=float)
    T[:3, 3] = xyz
    return T


def collision_geometry(urdf_path, bodies, held: dict) -> tuple[tuple, list[str]]:
    """``((body, shape, pos, quat), …)`` of every ``<collision>`` (mesh or box) of the URDF on the body of
    ``bodies`` (or ``world``, the root) it moves with through fixed joints and the ``held`` prismatic joints (at
    their values); and the links whose collision geometry is left out (another shape, or on a moving joint)."""
    import defusedxml.ElementTree as ET
    import mujoco

    root = ET.parse(str(urdf_path)).getroot()
    share = urdf_path.parents[3]   # …/share/example-robot-data/robots/<robot>/urdf/<file>
    parent_joint = {j.find("child").get("link"): j for j in root.findall("joint")}
    out, left_out = [], []
    for link in root.findall("link"):
        name, T, body = link.get("name"), np.eye(4), link.get("name")
        if not link.findall("collision"):
            continue
        while body not in bodies and body in parent_joint:
            joint = parent_joint[body]
            if joint.get("type") != "fixed" and joint.get("name") not in held:
                break
            step = _transform(joint.find("origin"))
            if joint.get("type") != "fixed":
                axis = joint.find("axis")
                step[:3, 3] += step[:3, :3] @ (held[joint.get("name")] *
                                               np.array([float(v) for v in axis.get("xyz").split()]))
            T = step @ T
            body = joint.find("parent").get("link")
        if body not in bodies and body not in parent_joint:
            body = "world"   # the fixed base (the root link)
        if body not in bodies and body != "world":
            left_out.append(name)
            continue
        for c in link.findall("collision"):
            M = T @ _transform(c.find("origin"))
            quat = np.zeros(4)
            mujoco.mju_mat2Quat(quat, M[:3, :3].ravel())
            mesh, box = c.find("geometry/mesh"), c.find("geometry/box")
            if mesh is not None:
                shape = ("mesh", share.parent / mesh.get("filename").replace("package://", ""))
            elif box is not None:
                shape = ("box", tuple(float(v) / 2 for v in box.get("size").split()))
            else:
                left_out.append(name)
                continue
            out.append((body, shape, tuple(float(v) for v in M[:3, 3]), tuple(float(v) for v in quat)))
    return tuple(out), left_out


DISTMAX = 0.05           # m: clearances above it are not computed exactly (mj_geomDistance's cap)
RATE_SLACK = 1.1         # the shrink rate's change within a step (see the module docstring)


def certified_contact_free(model, q0, qd0, steps: int) -> tuple[int, tuple[str, str] | None]:
    """The number of steps from ``(q0, qd0)`` over which ``model`` (contact detection pruned) provably makes no
    contact (see the module docstring), and the geom pair whose bound ends it (None: the whole ``steps``)."""
    pairs = model.collision_pairs()
    model.reset()
    model.set_state(q0, qd0)
    dt = float(model.model.opt.timestep)

    def clearance(k):
        model.forward()
        return model.clearance(pairs, DISTMAX)

    samples = model.rollout(steps, 1, clearance)
    for k in range(steps):
        (d0, r0), (d1, r1) = samples[k], samples[k + 1]
        bound = (d0 + d1) / 2 - RATE_SLACK * np.maximum(r0, r1) * dt / 2
        if np.min(bound) <= 0:
            a, b = pairs[int(np.argmin(bound))]
            return k, (model.geom_name(a), model.geom_name(b))
    return steps, None


def task(catalogue, repeats: int = REPEATS) -> dict:
    """Contact detection on (idle: nothing touches) against pruned (the collision geometry dropped,
    ``mjDSBL_CONTACT``), MuJoCo's own RK4; ``repeats`` runs of each, alternating, in this process: the ratio the
    median of the pairs' with its ≥ 99.5 % interval (:func:`~harness.scenes.phenomena.pruning.ratio_interval`), the
    seconds the fastest of each."""
    from harness.engines.mujoco_engine import CollisionMeshes, MujocoModel, Options, VisualGeomsDropped
    from harness.scenes.phenomena.pruning import paired, price, undecided
    from harness.export.numeric import instantiate
    from harness.scenes import simulate as sim

    system, robot = catalogue.get(ROBOT), catalogue.module(ROBOT)
    scene = next(s for s in catalogue.scenes(ROBOT) if s.name == SCENE)
    tree = instantiate(system, system.default_parameters())
    held = {"panda_finger_joint1": robot.FINGER_OPENING, "panda_finger_joint2": robot.FINGER_OPENING}  # mimic
    meshes, left_out = collision_geometry(robot.urdf_file(), {link.name for link in tree.links}, held)
    dt = scene.horizon / STEPS
    base = (CollisionMeshes(meshes, floor=FLOOR), Options(timestep=dt, integrator="RK4"))
    idle = MujocoModel(tree, transforms=base + (Options(enable=("contact", "constraint")),),
                       where="MjSpec.compile (collision meshes)")
    # pruned in MuJoCo's terms: the collision geometry dropped and mjDSBL_CONTACT set (the flag alone still poses
    # the 18 collision geoms at every stage: 2.84 x instead of 3.15 x, measured), the unread visual geoms dropped;
    # the certificate needs the geometry
    probe = MujocoModel(tree, transforms=base + (Options(enable=("contact", "constraint"), disable=("contact",)),),
                        where="MjSpec.compile (collision meshes, contact disabled: the clearances)")
    lean = MujocoModel(tree, transforms=(base[1], Options(disable=("contact",)), VisualGeomsDropped()),
                       where="MjSpec.compile (collision geometry dropped, contact pruned)")

    def run(model, steps, stop_at_contact=False):
        model.reset()
        model.set_state(np.asarray(scene.q0, float), np.asarray(scene.qd0, float))
        first = [None]

        data = model.data

        def sample(k):  # MuJoCo's state as it is; picked to our joints after the timing (measured: 7.6 µs a sample
            return data.time, data.qpos.copy(), data.qvel.copy()   # read through theta(), 9 % of a pruned run)

        def between(k):  # after mj_step1's collision detection: the first step with a contact
            if first[0] is None and model.data.ncon:
                first[0] = k

        start = time.perf_counter()
        out = model.rollout(steps, EVERY, sample, between=between if stop_at_contact else None,
                            check=f"{ROBOT} {SCENE} (contact pruning)")
        seconds = time.perf_counter() - start
        tr = sim.Trajectory("mujoco", np.array([x[0] for x in out]), np.array([x[1][model.qpos_index] for x in out]),
                            np.array([x[2][model.dof_index] for x in out]), seconds, steps)
        return tr, first[0]

    # the scene with contact on: where does the arm first touch itself or the floor?
    whole, first = run(idle, STEPS, stop_at_contact=True)
    pairs = []
    if first is not None:
        idle.reset()
        idle.set_state(np.asarray(scene.q0, float), np.asarray(scene.qd0, float))
        idle.rollout(first + 1)
        idle.forward()
        pairs = sorted({tuple(sorted((idle.geom_name(c.geom1), idle.geom_name(c.geom2))))
                        for c in idle.data.contact[:idle.data.ncon]})
    certified, ends_at = certified_contact_free(probe, np.asarray(scene.q0, float), np.asarray(scene.qd0, float),
                                                STEPS)
    free = (certified // EVERY) * EVERY   # contact provably idle: the samples before its bound ends
    lean_runs, idle_runs = paired(lambda: run(lean, free)[0], lambda: run(idle, free)[0], repeats,
                                  undecided(CONTACT_GOAL, runs=True))
    pruned_whole = run(lean, STEPS)[0]
    return {"system": ROBOT, "scene": SCENE, "source": "mujoco", "method": f"mj_step RK4, dt={dt:g}",
            "collision_geoms": len(meshes), "meshes": sum(g[1][0] == "mesh" for g in meshes), "left_out": left_out,
            "first_contact": None if first is None else first * dt, "first_contact_pairs": pairs,
            "certified_contact_free": certified * dt, "certificate_ends_at": list(ends_at or ()),
            "collision_pairs": len(probe.collision_pairs()), "pruned_geoms": lean.model.ngeom,
            "whole_horizon_error": sim.max_error(whole, pruned_whole),
            "measured_horizon": free * dt,
            **price([tr.seconds for tr in lean_runs], [tr.seconds for tr in idle_runs]),
            "error": sim.max_error(idle_runs[0], lean_runs[0]), "repeats": len(lean_runs)}
