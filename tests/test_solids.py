"""A link made of solids (``Link.solids``) is the body its mass, centre of mass and inertia tensor state: their volume
integrals (3.115), (3.118) find the link's, symbolically, and MuJoCo's compiler, given the same solids as geoms with
their density, finds the same numbers. The pictures show those solids (visual geoms of the exported MJCF)."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
import sympy as sp

import models
from harness.derivation.bodies import solid_inertia, solid_mass
from harness.errors import ModelError
from harness.export.mjcf import mjcf_spec, mjcf_string, model_scale
from harness.export.numeric import instantiate
from harness.modeling import Box, Cylinder, Link

MADE_OF_SOLIDS = [(name, link.name) for name, system in models.catalogue().items()
                  for link in system.links if link.solids]


def test_the_catalogue_has_links_made_of_solids():
    assert ("tower_crane", "tower") in MADE_OF_SOLIDS


@pytest.mark.parametrize("name, link_name", MADE_OF_SOLIDS)
def test_the_solids_volume_integrals_are_the_links_mass_centre_and_inertia(name, link_name):
    link = models.get(name).link(link_name)
    parts = [solid_mass(solid, density) for solid, density in link.solids]
    mass = sum((m for m, _ in parts), sp.Integer(0))
    first_moment = sum((c for _, c in parts), sp.zeros(3, 1))
    inertia = sum((solid_inertia(solid, density, about=tuple(link.com_vector)) for solid, density in link.solids),
                  sp.zeros(3, 3))
    assert sp.simplify(mass - link.mass) == 0
    assert sp.simplify(first_moment - link.mass * link.com_vector).is_zero_matrix
    assert sp.simplify(inertia - link.inertia.matrix).is_zero_matrix


@pytest.mark.parametrize("name, link_name", MADE_OF_SOLIDS)
def test_mujoco_finds_the_links_inertia_from_the_solids_and_the_picture_shows_them(name, link_name):
    """MuJoCo's compiler computes a body's inertia from its geoms and their density: the exported visual geoms of
    the solids, given the solids' densities, are a body of the link's mass, centre of mass and inertia tensor
    (float64 round-off: 1e-12 of its scale)."""
    system = models.get(name)
    values = {p.name: float(p.default) for p in system.parameters}
    link = next(k for k in instantiate(system, values).links if k.name == link_name)
    exported = mjcf_spec(instantiate(system, values))
    geoms = [g for g in exported.geoms if g.name.startswith(f"visual_{link_name}_solid_")]
    assert len(geoms) == len(link.solids)
    densities = [float(sp.sympify(density).subs({p.symbol: values[p.name] for p in system.parameters}))
                 for _, density in system.link(link_name).solids]
    mass, com, inertia = _mujoco_body(zip(geoms, densities))
    assert abs(mass - link.mass) <= 1e-12 * link.mass
    assert np.max(np.abs(com - link.com)) <= 1e-12 * max(1.0, np.max(np.abs(link.com)))
    assert np.max(np.abs(inertia - link.inertia)) <= 1e-12 * np.max(np.abs(link.inertia))


def _mujoco_body(geoms_and_densities) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass, centre of mass and inertia tensor (about it, in the body's axes) that MuJoCo's compiler computes for
    one body made of these geoms (their type, position, orientation and size) with these densities."""
    spec = mujoco.MjSpec()
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
    body = spec.worldbody.add_body(name="solids")
    body.add_freejoint()
    for geom, density in geoms_and_densities:
        body.add_geom(type=geom.type, pos=geom.pos, quat=geom.quat, size=geom.size, density=density)
    model = spec.compile()
    rotation = np.zeros(9)
    mujoco.mju_quat2Mat(rotation, model.body_iquat[1])
    rotation = rotation.reshape(3, 3)
    return model.body_mass[1], model.body_ipos[1], rotation @ np.diag(model.body_inertia[1]) @ rotation.T


def test_solids_are_given_as_solid_and_density_pairs_and_a_drawing_offset_as_three_numbers():
    with pytest.raises(ModelError, match=r"link tower: solids: give \(solid, density\) pairs"):
        Link("tower", 1.0, solids=(Cylinder(1, 2),))
    assert Link("tower", 1.0, solids=((Box.around((0, 0, 0), (1, 1, 1)), 2.0),)).solids
    for where in ((0, 0.5), "up", (0, 0, sp.Symbol("h"))):
        with pytest.raises(ModelError, match=r"link body: drawn_at: give three numbers in metres"):
            Link("body", 1.0, drawn_at=where)


def test_a_drawing_offset_on_a_link_merged_in_mujoco_is_one_clear_error():
    """A massless link is merged in MuJoCo with the link it carries: the picture has no body of its own to move."""
    import dataclasses

    from harness.report.render import Scene3D, mjcf_text

    system = models.get("cable_pulley")
    moved = tuple(dataclasses.replace(k, drawn_at=(0, 0, 0.5)) if k.name == "load_x" else k for k in system.links)
    edited = dataclasses.replace(system, links=moved)
    with pytest.raises(ModelError, match="link load_x: drawn_at: the MJCF has no body of that name"):
        Scene3D(edited, mjcf_text(edited))


