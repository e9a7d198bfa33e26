"""What every engine adapter takes (a :class:`State`) and gives (an :class:`Evaluation`), the map of
tree-joint quantities to lecture coordinates by virtual work (5.58)-(5.60), and what the tree engines share
(:class:`TreeEngine`: the interface; the springs, dampers, inputs and loads formed from an engine's own point
positions and Jacobians; the Christoffel C by polarization of a bias that is quadratic in the velocity)."""

from __future__ import annotations

import contextlib
import math
import os
import sys
import tempfile
from dataclasses import dataclass, field
from functools import cache, cached_property
from typing import NamedTuple

import numpy as np
import sympy as sp

from harness import limits
from harness.derivation.compile import call_floats, compiled, float_function
from harness.errors import InputError
from harness.export.numeric import NumericTree, exact_key, instantiate
from harness.modeling.system import WORLD, System


@dataclass(frozen=True)
class State:
    """A system at ``(q, q̇)`` with parameter values and inputs, all in lecture coordinates and names."""

    system: System
    q: np.ndarray
    qd: np.ndarray
    params: dict
    u: dict

    @staticmethod
    def make(system: System, q, qd=None, params: dict | None = None, u: dict | None = None) -> "State":
        n = len(system.coordinates)
        qd = np.zeros(n) if qd is None else qd
        names = ", ".join(c.name for c in system.coordinates)
        for label, vec in (("q", q), ("qd", qd)):
            if len(vec) != n:
                raise InputError(f"{system.name}: --{label} needs {n} value(s) ({names}), got {len(vec)}")
            if not all(math.isfinite(float(v)) for v in vec):
                raise InputError(f"{system.name}: --{label} must be finite numbers, got {list(vec)}")
            if any(abs(float(v)) > limits.MAGNITUDE for v in vec):
                raise InputError(f"{system.name}: --{label} {list(vec)}: exceeds {limits.MAGNITUDE:g} in magnitude "
                                 "(harness.limits.MAGNITUDE: results would overflow)")
        values = system.default_parameters()
        for name, value in (params or {}).items():
            system.parameter(name).check(float(value))
            try:
                limits.check_magnitude(f"parameter {name}", float(value))
            except ValueError as exc:
                raise InputError(f"{system.name}: {exc}") from None
            values[name] = float(value)
        inputs = {i.name: 0.0 for i in system.inputs}
        for name, value in (u or {}).items():
            if name not in inputs:
                known = ", ".join(inputs) or "none"
                raise InputError(f"{system.name}: unknown input {name!r} (inputs: {known})")
            if not math.isfinite(float(value)):
                raise InputError(f"{system.name}: input {name} must be finite")
            if abs(float(value)) > limits.MAGNITUDE:
                raise InputError(f"{system.name}: input {name}={value!r}: exceeds {limits.MAGNITUDE:g} in magnitude")
            inputs[name] = float(value)
        state = State(system, np.asarray(q, dtype=float), np.asarray(qd, dtype=float), values, inputs)
        state.tree  # instantiating checks that masses and inertia tensors are physical
        return state

    @property
    def p(self) -> np.ndarray:
        return np.array([self.params[p.name] for p in self.system.parameters])

    @property
    def u_vec(self) -> np.ndarray:
        return np.array([self.u[i.name] for i in self.system.inputs])

    @cached_property
    def tree(self) -> NumericTree:
        return instantiate(self.system, self.params)

    @cached_property
    def parameters_key(self) -> tuple:
        """The parameter values' exact bits (:func:`~harness.export.numeric.exact_key`)."""
        return exact_key(self.params)

    @cached_property
    def key(self) -> tuple:
        """The state's identity: the system object and every number's exact bits (``-0.0`` is not ``0.0``)."""
        return (id(self.system), self.q.tobytes(), self.qd.tobytes(), self.parameters_key, exact_key(self.u))

    # ----- the map theta = phi(q)
    @cached_property
    def _map(self):
        c = compiled(self.system)
        args = (self.q, self.qd, self.p, self.u_vec)
        return c("phi", *args).ravel(), c("J_phi", *args), c("J_phi_dot", *args)

    @property
    def theta(self) -> np.ndarray:
        return self._map[0]

    @property
    def J(self) -> np.ndarray:
        """``J = ∂phi/∂q``."""
        return self._map[1]

    @property
    def J_dot(self) -> np.ndarray:
        return self._map[2]

    @property
    def theta_dot(self) -> np.ndarray:
        return self.J @ self.qd

    @cached_property
    def loads(self) -> list["Load"]:
        """External forces and torques of the model (PointForce, BodyTorque) with their components
        evaluated at this state; each engine turns them into generalized forces with its own Jacobians."""
        return evaluated_loads(load_functions(self.system), self.q, self.qd, self.p, self.u_vec)


