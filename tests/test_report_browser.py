"""The report in a real browser: Debian's headless Chromium opens ``index.html``, follows every link and image,
and fails on a console error, a page error, a failed request or a broken link; it saves a screenshot.

The report is built from a small run (two systems, few examples) plus small synthetic files for the parts other
commands produce (a scene's series, the errata, benchmarks, hard cases, importer findings), so that every
page kind is rendered and visited. Nothing is downloaded: the browser is ``/usr/bin/chromium``."""

from __future__ import annotations

import json
from pathlib import Path
from urllib.parse import unquote, urldefrag, urlparse

import numpy as np
import pytest

from harness import cli

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
SYSTEMS = ("pendulum", "cart_pendulum")


def synthetic_series(system: str, scene: str) -> dict:
    """A small series file of the shape ``harness check`` writes (trajectories/<system>.<scene>.json)."""
    t = np.linspace(0.0, 2.0, 501)
    q = 1.0472 * np.cos(3.13 * t)
    sources = {name: {"q": [[v + eps * k] for k, v in enumerate(q)], "qd": [[0.0]] * len(t),
                      "energy": list(4.905 + eps * t)}
               for name, eps in (("symbolic", 0.0), ("pinocchio", 1e-12), ("mujoco", 1e-10))}
    return {"system": system, "scene": scene, "coordinates": ["phi"], "t": list(t), "sources": sources,
            "error": {"pinocchio": list(1e-12 * t + 1e-16), "mujoco": list(1e-10 * t + 1e-16)}}


def add_other_artifacts(out: Path) -> None:
    """What the scene runs, `harness claims`, `harness bench`, the hard cases and the importer add."""
    (out / "trajectories").mkdir(exist_ok=True)
    (out / "trajectories" / "pendulum.swing.json").write_text(json.dumps(synthetic_series("pendulum", "swing")))
    doc = json.loads((out / "results.json").read_text())
    for record in doc["systems"]:
        if record["system"] == "pendulum":
            record["scenes"] = [{"scene": "swing", "description": "released at 60° from rest", "effects": ["gravity"],
                                 "horizon": 2.0, "passed": True, "notes": {"mj_step RK4 error ratio": 16.0},
                                 "checks": [{"check": "trajectory", "source": "pinocchio", "max_error": 2e-12,
                                             "tolerance": 1e-6, "passed": True}],
                                 "series": "trajectories/pendulum.swing.json"}]
    (out / "results.json").write_text(json.dumps(doc, indent=1))
    (out / "claims.json").write_text(json.dumps([
        {"system": "pendulum", "equation": "(3.111)", "quantity": "eom", "description": "m l² phi'' = -m g l sin(phi)",
         "classification": "confirmed", "printed": "m*l**2*phi_ddot + g*l*m*sin(phi)", "corrected": None,
         "convention": None, "counterexample": None, "note": "", "examples": 5, "errors_over_tolerance": {}},
        {"system": "cart_pendulum", "equation": "Solution (m_S)", "quantity": "parameter", "description": "rod mass",
         "classification": "erratum", "printed": "b_S*g*h_S*l_S*rho_S", "corrected": "b_S*h_S*l_S*rho_S",
         "convention": None, "counterexample": "q=[0.0, 0.0]", "note": "", "examples": 5,
         "errors_over_tolerance": {"derivation": 9.5e11}}]))
    svg = '<svg xmlns="http://www.w3.org/2000/svg" width="40" height="20"><rect width="40" height="20"/></svg>'
    for kind in ("bench", "hard"):
        (out / kind).mkdir()
        (out / kind / "figure.svg").write_text(svg)
        (out / f"{kind}.json").write_text(json.dumps({"cases": [{"system": "pendulum", "error": 1.5e-9}]}))
    (out / "bench.md").write_text("# Work-precision\n\n| scene | error |\n|---|---|\n| pendulum/swing | 1e-9 |\n\n"
                                  "![work-precision](bench/figure.svg)\n\n- a [link out of the report](../x.md)\n")
    (out / "importer.json").write_text(json.dumps({"findings": ["inertia frame rotated"], "checked": 3}))


# Every <math> element: well-formed as XML (its own markup, parsed alone), no <merror>, and laid out with a
# non-zero box (Chromium's MathML Core renders it; an element it does not know would collapse).
MATH_PROBLEMS = """() => {
  const out = [];
  const parser = new DOMParser();
  for (const m of document.getElementsByTagName('math')) {
    const text = new XMLSerializer().serializeToString(m);
    const doc = parser.parseFromString(text, 'application/xml');
    if (doc.getElementsByTagName('parsererror').length) out.push('MathML does not parse: ' + text.slice(0, 120));
    if (m.getElementsByTagName('merror').length) out.push('MathML error: ' + m.textContent.slice(0, 80));
    const box = m.getBoundingClientRect();
    if (box.width === 0 || box.height === 0) out.push('MathML not rendered: ' + text.slice(0, 120));
  }
  return out;
}"""


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("report")
    assert cli.main(["check", *SYSTEMS, "--examples", "5", "--no-scenes", "--out", str(out)]) == 0
    add_other_artifacts(out)
    assert cli.main(["report", *SYSTEMS, "--out", str(out)]) == 0
    return out


def _local(url: str) -> Path | None:
    parsed = urlparse(url)
    return Path(unquote(parsed.path)) if parsed.scheme == "file" else None


