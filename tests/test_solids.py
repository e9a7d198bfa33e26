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
from harness.export.mjcf import mjcf_spec
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

    spec = mujoco.MjSpec()
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
    body = spec.worldbody.add_body(name="solids")
    body.add_freejoint()
    for geom, (_, density) in zip(geoms, system.link(link_name).solids):
        body.add_geom(type=geom.type, pos=geom.pos, size=geom.size, density=float(sp.sympify(density).subs(
            {p.symbol: values[p.name] for p in system.parameters})))
    model = spec.compile()
    rotation = np.zeros(9)
    mujoco.mju_quat2Mat(rotation, model.body_iquat[1])
    rotation = rotation.reshape(3, 3)
    inertia = rotation @ np.diag(model.body_inertia[1]) @ rotation.T
    assert abs(model.body_mass[1] - link.mass) <= 1e-12 * link.mass
    assert np.max(np.abs(model.body_ipos[1] - link.com)) <= 1e-12 * max(1.0, np.max(np.abs(link.com)))
    assert np.max(np.abs(inertia - link.inertia)) <= 1e-12 * np.max(np.abs(link.inertia))


def test_solids_are_given_as_solid_and_density_pairs():
    with pytest.raises(ModelError, match=r"link tower: solids: give \(solid, density\) pairs"):
        Link("tower", 1.0, solids=(Cylinder(1, 2),))
    assert Link("tower", 1.0, solids=((Box.around((0, 0, 0), (1, 1, 1)), 2.0),)).solids
