"""Reports: results.json is byte-identical for the same seed (timings go to timings.json), it follows its
documented schema, summary.md and the pages come from one writer, and one system raising never loses the others."""

from __future__ import annotations

import importlib
import json
import re
import shutil
from pathlib import Path

import pytest

import models
from harness import cli
from harness.report import build_site
from harness.report.results import split_timings

SCHEMA = Path(__file__).resolve().parent.parent / "docs" / "results.schema.json"


@pytest.fixture(scope="module")
def two_runs(tmp_path_factory):
    """``harness check pendulum --out`` twice in one process; between the runs, modules a scene run imports are
    loaded (hypothesis would otherwise mix constants from their source into the draws)."""
    runs = []
    for k in range(2):
        out = tmp_path_factory.mktemp(f"run{k}")
        assert cli.main(["check", "pendulum", "--examples", "10", "--no-scenes", "--out", str(out)]) == 0
        runs.append(out)
        for module in ("harness.report.site", "harness.scenes.trajectories"):
            importlib.import_module(module)
    return runs


def test_same_seed_gives_byte_identical_results(two_runs):
    a, b = (run / "results.json" for run in two_runs)
    assert a.read_bytes() == b.read_bytes()
    doc = json.loads(a.read_text())
    assert doc["hypothesis"]["profile"] and doc["hypothesis"]["derandomize"] is True
    assert "database" in doc["hypothesis"] and doc["versions"]["mujoco"] and doc["versions"]["pinocchio"]
    assert "seconds" not in a.read_text() and "time ratio" not in a.read_text()
    timings = json.loads((two_runs[0] / "timings.json").read_text())
    assert timings["systems/pendulum/seconds"] > 0


def test_explicit_seed_is_recorded_and_reproducible(tmp_path):
    for name in ("a", "b"):
        assert cli.main(["check", "pendulum", "--examples", "5", "--seed", "7", "--no-scenes",
                         "--out", str(tmp_path / name)]) == 0
    a, b = (tmp_path / name / "results.json" for name in ("a", "b"))
    assert a.read_bytes() == b.read_bytes()
    assert json.loads(a.read_text())["hypothesis"]["seed"] == 7


def test_results_follow_the_documented_schema(two_runs):
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads(SCHEMA.read_text())
    jsonschema.validate(json.loads((two_runs[0] / "results.json").read_text()), schema)


def test_timings_are_the_records_typed_field():
    """Clock values are in each system record's ``timings`` (not found by their names): the writer moves them out;
    a scene's measured numbers stay in its notes."""
    doc = {"schema": {}, "systems": [{"system": "p", "timings": {"seconds": 1.5}, "scenes": [
        {"scene": "s", "notes": {"mj_step RK4 error ratio": 16.0, "wall seconds of nothing": 2.0}}]}]}
    clean, timings = split_timings(doc)
    assert timings == {"systems/p/seconds": 1.5}
    assert clean["systems"][0]["scenes"][0] == {"scene": "s", "notes": {"mj_step RK4 error ratio": 16.0,
                                                                           "wall seconds of nothing": 2.0}}
    assert list(clean) == ["schema", "systems"] and "timings" not in clean["systems"][0]
    assert doc["systems"][0]["timings"] == {"seconds": 1.5}  # the document itself is left as it was


def test_a_system_page_that_fails_marks_only_that_system(two_runs, monkeypatch):
    from harness.report import site

    out = two_runs[1]
    doc = json.loads((out / "results.json").read_text())
    doc["systems"].append({**doc["systems"][0], "system": "cart_pendulum"})
    (out / "results.json").write_text(json.dumps(doc))
    real = site.model_view

    def broken(system):
        if system.name == "cart_pendulum":
            raise RuntimeError("simulated crash")
        return real(system)

    monkeypatch.setattr(site, "model_view", broken)
    result = build_site(out, models.CATALOGUE, progress=open("/dev/null", "w"))
    assert result["failed"] == {"cart_pendulum": "cart_pendulum: page not built: RuntimeError: simulated crash"}
    assert "simulated crash" in (out / "systems" / "cart_pendulum.html").read_text()
    page = (out / "systems" / "pendulum.html").read_text()
    assert "conformant" in page and "simulated crash" not in page
    assert "cart_pendulum" in (out / "index.html").read_text()


