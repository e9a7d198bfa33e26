"""Nothing clobbered, nothing blocked: `check --out` and `claims --out` merge by system into what the folder
holds; a user module that does not load is that module's failure while every other system still runs (an export
names it and fails); a claim that uses a symbol its system does not declare, or a scene that does not fit its
system, is refused when the module loads, with one line."""

from __future__ import annotations

import json
import sys

import pytest

import models
from harness import cli

BROKEN = {  # module name -> (its text, what the one-line failure says)
    "user_raises": ("raise RuntimeError('boom')\n", "does not load: RuntimeError: boom"),
    "user_syntax": ("def (:\n", "does not load (line 1): SyntaxError"),
    "user_exits": ("import sys\nsys.exit(0)\n", "does not load: calls sys.exit(0)"),
    "user_shadow": ("from models.pendulum import SYSTEM as _S\nimport dataclasses\n"
                    "SYSTEM = dataclasses.replace(_S, title='a fake')\n",
                    "its SYSTEM is named 'pendulum'; a system's module is named after it"),
    "aa_user_shadow": ("from models.pendulum import SYSTEM as _S\nimport dataclasses\n"  # sorts before pendulum
                       "SYSTEM = dataclasses.replace(_S, title='a fake')\n",
                       "rename the file to pendulum.py or the system to 'aa_user_shadow'"),
}
SCENE = ("import dataclasses\nfrom models.pendulum import SYSTEM as _S\nfrom harness.modeling import Constant, Scene\n"
         "SYSTEM = dataclasses.replace(_S, name='{module}')\nSCENES = [Scene('drop', '', {fields})]\n")
BROKEN |= {  # a scene that does not fit its system: refused when the module loads, the field and the fix named
    "user_scene_q0": (SCENE.format(module="user_scene_q0", fields="(0.1, 0.2), (0.0,), 1.0, {'gravity'}"),
                      "scene drop: q0 has 2 value(s); user_scene_q0 has 1 coordinate(s) (phi)"),
    "user_scene_input": (SCENE.format(module="user_scene_input",
                                      fields="(0.1,), (0.0,), 1.0, {'inputs'}, inputs={'tau': Constant(1.0)}"),
                         "scene drop: tau is not an input of user_scene_input (inputs: none)"),
    "user_scene_mass": (SCENE.format(module="user_scene_mass", fields="(0.1,), (0.0,), 1.0, {'gravity'}, "
                                     "params={'m': -1.0}"),
                        "scene drop: parameter m=-1.0: must be positive (point mass)"),
    "user_scene_event": ("import dataclasses\nfrom models.stick_slip import SYSTEM as _S, SCENES as _SC\n"
                         "SYSTEM = dataclasses.replace(_S, name='user_scene_event')\n"
                         "SCENES = [dataclasses.replace(_SC[0], events=(dataclasses.replace(_SC[0].events[0], "
                         "coordinate='y'),))]\n", "StickSlip.coordinate='y' is not a coordinate of user_scene_event"),
}
UNDECLARED_CLAIM = '''
import sympy as sp
from models.pendulum import SYSTEM as _S
import dataclasses
from harness.compare.claims import Claim
SYSTEM = dataclasses.replace(_S, name="{name}")
CLAIMS = [Claim("(9.99)", "T", sp.Symbol("l_3", positive=True) * SYSTEM.qd[0] ** 2)]
'''

MISSHAPEN_CLAIM = '''
import sympy as sp
from models.pendulum import SYSTEM as _S
import dataclasses
from harness.compare.claims import Claim
SYSTEM = dataclasses.replace(_S, name="{name}")
CLAIMS = [Claim("(9.98)", "M", sp.Matrix([[1, 0]]))]
'''


def _one_line(capsys) -> str:
    err = [line for line in capsys.readouterr().err.strip().splitlines() if line]
    assert len(err) == 1, err
    return err[0]


def test_check_out_merges_by_system(tmp_path, capsys):
    out = tmp_path / "reports"
    assert cli.main(["check", "pendulum", "--examples", "3", "--no-scenes", "--out", str(out)]) == 0
    assert cli.main(["check", "cart_pendulum", "--examples", "3", "--no-scenes", "--out", str(out)]) == 0
    doc = json.loads((out / "results.json").read_text())
    assert [r["system"] for r in doc["systems"]] == ["cart_pendulum", "pendulum"]  # catalogue order
    assert "systems/pendulum/seconds" in json.loads((out / "timings.json").read_text())