@dataclass(frozen=True)
class Loads:
    """The external loads of a system (PointForce, BodyTorque): ``(kind, point or link, frame)`` of each
    (``entries``), and the components of all of them, three a load in that order, as one compiled function of
    ``(q, q̇, p, u)`` on Python floats (``components``, :func:`~harness.derivation.compile.float_function`; None
    without loads). One call for every load: a NumPy function per load cost 2.9 µs a call, most of it its own call
    and the array it built (two_mass_oscillator's two torques: 7.8 µs, one call of all 1.9 µs)."""

    entries: tuple
    components: object = None

    def __len__(self) -> int:
        return len(self.entries)

    def __iter__(self):
        return iter(self.entries)

    def __getitem__(self, k):
        return self.entries[k]


@cache
def load_functions(system: System) -> Loads:
    """The external loads of ``system`` (:class:`Loads`), compiled once."""
    from harness.export.numeric import point_name
    from harness.modeling.system import BodyTorque, PointForce

    entries, components = [], []
    for f in system.forces:
        if isinstance(f, PointForce):
            entries.append(("force", point_name(f.point), f.frame))
            components += list(f.force)
        elif isinstance(f, BodyTorque):
            entries.append(("torque", f.link, f.frame))
            components += list(f.torque)
    return Loads(tuple(entries), float_function(system, components) if entries else None)


def evaluated_loads(loads: Loads, q, qd, p, u) -> list["Load"]:
    """The external loads ``loads`` (:func:`load_functions`) with their components at ``(q, q̇, p, u)``."""
    if not loads.entries:
        return []
    values = np.array(call_floats(loads.components, 3 * len(loads), q, qd, p, u), dtype=float)
    return [Load(kind, where, frame, values[3 * k:3 * k + 3]) for k, (kind, where, frame) in enumerate(loads)]


def loads_read_state(system: System) -> bool:
    """Whether an external load of ``system`` depends on ``q`` or ``q̇`` (a drag, a road force); one that does not
    (a rope's pull, a load torque: inputs and parameters alone) is evaluated without the lecture state."""
    from harness.modeling.system import BodyTorque, PointForce

    state = set(system.q) | set(system.qd)
    return any(sp.sympify(c).free_symbols & state for f in system.forces if isinstance(f, (PointForce, BodyTorque))
               for c in (f.force if isinstance(f, PointForce) else f.torque))


class Load(NamedTuple):
    """A force at a named point, or a torque on a link, components in ``frame`` (world or a link). A named tuple:
    made at every call of a simulation's right-hand side, in a third of a frozen dataclass's time."""

    kind: str
    where: str
    frame: str
    vector: np.ndarray


@dataclass
class Evaluation:
    """Quantities in lecture coordinates. ``C`` is the Christoffel C where the engine gives it, else None.
    ``calls`` names the engine calls that produced the numbers."""

    engine: str
    M: np.ndarray
    Cqd: np.ndarray
    g: np.ndarray
    g_gravity: np.ndarray
    g_spring: np.ndarray
    f_damper: np.ndarray
    qdd: np.ndarray
    C: np.ndarray | None = None
    extra: dict = field(default_factory=dict)
    calls: dict = field(default_factory=dict)


