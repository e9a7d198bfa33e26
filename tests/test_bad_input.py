"""Bad input and faults, beyond the command-line cases of test_cli.py: each class gives one clear ``error:`` line
on stderr, exit 2, no traceback and no partial output (stdout empty, output folder untouched).

Model files go through ``harness validate`` (harness/files/untrusted.py, harness/files/validate.py); the commands run
in-process (``cli.main``) with ``capfd``, which also captures what C libraries (urdfdom, MuJoCo) print."""

from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest

import models
from harness import cli
from harness.files import untrusted
from harness.engines.mujoco_engine import check_warnings
from harness.errors import EngineError, ModelError

INERTIA = '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.025"/>'


def urdf(inertial=f'<origin xyz="0.1 0 0" rpy="0 0 0"/><mass value="1.5"/>{INERTIA}', extra="", head=""):
    return f"""<?xml version="1.0"?>{head}
<robot name="arm">
  <link name="base"/>
  <link name="arm"><inertial>{inertial}</inertial>{extra}</link>
  <joint name="phi" type="revolute">
    <parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit effort="10" velocity="10" lower="-3" upper="3"/>
  </joint>
</robot>
"""


def mjcf(body='<inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/><joint name="phi"/>', head="", top=""):
    return f"""<?xml version="1.0"?>{head}
<mujoco model="m">{top}
  <worldbody><body name="arm" pos="0 0 1">{body}</body></worldbody>
</mujoco>
"""


def fails(capfd, args, message, out_dir: Path | None = None):
    """One ``error:`` line containing ``message``, exit 2, no traceback, nothing on stdout or in ``out_dir``."""
    code = cli.main([str(a) for a in args])
    out, err = capfd.readouterr()
    lines = err.strip().splitlines()
    assert code == 2, err
    assert len(lines) == 1 and lines[0].startswith("error: ") and message in lines[0], err
    assert "Traceback" not in err and out == ""
    if out_dir is not None:
        assert not out_dir.exists() or not any(out_dir.iterdir())
    return lines[0]


def validate_fails(capfd, tmp_path, text, message, name="model.urdf"):
    path = tmp_path / "model" / name
    path.parent.mkdir(exist_ok=True)
    path.write_bytes(text.encode() if isinstance(text, str) else text)
    return fails(capfd, ["validate", path], message)


# ----------------------------------------------------------------------------------- command line
@pytest.mark.parametrize("args, message", [
    (["eval", "pendulum", "--q", "inf"], "--q must be finite"),                          # inf in a state
    (["eval", "pendulum", "--q", "0", "--param", "l=0"], "l=0.0: must be positive"),      # a length that divides
    (["eval", "pendulum", "--q", "0", "--param", "m=nan"], "m=nan"),                      # NaN parameter
    (["scenes", "cart_pendulum", "--scene", "nope"], "unknown scene 'nope' of cart_pendulum"),
    (["validate", "no/such/file.urdf"], "no such file"),
])
def test_command_line(capfd, args, message):
    fails(capfd, args, message)


def test_unknown_system_writes_no_report(capfd, tmp_path):
    fails(capfd, ["importer", "no_such_system", "--out", tmp_path / "out"], "unknown system", tmp_path / "out")


