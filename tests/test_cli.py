"""The CLI contract of DESIGN.md: `list`, `eval --json` (same numbers from every engine), bad input as one
line on stderr with exit 2 and no traceback."""

import json
import re
import subprocess
import sys

import numpy as np
import pytest

import models
from harness import cli
from harness.engines import ENGINES, SOURCES


def run(*args):
    return subprocess.run([sys.executable, "-m", "harness", *args], capture_output=True, text=True, timeout=300)


def test_list_shows_every_system():
    out = run("list").stdout
    for name, system in models.catalogue().items():
        assert name in out and system.lecture in out


def test_a_reader_that_stops_early_gets_no_traceback():
    """`harness list | head -1`: the closed pipe ends the command quietly (exit 1, as Python's own advice has it).
    The reading end is closed before the command writes, so its first write meets the closed pipe."""
    import os

    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        proc = subprocess.run([sys.executable, "-m", "harness.cli", "list"], stdout=write_end,
                              stderr=subprocess.PIPE, text=True, timeout=120)
    finally:
        os.close(write_end)
    assert proc.returncode == 1
    assert "Traceback" not in proc.stderr and "Error" not in proc.stderr


def test_eval_planar_manipulator_agrees_across_engines(capsys):
    results = {}
    for engine in SOURCES:
        assert cli.main(["eval", "planar_manipulator", "--engine", engine, "--q", "0.3", "-0.7",
                         "--qd", "1", "2", "--json"]) == 0
        results[engine] = json.loads(capsys.readouterr().out)
    ref = results["symbolic"]
    assert ref["q"] == [0.3, -0.7] and ref["qd"] == [1.0, 2.0] and "m_1" in ref["params"]
    for engine in ENGINES:
        for key in ("M", "C", "Cqd", "g", "qdd"):
            a, b = np.array(results[engine][key]), np.array(ref[key])
            assert a.shape == b.shape
            assert np.max(np.abs(a - b)) <= 1e-12 * max(1.0, np.max(np.abs(b))), (engine, key)


@pytest.mark.parametrize("args, message", [
    (["eval", "no_such_system", "--q", "0"], "unknown system 'no_such_system'"),
    (["eval", "pendulum", "--engine", "bullet", "--q", "0"], "invalid choice: 'bullet'"),
    (["eval", "pendulum", "--q", "0", "1"], "--q needs 1 value(s) (phi), got 2"),
    (["eval", "pendulum", "--q", "0", "--qd", "nan"], "--qd must be finite"),
    (["eval", "pendulum", "--q", "0", "--param", "m=-2"], "m=-2.0: must be positive"),
    (["eval", "pendulum", "--q", "0", "--param", "mass=2"], "unknown parameter 'mass'"),
    (["eval", "pendulum", "--q", "0", "--param", "m=heavy"], "is not a number"),
    (["eval", "planar_manipulator", "--q", "0", "0", "--input", "tau_9=1"], "unknown input 'tau_9'"),
    (["eval", "planar_manipulator", "--q", "0", "0", "--param", "I_zz1=1"], "triangle inequality"),
    (["check", "no_such_system"], "unknown system"),
    (["frobnicate"], "invalid choice"),
])
def test_bad_input_is_one_clear_line(args, message):
    result = run(*args)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], result.stderr
    assert "Traceback" not in result.stderr


def test_one_system_raising_does_not_lose_the_others(monkeypatch, capsys, tmp_path):
    from harness.compare import conformance

    real_run = conformance.run

    def flaky(system, **kwargs):
        if system.name == "pendulum":
            raise RuntimeError("simulated crash")
        return real_run(system, **kwargs)

    monkeypatch.setattr(conformance, "run", flaky)
    assert cli.main(["check", "pendulum", "cart_pendulum", "--examples", "5", "--out", str(tmp_path)]) == 1
    doc = json.loads((tmp_path / "results.json").read_text())
    by_name = {r["system"]: r for r in doc["systems"]}
    assert by_name["pendulum"]["failure"] == "pendulum: RuntimeError: simulated crash"
    assert by_name["cart_pendulum"]["passed"] and by_name["cart_pendulum"]["checks"]