_VOLUME = {mujoco.mjtGeom.mjGEOM_BOX: lambda s: 8.0 * s[0] * s[1] * s[2],
           mujoco.mjtGeom.mjGEOM_CYLINDER: lambda s: 2.0 * np.pi * s[0] ** 2 * s[1],
           mujoco.mjtGeom.mjGEOM_SPHERE: lambda s: 4.0 / 3.0 * np.pi * s[0] ** 3}


def test_every_body_drawn_as_its_equivalent_solid_is_the_links_mass_centre_and_inertia():
    """A link that does not say what it is made of is drawn as the homogeneous cuboid, cylinder (two equal principal
    moments) or sphere (three) of its mass and inertia tensor (``harness.export.mjcf.add_visuals``). MuJoCo's
    compiler, given that geom with the density that makes it the link's mass, finds the link's mass, centre of mass
    and inertia tensor (float64 round-off: 1e-12 of its scale). Where the picture keeps a size visible (a slender
    rod's or a plate's zero thickness, clipped to 1 % of the mechanism), the geom is not that body: those links
    are counted apart, and a size of theirs is the clipped one. A cuboid built by ``Inertia.cuboid`` stays a
    cuboid where its section is square (the cart pendulum's cart), although its tensor is a cylinder's too."""
    kinds, clipped = {}, []
    for name, system in models.catalogue().items():
        values = {p.name: float(p.default) for p in system.parameters}
        tree = instantiate(system, values)
        geoms = {g.name: g for g in mjcf_spec(tree).geoms}
        for link in tree.links:
            geom = geoms.get(f"visual_{link.name}_body")
            if geom is None or link.solids:
                continue
            kinds.setdefault(geom.type, []).append(f"{name}/{link.name}")
            mass, com, inertia = _mujoco_body([(geom, link.mass / _VOLUME[geom.type](geom.size))])
            assert abs(mass - link.mass) <= 1e-12 * link.mass
            assert np.max(np.abs(com - link.com)) <= 1e-12 * max(1.0, np.max(np.abs(link.com)))
            if np.max(np.abs(inertia - link.inertia)) > 1e-12 * np.max(np.abs(link.inertia)):
                bounds = {0.01 * model_scale(tree), 2.0 * model_scale(tree)}
                assert bounds & set(geom.size), f"{name}/{link.name}: not its body, and no size clipped {geom.size}"
                clipped.append(f"{name}/{link.name}")
    assert "cart_pendulum/cart" in kinds[mujoco.mjtGeom.mjGEOM_BOX]
    assert {"drive_train/rotor", "two_mass_oscillator/body_1"} <= set(kinds[mujoco.mjtGeom.mjGEOM_CYLINDER])
    assert "rolling_sphere/sphere" in kinds[mujoco.mjtGeom.mjGEOM_SPHERE]
    assert sum(map(len, kinds.values())) - len(clipped) >= 30, (kinds, clipped)


def test_how_a_body_is_drawn_is_not_part_of_the_models_fingerprint():
    """``Link.solids``, ``Link.drawn_at`` and ``Inertia.shape`` say how a body is drawn, not what it is: an edit of
    them keeps the fingerprint that keys the derivations (nothing is derived again), while the exported MJCF, keyed
    by the numeric tree, draws the solids (a picture alone moves a link drawn elsewhere: the MJCF keeps it where the
    model puts it). The inertia's numbers are part of the fingerprint."""
    import dataclasses

    system = models.get("tower_crane")
    tower = system.link("tower")
    undrawn = dataclasses.replace(tower, solids=(), inertia=dataclasses.replace(tower.inertia, shape="cylinder"))
    edited = dataclasses.replace(system, links=tuple(undrawn if k is tower else k for k in system.links))
    assert edited.fingerprint() == system.fingerprint()
    values = {p.name: float(p.default) for p in system.parameters}
    assert ({g.name for g in mjcf_spec(instantiate(edited, values)).geoms}
            != {g.name for g in mjcf_spec(instantiate(system, values)).geoms})
    moved = dataclasses.replace(tower, drawn_at=(0.0, 0.0, 1.0))
    elsewhere = dataclasses.replace(system, links=tuple(moved if k is tower else k for k in system.links))
    assert elsewhere.fingerprint() == system.fingerprint()
    assert mjcf_string(instantiate(elsewhere, values)) == mjcf_string(instantiate(system, values))
    heavier = dataclasses.replace(tower, inertia=dataclasses.replace(tower.inertia, xx=2 * tower.inertia.xx))
    assert dataclasses.replace(system, links=tuple(heavier if k is tower else k for k in system.links)
                               ).fingerprint() != system.fingerprint()