def test_the_index_says_how_the_hard_cases_ended(two_runs):
    """The index names the hard cases' verdict and margins (hard.json, which the main job writes before the report);
    without a hard.json of their schema, nothing (a file of another shape had stopped the report: the browser
    test's)."""
    from harness.report import site

    out = two_runs[0]
    (out / "hard.json").write_text(json.dumps({"cases": [{"system": "pendulum"}]}))   # not the hard cases' schema
    site.build_site(out, models.CATALOGUE, progress=open("/dev/null", "w"))
    assert "Hard cases</a>:" not in (out / "index.html").read_text()
    shutil.copy(Path(__file__).parents[1] / "reports" / "hard.json", out / "hard.json")
    cases = len(json.loads((out / "hard.json").read_text())["cases"])
    site.build_site(out, models.CATALOGUE, progress=open("/dev/null", "w"))
    index = (out / "index.html").read_text()
    assert re.search(rf'<a href="hard.html">Hard cases</a>: {cases} of {cases} cases pass; margins: \d+ of \d+ checks '
                     r"above 0.1 of their bound \(\d+ on a derived bound, 0 on a margin bound\)\.", index)


def test_markdown_bold_and_italic_beside_links():
    """Bold and italic have one group, links two: each is rendered (a bold cell once crashed the site)."""
    from harness.report.mdhtml import markdown_html

    html = markdown_html("| goal | met |\n|---|---|\n| a | **no** |\n\n*x* [l](bench.md)")
    assert "<b>no</b>" in html and "<i>x</i>" in html and '<a href="bench.md">l</a>' in html


def test_an_in_page_link_reaches_its_heading_as_on_a_code_host():
    """A heading's anchor is a code host's (lower case, punctuation dropped, spaces as ``-``): ``[x](#slug)`` in our
    Markdown leads to it in the HTML too (the hard cases' table links each case's section)."""
    from harness.report.mdhtml import markdown_html, slug

    assert slug("pendulum_long_horizon: Pendulum over 10000 periods, `T/64`") == \
        "pendulum_long_horizon-pendulum-over-10000-periods-t64"
    html = markdown_html("[case](#a_b-c-d)\n\n## a_b: C d", local=lambda target: False)
    assert '<a href="#a_b-c-d">case</a>' in html and '<h3 id="a_b-c-d">a_b: C d</h3>' in html


def test_the_hard_cases_page_reads_case_by_case(tmp_path):
    """``hard.md`` (written with hard.json by harness hard; rendered as hard.html): a table of the cases linking
    each case's section, which shows what goes wrong naively with its number, the remedy, the checks against their
    bounds and the case's figure; the table gives each naive number with what it measures."""
    import json as _json

    from harness.report.markdown import hard_markdown
    from harness.report.mdhtml import markdown_html, slug

    doc = _json.loads((Path(__file__).parents[1] / "reports" / "hard.json").read_text())
    text = hard_markdown(doc)
    for case in doc["cases"]:
        heading = f"{case['id']}: {case['title']}"
        assert f"## {heading}" in text and f"(#{slug(heading)})" in text
        assert f"![{case['title']}]({case['figure']})" in text
        for check in case["checks"]:
            assert check["check"].replace("|", "\\|") in text
        assert f": {case['naive']['metric']} |" in text   # the summary says what the naive number measures
    html = markdown_html(text)
    assert html.count("<img") == sum(1 for c in doc["cases"] if c["figure"]) and "**" not in html
    # the margins: every check on a margin bound within 0.1 of it, the derived ones counted and their reason given
    assert "0 on a margin bound" in text and "- thin margin" not in text
    assert "derived bound (justified horizon): T* is the first time" in text
    # one margin check at half its bound: named above the table (a list the table does not swallow)
    doc["cases"][0]["checks"][0]["ratio"] = 0.5
    html = markdown_html(hard_markdown(doc))
    assert "<li>thin margin: spherical_pendulum_pole, reference confirmed" in html and "<table>" in html