@dataclass
class TreeQuantities:
    """An engine's numbers in its own tree joint coordinates ``theta`` (ordered as ``System.joints``)."""

    M: np.ndarray                  # M_theta
    Cqd: np.ndarray                # (C theta_dot)_theta
    g_gravity: np.ndarray
    g_spring: np.ndarray           # = -(spring generalized forces)
    f_damper: np.ndarray
    tau_input: np.ndarray          # generalized forces of the inputs
    qdd: np.ndarray | None         # theta_ddot from the engine's forward dynamics with the inputs
    C: np.ndarray | None = None    # Christoffel C_theta, = ½ ∂(C theta_dot)/∂theta_dot
    extra: dict = field(default_factory=dict)
    calls: dict = field(default_factory=dict)


def coriolis_to_lecture(state: State, M_theta: np.ndarray, C_theta: np.ndarray) -> np.ndarray:
    """``C_q = Jᵀ (M_θ J̇ + C_θ J)``: half the q̇-derivative of the mapped ``C q̇`` (quadratic in q̇)."""
    return state.J.T @ (M_theta @ state.J_dot + C_theta @ state.J)


def to_lecture(engine: str, state: State, t: TreeQuantities) -> Evaluation:
    """Bring tree-joint quantities to lecture coordinates with ``J = ∂phi/∂q`` (5.58)-(5.60):
    ``M_q = Jᵀ M J``, ``(C q̇)_q = Jᵀ (M J̇ q̇ + C θ̇)``, ``g_q = Jᵀ g``, ``C_q = Jᵀ (M J̇ + C_θ J)``.
    Forward dynamics: ``q̈ = J⁻¹ (θ̈ − J̇ q̇)`` when the map is square, else solved from the mapped terms."""
    J, Jd, qd = state.J, state.J_dot, state.qd
    M, Cqd, g_gravity, g_spring, f_damper = terms = _mapped_terms(state, t)
    C = None if t.C is None else coriolis_to_lecture(state, t.M, t.C)
    qdd = _mapped_qdd(state, t, *terms)
    # The map multiplies the tree's round-off: scales of the mapped terms (|J|, |J̇| times the tree terms),
    # used by the tolerance policy so that a large J (a small rolling radius) is not mistaken for an error.
    a, ad = _max_abs(J), _max_abs(Jd)
    extra = dict(t.extra)
    extra["map_scale"] = {"M": a * a * _max_abs(t.M),
                          # C_θ is made of terms of size |M_θ| |θ̇| even where they cancel (a pulley turning
                          # about its centre of mass: C_θ = 0 up to Pinocchio's round-off of m v ω terms)
                          "C": max(a * a * _max_abs(t.C) + a * ad * _max_abs(t.M),
                                   _max_abs(np.abs(J).T @ np.abs(t.M) @ np.abs(J)) * max(1.0, _max_abs(J @ qd)),
                                   _polarized_gravity(J, t.extra.get("C_subtracted"))),
                          # an engine that forms C θ̇ as bias(θ̇) − bias(0) (nonLinearEffects − gravity, qfrc_bias(v)
                          # − qfrc_bias(0)) leaves the round-off of the gravity it subtracts: Cqd_subtracted
                          "Cqd": a * (_max_abs(t.M) * ad * _max_abs(qd) + _max_abs(t.Cqd)
                                      + t.extra.get("Cqd_subtracted", 0.0)),
                          "g": a * max(_max_abs(t.g_gravity), _max_abs(t.g_spring)),
                          "g_spring": a * _max_abs(t.g_spring), "f_damper": a * _max_abs(t.f_damper)}
    return Evaluation(engine, M, Cqd, g_gravity + g_spring, g_gravity, g_spring, f_damper, qdd, C,
                      extra=extra, calls=dict(t.calls))


