"""``harness validate FILE``: check a user's own URDF or MJCF and load it in the engines, with a short report.

Steps (the first failure is one :class:`~harness.errors.HarnessError` line, exit 2 in the CLI):

1. safe parse and checks of :mod:`harness.files.untrusted` (no DTD/entities, files inside the model's folder, every
   number a plain finite decimal);
2. physical inertials (URDF): mass non-negative, inertia tensor positive semi-definite with principal moments
   satisfying the triangle inequality (3.128), the check our exporter applies
   (:func:`harness.export.numeric.check_inertia`); MuJoCo's compiler checks an MJCF's own inertials;
3. load: a URDF in Pinocchio (``buildModelFromXML``) and in MuJoCo's URDF importer, an MJCF in MuJoCo. What
   the engines print themselves (urdfdom's ``Error: …``, MuJoCo's compiler) is captured into that one line.
   MuJoCo's importer gets the URDF without ``<visual>``/``<collision>``: the dynamics do not depend on them and
   it cannot resolve ``package://`` URIs; a URDF it refuses as is (a point mass, a massless moving link) is
   loaded with MuJoCo's lower bound on masses and inertias, and the report says so. An MJCF that refers to files is compiled from its path (MuJoCo
   resolves them from the model's folder) after the checks;
4. MuJoCo steps the model for :data:`STEP_SECONDS` with zero controls: a warning counter (unstable, bad qacc,
   …) is an :class:`~harness.errors.EngineError`;
5. a URDF with only 1-dof joints: MuJoCo's import compared with Pinocchio (:func:`harness.files.importer.compare`,
   mass matrix, bias forces, what every joint moves, at random states). A difference is a finding: exit 1.

The work is bounded before any engine sees the file (:func:`harness.files.untrusted.check_work`, the counts of
:mod:`harness.limits`), and ``harness validate`` runs steps 3-5 in a child process (:func:`validate_isolated`)
with a time limit (:data:`~harness.limits.COMPILE_SECONDS`) and an address-space limit
(:data:`~harness.limits.COMPILE_MEMORY_BYTES`): whatever the engines do with a file, the command ends with
one line.
"""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

from typing import TYPE_CHECKING

import numpy as np

from harness.files import importer
from harness.files import untrusted
from harness import limits
from harness.engines.mujoco_engine import MujocoModel, compile_text
from harness.engines.pinocchio_engine import PinocchioModel, check_moves_mass, load_urdf, moving_joints
from harness.errors import EngineError, HarnessError, InputError, ModelError
from harness.export.numeric import check_inertia
from harness.compare.roundtrip import rpy_matrix

if TYPE_CHECKING:
    import mujoco

STEP_SECONDS = 1.0
MAX_STEPS = limits.MJCF_STEPS
"""At most this many ``mj_step`` calls (a model's own ``timestep`` below 50 µs shortens the 1 s run): a file
cannot make ``validate`` hang."""


@dataclass
class Validation:
    """What ``harness validate`` found: the facts of each engine's load and the comparison's findings."""

    source: str
    kind: str
    engines: dict[str, dict] = field(default_factory=dict)
    comparison: dict | None = None
    findings: list[str] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return not self.findings

    def lines(self) -> list[str]:
        out = [f"{self.source}: {self.kind.upper()}, parsed safely, numbers finite, files inside its folder"]
        for engine, facts in self.engines.items():
            out.append(f"  {engine}: " + "; ".join(f"{k}: {v}" for k, v in facts.items()))
        if self.comparison is not None:
            worst, checks = {}, self.comparison["checks"]
            for c in checks:
                worst[c["quantity"]] = max(worst.get(c["quantity"], 0.0), c["max_error"])
            bounded = ", plus what the compiler's bound may move it by" if any(c["allowance"] for c in checks) else ""
            out.append(f"  MuJoCo's import vs Pinocchio ({self.comparison['states']} random states): "
                       + ", ".join(f"{q} {e:.1e}" for q, e in worst.items())
                       + f" (tolerance {importer.TOLERANCE:.0e} of each one's scale{bounded}; the largest at "
                       + f"{max((c['ratio'] for c in checks), default=0.0):.2g} of what is allowed)")
        out += [f"  FINDING {f}" for f in self.findings]
        out.append("valid" if self.passed else f"{len(self.findings)} finding(s)")
        return out

    def to_json(self) -> dict:
        return {"source": self.source, "kind": self.kind, "engines": self.engines, "comparison": self.comparison,
                "findings": self.findings, "passed": self.passed}


def _floats(el, attr, default):
    value = el.get(attr) if el is not None else None
    return np.array([float(t) for t in value.split()]) if value is not None else np.array(default, dtype=float)


