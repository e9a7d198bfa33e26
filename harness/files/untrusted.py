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
  the file; symlinks followed) and refuses any that lands outside it, and any other URI scheme. "Every" is
  every attribute MuJoCo resolves to a path (``file`` of include/mesh/skin/hfield/texture/flexcomp, the six
  cube faces ``fileright`` … ``fileback`` of a texture, the compiler's ``assetdir``/``meshdir``/``texturedir``,
  in the main file and in its includes), against every folder MuJoCo may resolve it from. The refusal names
  what the model wrote, never what it resolves to, so it does not tell whether a file outside exists. A
  ``<model>`` asset (another model file) and engine plugins are refused outright.
* **Work without bound.** :func:`check_work` counts, before any engine sees the file, what the engines would
  build (elements after ``<replicate>`` expansion, height-field samples, texture pixels, MuJoCo's arena; links
  and joints of a URDF) against :mod:`harness.limits`.
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

import hashlib
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import unquote, urlsplit

import defusedxml
import defusedxml.ElementTree as safe_et
from lxml import etree

from harness import limits
from harness.errors import InputError, ModelError
from harness.io import existing_folder

MAX_BYTES = limits.MODEL_BYTES
MAX_DEPTH = limits.XML_DEPTH
MAX_INCLUDES = limits.INCLUDE_DEPTH
MAX_MAGNITUDE = limits.MAGNITUDE
"""The bounds of :mod:`harness.limits` (with their reasons) under the names this module has always used.
Joint limits and MJCF ``*range`` attributes are exempt from :data:`MAX_MAGNITUDE` (a huge limit means "no
limit")."""
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

# File references. URDF: (element, attribute). MJCF: every attribute MuJoCo resolves to a path (its XML schema,
# src/xml/mjcf.schema, and reader, src/xml/xml_native_reader.cc / xml.cc): the compiler folders, ``file`` of
# <include>, <mesh>, <skin>, <hfield>, <texture>, <flexcomp>, <model>, and the six cube faces of a <texture>.
# Any other attribute whose name starts with "file" is treated as a path too (a newer MuJoCo may add one).
URDF_FILES = {("mesh", "filename"), ("texture", "filename")}
MJCF_DIRS = ("assetdir", "meshdir", "texturedir")
MJCF_FILE_ATTRS = ("file", "fileright", "fileleft", "fileup", "filedown", "filefront", "fileback")
_MJCF_BASES = {  # the folders (compiler attributes, "" = the model's folder) MuJoCo may resolve a file against
    "include": ("",), "model": ("",), "flexcomp": ("", "meshdir", "assetdir"),
    "mesh": ("meshdir", "assetdir"), "skin": ("assetdir", "meshdir"), "hfield": ("assetdir",),
    "texture": ("texturedir", "assetdir"),
}
MJCF_REFUSED = {
    "model": "a <model> asset makes MuJoCo parse another model file, which these checks do not see",
    "plugin": "an engine plugin runs code of its own and may read files",
    "extension": "an engine plugin runs code of its own and may read files",
    "instance": "an engine plugin runs code of its own and may read files",
}
"""MJCF elements refused outright in a file we did not write."""


def _is_path_attr(attr: str) -> bool:
    return attr in MJCF_FILE_ATTRS or attr.startswith("file")


@dataclass
class ModelFile:
    """A parsed, not yet checked model file: its text, kind (``urdf``/``mjcf``), lxml root and root folder."""

    source: str
    text: str
    kind: str
    root: etree._Element
    folder: Path
    includes: list["ModelFile"] = field(default_factory=list)
    include_of: dict = field(default_factory=dict)  # id(<include> element) -> the ModelFile it includes

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
    digest = hashlib.sha256(data).digest()
    if digest not in _PASSED_GATE:
        _gate(data, source)
        if len(_PASSED_GATE) >= 1024:
            _PASSED_GATE.clear()
        _PASSED_GATE.add(digest)
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False,
                             remove_comments=True, remove_pis=True)
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as exc:  # expat accepted what libxml2 does not
        raise ModelError(f"{source}:{exc.lineno}: malformed XML: {exc.msg}") from None
    except LookupError as exc:
        raise ModelError(f"{source}: malformed XML: {exc}") from None
    return root


_PASSED_GATE: set = set()
"""SHA-256 digests of the texts :func:`_gate` let through in this process: the same robot's URDF is read by several
steps of its comparison (580 parses of 69 texts), and the gate's two expat passes cost more than the parse itself.
Only a text that passed is kept; a refused one is refused again with its message."""