def _polarized_gravity(J, subtracted) -> float:
    """The round-off a ``C`` polarized from a bias with gravity keeps (MuJoCo's ``qfrc_bias(v ± s e_j)``,
    ``C_subtracted`` = ``|g_θ| / s`` per tree coordinate, :func:`polarization_step`): entry ``(i, j)`` of ``C_θ`` carries
    ``ε |g_i| / s``, and ``C_q = Jᵀ C_θ J`` sums it into ``(|J|ᵀ |g| / s)_k (Σ_i |J_il|)``; 0 without. Measured on the
    ball on the beam (``r_K`` = 0.05 m, at rest): MuJoCo's ``C`` off by 8.5e-14, this bound times ε 8.7e-14."""
    if subtracted is None:
        return 0.0
    J = np.abs(J)
    return float(np.outer(J.T @ np.asarray(subtracted), J.sum(axis=0)).max(initial=0.0))


def _mapped_terms(state: State, t: TreeQuantities) -> tuple:
    """``M_q = Jᵀ M J``, ``(C q̇)_q = Jᵀ (M J̇ q̇ + C θ̇)``, ``g_gravity``, ``g_spring``, ``f_damper`` mapped by ``Jᵀ``."""
    J, Jd, qd = state.J, state.J_dot, state.qd
    return (J.T @ t.M @ J, J.T @ (t.M @ (Jd @ qd) + t.Cqd), J.T @ t.g_gravity, J.T @ t.g_spring,
            J.T @ t.f_damper)


def _mapped_qdd(state: State, t: TreeQuantities, M, Cqd, g_gravity, g_spring, f_damper) -> np.ndarray:
    """``q̈ = J⁻¹ (θ̈ − J̇ q̇)`` of a square map, else (5.93) in ``q`` from the mapped terms."""
    J = state.J
    if t.qdd is not None and J.shape[0] == J.shape[1]:
        return np.linalg.solve(J, t.qdd - state.J_dot @ state.qd)
    # more tree joints than lecture coordinates: the map is a constraint
    return np.linalg.solve(M, J.T @ t.tau_input + f_damper - Cqd - g_gravity - g_spring)


def _max_abs(x) -> float:
    return float(np.abs(x).max()) if x is not None and np.size(x) else 0.0