def test_a_scene_shows_the_work_precision_the_bench_measured(tmp_path):
    """The system page's work-precision of a scene: the bench's diagram (inside the report folder only) and the
    fastest configuration per source at the bench's accuracy, with the command and date of the run that measured
    them; nothing where the bench has not run the scene."""
    from harness.report.site import work_precision

    (tmp_path / "bench").mkdir()
    (tmp_path / "bench" / "pendulum-swing.svg").write_text("<svg xmlns='http://www.w3.org/2000/svg'/>")
    row = {"configuration": "symbolic DOP853 rtol=1e-09", "seconds": 0.0123456, "error": 4.2e-07, "evaluations": 88}
    bench = {"command": "harness bench --out reports", "generated": "2026-01-01", "machine": {"cpus": 2},
             "workprecision": {"accuracy": 1e-06, "scenes": [
                 {"system": "pendulum", "scene": "swing", "figure": "bench/pendulum-swing.svg",
                  "summary": {"fastest_at_accuracy": {"symbolic": row, "mujoco": None}}},
                 {"system": "pendulum", "scene": "outside", "figure": "../elsewhere.svg", "summary": {}}]}}
    view = work_precision(bench, tmp_path, "pendulum", "swing")
    assert view["figure"] == "bench/pendulum-swing.svg" and view["accuracy"] == 1e-06
    assert [r["source"] for r in view["fastest"]] == ["symbolic"] and view["fastest"][0]["seconds"] == "0.01235"
    assert work_precision(bench, tmp_path, "pendulum", "outside")["figure"] is None
    assert work_precision(bench, tmp_path, "pendulum", "unknown") is None and work_precision(None, tmp_path, "p", "s") is None
    assert (view["command"], view["generated"]) == ("harness bench --out reports", "2026-01-01")
    # a merge replaces the whole part: its numbers are the merged run's, and so are the command and date shown
    bench["updates"] = [{"parts": ["workprecision"], "command": "harness bench --parts workprecision --out x",
                         "generated": "2026-02-02", "machine": {"cpus": 4}},
                        {"parts": ["pruning"], "command": "harness bench --parts pruning --out y", "generated": "2026-03-03"}]
    view = work_precision(bench, tmp_path, "pendulum", "swing")
    assert (view["command"], view["generated"]) == ("harness bench --parts workprecision --out x", "2026-02-02")
    assert view["machine"].startswith("4 CPUs")


def test_a_system_page_shows_each_scenes_effects_and_pruning_ratios(tmp_path):
    """Per scene of a system page: the declared effects, the effects and force elements inferred idle with their
    reasons, the check's pruned = idle proof and the idle / pruned time ratio per source that the bench measured
    (bench.json's ``pruning``, here one run of each: the quarter car on a smooth road, its road force and tyre
    damper left out), or "nothing to prune" (the bump calls for every effect); pruning ratios that earlier
    versions kept in timings.json are dropped when the system is checked again."""
    import re

    from harness.bench.workprecision import pruning_task
    from harness.report.results import write_results
    from harness.scenes.trajectories import scene_record

    system = models.get("quarter_car")
    scenes = [scene_record(system, sc, models.CATALOGUE)[0] for sc in models.scenes("quarter_car")
              if sc.name in ("smooth_road", "bump")]
    assert all("timings" not in sc for sc in scenes)  # the check measures no time ratio
    stale = {"systems/quarter_car/scenes/bump/notes/pruning time ratio (idle / pruned), symbolic": 1.0}
    doc = {"systems": [{"system": "quarter_car", "lecture": "Ex. A.4", "passed": True, "checks": [],
                        "scenes": scenes, "timings": {"seconds": 1.0}}], "versions": {}}
    write_results(doc, tmp_path, timings=stale)
    assert not set(stale) & set(json.loads((tmp_path / "timings.json").read_text()))
    measured = pruning_task(models.CATALOGUE, "quarter_car", "smooth_road", repeats=1)
    (tmp_path / "bench.json").write_text(json.dumps({"command": "harness bench --parts pruning",
                                                     "generated": "2026-11-24T00:00:00+00:00",
                                                     "pruning": [measured]}))
    ratios = {s: measured["sources"][s]["ratio"] for s in ("symbolic", "pinocchio", "mujoco")}
    assert build_site(tmp_path, models.CATALOGUE, progress=open("/dev/null", "w"))["failed"] == {}
    page = (tmp_path / "systems" / "quarter_car.html").read_text()
    tables = [re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", t))
              for t in re.findall(r'<table class="pruning">.*?</table>', page, re.S)]
    bump, smooth = tables
    assert "declared dampers, external, gravity, springs" in bump and "nothing to prune" in bump
    assert "declared dampers, gravity, springs" in smooth
    assert "external: road: 0: v_U, x_U ≡ 0 over [0, 2] s" in smooth and "tyre_damper: d_R = 0" in smooth
    assert "left out when pruned external; force elements tyre_damper" in smooth
    assert "harness bench --parts pruning (2026-11-24T00:00:00+00:00)" in page
    for source, ratio in ratios.items():
        assert f"time idle / pruned, {source} {ratio:.3g} ×" in smooth


