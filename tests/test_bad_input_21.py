"""Bad input and faults, round two (files confined, work bounded, write errors, bad input that exited 0).

Each case: one ``error:`` line naming the problem, exit 2, no traceback, nothing written. Real engines and real
faults (a file size limit in a child process for a full disk), no mocks. The helpers of test_bad_input.py
(``fails``, ``validate_fails``, ``urdf``, ``mjcf``) are reused.
"""

import json
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from harness import cli, limits
from harness.errors import InputError, ModelError
from harness.modeling.scenes import Scene
from tests.test_bad_input import INERTIA, fails, mjcf, urdf, validate_fails

ROOT = Path(__file__).resolve().parent.parent


def _texture(attrs: str) -> str:
    return mjcf(top=f'<asset><texture name="t" type="cube" {attrs}/></asset>')


# ----------------------------------------------------------------------------------- paths stay in the folder
@pytest.mark.parametrize("attr", ["file", "fileright", "fileleft", "fileup", "filedown", "filefront", "fileback"])
@pytest.mark.parametrize("value", ["/etc/passwd", "../secret.png", "file:///etc/hostname", "sub/../../secret.png"])
def test_every_texture_file_attribute_is_confined(capfd, tmp_path, attr, value):
    (tmp_path / "secret.png").write_bytes(b"\x89PNG")
    line = validate_fails(capfd, tmp_path, _texture(f'{attr}="{value}"'), f"{attr}={value!r}", "m.xml")
    assert "is outside the model's folder" in line


@pytest.mark.parametrize("top", [
    '<asset><hfield name="h" file="../h.png"/></asset>',
    '<asset><skin file="../s.skn"/></asset>',
    '<asset><mesh name="m" file="/etc/passwd"/></asset>',
    '<compiler assetdir="../"/>',
    '<compiler texturedir="/usr/share"/>',
    '<compiler texturedir="tex"/><asset><texture name="t" type="2d" file="../../x.png"/></asset>',
    '<compiler assetdir="a/b"/><asset><hfield name="h" file="../../../x.png"/></asset>',
])
def test_every_path_attribute_of_mjcf_is_confined(capfd, tmp_path, top):
    line = validate_fails(capfd, tmp_path, mjcf(top=top), "is outside the model's folder", "m.xml")
    assert "Traceback" not in line


@pytest.mark.parametrize("name, text", [
    ("m.xml", mjcf(top='<asset><mesh name="m" file="../../outside.stl"/></asset>')),
    ("m.urdf", urdf(extra='<visual><geometry><mesh filename="../../outside.stl"/></geometry></visual>')),
])
def test_a_model_named_by_a_relative_path_with_folders_is_confined_the_same(capfd, tmp_path, monkeypatch, name, text):
    """``harness validate sub/deep/m.xml`` from the folder above: the model's folder is ``sub/deep`` once, not twice
    (a path joined to the root again let as many ``../`` out as the command line's path had folders, and MuJoCo
    read the file outside)."""
    (tmp_path / "outside.stl").write_bytes(b"solid x\nendsolid x\n")
    (tmp_path / "sub" / "deep").mkdir(parents=True)
    (tmp_path / "sub" / "deep" / name).write_text(text)
    monkeypatch.chdir(tmp_path)
    fails(capfd, ["validate", f"sub/deep/{name}"], "is outside the model's folder sub/deep")


def test_flexcomp_file_is_confined(capfd, tmp_path):
    body = '<flexcomp name="f" type="mesh" file="../../x.obj" dim="2"/>'
    validate_fails(capfd, tmp_path, mjcf(body=body), "file='../../x.obj' is outside the model's folder", "m.xml")


def test_the_message_does_not_tell_whether_an_outside_file_exists(capfd, tmp_path):
    """The same words for a file that exists and one that does not (only what the model wrote is named)."""
    lines = []
    for name in ("present", "absent"):
        folder = tmp_path / name
        folder.mkdir()
        if name == "present":
            (folder / "target.png").write_bytes(b"x")
        (folder / "model").mkdir()
        path = folder / "model" / "m.xml"
        path.write_text(_texture('fileright="../target.png"'))
        code = cli.main(["validate", str(path)])
        err = capfd.readouterr().err
        assert code == 2
        lines.append(err.replace(str(folder), "DIR"))
    assert lines[0] == lines[1] and "target.png" in lines[0]


