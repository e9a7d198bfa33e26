"""The exported files of a system: ``<system>.urdf`` (yourdfpy), ``<system>.xml`` (MJCF via MjSpec) and
``<system>.map.json`` (lecture coordinates and the map ``theta = phi(q)``), all with the default parameters;
:func:`harness.run.export` writes them into ``urdf/``, or beside the module of a folder added by
``HARNESS_MODELS_PATH``."""

from __future__ import annotations

import json

from harness.export.mjcf import mjcf_string
from harness.export.numeric import instantiate
from harness.export.urdf import urdf_string
from harness.modeling.system import System


def coordinate_map(system: System) -> str:
    doc = {"system": system.name,
           "coordinates": [{"name": c.name, "unit": c.unit, "description": c.description} for c in system.coordinates],
           "joints": [{"joint": j.name, "type": j.type, "theta": str(expr)} for j, expr in zip(system.joints, system.phi)]}
    return json.dumps(doc, indent=1) + "\n"


def system_files(system: System, tree=None) -> dict[str, str]:
    """The exported files of ``system`` at its default parameters (``tree``: their tree, when the caller has it)."""
    tree = instantiate(system, system.default_parameters()) if tree is None else tree
    return {f"{system.name}.urdf": urdf_string(tree), f"{system.name}.xml": mjcf_string(tree),
            f"{system.name}.map.json": coordinate_map(system)}