def test_profile_says_where_the_time_goes_and_changes_no_result(capsys, tmp_path, monkeypatch):
    """``check --profile`` prints and writes the phases (profile.json, profile.md) and leaves results.json as a run
    without it writes it; ``claims --profile`` adds its own section."""
    from harness.compare import strategies

    monkeypatch.setattr(strategies, "_kept_path", lambda *args: None)  # drawn, not read back: the draws are profiled
    plain, profiled = tmp_path / "plain", tmp_path / "profiled"
    args = ["check", "pendulum", "--no-scenes", "--examples", "20"]
    assert cli.main([*args, "--out", str(plain)]) == 0
    strategies._STATES.clear()  # the states are drawn once per process: drawn again, under the profile
    assert cli.main([*args, "--out", str(profiled), "--profile"]) == 0
    assert "Profile of `harness check`" in capsys.readouterr().err
    assert (plain / "results.json").read_text() == (profiled / "results.json").read_text()
    doc = json.loads((profiled / "profile.json").read_text())["check"]
    phases = {row["phase"]: row for row in doc["phases"]}
    for name in ("conformance", "conformance/draw states", "conformance/symbolic", "derivation and compilation",
                 "conformance/engine pinocchio/model", "conformance/engine mujoco/evaluate"):
        assert phases[name]["calls"] >= 1 and phases[name]["cpu"] >= 0, name
    from harness.compare.strategies import STATES_PER_DRAW

    assert phases["conformance/draw states"]["calls"] >= 20 // STATES_PER_DRAW  # one call a parameter draw
    assert doc["machine"]["cpus"] and "pendulum" in doc["systems"]
    assert cli.main(["claims", "pendulum", "--examples", "5", "--out", str(profiled), "--profile"]) == 0
    sections = json.loads((profiled / "profile.json").read_text())
    assert set(sections) == {"check", "claims"}
    page = (profiled / "profile.md").read_text()
    assert page.startswith("![CPU seconds per phase") and "harness claims" in page  # the figure on top
    assert "classified in the check's jobs" not in page  # here the claims ran on their own
    # a second run keeps what the one it replaces measured: before/after per phase on the page
    before = sections["check"]
    strategies._STATES.clear()
    assert cli.main([*args, "--out", str(profiled), "--profile"]) == 0
    again = json.loads((profiled / "profile.json").read_text())["check"]
    assert again["previous"]["at"] == before["at"] and "previous" not in again["previous"]
    assert again["previous"]["cpu"]["conformance"] == phases["conformance"]["cpu"]
    page = (profiled / "profile.md").read_text()
    assert "| phase | wall s | CPU s | calls | ms per call | CPU s before |" in page
    assert f"Before: the run this folder held before, {before['at']}" in page
    # the report's figure of it: a bar per phase of each command (text kept as text in the SVG)
    from harness.report.site import _profile_figure

    _profile_figure(profiled)
    svg = (profiled / "profile" / "time.svg").read_text()
    assert "harness check: " in svg and "harness claims: " in svg and "conformance / draw states" in svg
    (profiled / "profile.json").write_text('{"check": {"phases": "not a list"}}')  # another shape: no figure
    _profile_figure(profiled)
    assert not (profiled / "profile" / "time.svg").exists()


def test_scenes_run_simulates_and_prints_each_check():
    """``harness scenes NAME --run``, the step the scaffold's checklist names: every check with its ratio."""
    proc = run("scenes", "pendulum", "--run")
    assert proc.returncode == 0, proc.stderr[-2000:]
    verdicts = re.findall(r" ratio \S+\s+(ok|FAIL)$", proc.stdout, re.M)
    assert len(verdicts) >= 5 and set(verdicts) == {"ok"}, proc.stdout