def _gate(data: bytes, source: str) -> None:
    """The gate of :func:`parse_xml`: :class:`ModelError` for a DTD, entity, external reference, malformed XML or
    excessive nesting. One expat pass with any DTD forbidden (without a DTD there is no entity and no external
    reference); a text it does not accept is read as before by :func:`_two_passes`, whose error names what it holds."""
    try:
        tree = safe_et.fromstring(data, forbid_dtd=True, forbid_entities=True, forbid_external=True)
    except (ValueError, LookupError, RecursionError, safe_et.ParseError):  # defusedxml's errors are ValueErrors
        tree = _two_passes(data, source)
    level, depth = [tree], 1
    while level:  # level by level; the element named is the one a depth-first walk finds
        if depth > MAX_DEPTH:
            stack = [(tree, 1)]
            while stack:
                el, d = stack.pop()
                if d > MAX_DEPTH:
                    raise ModelError(f"{source}: elements nested deeper than {MAX_DEPTH} levels (<{el.tag}>)")
                stack.extend((child, d + 1) for child in el)
        level = [child for el in level for child in el]
        depth += 1


def _two_passes(data: bytes, source: str):
    """The gate's reading of a text with a DTD (or malformed): expat with entities and external references
    forbidden, then any DTD at all, so that an entity declaration or external reference is named as such."""
    try:
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
    return tree


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
        if path.is_dir():
            raise InputError(f"{path}: is a folder; give a URDF (.urdf) or MJCF (.xml) file in it")
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
LEAVES = "is outside the model's folder"
"""The refusal of a path outside the root: the same words whether or not the file exists (the message names
only what the model wrote, never what the path resolves to)."""


def _inside(path: Path, root: Path) -> bool:
    return path == root or root in path.parents


def resolve_uri(uri: str, root: Path, folder: Path | None = None, base: str = "") -> Path:
    """The file a URI names, which must lie inside ``root`` (symlinks followed).

    ``package://NAME/REST`` resolves to ``root/base/REST`` (the package is the root folder); a relative path
    against ``folder`` (the model's own folder, default ``root``) joined with ``base`` (an MJCF
    ``meshdir``-style folder); ``file://`` and absolute paths must already be inside ``root``; any other
    scheme is refused. A ``ValueError`` says why, in words that do not depend on anything outside ``root``:
    a path is first normalised without the file system and refused when it leaves ``root``; only a path
    inside is resolved (its symlinks followed, which may lead out again: refused the same way)."""
    folder = folder if folder is not None else root
    if "\x00" in uri:
        raise ValueError("holds a NUL character")
    parts = urlsplit(uri)
    scheme = parts.scheme.lower()
    if scheme == "package":
        rel = unquote(parts.path).lstrip("/")
        target = Path(root) / base / rel
    elif scheme == "file":
        target = Path(unquote(parts.path))
    elif scheme == "" or (len(scheme) == 1 and uri[1:2] == ":"):  # relative, absolute or a Windows drive
        if len(scheme) == 1:
            raise ValueError("is a Windows drive path: it is outside the model's folder")
        path = uri.replace("\\", "/")
        target = Path(path) if path.startswith("/") else Path(folder) / base / path
    else:
        raise ValueError(f"scheme {scheme}:// is not allowed (only package://, file:// and relative paths)")
    try:
        real_root = Path(root).resolve()
        # target is relative to the working folder, as root and folder are: never joined to root again (a model
        # named by a path with folders, sub/deep/m.urdf, would count sub/deep twice and let as many ../ out)
        lexical = Path(os.path.normpath(os.path.abspath(target)))
        lexical_root = Path(os.path.normpath(os.path.abspath(root)))
        if not _inside(lexical, lexical_root):
            raise ValueError(f"{LEAVES} {root}")
        resolved = lexical.resolve()
    except (OSError, RuntimeError):  # a symlink loop inside the folder
        raise ValueError(f"cannot be resolved (a symlink loop?); it may not leave the model's folder {root}") from None
    if not _inside(resolved, real_root):
        raise ValueError(f"{LEAVES} {root} (through a symlink)")
    return resolved


def _refuse(model: ModelFile, el, attr: str, value: str, exc: ValueError):
    raise ModelError(f"{model.where(el)}: {_owner(el)}: {attr}={value!r} {exc}") from None


def _all_files(model: ModelFile):
    """``model`` and every file it includes, with the folder of the including file (for nested includes)."""
    yield model
    for inc in model.includes:
        yield from _all_files(inc)