def test_a_symlink_out_of_the_folder_is_refused(capfd, tmp_path):
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "t.png").write_bytes(b"x")
    (tmp_path / "model").mkdir()
    (tmp_path / "model" / "link").symlink_to(tmp_path / "outside")
    line = validate_fails(capfd, tmp_path, _texture('fileup="link/t.png"'), "fileup='link/t.png'", "m.xml")
    assert "through a symlink" in line and str(tmp_path / "outside") not in line


@pytest.mark.parametrize("top, message", [
    ('<asset><model name="other" file="other.xml"/></asset>', "a <model> asset makes MuJoCo parse another model"),
    ('<extension><plugin plugin="mujoco.elasticity.cable"/></extension>', "an engine plugin runs code"),
])
def test_model_assets_and_plugins_are_refused(capfd, tmp_path, top, message):
    validate_fails(capfd, tmp_path, mjcf(top=top), message, "m.xml")


def test_files_of_an_included_file_are_confined(capfd, tmp_path):
    """An include's own compiler folders and files are checked like the main file's, and an include inside an
    included file may not leave the folder from the included file's folder either."""
    model = tmp_path / "model"
    (model / "parts").mkdir(parents=True)
    (model / "parts" / "a.xml").write_text('<mujoco><compiler assetdir="../../"/></mujoco>')
    validate_fails(capfd, tmp_path, mjcf(top='<include file="parts/a.xml"/>'), "assetdir='../../'", "m.xml")
    (model / "parts" / "a.xml").write_text('<mujoco><asset><texture name="t" type="cube" filedown="/etc/passwd"/>'
                                           '</asset></mujoco>')
    validate_fails(capfd, tmp_path, mjcf(top='<include file="parts/a.xml"/>'), "filedown='/etc/passwd'", "m.xml")
    (model / "parts" / "a.xml").write_text('<mujoco><include file="../../x.xml"/></mujoco>')
    validate_fails(capfd, tmp_path, mjcf(top='<include file="parts/a.xml"/>'), "<include> file='../../x.xml'",
                   "m.xml")


# ----------------------------------------------------------------------------------- bounds on work
def test_nested_replicate_is_refused_before_compiling(capfd, tmp_path):
    """The 300-byte file that ran past 90 s at 2.8 GB: refused from the counts, in well under a second."""
    body = ('<replicate count="1000" offset="0 0 1"><replicate count="1000" offset="1 0 0"><body><geom size="1"/>'
            '</body></replicate></replicate>')
    text = f'<mujoco><worldbody>{body}</worldbody></mujoco>'
    assert len(text) < 300
    start = time.perf_counter()
    validate_fails(capfd, tmp_path, text, "nested <replicate> make 1000000 copies, more than the 1000", "m.xml")
    assert time.perf_counter() - start < 5


def test_replicated_elements_are_counted(capfd, tmp_path):
    geoms = '<geom size="0.1"/>' * 25
    text = f'<mujoco><worldbody><replicate count="1000" offset="1 0 0"><body>{geoms}</body></replicate></worldbody></mujoco>'
    validate_fails(capfd, tmp_path, text, f"more than {limits.MJCF_ELEMENTS} elements after <replicate> expansion",
                   "m.xml")


@pytest.mark.parametrize("top, message", [
    ('<asset><hfield name="h" nrow="200000" ncol="200000" size="1 1 1 1"/></asset>',
     "nrow*ncol = 40000000000 samples"),
    ('<asset><texture name="t" type="cube" builtin="checker" width="100000" height="100000"/></asset>',
     "100000 x 100000 x 6 pixels"),
    ('<size memory="100G"/>', "memory='100G' exceeds"),
    ('<asset><mesh name="s" builtin="supersphere" params="100000 1 1"/></asset>', "builtin mesh resolution"),
])
def test_allocations_are_bounded(capfd, tmp_path, top, message):
    validate_fails(capfd, tmp_path, mjcf(top=top), message, "m.xml")


