"""The model section of a system page, written for a reader: the module's docstring rendered (paragraphs,
bullet lists, ``**bold**``; a double-back-quoted symbol name in the lecture's notation as MathML, other
double-back-quoted text as code), and the bodies, joints and force elements as small tables and sentences with
their laws as mathematics (:mod:`harness.report.mathml`), not as Python reprs."""

from __future__ import annotations

import html
import re

import sympy as sp
from sympy.printing.pretty.pretty_symbology import greek_unicode

from harness.report.equations import entry_by_entry
from harness.report.mathml import LINE_WIDTH, body, bold, math, width

_NAME = re.compile(r"^[A-Za-z]+[0-9]*(?:_[A-Za-z0-9]+)*(?:\^\{?[A-Za-z0-9]+\}?)?$")
_LITERAL = re.compile(r"``(.+?)``|:(?:func|mod|data|class|meth|attr|obj):`~?([^`]+)`")
"""A literal, or a cross-reference of Sphinx's Python roles (a name in the code: set as code, not as a symbol)."""
_STRONG = re.compile(r"\*\*(.+?)\*\*")
_EMPHASIS = re.compile(r"(?<![*\w])\*([^*\s][^*]*?)\*(?![*\w])")


def _marks(text: str) -> str:
    """``**bold**`` and ``*emphasis*`` of escaped text."""
    return _EMPHASIS.sub(r"<i>\1</i>", _STRONG.sub(r"<b>\1</b>", text))


def inline(expr, joints=()) -> str:
    """An expression as inline MathML (the coordinates of the tree joints ``joints`` as θ_joint, :func:`body`)."""
    return math(body(expr, joints=joints), display=False)


def _symbol(text: str) -> str | None:
    """A symbol name such as ``phi_1``, ``I_zz^{sK}``, ``r_dot`` as inline MathML; None for other text. A symbol's
    base is one letter or a Greek letter's name, as every coordinate, parameter and input of the catalogue: a word
    (``drive_train_armature``, ``frictionloss``, ``mj_applyFT``) is code, not a letter with subscripts."""
    base = re.split(r"[_^]", text, maxsplit=1)[0]
    if not _NAME.match(text) or len(text) > 24 or (len(base) > 1 and base not in greek_unicode):
        return None
    name = text.replace("{", "").replace("}", "")
    return math(body(sp.Symbol(name)), display=False)


def _inline_text(text: str) -> str:
    out, last = [], 0
    for match in _LITERAL.finditer(text):
        out.append(_marks(html.escape(text[last:match.start()])))
        inner = match.group(1)
        out.append(f"<code>{html.escape(match.group(2))}</code>" if inner is None else
                   _symbol(inner) or f"<code>{html.escape(inner)}</code>")
        last = match.end()
    out.append(_marks(html.escape(text[last:])))
    return "".join(out)


def docstring_html(doc: str) -> str:
    """The model's docstring as HTML paragraphs and lists."""
    blocks, parts = [], re.split(r"\n\s*\n", (doc or "").strip())
    for block in parts:
        lines = block.splitlines()
        if lines and all(re.match(r"^\s*([*-]\s|\s{2,})", ln) or k == 0 for k, ln in enumerate(lines)) \
                and re.match(r"^\s*[*-]\s", lines[0]):
            items, current = [], []
            for ln in lines:
                if re.match(r"^\s*[*-]\s", ln):
                    if current:
                        items.append(" ".join(current))
                    current = [re.sub(r"^\s*[*-]\s", "", ln)]
                else:
                    current.append(ln.strip())
            items.append(" ".join(current))
            blocks.append("<ul>" + "".join(f"<li>{_inline_text(i)}</li>" for i in items) + "</ul>")
        else:
            text = " ".join(ln.strip() for ln in lines)
            blocks.append(f"<p>{_inline_text(text)}</p>")
    return "\n".join(blocks)


# --------------------------------------------------------------------------- bodies, joints, forces
def _point(p) -> str:
    where = "the inertial frame" if p.link == "world" else f"link <code>{html.escape(p.link)}</code>"
    name = f"point <b>{html.escape(p.name)}</b> " if p.name else "the point "
    return f"{name}{inline(sp.Matrix(p.vector).T)} in {where}"


def _theta(system, joint: str) -> str:
    return inline(system.joint(joint).theta, (joint,))