def check_uris(model: ModelFile, root: Path | str | None = None) -> list[Path]:
    """Every file the model refers to stays inside ``root`` (default: the model's folder), against every
    folder MuJoCo may resolve it from (the model's folder, the compiler's ``assetdir``/``meshdir``/
    ``texturedir`` wherever they are set, the folder of an including file). Returns the files."""
    root = Path(root) if root is not None else model.folder
    files: list[Path] = []
    dirs: dict[str, set[str]] = {attr: set() for attr in MJCF_DIRS}
    for part in _all_files(model):  # compiler folders, in the main file and its includes, any kind of model
        for comp in part.root.iter("compiler"):
            for attr in MJCF_DIRS:
                value = comp.get(attr)
                if value is not None:
                    try:
                        resolve_uri(value, root, model.folder)
                    except ValueError as exc:
                        _refuse(part, comp, attr, value, exc)
                    dirs[attr].add(value)
    for part in _all_files(model):
        folders = {model.folder, Path(part.source).parent} if part is not model else {model.folder}
        for el in part.root.iter():
            if not isinstance(el.tag, str):
                continue
            if part.kind == URDF:
                for tag, attr in URDF_FILES:
                    if el.tag == tag and (value := el.get(attr)) is not None:
                        try:
                            files.append(resolve_uri(value, root, model.folder))
                        except ValueError as exc:
                            _refuse(part, el, attr, value, exc)
                continue
            if el.tag in MJCF_REFUSED and (el.tag != "model" or el.getparent() is not None
                                           and el.getparent().tag == "asset"):
                raise ModelError(f"{part.where(el)}: {_owner(el)}: refused: {MJCF_REFUSED[el.tag]}")
            for attr, value in el.attrib.items():
                if not _is_path_attr(attr):
                    continue
                bases = {""} | {d for key in _MJCF_BASES.get(el.tag, ("assetdir", "meshdir", "texturedir"))
                                if key for d in dirs.get(key, ())}
                for folder in folders:
                    for base in sorted(bases):
                        try:
                            resolved = resolve_uri(value, root, folder, base)
                        except ValueError as exc:
                            _refuse(part, el, attr, value, exc)
                if el.tag != "include":
                    files.append(resolved)
    return files


def _follow_includes(model: ModelFile, root: Path, level: int = 0) -> None:
    """Parse MJCF ``<include file=…>`` targets (inside ``root``) with the same safe parser. MuJoCo looks for
    an included file in the main model's folder, then in the folder of the including file: both must be
    inside ``root``."""
    if model.kind != MJCF:
        return
    main_folder = model.folder
    for el in model.root.iter("include"):
        value = el.get("file")
        if value is None:
            raise ModelError(f"{model.where(el)}: <include> without a file attribute")
        if level >= MAX_INCLUDES:
            raise ModelError(f"{model.where(el)}: <include> nested deeper than {MAX_INCLUDES} levels")
        candidates = []
        for folder in dict.fromkeys([main_folder, Path(model.source).parent if level else main_folder]):
            try:
                candidates.append(resolve_uri(value, root, folder))
            except ValueError as exc:
                raise ModelError(f"{model.where(el)}: <include> file={value!r} {exc}") from None
        path = next((p for p in candidates if p.is_file()), candidates[0])
        text = _read_text(path)
        root_el = parse_xml(text, str(path))
        inc = ModelFile(str(path), text, MJCF, root_el, main_folder)  # MuJoCo resolves from the main folder
        _follow_includes(inc, root, level + 1)
        model.includes.append(inc)
        model.include_of[id(el)] = inc


# ----------------------------------------------------------------------------------------------- work
_MEMORY = re.compile(r"\s*(\d+)\s*([KMGTPE]?)\s*\Z", re.IGNORECASE)


def _int_attr(model: ModelFile, el, attr: str, default: int = 0) -> int:
    value = el.get(attr)
    if value is None:
        return default
    try:
        return int(value.strip())
    except ValueError:
        raise ModelError(f"{model.where(el)}: {_owner(el)}: {attr}={value!r} is not an integer") from None


def _ints(model: ModelFile, el, attr: str) -> list[int]:
    value = el.get(attr)
    try:
        return [int(float(t)) for t in value.split()] if value is not None else []
    except (ValueError, OverflowError):
        raise ModelError(f"{model.where(el)}: {_owner(el)}: {attr}={value!r} is not a list of integers") from None