def _chain(links: int) -> str:
    parts = ['<robot name="c"><link name="l0"/>']
    for i in range(1, links):
        parts.append(f'<link name="l{i}"><inertial><origin xyz="0.1 0 0" rpy="0 0 0"/><mass value="1"/>{INERTIA}'
                     f'</inertial></link><joint name="j{i}" type="revolute"><parent link="l{i - 1}"/>'
                     f'<child link="l{i}"/><origin xyz="0.2 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/>'
                     '<limit effort="1" velocity="1" lower="-1" upper="1"/></joint>')
    return "".join(parts) + "</robot>"


def test_urdf_link_count_is_bounded(capfd, tmp_path):
    validate_fails(capfd, tmp_path, _chain(limits.URDF_LINKS + 1),
                   f"{limits.URDF_LINKS + 1} <link> elements, more than the {limits.URDF_LINKS} accepted")


def test_engine_stage_runs_under_a_time_limit(capfd, tmp_path, monkeypatch):
    """The engines load and step an untrusted file in a child process with a wall-clock limit (here set below
    the child's start-up time, so that it is reached with a valid model)."""
    monkeypatch.setattr(limits, "COMPILE_SECONDS", 0.05)
    validate_fails(capfd, tmp_path, urdf(), "took longer than 0.05 s (harness.limits.COMPILE_SECONDS)")


@pytest.mark.parametrize("args, message", [
    (["check", "pendulum", "--examples", "0"], "--examples: 0 must be at least 1"),
    (["check", "pendulum", "--examples", "100000000000000000000000000000"], "exceeds the limit of 10000"),
    (["check", "pendulum", "--examples", "1e29"], "'1e29' is not an integer"),
    (["check", "pendulum", "--jobs", "0"], "--jobs: 0 must be at least 1"),
    (["claims", "pendulum", "--jobs", "0"], "--jobs: 0 must be at least 1"),
    (["report", "pendulum", "--jobs", "-3"], "--jobs: -3 must be at least 1"),
    (["claims", "pendulum", "--examples", "0"], "--examples: 0 must be at least 1"),
    (["validate", "x.urdf", "--states", "0"], "--states: 0 must be at least 1"),
    (["importer", "pendulum", "--states", "0"], "--states: 0 must be at least 1"),
    (["importer", "pendulum", "--states", "99999999"], "exceeds the limit of 10000"),
])
def test_command_line_counts_are_bounded(capfd, args, message):
    fails(capfd, args, message)


def test_scene_horizon_is_bounded():
    with pytest.raises(InputError, match="horizon=1000000000.0 s must be positive and at most 1000 s"):
        Scene("long", "too long", (0.0,), (0.0,), 1e9, {"gravity"})
    with pytest.raises(InputError, match="horizon=-1"):
        Scene("back", "backwards", (0.0,), (0.0,), -1, {"gravity"})


# ----------------------------------------------------------------------------------- write errors
@pytest.mark.parametrize("command", [
    ["check", "pendulum", "--out"], ["claims", "pendulum", "--out"], ["report", "pendulum", "--out"],
    ["hard", "--quick", "--out"], ["importer", "pendulum", "--out"], ["export", "--dir"],
    ["bench", "--quick", "--out"],
])
@pytest.mark.parametrize("where", ["/proc/x", "a file", "below a file"])
def test_unwritable_destination_is_refused_before_the_work(capfd, tmp_path, command, where):
    afile = tmp_path / "afile"
    afile.write_text("keep\n")
    target = {"/proc/x": Path("/proc/x"), "a file": afile, "below a file": afile / "sub"}[where]
    message = {"/proc/x": "cannot write into /proc", "a file": "exists and is not a folder",
               "below a file": "is not a folder"}[where]
    fails(capfd, command + [target], message)  # one line on stderr: no progress line, so no work was done
    assert afile.read_text() == "keep\n"


@pytest.mark.parametrize("args, message", [
    (["export", "--check", "--dir", "{afile}"], "is not a folder of exported files"),
    (["main", "--out", "/proc/x"], "cannot write into /proc"),
    (["main", "--out", "{out}", "--dir", "/proc/x"], "is not a folder of exported files"),
    (["check", "pendulum", "--no-scenes", "--out", "{out}", "--junit", "/proc/x/j.xml"], "--junit /proc/x"),
])
def test_a_destination_or_folder_of_a_later_phase_is_refused_before_the_work(capfd, tmp_path, args, message):
    """Found by a user's trial: these ran the whole job (a check, the main job), wrote its results, and failed at the
    end (an unwritable JUnit file, a missing folder of exported files), or printed one error per phase."""
    afile = tmp_path / "afile"
    afile.write_text("keep\n")
    out = tmp_path / "out"
    fails(capfd, [a.format(afile=afile, out=out) for a in args], message)
    assert not out.exists() and afile.read_text() == "keep\n"