def test_a_picture_is_drawn_once_per_content_and_a_damaged_one_again(tmp_path, monkeypatch):
    """:mod:`harness.report.drawn`: the second report with the same inputs writes the kept bytes and what the
    drawing returned without drawing; other inputs, or a damaged entry, draw again."""
    from harness.report import drawn

    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path / "cache" / "derivations"))
    stale = drawn.folder() / "0123456789ab-scene-figure-0.json"   # kept by another installation
    stale.parent.mkdir(parents=True)
    stale.write_text("{}")
    calls = []

    def draw(path):
        calls.append(path)
        path.write_bytes(b"<svg>" + bytes(range(256)) + b"</svg>")
        return {"size": (3, 2), "caption": "drawn"}

    first = drawn.drawn(tmp_path / "a.svg", drawn.key("scene figure", b"series"), draw)
    again = drawn.drawn(tmp_path / "b.svg", drawn.key("scene figure", b"series"), draw)
    assert len(calls) == 1 and first == again == {"size": [3, 2], "caption": "drawn"} and not stale.exists()
    assert (tmp_path / "a.svg").read_bytes() == (tmp_path / "b.svg").read_bytes()
    assert drawn.key("scene figure", b"series") != drawn.key("scene figure", b"series ")
    assert drawn.key("scene figure", b"ab", b"c") != drawn.key("scene figure", b"a", b"bc")
    (entry,) = drawn.folder().glob("*.json")
    doc = json.loads(entry.read_text())
    entry.write_text(json.dumps({**doc, "bytes": doc["bytes"][:-8] + "AAAAAAA="}))   # other bytes, same checksum
    drawn.drawn(tmp_path / "c.svg", drawn.key("scene figure", b"series"), draw)
    entry.write_text("{not json")
    drawn.drawn(tmp_path / "d.svg", drawn.key("scene figure", b"series"), draw)
    assert len(calls) == 3 and (tmp_path / "d.svg").read_bytes() == (tmp_path / "a.svg").read_bytes()


def test_kept_pictures_start_no_rendering_process(tmp_path, monkeypatch):
    """render_all: a system whose pictures the cache holds is read in the report's process (no rendering process
    started: it costs 1.5-2 CPU s); one with a picture to draw goes to the process, and both give the same result."""
    from concurrent import futures

    from harness.report import render

    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path / "cache" / "derivations"))
    jobs = [{"system": "pendulum", "out": str(tmp_path), "catalogue": models.CATALOGUE, "scenes": []}]
    (tmp_path / "figures").mkdir()
    drawn = render.render_all(jobs)()  # nothing kept yet: drawn in the rendering process
    assert drawn["pendulum"]["picture"]["target"] == "figures/pendulum.png", drawn
    started = []
    real = futures.ProcessPoolExecutor
    monkeypatch.setattr(futures, "ProcessPoolExecutor", lambda *a, **k: started.append(1) or real(*a, **k))
    assert render.render_all(jobs)() == drawn and not started


def test_a_notation_typo_is_near_its_boundary_only_where_it_nearly_fails_under_its_renaming():
    """The index's table of printed equations near their verdict's boundary: a notation typo's recorded errors are
    those under its renaming, where it holds, so it is near its boundary like a confirmed claim (above 0.1 of the
    tolerance), not like a wrong one (below 10×). All 13 of the lecture's notation typos were listed before."""
    from harness.report import margins

    def record(classification, **errors):
        return {"system": "s", "equation": classification, "classification": classification,
                "errors_over_tolerance": errors}

    rows = margins.claim_rows([record("notation typo", derivation=2e-4), record("notation typo", derivation=0.5),
                               record("confirmed", derivation=0.5, mujoco=0.01), record("confirmed", derivation=0.01),
                               record("erratum", derivation=5.0, mujoco=3e7), record("erratum", derivation=1e9)])
    assert [(r["classification"], r["ratio"]) for r in rows] == [("notation typo", 0.5), ("confirmed", 0.5),
                                                                 ("erratum", 5.0)]


def test_a_system_page_says_where_a_target_is_out_of_reach_and_what_pruning_held():
    """The pruning block of a scene shows a DOP853 source's ratio per call of its right-hand side beside the run's,
    and "out of reach" where the per-call interval's high end is below the target (no run can gain more with the
    same evaluations); a friction held in the pruned run is named among what pruning leaves out."""
    from harness.report.site import pruning_view
    from harness.scenes.phenomena.pruning import CHECK

    pairs = [1.0 + 0.002 * k for k in range(21)]
    m = {"ratio": 1.01, "idle_all": pairs, "pruned_all": [1.0] * 21, "idle_seconds": 0.0221, "pruned_seconds": 0.022,
         "evaluations": [1172, 1172],
         "per_call": {"ratio": 1.02, "idle_all": pairs, "pruned_all": [1.0] * 21, "idle_seconds": 10.6e-6,
                      "pruned_seconds": 10.5e-6}}
    scene = {"scene": "released", "notes": {"effects declared": "gravity", "pruning: effects left out": "dampers",
                                           "pruning: friction held": "x"},
             "checks": [{"check": CHECK, "source": "symbolic"}]}
    view = pruning_view("cart_pendulum", scene, {"pruning": [{"system": "cart_pendulum", "scene": "released",
                                                              "sources": {"symbolic": m}}]})
    shown = next(r["ratio"] for r in view["ratios"] if r["source"] == "symbolic")
    assert "per call 1.020 ×" in shown and "1.3 × out of reach of this source" in shown
    assert view["held"] == "x"
    fast = {**m, "per_call": {**m["per_call"], "idle_all": [2.0] * 21}}   # per call 2 ×: the target can be met
    view = pruning_view("cart_pendulum", scene, {"pruning": [{"system": "cart_pendulum", "scene": "released",
                                                              "sources": {"symbolic": fast}}]})
    assert "out of reach" not in next(r["ratio"] for r in view["ratios"] if r["source"] == "symbolic")


