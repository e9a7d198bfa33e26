"""Reading a URDF or MJCF that we did not write: parse it safely and check it before any engine sees it.

A model file from a user is untrusted input. Three things go wrong silently or dangerously if it reaches an
engine (or lxml/yourdfpy) unchecked:

* **XML attacks.** External entities (XXE: ``<!ENTITY x SYSTEM "file:///etc/passwd">``) read local files or
  the network; nested entity expansion ("billion laughs") eats all memory. A URDF or MJCF needs no DTD at
  all, so :func:`parse_xml` refuses any ``<!DOCTYPE>``, entity declaration or external reference
  (``defusedxml`` gate), then builds the tree with lxml (no network, no entity resolution) for line numbers.
  Size (:data:`MAX_BYTES`) and nesting depth (:data:`MAX_DEPTH`) are bounded as well.
* **Files outside the model.** A mesh ``filename="package://p/../../../../etc/shadow"``, ``file:///...`` or
  an MJCF ``<include file="/...">`` makes the loader read files the model does not own.
  :func:`check_uris` resolves every file reference against the model's root folder (by default the folder of
  the file; symlinks followed) and refuses any that lands outside it, and any other URI scheme.
* **Numbers that are not numbers.** urdfdom drops a link's whole ``<inertial>`` (the link loads massless,
  the complaint goes to stderr only) when one number does not parse; NaN/inf parse and poison every result.
  :func:`check_numbers` requires every numeric attribute the URDF/MJCF parsers read to be a plain finite
  decimal (at most :data:`MAX_MAGNITUDE` in size, limits exempt) with the count the parser expects (URDF),
  and the attributes urdfdom requires to be present.

Every refusal is one :class:`~harness.errors.ModelError` line naming the file, line, element (with its
owner, e.g. ``<inertia> of link 'arm'``) and attribute; an unreadable file is an
:class:`~harness.errors.InputError`. :func:`read_model` does all of it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import unquote, urlsplit

import defusedxml
import defusedxml.ElementTree as safe_et
from lxml import etree

from harness.errors import InputError, ModelError

MAX_BYTES = 8 * 2**20
"""Largest model file read (8 MiB): the largest public robot descriptions are a few hundred kB of XML."""

MAX_DEPTH = 200
"""Deepest element nesting accepted. A URDF is flat (depth ≤ 5); an MJCF nests one ``<body>`` per link of a
chain. 200 is far beyond any robot, keeps the engines' recursive parsers away from stack exhaustion and
stays below libxml2's own limit (256)."""

MAX_INCLUDES = 16
"""MJCF ``<include>`` nesting depth followed by the checks."""

MAX_MAGNITUDE = 1e12
"""Largest magnitude of a geometric, inertial or force-element number (SI: kg, m, kg m², N/m, N s/m): beyond
any mechanism, and products of a few such numbers stay far from float64 overflow. A file with mass
1.79e308 passes "finite" yet overflows every engine to NaN (found by the fuzz test). Joint limits and MJCF
``*range`` attributes are exempt (a huge limit means "no limit")."""
UNBOUNDED_URDF = frozenset({"limit", "safety_controller", "calibration"})

URDF, MJCF = "urdf", "mjcf"

_DECIMAL = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
"""A plain decimal: what every parser reads the same way (no hex floats, underscores, ``nan``, ``inf``,
locale commas or units)."""