def test_unwritable_cache_folder_is_refused_before_the_work(capfd, tmp_path, monkeypatch):
    (tmp_path / "afile").write_text("")
    for cache in ("/proc/x", str(tmp_path / "afile")):
        monkeypatch.setenv("HARNESS_CACHE_DIR", cache)
        fails(capfd, ["eval", "pendulum", "--q", "0"], f"HARNESS_CACHE_DIR {cache}")


FULL_DISK = textwrap.dedent("""
    import resource, signal, sys
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # writing past the limit fails with EFBIG, as on a full disk
    # no bytecode from this process: CPython writes a .pyc with one unchecked write, so under the limit a module
    # imported here for the first time would leave a truncated .pyc that breaks every later import of it
    sys.dont_write_bytecode = True
    resource.setrlimit(resource.RLIMIT_FSIZE, (64, 64))
    from harness import cli
    sys.exit(cli.main(sys.argv[1:]))
""")


def test_full_disk_while_writing_is_one_line_and_leaves_nothing_half_written(tmp_path):
    """The disk fills up after the work, while the first file is written (a 64-byte file size limit in a child
    process): one line, exit 2, the old file whole, no temporary file left."""
    out = tmp_path / "urdf"
    out.mkdir()
    (out / "pendulum.urdf").write_text("old\n")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.run([sys.executable, "-c", FULL_DISK, "export", "--dir", str(out)], capture_output=True,
                          text=True, env=env, timeout=300)
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2, proc.stderr
    assert len(lines) == 1 and lines[0].startswith("error: ") and "cannot write: File too large" in lines[0]
    assert "Traceback" not in proc.stderr and proc.stdout == ""
    assert [p.name for p in out.iterdir()] == ["pendulum.urdf"]
    assert (out / "pendulum.urdf").read_text() == "old\n"


# ----------------------------------------------------------------------------------- bad input that exited 0
@pytest.mark.parametrize("args, message", [
    (["eval", "pendulum", "--q", "0", "--param", "m=1", "--param", "m=2"], "--param m is given twice"),
    (["eval", "pendulum", "--q", "0", "--param", "m=1", "m=2"], "--param m is given twice"),
    (["eval", "cart_pendulum", "--q", "0", "0", "--input", "f=1", "--input", "f=2"], "--input f is given twice"),
    (["eval", "pendulum", "--q", "0.3", "--param", "m=1e308"], "parameter m=1e+308: exceeds 1e+12 in magnitude"),
    (["eval", "pendulum", "--q", "0.3", "--param", "m=1e308", "--engine", "pinocchio"], "parameter m=1e+308"),
    (["eval", "pendulum", "--q", "0.3", "--param", "l=1e200", "--engine", "mujoco"], "parameter l=1e+200"),
    (["eval", "pendulum", "--q", "0.3", "--param", "m=inf"], "parameter m=inf"),
    (["eval", "pendulum", "--q", "0.3", "--qd", "1e300"], "--qd [1e+300]: exceeds 1e+12"),
])
def test_bad_values_that_exited_0(capfd, args, message):
    fails(capfd, args, message)


@pytest.mark.parametrize("system, q", [("spherical_pendulum", ["0", "0"]), ("governor", ["0", "0"])])
def test_one_verdict_at_a_singular_state(capfd, system, q):
    """Before: symbolic exit 2, Pinocchio NaN (or a LinAlgError traceback) with exit 0, MuJoCo q̈ = 0 with exit 0."""
    lines = {fails(capfd, ["eval", system, "--q", *q, "--qd", "1", "1", "--engine", engine],
                   f"coordinate singularity at {'theta' if system == 'spherical_pendulum' else 'phi'} = 0")
             for engine in ("symbolic", "pinocchio", "mujoco")}
    assert len(lines) == 1