def test_a_system_page_shows_constraint_rows_proved_inactive_and_their_price():
    """The pruning block names the constraint rows proved inactive (the proof), those left out, and per engine with
    the check's open = constrained proof the bench's constrained / open time ratio; a scene whose rows are needed
    shows the counterexample."""
    from harness.report.site import pruning_view
    from harness.scenes.phenomena.closures import ROWS_CHECK

    m = {"ratio": 2.1, "idle_all": [2.0 + 0.01 * k for k in range(21)], "pruned_all": [1.0] * 21,
         "idle_seconds": 0.04, "pruned_seconds": 0.02}
    scene = {"scene": "coast", "notes": {"effects declared": "gravity", "pruning": "nothing to prune",
                                        "constraint rows inferred inactive": "proved 0",
                                        "pruning: constraint rows left out": "coupling alpha_2 = -2 alpha_1"},
             "checks": [{"check": ROWS_CHECK, "source": "pinocchio"}]}
    view = pruning_view("governor", scene, {"pruning": [{"system": "governor", "scene": "coast",
                                                         "rows": {"sources": {"pinocchio": m}}}]})
    assert view["rows_idle"] == "proved 0" and view["rows_left_out"] == "coupling alpha_2 = -2 alpha_1"
    assert [r["source"] for r in view["rows_ratios"]] == ["pinocchio"]
    assert view["rows_ratios"][0]["ratio"].startswith("2.1 ×")
    notes = {"effects declared": "gravity", "constraint rows needed": "at q = [0.1] …"}
    needed = pruning_view("toggle_press", {"scene": "return", "notes": notes}, None)
    assert needed["rows_needed"] == "at q = [0.1] …" and not needed["rows_ratios"]


def test_a_spring_between_points_is_drawn_as_a_line_in_the_picture(tmp_path):
    """The spring-mass-damper's springs hang its masses from the bar: spatial tendons, which MuJoCo draws 3 mm wide,
    under a pixel in a picture of the whole mechanism. They are drawn at a width relative to the picture's extent
    (``render.TENDON_WIDTH``): hidden, hundreds of pixels fewer are drawn; the caption says what the lines are. A
    scene's filmstrip shows those its effects call for (the planar manipulator's swing leaves out its spring). Those
    in joints: a spring in a prismatic joint (the quarter car's) is a line between the two bodies the joint joins;
    the others (a damper in a joint may be its own friction) have no points to draw between: the caption says which.
    Rendered in a process of its own, as the report renders (its OpenGL backend chosen before MuJoCo is imported)."""
    import subprocess
    import sys

    script = f"""
import json
import re
import shutil
from pathlib import Path
from harness.report import render
render.backend()
import models
system = models.CATALOGUE.get("spring_mass_damper")
scenes = models.CATALOGUE.scenes("spring_mass_damper")
scene = render.Scene3D(system, render.mjcf_text(system))
scene.frame(render._states(system, scenes))
drawn = int((scene.render() < 250).any(axis=2).sum())
scene.option.tendongroup[:] = 0
hidden = int((scene.render() < 250).any(axis=2).sum())
scene.close()
caption = render.picture(system, render.mjcf_text(system), Path({str(tmp_path / "smd.png")!r}), scenes)["caption"]
arm = models.CATALOGUE.get("planar_manipulator")   # its spring and damper between points: one tendon
series = {{"t": [0.0, 1.0], "sources": {{"symbolic": {{"q": [[0.1, 0.2], [0.3, 0.4]]}}}}}}
folder = Path({str(tmp_path)!r})
shown = [render.filmstrip(arm, render.mjcf_text(arm), series, folder / f"{{k}}.png", effects)["tendons"]
         for k, effects in enumerate(({{"gravity"}}, {{"gravity", "springs"}}, None))]
in_joints = render._in_joints(models.CATALOGUE.get("quarter_car"))   # its springs and dampers: in joints
print(json.dumps([drawn, hidden, caption, shown, in_joints]))
"""
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300,
                         cwd=Path(models.__file__).parent.parent)
    assert run.returncode == 0, run.stderr[-2000:]
    drawn, hidden, caption, shown, in_joints = json.loads(run.stdout.strip().splitlines()[-1])
    assert drawn - hidden > 300, (drawn, hidden)
    assert "lines: its springs and dampers between points" in caption
    assert shown == [0, 1, 1]   # a scene's filmstrip: only the springs and dampers it calls for
    assert "not drawn" not in caption   # the spring-mass-damper has no spring or damper in a joint
    assert in_joints == ("; black lines between the bodies a prismatic joint joins: its springs (tyre_spring, "
                         "suspension_spring); not drawn: the other springs and dampers in joints (tyre_damper, "
                         "suspension_damper), which act along their joint's own coordinate and have no points to "
                         "draw a line between")