# URDF: element -> {attribute: number of values}, as urdfdom reads them (urdf_parser/src/*.cpp).
URDF_NUMBERS: dict[str, dict[str, int]] = {
    "origin": {"xyz": 3, "rpy": 3},
    "mass": {"value": 1},
    "inertia": {name: 1 for name in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")},
    "axis": {"xyz": 3},
    "limit": {"lower": 1, "upper": 1, "effort": 1, "velocity": 1},
    "dynamics": {"damping": 1, "friction": 1},
    "safety_controller": {"soft_lower_limit": 1, "soft_upper_limit": 1, "k_position": 1, "k_velocity": 1},
    "calibration": {"rising": 1, "falling": 1, "reference_position": 1},
    "mimic": {"multiplier": 1, "offset": 1},
    "box": {"size": 3},
    "cylinder": {"radius": 1, "length": 1},
    "capsule": {"radius": 1, "length": 1},
    "sphere": {"radius": 1},
    "mesh": {"scale": 3},
    "color": {"rgba": 4},
}
URDF_REQUIRED: dict[str, tuple[str, ...]] = {
    "mass": ("value",),
    "inertia": ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"),
}
"""Attributes urdfdom needs: without them it drops the ``<inertial>`` or refuses the model."""

# MJCF: attributes MuJoCo reads as numbers (any count), wherever they appear.
MJCF_NUMBERS = frozenset("""
pos quat axisangle xyaxes zaxis euler mass diaginertia fullinertia size fromto axis range stiffness damping
springref springlength springdamper armature frictionloss ref margin gap friction solref solimp solreflimit
solimplimit solreffriction solimpfriction density gear ctrlrange forcerange actuatorfrcrange lengthrange
gravity wind magnetic timestep impratio tolerance viscosity o_margin o_solref o_solimp o_friction rgba kp kv
gainprm biasprm dynprm polycoef refpos refquat fovy ipd radius width qpos qvel act ctrl mocap_pos mocap_quat
time value scale boundmass boundinertia settotalmass fitscale rgb1 rgb2 markrgb random inertia shellinertia
cutoff noise lengthscale
""".split()) - {"shellinertia"}

# File references: URDF (element, attribute); MJCF: any ``file`` attribute, plus compiler folders.
URDF_FILES = {("mesh", "filename"), ("texture", "filename")}
MJCF_DIRS = ("assetdir", "meshdir", "texturedir")
_MJCF_DIR_FOR = {"mesh": "meshdir", "skin": "meshdir", "hfield": "assetdir", "texture": "texturedir"}


@dataclass
class ModelFile:
    """A parsed, not yet checked model file: its text, kind (``urdf``/``mjcf``), lxml root and root folder."""

    source: str
    text: str
    kind: str
    root: etree._Element
    folder: Path
    includes: list["ModelFile"] = field(default_factory=list)

    def where(self, el) -> str:
        return f"{self.source}:{el.sourceline}"


def _owner(el) -> str:
    """``<inertia> of link 'arm'``: the element and its nearest named ancestor (itself if named)."""
    tag = f"<{el.tag}>"
    node = el
    while node is not None:
        name = node.get("name")
        if name is not None:
            return f"{tag} '{name}'" if node is el else f"{tag} of {node.tag} '{name}'"
        node = node.getparent()
    return tag


def parse_xml(text: str | bytes, source: str = "<string>") -> etree._Element:
    """The root element of untrusted XML text; :class:`ModelError` for a DTD, entity, external reference,
    malformed XML, excessive size or nesting."""
    data = text.encode() if isinstance(text, str) else text
    if len(data) > MAX_BYTES:
        raise ModelError(f"{source}: {len(data)} bytes, larger than the {MAX_BYTES} accepted for a model file")
    try:  # the gate: expat with entities and external references forbidden, then any DTD at all
        tree = safe_et.fromstring(data, forbid_dtd=False, forbid_entities=True, forbid_external=True)
        safe_et.fromstring(data, forbid_dtd=True, forbid_entities=True, forbid_external=True)
    except defusedxml.EntitiesForbidden as exc:
        if exc.sysid or exc.pubid:
            raise ModelError(f"{source}: refused: external entity '{exc.name}' -> {exc.sysid or exc.pubid!r} "
                             "(XXE: a model file may not read other files)") from None
        raise ModelError(f"{source}: refused: entity declaration '{exc.name}' (entity expansion)") from None
    except defusedxml.ExternalReferenceForbidden as exc:
        raise ModelError(f"{source}: refused: external reference {exc.sysid!r} (XXE)") from None
    except defusedxml.DTDForbidden:
        raise ModelError(f"{source}: refused: a model file may not contain a <!DOCTYPE> (DTDs carry entity "
                         "expansion and external entities)") from None
    except safe_et.ParseError as exc:
        line, column = exc.position
        raise ModelError(f"{source}:{line}:{column}: malformed XML: {str(exc).split(':')[0]}") from None
    except (ValueError, LookupError, RecursionError) as exc:  # LookupError: an unknown encoding= declared
        raise ModelError(f"{source}: malformed XML: {exc}") from None
    stack = [(tree, 1)]
    while stack:
        el, d = stack.pop()
        if d > MAX_DEPTH:
            raise ModelError(f"{source}: elements nested deeper than {MAX_DEPTH} levels (<{el.tag}>)")
        stack.extend((child, d + 1) for child in el)
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False,
                             remove_comments=True, remove_pis=True)
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as exc:  # expat accepted what libxml2 does not
        raise ModelError(f"{source}:{exc.lineno}: malformed XML: {exc.msg}") from None
    except LookupError as exc:
        raise ModelError(f"{source}: malformed XML: {exc}") from None
    return root