# ----------------------------------------------------------------------------------- model files
@pytest.mark.parametrize("name, text, message", [
    ("malformed URDF", '<robot name="a"><link name="x"></robot>', "malformed XML: mismatched tag"),
    ("malformed MJCF", mjcf().replace("</body>", ""), "malformed XML"),
    ("neither URDF nor MJCF", "<html><body/></html>", "neither <robot> (URDF) nor <mujoco> (MJCF)"),
    ("unreadable number", urdf(f'<mass value="1,5"/>{INERTIA}'), "value='1,5' holds '1,5', not a plain decimal"),
    ("number with a unit", urdf(f'<mass value="1.5kg"/>{INERTIA}'), "<mass> of link 'arm'"),
    ("NaN", urdf(f'<mass value="nan"/>{INERTIA}'), "not a finite number"),
    ("overflow", urdf(f'<mass value="1e999"/>{INERTIA}'), "overflows to infinity"),
    ("finite but absurd", urdf(f'<mass value="1.7976931348623155e+308"/>{INERTIA}'), "exceeds 1e+12 in magnitude"),
    ("wrong count", urdf(f'<origin xyz="0.1 0"/><mass value="1"/>{INERTIA}'), "xyz='0.1 0' needs 3 number(s), got 2"),
    ("missing attribute", urdf('<mass value="1"/><inertia ixx="1" iyy="1" izz="1"/>'), "attribute ixy is missing"),
    ("inf in MJCF", mjcf('<inertial pos="0 0 inf" mass="1" diaginertia="1 1 1"/><joint/>'), "pos='0 0 inf'"),
    ("XXE", urdf(head='<!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]>').replace('"arm">', '"&x;">', 1),
     "external entity 'x' -> 'file:///etc/passwd'"),
    ("billion laughs", mjcf(head='<!DOCTYPE m [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;">'
                                 '<!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;">]>').replace('model="m"', 'model="&c;"'),
     "entity declaration 'a' (entity expansion)"),
    ("DOCTYPE", urdf(head='<!DOCTYPE robot SYSTEM "robot.dtd">'), "may not contain a <!DOCTYPE>"),
    ("deep nesting", mjcf(body="<body>" * 300 + "</body>" * 300), "nested deeper than 200"),
    ("not UTF-8", b'<robot name="\xff\xfe"/>', "not UTF-8"),
    ("unknown encoding", '<?xml version="1.0" encoding="U0TF-8"?><robot name="a"/>', "unknown encoding: U0TF-8"),
])
def test_model_file(capfd, tmp_path, name, text, message):
    fails_name = "model.xml" if isinstance(text, str) and "<mujoco" in text else "model.urdf"
    validate_fails(capfd, tmp_path, text, message, fails_name)


@pytest.mark.parametrize("uri", [
    "package://arm/../../secret.stl", "file:///etc/passwd", "/etc/passwd", "../secret.stl",
    "http://example.com/arm.stl", "meshes/../../secret.stl",
])
def test_mesh_uri_escaping_its_folder(capfd, tmp_path, uri):
    (tmp_path / "secret.stl").write_text("solid x\nendsolid x\n")
    extra = f'<visual><geometry><mesh filename="{uri}"/></geometry></visual>'
    line = validate_fails(capfd, tmp_path, urdf(extra=extra), "<mesh> of link 'arm': filename=")
    assert "outside the model's folder" in line or "not allowed" in line


def test_mjcf_include_and_meshdir_escaping_their_folder(capfd, tmp_path):
    validate_fails(capfd, tmp_path, mjcf(top='<include file="../other.xml"/>'), "<include>", "m.xml")
    validate_fails(capfd, tmp_path, mjcf(top='<compiler meshdir="/usr/share"/>'), "meshdir='/usr/share'", "m.xml")
    top = '<compiler meshdir="meshes"/><asset><mesh name="x" file="../../x.stl"/></asset>'
    validate_fails(capfd, tmp_path, mjcf(top=top), "file='../../x.stl' is outside the model's folder", "m.xml")


def test_a_uri_inside_the_folder_is_accepted(tmp_path):
    (tmp_path / "meshes").mkdir()
    model = untrusted.parse_model(urdf(extra='<visual><geometry><mesh filename="package://arm/meshes/a.stl"/>'
                                             '</geometry></visual>'), "m.urdf", tmp_path)
    assert untrusted.check_uris(model) == [(tmp_path / "meshes" / "a.stl").resolve()]


@pytest.mark.parametrize("inertial, message", [
    (f'<mass value="-1"/>{INERTIA}', "mass -1.0 must be non-negative"),
    ('<mass value="1"/><inertia ixx="-0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.025"/>',
     "not positive (semi-)definite"),
    ('<mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.05"/>', "triangle inequality"),
    ('<origin rpy="0.3 0.2 0.1"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.05"/>',
     "triangle inequality"),
])
def test_non_physical_urdf_inertial(capfd, tmp_path, inertial, message):
    line = validate_fails(capfd, tmp_path, urdf(inertial), message)
    assert "<inertial> of link 'arm'" in line