def test_every_page_and_link_works_in_chromium(report, tmp_path):
    from playwright.sync_api import sync_playwright

    assert CHROMIUM.exists(), "Debian's chromium is missing: `make setup` installs it"

    problems: list[str] = []
    math_count: dict[str, int] = {}
    visited: set[Path] = set()
    todo = [(report / "index.html").resolve()]
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
        page = browser.new_page()
        page.on("console", lambda m: problems.append(f"console {m.type}: {m.text}") if m.type == "error" else None)
        page.on("pageerror", lambda e: problems.append(f"page error: {e}"))
        page.on("requestfailed", lambda r: problems.append(f"request failed: {r.url}"))
        while todo:
            path = todo.pop()
            if path in visited:
                continue
            visited.add(path)
            page.goto(path.as_uri())
            page.wait_for_load_state("load")
            if path.name == "index.html" and path.parent == report.resolve():
                page.screenshot(path=str(tmp_path / "index.png"), full_page=True)
            if path.name == "cart_pendulum.html":
                page.screenshot(path=str(tmp_path / "cart_pendulum.png"), full_page=True)
            broken_images = page.evaluate(
                "Array.from(document.images).filter(i => !i.complete || i.naturalWidth === 0 || i.naturalHeight === 0"
                " || i.getBoundingClientRect().width === 0).map(i => i.src)")
            problems += [f"{path.name}: image not shown: {src}" for src in broken_images]
            problems += [f"{path.name}: {issue}" for issue in page.evaluate(MATH_PROBLEMS)]
            math_count[path.name] = page.evaluate("document.getElementsByTagName('math').length")
            for href in page.eval_on_selector_all("a[href]", "els => els.map(e => e.href)"):
                target, fragment = urldefrag(href)
                local = _local(target)
                if local is None:
                    problems.append(f"{path.name}: link leaves the report: {href}")
                elif not local.is_file():
                    problems.append(f"{path.name}: broken link {href}")
                elif report.resolve() not in local.resolve().parents:
                    problems.append(f"{path.name}: link outside the report folder: {href}")
                else:
                    if fragment and local.resolve() == path and not page.query_selector(f"[id='{fragment}']"):
                        problems.append(f"{path.name}: no anchor #{fragment}")
                    if local.suffix == ".html":
                        todo.append(local.resolve())
        browser.close()
    assert not problems, "\n".join(problems)
    names = {p.name for p in visited}
    assert {"index.html", "pendulum.html", "cart_pendulum.html", "errata.html", "bench.html", "hard.html",
            "importer.html"} <= names
    assert (tmp_path / "index.png").stat().st_size > 10_000
    assert (tmp_path / "cart_pendulum.png").stat().st_size > 10_000   # screenshots kept as test artifacts
    assert (report / "figures" / "pendulum.swing.svg").is_file()
    assert math_count["cart_pendulum.html"] > 20 and math_count["pendulum.html"] > 5
    for picture in ("pendulum.png", "cart_pendulum.png", "pendulum.swing.strip.png"):  # rendered by MuJoCo
        assert (report / "figures" / picture).stat().st_size > 500, picture


OVERFLOWING = """() => Array.from(document.querySelectorAll('.eq'))
  .filter(e => e.scrollWidth > e.clientWidth + 1)
  .map(e => [e.scrollWidth, e.clientWidth, e.textContent.slice(0, 60)])"""


# one worker for the tests that read every page's equations: on a cold cache the first computes them, the others
# read them (not each worker all of them again)
@pytest.mark.xdist_group("page-equations")
def test_no_equation_of_the_catalogue_scrolls_in_chromium():
    """Every derived and printed equation of every system page, laid out by Chromium at the report's 1300 px: none
    is wider than its row (an equation that scrolls sideways takes its equation numbers with it). 38 rows were in
    the report of f55748a: the trebuchet's M and C, the rotating body's and planar manipulator's entries before
    their common subexpressions were named (:func:`harness.report.equations.abbreviated`), the printed equations
    and their derived forms before they were broken over lines, the tower crane's printed Jacobian (4.73) before it
    was written column by column (:func:`harness.report.equations.wide_math`). No table of bodies is wider than the
    page either: the tower crane's and the rotating body's inertia tensors had made theirs three and four screens wide
    before they were written below it, entry by entry (:func:`harness.report.model_text.link_rows`)."""
    import models
    from playwright.sync_api import sync_playwright

    from harness.report.equations import page_equations
    from harness.report.model_text import link_rows
    from harness.report.templates import CSS, environment

    derived, printed = environment().get_template("equations"), environment().get_template("claims")
    bodies = environment().get_template("bodies")
    rows, below = "", 0
    for name in models.names():
        page = page_equations(models.get(name), models.claims(name))
        links = link_rows(models.get(name))
        below += sum(len(link["below"]) for link in links)
        rows += f"<h2>{name}</h2>" + bodies.render(model={"links": links})
        rows += derived.render(model={"equations": page["equations"]})
        rows += printed.render(model={"claims": [{**c, "record": None} for c in page["claims"]]})
    html = f'<!DOCTYPE html><html><head><meta charset="utf-8"><style>{CSS}</style></head><body>{rows}</body></html>'
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1300, "height": 900})
        page.set_content(html)
        wide = page.evaluate(OVERFLOWING)
        tables = page.evaluate("""() => Array.from(document.querySelectorAll('div.wide'))
          .filter(e => e.scrollWidth > e.clientWidth + 1).map(e => [e.scrollWidth, e.textContent.slice(0, 60)])""")
        shown = page.evaluate("document.querySelectorAll('.eq').length")
        browser.close()
    assert shown > 700 and below == 2   # the tower crane's and the rotating body's inertia tensors
    assert not wide, wide
    assert not tables, tables