BASE = '<link name="base"/>'
JOINT = ('<joint name="{name}" type="{type}"><parent link="{parent}"/><child link="{child}"/><axis xyz="0 0 1"/>'
         '<limit effort="1" velocity="1" lower="-1" upper="1"/></joint>')


def _robot(*parts) -> str:
    return '<robot name="r">' + "".join(parts) + "</robot>"


@pytest.mark.parametrize("text, message", [
    (_robot(BASE, '<link name="arm"/>', JOINT.format(name="phi", type="revolute", parent="base", child="arm")),
     "link 'arm' (moved by joint 'phi') and everything it carries have no mass and no inertia"),
    (_robot(BASE, '<link name="arm"><inertial><mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" '
                  'izz="0"/></inertial></link>', JOINT.format(name="phi", type="revolute", parent="base", child="arm")),
     "link 'arm' (moved by joint 'phi')"),
    (_robot(BASE, '<link name="arm"><inertial><origin xyz="0 0 0.3" rpy="0 0 0"/><mass value="2"/><inertia ixx="0" '
                  'ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>',
            JOINT.format(name="phi", type="revolute", parent="base", child="arm")),
     "a motion of joint 'phi' (link 'arm') moves no mass"),
    (_robot(BASE, '<link name="arm"/>', '<link name="arm"/>',
            JOINT.format(name="phi", type="revolute", parent="base", child="arm")),
     "link 'arm' is defined twice"),
    (_robot(BASE, '<link name="a"/>', '<link name="b"/>', JOINT.format(name="j1", type="revolute", parent="base",
                                                                        child="a"),
            JOINT.format(name="j2", type="revolute", parent="a", child="b"),
            JOINT.format(name="j3", type="revolute", parent="b", child="a")),
     "link 'a' is the child of two joints ('j1' and 'j3')"),
    (_robot('<link name="a"/>', '<link name="b"/>', JOINT.format(name="j1", type="revolute", parent="a", child="b"),
            JOINT.format(name="j2", type="revolute", parent="b", child="a")),
     "the joints form a cycle through link 'a'"),
    (_robot(BASE, JOINT.format(name="phi", type="revolute", parent="base", child="ghost")),
     "joint 'phi' names child link 'ghost', which is not defined"),
    (_robot(BASE, '<link name="x"/>'), "links 'base' and 'x' are both roots"),
])
def test_invalid_urdf_names_the_link(capfd, tmp_path, text, message):
    validate_fails(capfd, tmp_path, text, message)


def test_urdfdom_message_is_kept_when_pinocchio_refuses():
    from harness.engines.pinocchio_engine import load_urdf

    text = _robot(BASE, '<link name="arm"/>', '<link name="arm"/>',
                  JOINT.format(name="phi", type="revolute", parent="base", child="arm"))
    with pytest.raises(ModelError, match="urdfdom: Error: +link 'arm' is not unique"):
        load_urdf(text, "dup.urdf")


def test_a_valid_model_still_validates_in_the_child(capfd, tmp_path):
    path = tmp_path / "model" / "m.urdf"
    path.parent.mkdir()
    path.write_text(urdf(extra='<visual><geometry><mesh filename="package://arm/meshes/a.stl"/></geometry></visual>'))
    assert cli.main(["validate", str(path), "--states", "2"]) == 0
    assert capfd.readouterr().out.strip().endswith("valid")


# ----------------------------------------------------------------------------------- a user's second trial
@pytest.mark.parametrize("args, message", [
    (["eval", "pendulum", "--q", "-inf"], "--q must be finite numbers, got [-inf]"),
    (["eval", "pendulum", "--q", "-nan"], "--q must be finite numbers"),
    (["validate", "{folder}"], "is a folder; give a URDF (.urdf) or MJCF (.xml) file in it"),
    (["validate", "{urdf}", "--root", "{afile}"], "--root {afile}: is not a folder"),
    (["validate", "{urdf}", "--root", "{missing}"], "--root {missing}: no such folder"),
    (["new", "my_system", "--dir", "{afile}"], "new --dir {afile}: is not a folder"),
    (["eval", "spring_mass_damper", "--q", "0.1", "0", "0", "--engine", "mujoco"],
     "g(q) (5.96) not finite at s_1 = 0.1, s_2 = 0, s_3 = 0 in spring_mass_damper: a force element is singular"),
])
def test_a_negative_number_a_folder_or_a_singular_force_gets_its_own_message(capfd, tmp_path, args, message):
    """Found by trying the commands by hand: `--q -inf` (and `-1e-3`) was taken for an option ("expected at least one
    argument"); a folder given to validate was "no such file"; `--root` a file or a missing folder was accepted; `new
    --dir` a file said the folder "does not exist"; a spring of length 0 was "the mass matrix M is not finite", after
    a page of RuntimeWarnings, and MuJoCo answered with a zero-length tendon's force 0."""
    names = {"folder": tmp_path / "models", "afile": tmp_path / "afile", "missing": tmp_path / "missing",
             "urdf": tmp_path / "models" / "m.urdf"}
    names["folder"].mkdir()
    names["afile"].write_text("keep\n")
    names["urdf"].write_text(urdf())
    fails(capfd, [a.format(**names) for a in args], message.format(**names))
    assert names["afile"].read_text() == "keep\n" and not names["missing"].exists()