def test_non_physical_mjcf_is_mujocos_message_on_one_line(capfd, tmp_path):
    body = '<inertial pos="0 0 0" mass="-1" diaginertia="1 1 1"/><joint/>'
    validate_fails(capfd, tmp_path, mjcf(body), "MuJoCo refused the model: Error: mass and inertia of moving", "m.xml")


def test_non_positive_timestep(capfd, tmp_path):
    """MuJoCo compiles <option timestep="-1"> and then steps nowhere: refused."""
    validate_fails(capfd, tmp_path, mjcf(top='<option timestep="-1"/>'), "timestep=-1> must be positive", "m.xml")


def test_urdfdom_complaint_becomes_one_line(capfd, tmp_path):
    """urdfdom prints 'Error: … at line … in …/joint.cpp' over several lines on stderr itself: captured."""
    text = urdf().replace('<limit effort="10" velocity="10" lower="-3" upper="3"/>', "")
    validate_fails(capfd, tmp_path, text, "Pinocchio refused the URDF: The XML stream does not contain a valid URDF")


def test_urdfdom_silently_drops_an_unreadable_inertial():
    """Why the number check exists: urdfdom loads the link massless, exit status fine, when a number does not
    parse (here Pinocchio, which reads URDF through urdfdom); our check refuses the file first."""
    from harness.engines.base import captured_output

    with captured_output():
        model = pin.buildModelFromXML(urdf(f'<mass value="1,5"/>{INERTIA}'))
    assert model.inertias[model.getJointId("phi")].mass == 0.0
    with pytest.raises(ModelError, match="not a plain decimal"):
        untrusted.check_text(urdf(f'<mass value="1,5"/>{INERTIA}'), "arm.urdf")


def test_valid_model_file_passes(capfd):
    assert cli.main(["validate", str(Path(cli.PROJECT_ROOT) / "harness/files/fixtures/rotated_inertials.urdf")]) == 0
    out, err = capfd.readouterr()
    assert out.strip().endswith("valid") and err == ""


# ----------------------------------------------------------------------------------- MuJoCo warnings
def test_mujoco_bad_state_is_an_engine_error_not_nan(capfd):
    """Before: `eval --engine mujoco` printed NaN for C, Cqd, qdd with exit 0 (mj_forward skips MuJoCo's checks).
    A rate at the bound of harness.limits.MAGNITUDE (beyond it the state is refused before any engine)."""
    fails(capfd, ["eval", "cart_pendulum", "--engine", "mujoco", "--q", "0", "0", "--qd", "0", "1e12"],
          "cart_pendulum: MuJoCo warning at t=0 s: NaN, inf or huge value in qvel")


def test_unstable_mujoco_run_is_an_engine_error():
    """MuJoCo's own integrator (RK4) with a 1 s step, far too large for the cart's spring: the state grows to
    |qvel| ~ 5e26 in 4 steps without MuJoCo failing (mj_step checks the state it steps from, not the last
    one); check_warnings after the run makes it a reported failure."""
    from harness.scenes.simulate import mujoco_native

    system = models.get("cart_pendulum")
    scene = models.scenes("cart_pendulum")[0]
    with pytest.raises(EngineError, match=r"cart_pendulum scene shaken: MuJoCo warning .*unstable"):
        mujoco_native(system, scene, timestep=1.0, integrator="RK4")


def test_check_warnings_names_every_counter():
    model = mujoco.MjModel.from_xml_string(mjcf())
    data = mujoco.MjData(model)
    check_warnings(model, data, "clean")  # nothing counted: no error
    data.qvel[:] = np.inf
    mujoco.mj_step(model, data)
    with pytest.raises(EngineError, match=r"^stepped: MuJoCo warning at t=.*qvel.*\(1x, last index 0\)$"):
        check_warnings(model, data, "stepped")