def check_work(model: ModelFile) -> None:
    """The bounds of :mod:`harness.limits` on what the engines would build from the file, counted from the
    XML before any engine sees it: elements after ``<replicate>`` expansion, copies of nested replicates,
    height-field samples, texture pixels, MuJoCo's arena size (MJCF); links and joints (URDF)."""
    if model.kind == URDF:
        for tag in ("link", "joint"):
            n = len(model.root.findall(tag))  # the robot's own links and joints (not a transmission's)
            if n > limits.URDF_LINKS:
                raise ModelError(f"{model.source}: {n} <{tag}> elements, more than the {limits.URDF_LINKS} "
                                 f"accepted (harness.limits.URDF_LINKS: validation time grows with the cube)")
        return
    total = 0
    stack = [(model, model.root, 1)]  # iterative: includes nest up to 16 files of 200 levels each
    while stack:
        part, el, copies = stack.pop()
        if not isinstance(el.tag, str):
            continue
        if el.tag == "replicate":
            count = _int_attr(part, el, "count", 1)
            if count < 1:
                raise ModelError(f"{part.where(el)}: <replicate> count={count} must be positive")
            copies *= count
            if copies > limits.REPLICATE_COPIES:
                raise ModelError(f"{part.where(el)}: nested <replicate> make {copies} copies, more than the "
                                 f"{limits.REPLICATE_COPIES} accepted (harness.limits.REPLICATE_COPIES)")
        generated = 1
        if el.tag in ("composite", "flexcomp"):
            for attr in ("count", "cellcount"):
                for n in _ints(part, el, attr):
                    generated *= max(n, 1)
        total += copies * generated
        if total > limits.MJCF_ELEMENTS:
            raise ModelError(f"{part.where(el)}: more than {limits.MJCF_ELEMENTS} elements after <replicate> "
                             f"expansion (harness.limits.MJCF_ELEMENTS: MuJoCo's compile time and memory grow "
                             f"with the count)")
        if el.tag == "hfield":
            cells = _int_attr(part, el, "nrow") * _int_attr(part, el, "ncol")
            if cells > limits.HFIELD_CELLS:
                raise ModelError(f"{part.where(el)}: {_owner(el)}: nrow*ncol = {cells} samples, more than the "
                                 f"{limits.HFIELD_CELLS} accepted (harness.limits.HFIELD_CELLS)")
        if el.tag == "texture":
            width = _int_attr(part, el, "width")
            height = _int_attr(part, el, "height") or width
            faces = 6 if el.get("type") in ("cube", "skybox") else 1
            if width * height * faces > limits.TEXTURE_PIXELS:
                raise ModelError(f"{part.where(el)}: {_owner(el)}: {width} x {height} x {faces} pixels, more "
                                 f"than the {limits.TEXTURE_PIXELS} accepted (harness.limits.TEXTURE_PIXELS)")
        if el.tag == "mesh" and el.get("builtin") is not None:
            if any(abs(n) > 1000 for n in _ints(part, el, "params")):
                raise ModelError(f"{part.where(el)}: {_owner(el)}: params={el.get('params')!r}: a builtin mesh "
                                 "resolution above 1000 is refused (its vertices grow with the square)")
        if el.tag == "size" and (memory := el.get("memory")) is not None and memory.strip() != "-1":
            match = _MEMORY.match(memory)
            if match is None:
                raise ModelError(f"{part.where(el)}: <size> memory={memory!r} is not a size such as 64M")
            size = int(match[1]) * 1024 ** " KMGTPE".index(match[2].upper() or " ")
            if size > limits.MJCF_MEMORY_BYTES:
                raise ModelError(f"{part.where(el)}: <size> memory={memory!r} exceeds the "
                                 f"{limits.MJCF_MEMORY_BYTES} bytes accepted (harness.limits.MJCF_MEMORY_BYTES)")
        if el.tag == "include" and id(el) in part.include_of:
            inc = part.include_of[id(el)]
            stack.append((inc, inc.root, copies))
        stack.extend((part, child, copies) for child in el)


# ----------------------------------------------------------------------------------------------- entry
def check_model(model: ModelFile, root: Path | str | None = None) -> ModelFile:
    """All checks of this module on a parsed model; returns it."""
    root = Path(root) if root is not None else model.folder
    _follow_includes(model, root)  # each include is checked to lie inside root before it is read
    check_uris(model, root)
    check_work(model)
    check_numbers(model)
    return model


def read_model(path: Path | str, root: Path | str | None = None) -> ModelFile:
    """Read, safely parse and check a ``.urdf`` or MJCF ``.xml`` file; ``root`` bounds the files it may refer
    to (default: its own folder)."""
    path = Path(path)
    if root is not None:
        existing_folder(root, "--root")
    text = _read_text(path)
    model = parse_model(text, str(path), path.parent)
    return check_model(model, root)


def check_text(text: str | bytes, source: str = "<string>", folder: Path | str | None = None) -> ModelFile:
    """Safely parse and check model text (for text that never was a file, e.g. a generated export)."""
    return check_model(parse_model(text, source, folder))