def test_a_picture_looks_where_the_mechanism_s_links_show_whole():
    """The camera looks square-on where that foreshortens the mechanism's most foreshortened link least (links: a
    body's joint from its parent's, its centre of mass from its joint), obliquely where that shows it 1.5 times as
    long: a planar mechanism from the side its plane faces; a Furuta pendulum (its arm along x, the pendulum
    swinging across it) obliquely, not along its least extent, the arm (the arm would be a dot); a tower crane whose
    large body's bounding sphere makes every extent equal from the side its tower, jib and rope show. Among views
    alike, along the least extent, as before."""
    import numpy as np

    from harness.report.render import Scene3D, _axes

    def looks_along(pts, links):
        return tuple(np.round(_axes(*Scene3D.view(np.asarray(pts, float), np.asarray(links, float)))[2], 6))

    rng = np.random.default_rng(0)
    planar = np.column_stack([rng.uniform(-1, 1, (8, 2)), np.zeros(8)])
    assert looks_along(planar, planar) == (0, 0, -1)
    # the arm: the pendulum's joint 0.2 along x, its centre of mass at 0.1; the pendulum's centre of mass 0.15 below
    # its joint at q = 0, and swung by 60° across the arm; the bodies' bounding spheres least along x
    furuta = [[0.2, 0, 0], [0.1, 0, 0], [0, 0, -0.15], [0, 0.13, -0.075]]
    reach = [[-0.1, -0.2, -0.25], [0.28, 0.21, 0.18]]
    assert np.argmin(np.ptp(reach, axis=0)) == 0 and abs(looks_along(reach, furuta)[0]) < 0.9
    assert abs(looks_along(reach, furuta)[2]) not in (0.0, 1.0)   # oblique
    crane = [[0, 0, 3.0], [1.5, 0, 0], [0, 0, -2.0]]   # the tower, the jib to the trolley, the rope to the load
    assert looks_along([[-2.2, -2.2, -0.7], [2.2, 2.2, 3.7]], crane) == (0, 1, 0)
    line = [[1.0, 0, 0], [0.5, 0, 0]]   # a mechanism along x: seen across its least extent
    assert looks_along([[0, 0, 0], [2, 1, 0.5]], line) == (0, 0, -1)
    assert looks_along([[0, 0, 0], [2, 0.5, 1]], line) == (0, 1, 0)