def check_urdf_inertials(model: untrusted.ModelFile) -> None:
    """Every ``<link><inertial>``: non-negative mass, physical inertia tensor (check_inertia)."""
    for link in model.root.iter("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        mass_el, inertia_el = inertial.find("mass"), inertial.find("inertia")
        where = f"{model.where(inertial)}: <inertial> of link '{link.get('name')}'"
        if mass_el is None or inertia_el is None:
            raise ModelError(f"{where}: needs <mass> and <inertia> (urdfdom would drop it)")
        v = {k: float(inertia_el.get(k)) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
        tensor = np.array([[v["ixx"], v["ixy"], v["ixz"]], [v["ixy"], v["iyy"], v["iyz"]],
                           [v["ixz"], v["iyz"], v["izz"]]])
        R = rpy_matrix(_floats(inertial.find("origin"), "rpy", [0, 0, 0]))
        check_inertia(where, float(mass_el.get("value")), R @ tensor @ R.T)


def check_urdf_tree(model: untrusted.ModelFile) -> None:
    """The links and joints form one tree: names unique, every joint between two defined links, each link the
    child of at most one joint, one root, no cycle. Each refusal names the link or joint (urdfdom's own
    message for some of these is "The XML stream does not contain a valid URDF model")."""
    links: dict[str, object] = {}
    for el in model.root.findall("link"):
        name = el.get("name")
        if name in links:
            raise ModelError(f"{model.where(el)}: link {name!r} is defined twice (first at line "
                             f"{links[name].sourceline}): link names must be unique")
        links[name] = el
    parent_of: dict[str, tuple[str, str]] = {}  # child link -> (joint, parent link)
    joints: dict[str, object] = {}
    for el in model.root.findall("joint"):
        name = el.get("name")
        if name in joints:
            raise ModelError(f"{model.where(el)}: joint {name!r} is defined twice: joint names must be unique")
        joints[name] = el
        ends = {}
        for end in ("parent", "child"):
            ref = el.find(end)
            link = ref.get("link") if ref is not None else None
            if link is None:
                raise ModelError(f"{model.where(el)}: joint {name!r} has no <{end} link=…>")
            if link not in links:
                raise ModelError(f"{model.where(el)}: joint {name!r} names {end} link {link!r}, which is not defined")
            ends[end] = link
        if ends["child"] in parent_of:
            raise ModelError(f"{model.where(el)}: link {ends['child']!r} is the child of two joints "
                             f"({parent_of[ends['child']][0]!r} and {name!r}): a URDF is a tree, a closed loop of "
                             "joints is not allowed")
        if ends["child"] == ends["parent"]:
            raise ModelError(f"{model.where(el)}: joint {name!r} connects link {ends['child']!r} to itself")
        parent_of[ends["child"]] = (name, ends["parent"])
    roots = [name for name in links if name not in parent_of]
    if not roots and links:
        first = next(iter(links))
        raise ModelError(f"{model.source}: the joints form a cycle through link {first!r}: no root link")
    if len(roots) > 1:
        raise ModelError(f"{model.source}: links {roots[0]!r} and {roots[1]!r} are both roots (not connected by "
                         "a joint): a URDF is one tree")
    for name in links:  # with one parent each and one root, a link not reaching the root lies on a cycle
        seen, link = set(), name
        while link in parent_of:
            if link in seen:
                raise ModelError(f"{model.source}: link {link!r} lies on a cycle of joints "
                                 f"(through joint {parent_of[link][0]!r}): a URDF is a tree")
            seen.add(link)
            link = parent_of[link][1]


def _loaded_and_stepped(model: "mujoco.MjModel", source: str) -> dict:
    """What MuJoCo loaded, and :data:`STEP_SECONDS` of its own stepping with zero controls."""
    if not model.opt.timestep > 0:
        raise ModelError(f"{source}: <option timestep={model.opt.timestep:g}> must be positive")
    mm = MujocoModel.loaded(model, [])
    steps = min(MAX_STEPS, int(round(STEP_SECONDS / model.opt.timestep)))
    mm.rollout(steps, check=f"{source}: {steps} x mj_step with zero controls")
    return {**mm.facts(), "steps": f"{steps} x mj_step ({mm.time:g} s), no warnings"}


def validate(path: Path | str, root: Path | str | None = None, states: int = importer.STATES,
             seed: int = importer.SEED) -> Validation:
    path = Path(path)
    model = untrusted.read_model(path, root)
    result = Validation(str(path), model.kind)
    if model.kind == untrusted.URDF:
        check_urdf_tree(model)
        check_urdf_inertials(model)
        pmodel = load_urdf(model.text, str(path))
        check_moves_mass(pmodel, str(path), seed)
        result.engines["Pinocchio"] = PinocchioModel.loaded(pmodel, []).facts()
        mj, refused, bound = importer.load_import(importer.without_geometry(model.text, str(path)),
                                                  f"{path} (MuJoCo's URDF importer)")
        facts = {"refused as is": refused, "loaded with": importer.BOUND_NOTE} if refused else {}
        result.engines["MuJoCo (URDF importer)"] = {**_loaded_and_stepped(mj, str(path)), **facts}
        try:
            reference = PinocchioModel.loaded(pmodel, moving_joints(pmodel))
        except ModelError as exc:
            result.engines["comparison"] = {"skipped": str(exc)}
        else:
            joints, prismatic = reference.joints, reference.prismatic
            imported = MujocoModel.loaded(mj, joints)
            imported.set_gravity(reference.gravity)
            checks = importer.compare(imported, reference, joints, prismatic, states, seed, bound)
            result.comparison = {"states": states, "seed": seed, "checks": checks}
            result.findings = [importer.finding(c) for c in checks if not c["passed"]]
    else:
        refers_to_files = bool(untrusted.check_uris(model, root)) or bool(model.includes)
        mj_path = path if refers_to_files else None  # MuJoCo resolves them from the model's own folder
        mj = compile_text(model.text, str(path), mj_path)
        result.engines["MuJoCo"] = _loaded_and_stepped(mj, str(path))
    return result


# ----------------------------------------------------------------------------------------- isolation
_ERRORS = {cls.__name__: cls for cls in (ModelError, EngineError, InputError, HarnessError)}


def _limit_memory() -> None:
    """In the child, after the engines are imported: bound its address space (a forked ``preexec_fn`` is
    not safe in a process with threads)."""
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (limits.COMPILE_MEMORY_BYTES, limits.COMPILE_MEMORY_BYTES))


def validate_isolated(path: Path | str, root: Path | str | None = None, states: int = importer.STATES,
                      seed: int = importer.SEED) -> Validation:
    """:func:`validate` with the engines in a child process: the checks of the file run here (their errors
    need no child), then the child loads, steps and compares under :data:`~harness.limits.COMPILE_SECONDS`
    and :data:`~harness.limits.COMPILE_MEMORY_BYTES`. A timeout or a crash of the engines is one
    :class:`ModelError` line; nothing is written."""
    path = Path(path)
    model = untrusted.read_model(path, root)
    if model.kind == untrusted.URDF:
        check_urdf_tree(model)
        check_urdf_inertials(model)
    request = json.dumps({"path": str(path), "root": None if root is None else str(root), "states": states,
                          "seed": seed})
    import os

    env = dict(os.environ)
    package_root = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = os.pathsep.join([package_root] + [p for p in [env.get("PYTHONPATH")] if p])
    try:
        proc = subprocess.run([sys.executable, "-m", "harness.files.validate", request], capture_output=True,
                              timeout=limits.COMPILE_SECONDS, env=env, check=False)
    except subprocess.TimeoutExpired:
        raise ModelError(f"{path}: loading and stepping the model in the engines took longer than "
                         f"{limits.COMPILE_SECONDS:g} s (harness.limits.COMPILE_SECONDS); refused") from None
    lines = proc.stdout.decode(errors="replace").strip().splitlines()
    try:
        answer = json.loads(lines[-1])
    except (IndexError, ValueError):
        answer = None
    if not isinstance(answer, dict):
        memory = b"MemoryError" in proc.stderr or b"bad_alloc" in proc.stderr
        why = (f"ran out of the {limits.COMPILE_MEMORY_BYTES} bytes of memory allowed "
               "(harness.limits.COMPILE_MEMORY_BYTES)" if memory else f"crashed (exit status {proc.returncode})")
        raise ModelError(f"{path}: the engines {why} while loading the model; refused")
    if "error" in answer:
        raise _ERRORS.get(answer.get("kind"), HarnessError)(answer["error"])
    doc = answer["result"]
    return Validation(doc["source"], doc["kind"], doc["engines"], doc["comparison"], doc["findings"])


def _child(request: str) -> int:
    """The child of :func:`validate_isolated`: one JSON line on stdout, the result or the error."""
    args = json.loads(request)
    try:
        _limit_memory()
        result = validate(args["path"], args["root"], args["states"], args["seed"])
        answer = {"result": result.to_json()}
    except HarnessError as exc:
        answer = {"error": str(exc), "kind": type(exc).__name__}
    except MemoryError:
        answer = {"error": f"{args['path']}: the engines ran out of the {limits.COMPILE_MEMORY_BYTES} bytes of "
                           "memory allowed (harness.limits.COMPILE_MEMORY_BYTES); refused", "kind": "ModelError"}
    except Exception as exc:  # noqa: BLE001 - an engine failing on a file we did not write: one line
        answer = {"error": f"{args['path']}: the engines failed on the model: {type(exc).__name__}: "
                           f"{importer.one_line(exc)}", "kind": "EngineError"}
    print(json.dumps(answer), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(_child(sys.argv[1]))