def test_claims_say_under_an_erratum_what_is_wrong(capsys):
    """``harness claims NAME``: an erratum's line is followed by its correction, as the errata sheet says it, so
    that a reader of the terminal need not open the sheet; a confirmed equation has its line alone."""
    assert cli.main(["claims", "cart_pendulum", "--examples", "5"]) == 0
    lines = capsys.readouterr().out.splitlines()
    k = next(i for i, line in enumerate(lines) if "Solution of Exc. 5.2 (m_S)" in line and line.endswith("erratum"))
    assert lines[k + 1].strip() == "Solution of Exc. 5.2 (m_S): the factor g does not belong."
    confirmed = next(i for i, line in enumerate(lines) if line.endswith(" confirmed"))
    assert lines[confirmed + 1].startswith("cart_pendulum ")


def test_the_main_job_runs_every_phase_as_its_command_and_exits_with_the_worst(monkeypatch, capsys, tmp_path):
    """`harness main` (the README's `make check`): export --check beside check, then claims, robots --symbolic,
    hard and report, each given the same --jobs and --out (check and claims --profile); a failing phase does not stop
    the report; the exit code is the largest; Ctrl-C (130) stops the phases. The commands are recorded here: each runs
    for real in the tests of its own (and `make check` runs this one in CI)."""
    from harness import run as application

    calls, codes = [], {"check": 1, "claims": 0, "robots": 0, "hard": 0, "report": 0}

    def command(name):
        def record(args, **extra):
            calls.append((name, args.jobs, args.out, getattr(args, "symbolic", None), getattr(args, "profile", None)))
            if codes[name] == 130:  # Ctrl-C in a phase
                raise application.Interrupted([], 1)
            return codes[name]
        return record

    for name in codes:
        monkeypatch.setattr(cli, f"cmd_{name}", command(name))
    monkeypatch.setattr(application, "stale_exports", lambda catalogue, folder: ["pendulum.xml"])
    out = str(tmp_path / "reports")
    assert cli.main(["main", "--jobs", "1", "--out", out]) == 1
    assert calls == [("check", 1, out, None, True), ("claims", 1, out, None, True), ("robots", 1, out, True, None),
                     ("hard", 1, out, None, None), ("report", 1, out, None, None)]   # check and claims profiled
    err = capsys.readouterr().err
    assert "stale: " in err and f"== harness claims --jobs 1 --profile --out {out}" in err
    assert re.search(r"main job: check exit 1 \(\d+\.\d s\), export --check exit 1, claims ok \(\d+\.\d s\), .*"
                     r"report ok \(\d+\.\d s\); exit 1 after \d+\.\d s\n$", err)
    # the profile page's overview, written before the report: each phase with its exit code, the figure below it
    main = json.loads((tmp_path / "reports" / "profile.json").read_text())["main"]
    assert [(s["phase"], s["exit"]) for s in main["steps"]] == [("check", 1), ("export --check", 1), ("claims", 0),
                                                                 ("robots", 0), ("hard", 0)]
    page = (tmp_path / "reports" / "profile.md").read_text()
    assert page.startswith("# The main job (`harness main --jobs 1 --out") and "| check | " in page
    assert page.index("| robots | ") < page.index("](profile/time.svg)")
    assert "before |" not in page  # the first main job in this folder: nothing before it

    calls.clear()
    monkeypatch.setattr(application, "stale_exports", lambda catalogue, folder: [])
    codes.update(check=0, claims=2)
    assert cli.main(["main", "--jobs", "1", "--out", out]) == 2 and len(calls) == 5
    page = (tmp_path / "reports" / "profile.md").read_text()
    assert "| phase | s | exit | before |" in page and "| claims | " in page  # the job before this one beside it

    calls.clear()
    codes.update(claims=130)
    assert cli.main(["main", "--jobs", "1", "--out", out]) == 130
    assert [c[0] for c in calls] == ["check", "claims"]