def force_rows(system) -> list[dict]:
    """Per force element: ``{"name", "kind", "sentence"}`` (HTML with inline MathML)."""
    from harness.modeling import system as m

    rows = []
    for f in system.forces:
        if isinstance(f, m.Spring):
            r = sp.Symbol("r")
            law = sp.Eq(sp.Symbol("V"), f.stiffness / 2 * (sp.Abs(r) - f.rest_length) ** 2, evaluate=False)
            text = (f"a linear spring between {_point(f.a)} and {_point(f.b)}, stiffness {inline(f.stiffness)}, "
                    f"relaxed length {inline(f.rest_length)}: {inline(law)} with r the vector between the points "
                    "(3.84)")
            kind = "spring"
        elif isinstance(f, m.Damper):
            text = (f"a linear damper between {_point(f.a)} and {_point(f.b)}, damping {inline(f.damping)}, "
                    "acting along their connecting line against the rate of its length (3.88)")
            kind = "damper"
        elif isinstance(f, m.JointSpring):
            th = system.joint(f.joint).theta
            law = sp.Eq(sp.Symbol("V"), f.stiffness / 2 * (th - f.rest) ** 2, evaluate=False)
            text = f"a spring in joint <code>{html.escape(f.joint)}</code>: {inline(law, (f.joint,))}"
            kind = "joint spring"
        elif isinstance(f, m.JointDamper):
            th = sp.Symbol(f"{system.joint(f.joint).theta.name}_dot")
            text = (f"viscous friction in joint <code>{html.escape(f.joint)}</code>: the generalized force "
                    f"{inline(-sp.sympify(f.damping) * th, (f.joint,))} on its coordinate {_theta(system, f.joint)}")
            kind = "joint damper"
        elif isinstance(f, m.JointInput):
            joint = system.joint(f.joint)
            what = "torque" if joint.type == "revolute" else "force"
            text = (f"the input {inline(sp.Symbol(str(f.input)))} acts as a {what} in joint "
                    f"<code>{html.escape(f.joint)}</code> (between <code>{html.escape(joint.parent)}</code> and "
                    f"<code>{html.escape(joint.child)}</code>)")
            kind = "input"
        elif isinstance(f, m.PointForce):
            frame = "inertial" if f.frame == "world" else f"link <code>{html.escape(f.frame)}</code> (a follower force)"
            text = (f"the external force {inline(sp.Matrix(f.force).T)} at {_point(f.point)}, components in the "
                    f"{frame} frame; generalized force by (5.73)")
            kind = "external force"
        elif isinstance(f, m.BodyTorque):
            frame = "inertial" if f.frame == "world" else f"link <code>{html.escape(f.frame)}</code>"
            text = (f"the external torque {inline(sp.Matrix(f.torque).T)} on link <code>{html.escape(f.link)}</code>, "
                    f"components in the {frame} frame; generalized force by (5.73)")
            kind = "external torque"
        else:
            text, kind = html.escape(str(f)), type(f).__name__
        rows.append({"name": f.name, "kind": kind, "sentence": text[0].upper() + text[1:] + "."})
    return rows


def link_rows(system) -> list[dict]:
    """Per link: mass, centre of mass, inertia about it as inline MathML; an inertia tensor or centre of mass wider
    than a line (:data:`~harness.report.mathml.LINE_WIDTH`) is written below the table instead, entry by entry
    (``below``: ``[(title, MathML)]``, :func:`~harness.report.equations.entry_by_entry`): in its cell it had made
    the table four screens wide."""
    rows = []
    for k in system.links:
        row = {"name": k.name, "mass": inline(k.mass), "description": k.description, "below": []}
        for key, letter, value, what in (("com", "r", sp.Matrix(k.com_vector), "centre of mass (link frame)"),
                                         ("inertia", "I", k.inertia.matrix, "inertia about the centre of mass "
                                          "(symmetric: its entries on and above the diagonal)")):
            if key == "inertia" and not k.has_mass:
                row[key] = "—"
            elif key == "inertia" and k.is_point_mass:
                row[key] = "point mass"
            elif width(value) > LINE_WIDTH:
                row[key] = "written below the table (too wide for it)"
                row["below"].append((f"{k.name}: {what}", entry_by_entry(letter, value, k.name)))
            else:
                row[key] = inline(value)
        rows.append(row)
    return rows


def joint_rows(system) -> list[dict]:
    """Per tree joint: type, parent → child, axis, origin, and its map θ = φ(q) as inline MathML."""
    rows = []
    for j, expr in zip(system.joints, system.phi):
        rows.append({"name": j.name, "type": j.type, "parent": j.parent, "child": j.child,
                     "axis": inline(sp.Matrix(j.axis_vector).T), "origin": inline(sp.Matrix(j.origin_vector).T),
                     "phi": math(body(j.theta, joints=(j.name,)), "<mo>=</mo>", body(expr), display=False)})
    return rows


def gravity_sentence(system) -> str:
    if system.gravity is None:
        return "No gravity."
    direction = sp.Matrix(system.gravity.direction).T
    return (f"Gravity {inline(system.gravity.g)} along {math(bold('e', subscript='g'), display=False)} = "
            f"{inline(direction)} (5.20).")
