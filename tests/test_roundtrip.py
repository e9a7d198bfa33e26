"""What the engines load from our exported files equals what we meant (harness.compare.roundtrip)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from lxml import etree

from harness.engines.mujoco_engine import MujocoModel
from harness.engines.warnings_log import compile_spec, drain
from harness.engines.pinocchio_engine import PinocchioModel
from harness.errors import EngineError
from harness.export.mjcf import mjcf_spec, mjcf_string
from harness.export.numeric import instantiate
from harness.export.urdf import urdf_string
from harness.export.mjcf import fused_links
from harness.compare.roundtrip import mjcf_roundtrip, roundtrip, urdf_roundtrip
from models import catalogue


def default_tree(name: str, **overrides):
    system = catalogue()[name]
    return instantiate(system, system.default_parameters() | overrides)


def items(findings, engine):
    return {f.item for f in findings if f.engine == engine}


def edit_urdf(urdf: str, path: str, attribute: str, value: str) -> str:
    """The URDF with one attribute of the single element at ``path`` replaced."""
    root = etree.fromstring(urdf.encode())
    (element,) = root.xpath(path)
    element.set(attribute, value)
    return etree.tostring(root, encoding="unicode")


@pytest.mark.parametrize("name", list(catalogue()))
def test_catalogue_loads_as_exported(name):
    tree = default_tree(name)
    pin_model, mj_model = PinocchioModel(tree), MujocoModel(tree)
    assert [str(f) for f in roundtrip(tree, pin_model, mj_model)] == []
    # not vacuous: every link, joint and point was compared by both engines (a massless link fused into its
    # child's MuJoCo body has no body of its own: its joint is compared there)
    names = {link.name for link in tree.links} | {j.name for j in tree.joints} | {p.name for p in tree.points}
    for compared, skipped in ((urdf_roundtrip(tree, pin_model), set()),
                              (mjcf_roundtrip(tree, mj_model), fused_links(tree))):
        assert names - skipped <= {e.item.split()[0] for e in compared}


def general_tree():
    """Rotated joint frame, unaligned axis, full inertia tensor, non-decimal numbers."""
    tree = default_tree("planar_manipulator", l_1=1 / 3, m_2=0.1 + 0.2, l_s2=2 / 7)
    q, _ = np.linalg.qr(np.random.default_rng(1).normal(size=(3, 3)))
    inertia = q @ np.diag([0.03, 0.04, 0.05]) @ q.T
    links = (tree.links[0], dataclasses.replace(tree.links[1], inertia=(inertia + inertia.T) / 2))
    joints = (tree.joints[0], dataclasses.replace(tree.joints[1], rpy=np.array([0.3, -0.7, 1.1]),
                                                  axis=np.array([0.0, -0.6, 0.8])))
    return dataclasses.replace(tree, links=links, joints=joints)


def test_general_geometry_loads_as_exported():
    """Exact up to ulps (Pinocchio's RevoluteUnaligned path, MuJoCo's principal-axis decomposition)."""
    tree = general_tree()
    assert [str(f) for f in roundtrip(tree, PinocchioModel(tree), MujocoModel(tree))] == []


def test_a_small_inertia_far_from_its_link_origin_round_trips_through_drake():
    """Drake keeps a body's inertia about the body origin, ``I_o = I_c + m (|c|² 1 − c cᵀ)``: the tensor about the
    centre of mass it gives back carries the round-off of ``I_o``, ε max|I_o| / max|I_c| relative to ``I_c`` (a
    1 cm ball on a 1 m pendulum: 6.6e-12, a round trip 'failed' for a model that is right). Compared about the
    origin, as Drake keeps it, every item is within a few ulps; a wrong inertia is still found."""
    from harness.engines.drake_engine import DrakeModel

    tree = default_tree("planar_manipulator", I_xx2=4e-7, I_yy2=4e-7, I_zz2=4e-7)   # a small ball at l_s2 = 0.4 m
    model = DrakeModel(tree)
    findings = urdf_roundtrip(tree, model)
    inertia = next(f for f in findings if f.item == "link_2 inertia about its origin")
    assert max(f.error for f in findings) < 1e-15 and inertia.loaded[0] == pytest.approx(4e-7)   # I_xx: c on x
    about_com = model.link_as_loaded("link_2")["inertia"]
    assert abs(about_com[2][2] - 4e-7) / 4e-7 > 1e-12   # the tensor Drake gives back about the centre of mass
    urdf = edit_urdf(urdf_string(tree), "/robot/link[@name='link_2']/inertial/inertia", "izz", repr(4e-7 * 1.001))
    wrong = urdf_roundtrip(tree, DrakeModel(tree, urdf=urdf))
    assert {f.item for f in wrong if f.error > 1e-12} == {"link_2 inertia about its origin"}


def test_moved_com_in_urdf_is_found():
    tree = default_tree("planar_manipulator")
    urdf = edit_urdf(urdf_string(tree), "/robot/link[@name='link_2']/inertial/origin", "xyz", "0.45 0 0")
    findings = roundtrip(tree, PinocchioModel(tree, urdf=urdf), None)
    assert items(findings, "pinocchio") == {"link_2 com"}
    (finding,) = findings
    assert finding.intended == [0.4, 0.0, 0.0] and finding.loaded == [0.45, 0.0, 0.0]
    assert finding.error == pytest.approx(0.05 / 0.4)


def test_moved_com_in_mjcf_is_found():
    tree = default_tree("planar_manipulator")
    spec = mjcf_spec(tree)
    spec.body("link_2").ipos = [0.45, 0.0, 0.0]
    spec.compile()
    findings = roundtrip(tree, None, MujocoModel(tree, xml=spec.to_xml()))
    assert items(findings, "mujoco") == {"link_2 com"}


MJCF_ARRAYS = ["body_pos", "body_quat", "body_ipos", "body_iquat", "body_mass", "body_inertia", "jnt_axis",
               "jnt_stiffness", "qpos_spring", "dof_damping", "site_pos", "tendon_stiffness", "tendon_damping",
               "tendon_lengthspring", "actuator_gear"]
TEXT_TREES = {name: lambda name=name: default_tree(name) for name in catalogue()} | {"general": general_tree}


@pytest.mark.parametrize("name", list(TEXT_TREES))
def test_mjcf_text_loads_as_the_spec(name):
    """MjSpec.to_xml() prints 6 significant digits (pos="0.333333" for l_1 = 1/3, a 1e-6 error);
    mjcf_string rewrites every number in full precision, so the MJCF *text* (the committed urdf/*.xml)
    loads into the model of the spec itself."""
    tree = TEXT_TREES[name]()
    text = mjcf_string(tree)
    assert [str(f) for f in roundtrip(tree, None, MujocoModel(tree, xml=text))] == []
    loaded, built = MujocoModel(tree, xml=text).model, compile_spec(mjcf_spec(tree), tree, "test")
    assert all(w["explained"] for w in drain(tree.system))  # the tower crane's qpos0 (rope length 0) is singular
    pairs = [(array, getattr(loaded, array), getattr(built, array)) for array in MJCF_ARRAYS]
    for array, a, b in pairs + [("opt.gravity", loaded.opt.gravity, built.opt.gravity)]:
        assert a.shape == b.shape, array
        scale = np.abs(b).max(initial=0.0) or 1.0
        assert np.abs(a - b).max(initial=0.0) <= 1e-15 * scale, array


# Corrupted numbers in the URDF. urdfdom only logs to stderr when a link's <inertial> has a number it cannot
# parse and drops that *whole* <inertial> (mass 1.5kg -> massless link; ixx 0.001kg -> mass kept, inertia
# tensor all zero); a bad joint origin makes Pinocchio raise. Either way the harness must not pass silently.
CORRUPTIONS = [
    ("/robot/link[@name='link_2']/inertial/mass", "value", "1.5kg", "link_2 mass"),
    ("/robot/link[@name='link_2']/inertial/mass", "value", "1,5", "link_2 mass"),
    ("/robot/link[@name='link_2']/inertial/origin", "xyz", "0.4m 0 0", "link_2 mass"),
    ("/robot/link[@name='link_2']/inertial/inertia", "ixx", "0.001kg", "link_2 inertia"),
    ("/robot/joint[@name='phi_2']/origin", "xyz", "1.0m 0 0", None),
]


@pytest.mark.parametrize("path, attribute, value, expected", CORRUPTIONS)
def test_unparsable_urdf_number_never_passes(path, attribute, value, expected):
    tree = default_tree("planar_manipulator")
    urdf = edit_urdf(urdf_string(tree), path, attribute, value)
    try:
        model = PinocchioModel(tree, urdf=urdf)
    except (ValueError, RuntimeError, EngineError):
        return  # refusing the file is fine (Pinocchio 4.1.0 does so for a bad joint origin)
    findings = roundtrip(tree, model, None)
    assert findings, "a corrupted URDF passed the round trip"
    if expected is not None:
        assert expected in items(findings, "pinocchio")


def test_unparsable_mjcf_number_raises():
    tree = default_tree("planar_manipulator")
    xml = mjcf_string(tree).replace('mass="1.5"', 'mass="1.5kg"')
    with pytest.raises(ValueError, match="bad format"):
        MujocoModel(tree, xml=xml)


def test_missing_point_is_found():
    tree = default_tree("planar_manipulator")
    spec = mjcf_spec(tree)
    spec.delete(spec.site("e2"))  # a tendon references it: rebuild without the tendon
    for tendon in list(spec.tendons):
        spec.delete(tendon)
    spec.compile()
    (finding,) = roundtrip(tree, None, MujocoModel(tree, xml=spec.to_xml()))
    assert (finding.item, finding.loaded, finding.error) == ("e2 present", [], float("inf"))


def test_an_items_error_is_the_relative_max_difference_bit_for_bit():
    """``_numbers`` in Python floats gives NumPy's ``max|loaded − intended| / max|intended|`` exactly (absolute for
    an all-zero item); a missing number or one not finite is an infinite error."""
    from harness.compare.roundtrip import _numbers

    rng = np.random.default_rng(3)
    for size in (1, 3, 9, 12):
        for _ in range(200):
            intended = rng.normal(size=size) * 10.0 ** rng.integers(-8, 8)
            loaded = intended * (1 + rng.normal(size=size) * 1e-14)
            expected = float(np.abs(loaded - intended).max() / np.abs(intended).max())
            assert _numbers("e", "item", intended, loaded).error.hex() == expected.hex()
    assert _numbers("e", "zero", np.zeros(3), [0.0, 1e-20, -2e-20]).error == 2e-20
    assert _numbers("e", "shape", np.eye(3), np.eye(3)[:2]).error == np.inf
    assert _numbers("e", "nan", [1.0, 2.0], [1.0, np.nan]).error == np.inf
    found = _numbers("e", "rotation", np.eye(3), np.eye(3))
    assert found.error == 0.0 and found.intended == np.eye(3).ravel().tolist() == found.loaded