def test_claims_out_merges_by_system(tmp_path, capsys):
    out = tmp_path / "reports"
    assert cli.main(["claims", "pendulum", "--examples", "3", "--jobs", "1", "--out", str(out)]) == 0
    assert cli.main(["claims", "pulley", "--examples", "3", "--jobs", "1", "--out", str(out)]) == 0
    records = json.loads((out / "claims.json").read_text())
    assert {r["system"] for r in records} == {"pendulum", "pulley"}
    assert "| pendulum |" in (out / "errata.md").read_text()
    # a rerun of one system replaces its records, it does not add a second copy
    assert cli.main(["claims", "pendulum", "--examples", "3", "--jobs", "1", "--out", str(out)]) == 0
    again = json.loads((out / "claims.json").read_text())
    assert len(again) == len(records)


@pytest.mark.parametrize("module", sorted(BROKEN))
def test_a_broken_user_module_blocks_nothing_else(user_models, capsys, module):
    text, message = BROKEN[module]
    (user_models / f"{module}.py").write_text(text)
    # the catalogue still loads (the real pendulum, not a fake); the broken module is a failure of its own
    assert "pendulum" in models.catalogue() and models.catalogue()["pendulum"].title != "a fake"
    failures = models.failures()
    assert list(failures) == [module] and message in failures[module] and f"{module}.py" in failures[module]
    assert module in models.names()
    # other systems run; the broken one named by the user is one line and exit 2
    assert cli.main(["eval", "pendulum", "--q", "0.3"]) == 0
    assert cli.main(["list"]) == 0 and module in capsys.readouterr().out
    assert cli.main(["check", module, "--examples", "2", "--no-scenes"]) == 2
    assert message in _one_line(capsys)


def test_an_export_names_a_module_that_does_not_load_and_fails(user_models, tmp_path, capsys):
    """Its files are neither written nor compared (they may be stale): the export says so and exits 2; every other
    system's files are written."""
    (user_models / "user_raises.py").write_text(BROKEN["user_raises"][0])
    folder = tmp_path / "urdf"
    assert cli.main(["export", "--dir", str(folder)]) == 2
    line = _one_line(capsys)
    assert "user_raises.py does not load" in line and "not exported" in line
    assert (folder / "pendulum.urdf").is_file()
    assert cli.main(["export", "--check", "--dir", str(folder)]) == 2
    assert "user_raises.py does not load" in _one_line(capsys)


def test_a_users_system_is_exported_beside_its_module_not_into_the_repository(user_models, tmp_path, capsys):
    """A system of a folder added by HARNESS_MODELS_PATH has its files in that folder's urdf/: the repository's
    exports (here ``--dir``) neither get them nor miss them, so ``export --check`` (the main job's) passes there
    once they are written, and names them by their own path while they are not."""
    (user_models / "user_rod.py").write_text("import dataclasses\nfrom models.pendulum import SYSTEM as _S\n"
                                             "SYSTEM = dataclasses.replace(_S, name='user_rod')\n")
    folder = tmp_path / "urdf"
    assert cli.main(["export", "--dir", str(folder)]) == 0
    ours = len(list(folder.iterdir()))   # 3 files of each catalogued system
    assert capsys.readouterr().out == (f"exported {ours} files to {folder}/, 3 files to {user_models / 'urdf'}/: "
                                       f"{ours + 3} changed and written, 0 current and left as they are\n")
    written = {p: p.stat().st_mtime_ns for p in [*folder.iterdir(), *(user_models / "urdf").iterdir()]}
    assert cli.main(["export", "--dir", str(folder)]) == 0   # again: nothing changed, nothing written
    assert capsys.readouterr().out.endswith(f": 0 changed and written, {ours + 3} current and left as they are\n")
    assert {p: p.stat().st_mtime_ns for p in written} == written
    assert sorted(p.name for p in (user_models / "urdf").iterdir()) == ["user_rod.map.json", "user_rod.urdf",
                                                                       "user_rod.xml"]
    assert (folder / "pendulum.urdf").is_file() and not list(folder.glob("user_rod.*"))
    assert cli.main(["export", "--check", "--dir", str(folder)]) == 0
    (user_models / "urdf" / "user_rod.xml").unlink()
    assert cli.main(["export", "--check", "--dir", str(folder)]) == 1
    assert capsys.readouterr().err == f"stale: {user_models / 'urdf' / 'user_rod.xml'} (run `harness export`)\n"
    from harness import run   # the importer study names its files where they are (it had said urdf/user_rod.urdf)

    (record,) = run.importer(models.CATALOGUE, ["user_rod"], states=2)[0]["models"][:1]
    assert (record["urdf"], record["reference"]) == (str(user_models / "urdf" / "user_rod.urdf"),
                                                      f"our MJCF {user_models / 'urdf' / 'user_rod.xml'}")