def test_a_picture_frames_the_state_it_shows_and_marks_a_slide_on_the_body_it_moves(tmp_path):
    """The picture shows one state, the first scene's initial state, and is framed around it alone (the view is
    still chosen over every scene's state): free_fall_drag's body at 39 km had been framed with the ground, a
    speck in an empty picture. A prismatic joint's label sits on the body it moves (MuJoCo's ``xanchor`` of a slide
    is where θ = 0 puts it: that label had stood at the ground). drive_train's bodies sit along their common axis
    and are seen across it, apart (they had all been at one point, the largest disc hiding the others). The quarter
    car's body is drawn above its wheel (``Link.drawn_at``; its height x_A puts it 0.2 m below at rest), its label
    with it, and the caption says so. Rendered in a process of its own, as the report renders."""
    import subprocess
    import sys

    import numpy as np

    script = f"""
import json
from pathlib import Path
import numpy as np
from PIL import Image
from harness.report import render
render.backend()
import models
out = {{}}
for name in ("free_fall_drag", "drive_train", "quarter_car"):
    system, scenes = models.CATALOGUE.get(name), models.CATALOGUE.scenes(name)
    path = Path({str(tmp_path)!r}) / f"{{name}}.png"
    caption = render.picture(system, render.mjcf_text(system), path, scenes)["caption"]
    drawn = float((np.asarray(Image.open(path).convert("RGB")) < 250).any(axis=2).mean())
    scene = render.Scene3D(system, render.mjcf_text(system))
    q = np.asarray(scenes[0].q0, dtype=float)
    scene.frame(render._states(system, scenes), shown=[q])
    scene.set_q(q)
    scene.render()
    marks = [scene.project(point)[0].tolist() for point, _ in scene.joint_marks()]
    out[name] = [drawn, marks, scene.project(scene.data.xpos[1:]).tolist(), caption]
    scene.close()
print(json.dumps(out))
"""
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300,
                         cwd=Path(models.__file__).parent.parent)
    assert run.returncode == 0, run.stderr[-2000:]
    out = json.loads(run.stdout.strip().splitlines()[-1])
    drawn, marks, bodies, _ = out["free_fall_drag"]
    assert drawn > 0.05, drawn   # 0.0007 when framed with the ground
    assert np.allclose(marks, bodies, atol=1.0), (marks, bodies)   # h on the falling body
    drawn, marks, bodies, _ = out["drive_train"]
    assert drawn > 0.05, drawn
    gaps = [np.hypot(*np.subtract(a, b)) for k, a in enumerate(bodies) for b in bodies[k + 1:]]
    assert min(gaps) > 30, bodies   # the rotor, body 1 and body 2 seen apart, in pixels
    assert np.allclose(marks, bodies, atol=1.0), (marks, bodies)   # each joint's label on its body
    _, marks, (wheel, body), caption = out["quarter_car"]
    assert body[1] < wheel[1] - 30, (wheel, body)   # above it in the picture (pixel rows count down)
    assert np.allclose(marks, [wheel, body], atol=1.0), (marks, wheel, body)
    assert "for the picture only: body by (0, 0, 0.5) m" in caption, caption


def test_a_filmstrip_draws_every_source_and_the_values_no_frame_can_show(tmp_path):
    """A scene's series names the symbolic model's solution ``reference``: the filmstrip poses its frames there and
    draws its path (grey, wide) under the engines' (it had read only ``symbolic``, a name no series has, and posed the
    frames at Pinocchio's). Discs spinning about their own axes show no motion: under each frame's time the strip
    writes the values of such coordinates (drive_train's φ₁, φ₂), over lines no wider than the frame
    (two_mass_oscillator's small angles), and the caption says why; a box turning (euler_top) and a swinging
    pendulum are seen, nothing written. The caption names the lines a strip draws (the quarter car's springs in its
    prismatic joints). Through the report, which renders in a process of its own."""
    from harness.report.results import write_results

    states = {"drive_train": [[0.0, 0.0], [6.0, 5.5], [20.0, 19.0]],
              "two_mass_oscillator": [[0.3, 0.0], [-0.0164, -0.0437], [-0.0338, -0.0856]],
              "euler_top": [[0.0, 0.5, 0.0], [0.0, 0.5, 2.0], [0.0, 0.5, 4.0]],
              "pendulum": [[0.3], [-0.3], [0.3]],
              "quarter_car": [[0.0, 0.0], [0.01, 0.02], [0.0, 0.0]]}
    systems = []
    for name, q in states.items():
        scene = models.scenes(name)[0].name
        source = {"t": [0.0, 1.0, 2.0], "q": q, "qd": q, "energy": None}
        series = f"trajectories/{name}.{scene}.json"
        (tmp_path / "trajectories").mkdir(exist_ok=True)
        (tmp_path / series).write_text(json.dumps({
            "system": name, "scene": scene, "t": [0.0, 1.0, 2.0], "error": {},
            "sources": {"reference": source, "pinocchio": source, "mujoco": source}}))
        systems.append({"system": name, "lecture": "-", "passed": True, "checks": [], "timings": {"seconds": 1.0},
                        "scenes": [{"scene": scene, "description": "-", "effects": [], "horizon": 2.0,
                                    "series": series, "passed": True, "failure": None, "checks": [], "notes": {}}]})
    write_results({"systems": systems, "versions": {}}, tmp_path)
    assert build_site(tmp_path, models.CATALOGUE, progress=open("/dev/null", "w"))["failed"] == {}
    shown = {}
    for name in states:
        page = (tmp_path / "systems" / f"{name}.html").read_text()
        figure = re.search(r'<figure class="strip"><img src="[^"]+" width="(\d+)" height="(\d+)".*?<figcaption>(.*?)'
                           r'</figcaption>', page, re.S)
        shown[name] = int(figure.group(2)), re.sub(r"<[^>]+>", "", figure.group(3))
    from harness.report.render import FRAME, TIME_LINE, VALUE_LINE

    frame, line = FRAME[1] + TIME_LINE, VALUE_LINE   # a frame and its time; a line of values under it
    assert all("as computed by mujoco, pinocchio, symbolic" in caption for _, caption in shown.values()), shown
    assert shown["drive_train"][0] == frame + line
    assert "the value of φ₁, φ₂, which turn bodies only about their own axes of symmetry" in shown["drive_train"][1]
    assert shown["two_mass_oscillator"][0] == frame + 2 * line   # φ₁ = −0.0164 rad, φ₂ = −0.0437 rad: two lines
    for name in ("euler_top", "pendulum"):
        assert shown[name][0] == frame and "the value of" not in shown[name][1], shown[name]
        assert "black lines" not in shown[name][1]
    assert "the black lines joining two bodies along a prismatic joint are its springs" in shown["quarter_car"][1]
    assert "between points" not in shown["quarter_car"][1]   # the quarter car has no spring between points