# --------------------------------------------------------------------------------------------- tree engines
class TreeEngine:
    """One tree loaded in one engine, seen through named one-degree-of-freedom joints in our order (``θ``).

    An adapter is built from our exported text of a :class:`NumericTree` (``Engine(tree)``, or
    ``Engine(tree, text)`` for another text) or, without a tree, from a model the engine has already loaded and
    the names of the joints to look through (``Engine.loaded(model, joints)``, for files of other origin:
    :mod:`harness.files.importer`). Every number comes from a named engine call, recorded in ``calls``.

    Class attributes: ``name`` (the registry key and the source of its checks), ``reads`` (the exported text it
    loads: ``"URDF"`` or ``"MJCF"``), ``integrators`` (its own time stepping, :meth:`rollout`; empty for an
    engine that only gives the dynamics), ``natively`` (the scene phenomena it simulates itself, beyond the
    forward dynamics every engine gives: ``"stepping"``, ``"dry friction"``, ``"contact"``, ``"soft
    constraints"``, ``"kkt constraints"``; the scene code asks for a phenomenon, never for an engine by name)."""

    name: str = ""
    reads: str = ""
    integrators: tuple = ()
    natively: frozenset = frozenset()
    tree: NumericTree | None = None

    @classmethod
    def applies(cls, system: System) -> str | None:
        """``None`` when the engine applies to ``system``, else the reason it does not
        (``System.not_in_engines``)."""
        return system.engine_note(cls.name)

    @classmethod
    def simulates(cls, phenomenon: str) -> bool:
        """Whether the engine simulates ``phenomenon`` itself (one of :attr:`natively`)."""
        return phenomenon in cls.natively

    @property
    def label(self) -> str:
        """What error messages name: the system of the tree, or the engine for a model loaded without one."""
        return self.tree.system if self.tree is not None else self.name

    def quantities(self, theta, theta_dot, u: dict, loads=(), christoffel: bool = True) -> TreeQuantities:
        """Everything in tree coordinates; ``christoffel=False`` skips the Coriolis matrices (simulation)."""
        raise NotImplementedError

    def forward_dynamics(self, theta, theta_dot, u: dict, loads=()) -> np.ndarray:
        """``θ̈`` alone, the call a simulation makes."""
        return self.quantities(theta, theta_dot, u, loads, christoffel=False).qdd

    def mass_and_forces(self, theta, theta_dot, u: dict, loads=(), acceleration=None) -> tuple[np.ndarray, np.ndarray]:
        """``(M, h)`` of ``M θ̈ = h`` in tree coordinates, ``h = τ_input + f_damper − C θ̇ − g_gravity − g_spring``:
        what a simulation through a map with more tree joints than lecture coordinates projects (5.58–5.60). With
        ``acceleration`` ``a`` (the map's ``J̇ q̇``), ``h − M a``: the balance at ``θ̈ = J q̈ + a`` is
        ``M J q̈ = h − M a``."""
        t = self.quantities(theta, theta_dot, u, loads, christoffel=False)
        h = t.tau_input + t.f_damper - t.Cqd - t.g_gravity - t.g_spring
        return t.M, h if acceleration is None else h - t.M @ acceleration

    def evaluate(self, state: State) -> Evaluation:
        """The quantities at ``state`` in lecture coordinates (:func:`to_lecture`)."""
        return to_lecture(self.name, state, self.quantities(state.theta, state.theta_dot, state.u, state.loads))


def polarization_step(theta_dot) -> float:
    """The step ``s`` of :func:`polarization`: ``max(1, |θ̇|)``. A bias that holds gravity (MuJoCo's ``qfrc_bias``)
    leaves its round-off in ``C`` divided by ``2 s``: ``|g| / s`` is what the polarization subtracts per unit step."""
    return max(1.0, float(np.max(np.abs(theta_dot)))) if len(theta_dot) else 1.0


def polarization(bias, theta_dot) -> np.ndarray:
    """The Christoffel ``C = ½ ∂(C θ̇)/∂θ̇`` from an engine's bias ``b(v)`` (``C(θ, v) v`` plus terms that do not
    depend on ``v``): ``b`` is exactly quadratic in ``v``, so ``C e_j = (b(v + s e_j) − b(v − s e_j)) / (4 s)``
    holds for any step ``s`` with no truncation error, only round-off (not a finite-difference approximation)."""
    n = len(theta_dot)
    step = polarization_step(theta_dot)
    C = np.zeros((n, n))
    for j in range(n):
        e = np.zeros(n)
        e[j] = step
        C[:, j] = (bias(theta_dot + e) - bias(theta_dot - e)) / (4 * step)
    return C