def test_a_broken_module_is_a_failed_record_in_a_catalogue_run(user_models):
    from harness.run import run_checks

    (user_models / "user_raises.py").write_text(BROKEN["user_raises"][0])
    records = run_checks(models.CATALOGUE, ["pendulum", "user_raises"], examples=2, scenes=False,
                         progress=sys.stderr)
    by_name = {r["system"]: r for r in records}
    assert by_name["pendulum"]["passed"]
    assert not by_name["user_raises"]["passed"] and "RuntimeError: boom" in by_name["user_raises"]["failure"]


def test_a_claim_of_another_shape_than_its_quantity_is_refused_when_the_module_loads(user_models, capsys):
    """A printed M of 1 × 2 for a system of one coordinate: one line naming both shapes and how to claim a part (it
    had failed the classification with NumPy's "cannot reshape array of size 1 into shape (1,2)"); a position of a
    point the system does not name, one line with the names it knows."""
    (user_models / "user_shape.py").write_text(MISSHAPEN_CLAIM.format(name="user_shape"))
    assert cli.main(["claims", "user_shape", "--examples", "2"]) == 2
    line = _one_line(capsys)
    assert line.endswith("user_shape.py: claim (9.98): the printed M is 1 × 2, user_shape's is 1 × 1 (1 "
                         "coordinate(s)); give the whole quantity, or one entry with Claim(..., index=(i, j)) or one "
                         "row with index=(i,)")
    # a position of a point the system does not name: the names it knows
    (user_models / "user_point.py").write_text(MISSHAPEN_CLAIM.replace('"M", sp.Matrix([[1, 0]])',
                                                                       '"position:Q", sp.Matrix([0, 0, 0])')
                                               .format(name="user_point"))
    models.reload()
    assert cli.main(["claims", "user_point", "--examples", "2"]) == 2
    assert _one_line(capsys).endswith("user_point.py: claim (9.98): user_point: no point or link named 'Q' "
                                      "(known: bob)")


def test_a_claim_with_an_undeclared_symbol_is_refused_when_the_module_loads(user_models, capsys):
    (user_models / "user_claim.py").write_text(UNDECLARED_CLAIM.format(name="user_claim"))
    assert cli.main(["claims", "user_claim", "--examples", "2"]) == 2
    line = _one_line(capsys)
    assert "user_claim.py" in line and "claim (9.99)" in line and "'l_3'" in line and "declare it" in line
    assert cli.main(["eval", "pendulum", "--q", "0.1"]) == 0


def test_collecting_the_suite_derives_nothing_and_writes_nothing_to_the_project_cache(tmp_path):
    """The tests' cache is a folder of their own (``tests/conftest.py``), set up when the session starts, after
    collection: what a test module computes when it is imported would be written to the project's cache, and be
    computed by the workers before their first test. ``test_engines.py`` had derived all 33 systems so, into the
    developer's ``.cache/``, to learn which maps are not the identity, which the model says by itself
    (``System.identity_map``): on a cold clone the first test started 63 s after pytest. Collected here against an
    empty cache."""
    import os
    import subprocess
    from pathlib import Path

    cache = tmp_path / "cache" / "derivations"
    env = {**os.environ, "HARNESS_CACHE_DIR": str(cache)}
    root = Path(__file__).resolve().parent.parent
    done = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider",
                           "-p", "no:xdist", str(root / "tests")], cwd=root, env=env, capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert "tests collected" in done.stdout
    written = [str(p.relative_to(tmp_path)) for p in (tmp_path / "cache").rglob("*") if p.is_file()]
    assert not written, written