def test_a_label_and_a_line_stand_on_the_bodies_drawn(tmp_path):
    """What the pictures draw over MuJoCo's image (joint labels, the paths of a filmstrip, the lines of springs in
    prismatic joints) is projected through the camera MuJoCo renders with, the average of its two eyes: through the
    left eye alone every label had stood 17.6 px to the right of the quarter car's wheel. The quarter car's tyre and
    suspension springs are drawn as black lines between road and wheel and between wheel and body; the torsion
    spring of torsion_spring_body, in a revolute joint, is named as not drawn (and so are the dampers in joints,
    which may be a joint's own friction). Rendered in a process of its own."""
    import subprocess
    import sys

    import numpy as np
    from PIL import Image

    script = f"""
import json
from pathlib import Path
import numpy as np
from harness.report import render
render.backend()
import models
system, scenes = models.CATALOGUE.get("quarter_car"), models.CATALOGUE.scenes("quarter_car")
scene = render.Scene3D(system, render.mjcf_text(system))
q = np.asarray(scenes[0].q0, dtype=float)
scene.frame(render._states(system, scenes), shown=[q])
scene.set_q(q)
image = scene.render()
drawn = (image < 200).any(axis=2)
centres = []
for body in (1, 2):   # the wheel and the body: each a sphere at its origin, in its own half of the picture
    rows = slice(135, 270) if body == 1 else slice(0, 135)
    ys, xs = np.nonzero(drawn[rows])
    centres.append([float(xs.mean()) + 0.5, float(ys.mean()) + rows.start + 0.5])   # pixel k spans [k, k + 1)
projected = scene.project(scene.data.xpos[1:]).tolist()
lines = [scene.project(np.array(line)).tolist() for line in scene.slide_lines()]
scene.close()
caption = render.picture(system, render.mjcf_text(system), Path({str(tmp_path / "qc.png")!r}), scenes)["caption"]
torsion = render._in_joints(models.CATALOGUE.get("torsion_spring_body"))
series = {{"t": [0.0, 1.0], "sources": {{"reference": {{"q": [list(q), list(q)]}}}}}}
slides = [render.filmstrip(system, render.mjcf_text(system), series, Path({str(tmp_path)!r}) / f"{{k}}.png",
                           effects)["slides"] for k, effects in enumerate(({{"gravity"}}, {{"springs"}}, None))]
print(json.dumps([centres, projected, lines, caption, torsion, slides]))
"""
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300,
                         cwd=Path(models.__file__).parent.parent)
    assert run.returncode == 0, run.stderr[-2000:]
    centres, projected, lines, caption, torsion, slides = json.loads(run.stdout.strip().splitlines()[-1])
    assert np.allclose(projected, centres, atol=1.0), (projected, centres)   # 17.6 px off through one eye; a
    # sphere seen off the axis is drawn 0.6 px from its projected centre
    wheel, body = projected
    assert len(lines) == 2 and np.allclose(lines[1], [wheel, body], atol=1e-6), lines   # suspension: wheel to body
    assert np.allclose(lines[0][1], wheel, atol=1e-6)   # tyre: from the road to the wheel
    picture = np.asarray(Image.open(tmp_path / "qc.png").convert("RGB"))
    x, y = np.round(np.mean([wheel, body], axis=0)).astype(int)   # between the spheres: the suspension's line
    assert (picture[y, x - 1:x + 2] < 80).all(axis=1).any(), picture[y, x - 3:x + 4]
    assert "black lines between the bodies a prismatic joint joins" in caption
    assert torsion.startswith("; not drawn: the springs and dampers in joints (spring_F)"), torsion
    assert slides == [0, 2, 2]   # a filmstrip: the springs in prismatic joints where its scene calls for springs