def spring_damper_forces(tree: NumericTree, nv: int, q, v, position, jacobian, q_index: dict, v_index: dict):
    """Generalized forces ``(f_spring, f_damper)`` in an engine's own order: tendons (springs/dampers between
    points) ``Σ J_bᵀ f − J_aᵀ f`` from the engine's point positions ``position(point)`` (world) and
    translational Jacobians ``jacobian(point)`` (``3 x nv``), joint springs and dampers at the engine's
    position and velocity indices of each joint. A tendon's spring or damper that is not in the model (None, a
    spring alone between its points) is not evaluated; one of stiffness or damping 0 is, as any other."""
    f_spring = np.zeros(nv)
    f_damper = np.zeros(nv)
    for name, a, b, stiffness, rest, damping in tree.tendons:
        r = position(b) - position(a)
        length = math.sqrt(r @ r)                             # np.linalg.norm's own formula, without its checks
        moment = r @ (jacobian(b) - jacobian(a))              # length ∂length/∂θ = rᵀ (J_b − J_a): one product
        if stiffness is not None:                             # f = −c (length − rest) ∂length/∂θ
            f_spring -= (stiffness * (length - rest) / length) * moment
        if damping is not None:                               # f = −d (∂length/∂θ θ̇) ∂length/∂θ
            f_damper -= (damping * float(moment @ v) / (length * length)) * moment
    for joint, (stiffness, rest) in tree.joint_stiffness.items():
        f_spring[v_index[joint]] += -stiffness * (q[q_index[joint]] - rest)
    for joint, damping in tree.joint_damping.items():
        k = v_index[joint]
        f_damper[k] += -damping * v[k]
    return f_spring, f_damper


def input_forces(tree: NumericTree, nv: int, u: dict, loads, v_index: dict, rotation, point_jacobian,
                 angular_jacobian) -> np.ndarray:
    """Inputs on joints, and external forces/torques by (5.73) in an engine's own order: a force at a point
    through the point's translational Jacobian ``point_jacobian(point)``, a torque on a link through its angular
    Jacobian ``angular_jacobian(link)`` (both ``3 x nv``, world axes), components in a link's frame turned to
    world axes by ``rotation(link)``."""
    tau = np.zeros(nv)
    for input_name, joint in tree.actuators:
        tau[v_index[joint]] += u[input_name]
    for load in loads:
        vector = load.vector if load.frame == WORLD else rotation(load.frame) @ load.vector
        J = point_jacobian(load.where) if load.kind == "force" else angular_jacobian(load.where)
        tau += J.T @ vector
    return tau


@contextlib.contextmanager
def captured_output():
    """Capture what C libraries print on file descriptors 1 and 2 (urdfdom's ``Error: …`` lines, MuJoCo's
    compiler) while loading; yields a list that holds the text afterwards."""
    sys.stdout.flush()
    sys.stderr.flush()
    text: list[str] = []
    saved = [os.dup(1), os.dup(2)]
    with tempfile.TemporaryFile(mode="w+b") as tmp:
        try:
            os.dup2(tmp.fileno(), 1)
            os.dup2(tmp.fileno(), 2)
            yield text
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])
            tmp.seek(0)
            text.append(tmp.read().decode(errors="replace"))


def one_line(message: str) -> str:
    return "; ".join(line.strip() for line in str(message).splitlines() if line.strip())


# --------------------------------------------------------------------------------------------- floating bases
FREE_JOINT = "root_joint"
"""Name of the free-flyer joint of a floating base loaded from a URDF of other origin: Pinocchio's default name for
a root joint, given to MuJoCo's free joint too, so that the base is matched by name like every other joint."""


@dataclass(frozen=True)
class Base:
    """State of a floating base in Pinocchio's free-flyer convention, the one every adapter reports in:
    position of the root link's frame in the world, its orientation as a unit quaternion (x, y, z, w) and its
    spatial velocity in the local frame (linear velocity of the frame's origin, then angular velocity, both in
    the root link's axes)."""

    position: np.ndarray
    quat_xyzw: np.ndarray
    velocity: np.ndarray

    @staticmethod
    def rest() -> "Base":
        return Base(np.zeros(3), np.array([0.0, 0.0, 0.0, 1.0]), np.zeros(6))

    def at_rest(self) -> "Base":
        """The same placement, velocity zero."""
        return Base(self.position, self.quat_xyzw, np.zeros(6))

    def record(self) -> dict:
        return {"position": self.position.tolist(), "quat_xyzw": self.quat_xyzw.tolist(),
                "velocity_local": self.velocity.tolist()}