def test_new_creates_the_folder_of_your_own_models_and_leaves_nothing_when_it_fails(capfd, tmp_path, monkeypatch):
    """`harness new NAME --dir FOLDER` for a folder not made yet (the first model of one's own, FOLDER already in
    HARNESS_MODELS_PATH as the docs say): the folder was "no such folder" on its own, and with the variable set every
    command, `new` too, stopped on it. Now `new` creates it with the module; a write that fails removes the folders
    it made."""
    import harness.scaffold
    from harness.catalogue import check_search_path

    folder = tmp_path / "mine" / "models"
    monkeypatch.setenv("HARNESS_MODELS_PATH", str(folder))
    monkeypatch.setattr(harness.scaffold, "atomic_write_text", lambda *a, **k: (_ for _ in ()).throw(
        OSError(28, "No space left on device")))
    fails(capfd, ["new", "my_first", "--dir", str(folder)], f"new --dir {folder}: No space left on device")
    assert not (tmp_path / "mine").exists()
    monkeypatch.undo()
    monkeypatch.setenv("HARNESS_MODELS_PATH", str(folder))
    assert cli.main(["new", "my_first", "--dir", str(folder)]) == 0
    assert (folder / "my_first.py").is_file()
    check_search_path()   # every other command, which had stopped on the missing folder, now finds it


def test_a_negative_number_in_scientific_notation_is_a_value(capfd):
    assert cli.main(["eval", "pendulum", "--q", "-1e-3", "--qd", "-2.5E+1", "--json"]) == 0
    doc = json.loads(capfd.readouterr().out)
    assert doc["q"] == [-1e-3] and doc["qd"] == [-25.0] and doc["f_damper"] == [0.0]


@pytest.mark.parametrize("where, message", [("missing", "no such folder"), ("afile", "is not a folder")])
def test_a_models_path_that_names_no_folder_is_refused(capfd, tmp_path, monkeypatch, where, message):
    """A mistyped HARNESS_MODELS_PATH was ignored without a word: the user's systems were simply not listed."""
    (tmp_path / "afile").write_text("")
    monkeypatch.setenv("HARNESS_MODELS_PATH", str(tmp_path / where))
    fails(capfd, ["list"], f"HARNESS_MODELS_PATH {tmp_path / where}: {message}")


@pytest.mark.parametrize("shadowed", ["pendulum", "mine"])
def test_a_models_path_module_that_a_folder_before_it_names_is_refused(capfd, tmp_path, monkeypatch, shadowed):
    """A copy of models/pendulum.py in an added folder, to be edited, was never loaded (Python imports the module of
    that name found first), and nothing said so: the user's edits made no difference. Two added folders with one
    module name: the same."""
    first, second = tmp_path / "first", tmp_path / "second"
    first.mkdir(), second.mkdir()
    (first / "mine.py").write_text("")
    (second / f"{shadowed}.py").write_text("")
    monkeypatch.setenv("HARNESS_MODELS_PATH", os.pathsep.join([str(first), str(second)]))
    before = "models/pendulum.py" if shadowed == "pendulum" else str(first / "mine.py")
    fails(capfd, ["list"], f"HARNESS_MODELS_PATH: {second / (shadowed + '.py')} has the module name of {before}, "
                           "which is searched first and loaded instead; rename the file (and its SYSTEM)")