def parse_model(text: str | bytes, source: str = "<string>", folder: Path | str | None = None) -> ModelFile:
    """Parse URDF (root ``<robot>``) or MJCF (root ``<mujoco>``) text; the kind comes from the root tag."""
    root = parse_xml(text, source)
    kind = {"robot": URDF, "mujoco": MJCF}.get(root.tag)
    if kind is None:
        raise ModelError(f"{source}: root element <{root.tag}> is neither <robot> (URDF) nor <mujoco> (MJCF)")
    if isinstance(text, bytes):
        try:
            text = text.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise ModelError(f"{source}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    return ModelFile(source, text, kind, root, Path(folder) if folder is not None else Path.cwd())


def _read_text(path: Path) -> str:
    try:
        if not path.is_file():
            raise InputError(f"{path}: no such file")
        if path.stat().st_size > MAX_BYTES:
            raise ModelError(f"{path}: {path.stat().st_size} bytes, larger than the {MAX_BYTES} accepted")
        return path.read_bytes().decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ModelError(f"{path}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None


# ----------------------------------------------------------------------------------------------- numbers
def _check_value(model: ModelFile, el, attr: str, value: str, count: int | None, bounded: bool = True) -> None:
    tokens = value.split()
    bad = [t for t in tokens if not _DECIMAL.fullmatch(t)]
    if bad or not tokens:
        what = "is empty" if not tokens else (f"holds {bad[0]!r}, not a finite number"
                                            if bad[0].lower().lstrip("+-") in ("nan", "inf", "infinity")
                                            else f"holds {bad[0]!r}, not a plain decimal number")
        raise ModelError(f"{model.where(el)}: {_owner(el)}: {attr}={value!r} {what}")
    if any(abs(float(t)) == float("inf") for t in tokens):
        raise ModelError(f"{model.where(el)}: {_owner(el)}: {attr}={value!r} overflows to infinity")
    if bounded and any(abs(float(t)) > MAX_MAGNITUDE for t in tokens):
        raise ModelError(f"{model.where(el)}: {_owner(el)}: {attr}={value!r} exceeds {MAX_MAGNITUDE:g} in magnitude")
    if count is not None and len(tokens) != count:
        raise ModelError(f"{model.where(el)}: {_owner(el)}: {attr}={value!r} needs {count} number(s), "
                         f"got {len(tokens)}")


def check_numbers(model: ModelFile) -> None:
    """Every numeric attribute the parser of ``model.kind`` reads is present where required, a plain finite
    decimal, with the right count (URDF)."""
    for el in model.root.iter():
        if not isinstance(el.tag, str):
            continue
        if model.kind == URDF:
            for attr in URDF_REQUIRED.get(el.tag, ()):
                if el.get(attr) is None:
                    raise ModelError(f"{model.where(el)}: {_owner(el)}: attribute {attr} is missing "
                                     "(urdfdom would drop the inertial)")
            for attr, count in URDF_NUMBERS.get(el.tag, {}).items():
                if (value := el.get(attr)) is not None:
                    _check_value(model, el, attr, value, count, el.tag not in UNBOUNDED_URDF)
        elif el.tag != "flag":  # <option><flag frictionloss="disable"/>: keywords, not numbers
            for attr, value in el.attrib.items():
                if attr in MJCF_NUMBERS:
                    _check_value(model, el, attr, value, None, not attr.endswith("range"))
    for inc in model.includes:
        check_numbers(inc)


# ----------------------------------------------------------------------------------------------- files
def resolve_uri(uri: str, root: Path, folder: Path | None = None, base: str = "") -> Path:
    """The file a URI names, which must lie inside ``root`` (symlinks followed).

    ``package://NAME/REST`` resolves to ``root/REST`` (the package is the root folder); a relative path
    against ``folder`` (the model's own folder, default ``root``) joined with ``base`` (an MJCF
    ``meshdir``-style folder); ``file://`` and absolute paths must already be inside ``root``; any other
    scheme is refused. A ``ValueError`` says why."""
    folder = folder if folder is not None else root
    parts = urlsplit(uri)
    scheme = parts.scheme.lower()
    if scheme == "package":
        rel = unquote(parts.path).lstrip("/")
        target = root / base / rel
    elif scheme == "file":
        target = Path(unquote(parts.path))
    elif scheme == "" or (len(scheme) == 1 and uri[1:2] == ":"):  # relative, absolute or a Windows drive
        if len(scheme) == 1:
            raise ValueError("a Windows drive path leaves the model's folder")
        path = uri.replace("\\", "/")
        target = Path(path) if path.startswith("/") else folder / base / path
    else:
        raise ValueError(f"scheme {scheme}:// is not allowed (only package://, file:// and relative paths)")
    real_root = root.resolve()
    resolved = target.resolve()
    if resolved != real_root and real_root not in resolved.parents:
        raise ValueError(f"resolves to {resolved}, outside the model's folder {real_root}")
    return resolved


def _check_dir(model: ModelFile, el, attr: str, root: Path) -> None:
    value = el.get(attr)
    if value is not None:
        try:
            resolve_uri(value, root, model.folder)
        except ValueError as exc:
            raise ModelError(f"{model.where(el)}: {_owner(el)}: {attr}={value!r} {exc}") from None


def check_uris(model: ModelFile, root: Path | str | None = None) -> list[Path]:
    """Every file the model refers to stays inside ``root`` (default: the model's folder). Returns them."""
    root = Path(root) if root is not None else model.folder
    files = []
    dirs: dict[str, str] = {}
    if model.kind == MJCF:
        for comp in model.root.iter("compiler"):
            for attr in MJCF_DIRS:
                _check_dir(model, comp, attr, root)
                if comp.get(attr) is not None:
                    dirs[attr] = comp.get(attr)
    for el in model.root.iter():
        if not isinstance(el.tag, str):
            continue
        if model.kind == URDF:
            attrs = [a for (tag, a) in URDF_FILES if tag == el.tag]
            base = ""
        else:
            attrs = ["file"] if "file" in el.attrib else []
            key = _MJCF_DIR_FOR.get(el.tag)
            base = dirs.get(key, dirs.get("assetdir", "")) if key else ""
        for attr in attrs:
            value = el.get(attr)
            if value is None:
                continue
            try:
                files.append(resolve_uri(value, root, model.folder, base))
            except ValueError as exc:
                raise ModelError(f"{model.where(el)}: {_owner(el)}: {attr}={value!r} {exc}") from None
    for inc in model.includes:
        files += check_uris(inc, root)
    return files


def _follow_includes(model: ModelFile, root: Path, level: int = 0) -> None:
    """Parse MJCF ``<include file=…>`` targets (inside ``root``) with the same safe parser."""
    if model.kind != MJCF:
        return
    for el in model.root.iter("include"):
        value = el.get("file")
        if value is None:
            raise ModelError(f"{model.where(el)}: <include> without a file attribute")
        if level >= MAX_INCLUDES:
            raise ModelError(f"{model.where(el)}: <include> nested deeper than {MAX_INCLUDES} levels")
        try:
            path = resolve_uri(value, root, model.folder)
        except ValueError as exc:
            raise ModelError(f"{model.where(el)}: <include> file={value!r} {exc}") from None
        text = _read_text(path)
        root_el = parse_xml(text, str(path))
        inc = ModelFile(str(path), text, MJCF, root_el, model.folder)  # MuJoCo resolves from the main folder
        _follow_includes(inc, root, level + 1)
        model.includes.append(inc)


# ----------------------------------------------------------------------------------------------- entry
def check_model(model: ModelFile, root: Path | str | None = None) -> ModelFile:
    """All checks of this module on a parsed model; returns it."""
    root = Path(root) if root is not None else model.folder
    _follow_includes(model, root)  # each include is checked to lie inside root before it is read
    check_uris(model, root)
    check_numbers(model)
    return model


def read_model(path: Path | str, root: Path | str | None = None) -> ModelFile:
    """Read, safely parse and check a ``.urdf`` or MJCF ``.xml`` file; ``root`` bounds the files it may refer
    to (default: its own folder)."""
    path = Path(path)
    text = _read_text(path)
    model = parse_model(text, str(path), path.parent)
    return check_model(model, root)


def check_text(text: str | bytes, source: str = "<string>", folder: Path | str | None = None) -> ModelFile:
    """Safely parse and check model text (for text that never was a file, e.g. a generated export)."""
    return check_model(parse_model(text, source, folder))
