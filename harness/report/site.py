"""``index.html`` and one page per system, plus the errata, hard cases, benchmarks and importer findings when
their JSON is in the report folder. Static, no scripts, no external resources: the folder works offline.

Fault isolation: a system whose page cannot be built (its model no longer loads, a figure fails) still gets a
page, marked failed with the reason; the other pages are unaffected.
"""

from __future__ import annotations

import html
import json
import re
import sys
from collections import Counter
from pathlib import Path

from harness.io import atomic_write_text
from harness.report.markdown import check_cells
from harness.report.mdhtml import markdown_html
from harness.report.templates import environment

# optional pages: (file, title, json, markdown, figure folder); rendered only when the JSON exists
OPTIONAL_PAGES = (
    ("hard.html", "Hard cases", "hard.json", "hard.md", "hard"),
    ("bench.html", "Benchmarks", "bench.json", "bench.md", "bench"),
    ("importer.html", "Importer findings", "importer.json", "importer.md", None),
    ("robots.html", "Robots", "robots.json", "robots.md", None),  # harness robots: one table over all robots
    ("changes.html", "Changes", "changes.json", "changes.md", None),  # harness check --baseline
    ("profile.html", "Profile", "profile.json", "profile.md", "profile"),  # harness check/claims --profile
)


NO_PICTURE = {"picture": None, "picture_size": (0, 0), "picture_caption": "", "picture_note": ""}


def _read_json(path: Path):
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None


def _hard_line(doc) -> str | None:
    """The index's line on the hard cases (``hard.json``, which the main job writes before the report): how many
    pass, and their margins; None without a document of the hard cases' schema."""
    from harness.report import margins

    if not isinstance(doc, dict) or not str(doc.get("schema", "")).startswith("hard-cases/") or not doc.get("cases"):
        return None
    cases = doc["cases"]
    return (f"{sum(bool(c.get('passed')) for c in cases)} of {len(cases)} cases pass"
            f"{', at shortened horizons' if doc.get('quick') else ''}; {margins.summary_line(doc)}")


# --------------------------------------------------------------------------- the model in the lecture's terms
def model_view(system) -> dict:
    """Coordinates, parameters (units, defaults), bodies, joints with the map, force elements, engine notes, for
    a reader: the docstring rendered, symbols and laws as MathML (harness.report.model_text)."""
    from harness.compare.strategies import drawn_spans
    from harness.report import model_text as mt

    q_spans, p_spans, rest = drawn_spans(system)
    return {
        "status": system.status, "doc": mt.docstring_html(system.doc or ""),
        "not_in_engines": list(system.not_in_engines),
        "coordinates": [{"name": c.name, "symbol": mt.inline(c), "rate": mt.inline(c.rate), "unit": c.unit,
                         "description": c.description,
                         "range": q_spans[c.name]} for c in system.coordinates],
        "drawn_rest": rest,
        "parameters": [{"name": p.name, "symbol": mt.inline(p), "default": p.default, "unit": p.unit,
                        "description": p.description, "assumption": p.assumption,
                        "range": p_spans[p.name]} for p in system.parameters],
        "inputs": [{"name": i.name, "symbol": mt.inline(i), "unit": i.unit, "description": i.description}
                   for i in system.inputs],
        "links": mt.link_rows(system), "joints": mt.joint_rows(system), "forces": mt.force_rows(system),
        "gravity": mt.gravity_sentence(system), "scene_names": [],
    }


# --------------------------------------------------------------------------- per-system view
def _check_view(c: dict) -> dict:
    value, bound, ratio, _ = check_cells(c)
    return {"check": c.get("check", ""), "source": c.get("source", ""), "passed": bool(c.get("passed")),
            "error": value, "tolerance": bound, "ratio": ratio, "basis": c.get("basis", "")}


def work_precision(bench: dict | None, out: Path, system: str, scene: str) -> dict | None:
    """The work-precision of one scene as ``harness bench`` measured it (``out/bench.json``): its diagram and the
    fastest configuration per source at the bench's accuracy; None where the bench has not run it."""
    if not bench:
        return None
    study = bench.get("workprecision") or {}
    found = next((sc for sc in study.get("scenes") or [] if sc.get("system") == system and sc.get("scene") == scene),
                 None)
    if found is None:
        return None
    figure = found.get("figure")
    fastest = [{"source": source, "configuration": row["configuration"], "error": _scalar(row["error"]),
                "seconds": _scalar(row["seconds"]), "evaluations": row.get("evaluations", "")}
               for source, row in ((found.get("summary") or {}).get("fastest_at_accuracy") or {}).items() if row]
    run = _bench_run(bench, "workprecision", system, scene)
    machine = run.get("machine") or {}
    return {"figure": figure if figure and _inside(out, figure) and (out / figure).is_file() else None,
            "fastest": fastest, "accuracy": study.get("accuracy"), "command": run.get("command", "harness bench"),
            "generated": run.get("generated", "?"),
            "machine": f"{machine.get('cpus', '?')} CPUs, {machine.get('platform', '?')}"}


def _bench_run(bench: dict, part: str, system: str, scene: str) -> dict:
    """The run of ``harness bench`` that measured the scene's row of ``part`` last: the latest merged update of it
    that covers the scene (``updates``: its command, time and machine; a run of some systems or scenes covers their
    rows alone, :func:`harness.bench.covers`), else the bench's own run."""
    from harness.bench import covers

    row = {"system": system, "scene": scene}
    runs = [u for u in bench.get("updates") or [] if part in (u.get("parts") or []) and covers(u.get("selection"), row)]
    return runs[-1] if runs else bench


# the scene notes the pruning block shows (harness.scenes.effects.Inferred.notes, harness.scenes.phenomena.pruning)
_PRUNING_NOTES = {"effects declared": "declared", "effects inferred to act": "acting",
                  "effects inferred idle": "idle", "force elements inferred idle": "idle_elements",
                  "never switches": "never_switches",
                  "pruning": "nothing", "pruning: effects left out": "left_out",
                  "pruning: force elements left out": "left_out_elements", "pruning: friction held": "held",
                  "constraint rows inferred inactive": "rows_idle", "constraint rows needed": "rows_needed",
                  "pruning: constraint rows left out": "rows_left_out"}


def pruning_view(system: str, scene: dict, bench: dict | None) -> dict | None:
    """A scene's effects and their pruning: declared, inferred idle effects and force elements with their reasons
    and the disagreements (its notes), and per source the idle / pruned time ratio that ``harness bench --parts
    pruning`` measured (``bench``: bench.json; only where the scene has the check's pruned = idle proof of that
    source, else why not) or "nothing to prune"."""
    from harness.scenes.phenomena.pruning import CHECK, LOOKS, PRUNING_GOAL, SOURCES, attainable, bound, interval

    notes = scene.get("notes") or {}
    if "effects declared" not in notes:
        return None
    view = {field: notes.get(key, "") for key, field in _PRUNING_NOTES.items()}
    view["disagreements"] = {k.split(": ", 1)[1]: v for k, v in notes.items() if k.startswith("effects disagreement")}
    measured = next((m for m in (bench or {}).get("pruning") or []
                     if m.get("system") == system and m.get("scene") == scene.get("scene")), None)
    run = _bench_run(bench, "pruning", system, scene.get("scene")) if bench else {}
    view["ratios"], view["repeats"] = [], (measured or {}).get("repeats")
    view["most_pairs"], view["goal"] = LOOKS * (view["repeats"] or 0), f"{PRUNING_GOAL:g}"
    view["measured"] = f"{run['command']} ({run.get('generated', '?')})" if run.get("command") else ""
    view["rows_ratios"] = _rows_ratios(scene, (measured or {}).get("rows")) if view["rows_left_out"] else []
    if view["nothing"]:
        return view
    checked = {c.get("source") for c in scene.get("checks") or [] if c.get("check") == CHECK}
    for source in SOURCES:
        m = ((measured or {}).get("sources") or {}).get(source) or {}
        if source in checked and isinstance(m.get("ratio"), (int, float)):
            shown = _ratio_shown(m)
            if bound(m):  # one evaluation of the right-hand side, MuJoCo's acting tree: the most the ratio can be
                label, c = bound(m)
                low, high = interval(c)
                shown += f"; {label} {c['ratio']:.3f} ×" + (f" [{low:.2f}, {high:.2f}]" if high > low else "")
                if attainable(m, PRUNING_GOAL):
                    shown += f": {PRUNING_GOAL:g} × out of reach of this source"
        elif source in checked:
            shown = m.get("skipped") or "not measured by the bench yet (harness bench --parts pruning)"
        else:
            shown = notes.get(f"pruning, {source}", "not run")
        view["ratios"].append({"source": source, "ratio": shown})
    return view


def _rows_ratios(scene: dict, measured: dict | None) -> list[dict]:
    """Per engine, the time of the constrained tree / the open tree (its constraint rows proved inactive), where
    the scene has the check's proof of that engine (:data:`~harness.scenes.phenomena.closures.ROWS_CHECK`)."""
    from harness.scenes.phenomena.closures import ROWS_CHECK

    checked = {c.get("source") for c in scene.get("checks") or [] if c.get("check") == ROWS_CHECK}
    out = []
    for source in sorted(checked):
        m = ((measured or {}).get("sources") or {}).get(source) or {}
        shown = _ratio_shown(m) if "ratio" in m else "not measured by the bench yet (harness bench --parts pruning)"
        out.append({"source": source, "ratio": shown})
    return out


def _ratio_shown(m: dict) -> str:
    """A bench ratio on a system page: the median, its interval (:func:`~harness.scenes.phenomena.pruning.interval`)
    over the pairs taken, its verdict against the target (:func:`~harness.scenes.phenomena.pruning.against`) and,
    below 1, what that is (:func:`~harness.scenes.phenomena.pruning.slower_pruned`)."""
    from harness.scenes.phenomena.pruning import PRUNING_GOAL, against, interval, slower_pruned

    (low, high), finding, pairs = interval(m), slower_pruned(m), len(m.get("idle_all") or ())
    return (f"{m['ratio']:.3g} ×" + (f" [{low:.2f}, {high:.2f}] over {pairs} pairs" if high > low else "")
            + (f" ({finding})" if finding else "") + f": {PRUNING_GOAL:g} × {against(m, PRUNING_GOAL)}")


def _profile_figure(out: Path) -> None:
    """``profile/time.svg``, where the time went (:func:`harness.report.figures.profile_figure`), beside the
    profile page's tables; none without ``profile.json``."""
    from harness.profiling import FIGURE
    from harness.report.figures import profile_figure

    sections, target = _read_json(out / "profile.json"), out / FIGURE
    if not isinstance(sections, dict) or not sections:
        target.unlink(missing_ok=True)
        return
    try:
        atomic_write_text(target, profile_figure(sections))
    except (KeyError, TypeError, ValueError):  # a profile.json of another shape: its tables only
        target.unlink(missing_ok=True)


def system_view(record: dict, claims: list[dict], out: Path, figures: set, bench: dict | None = None) -> dict:
    """What the index and the system page show of one record; figures are rendered into ``out/figures``; the
    scenes' work-precision and pruning time ratios come from ``bench`` (``out/bench.json``) where it has them."""
    from harness.report.drawn import drawn, key
    from harness.report.figures import draw_scene_figure

    name = record["system"]
    checks = [_check_view(c) for c in record.get("checks", [])]
    matrix: dict[str, list] = {}
    for c in checks:
        matrix.setdefault(c["check"], []).append(c)
    scenes = []
    for sc in record.get("scenes") or []:
        view = {"scene": sc.get("scene", "?"), "description": sc.get("description", ""),
                "effects": list(sc.get("effects") or []), "horizon": sc.get("horizon"),
                "passed": bool(sc.get("passed")),
                "notes": {k: format(v, ".4g") if isinstance(v, float) else v for k, v in (sc.get("notes") or {}).items()
                          if k not in _PRUNING_NOTES and not k.startswith(("effects disagreement", "pruning, "))},
                "pruning": pruning_view(name, sc, bench),
                "checks": [_check_view(c) for c in sc.get("checks", [])], "figure": None,
                "figure_note": "", "series": sc.get("series"), "strip": None, "strip_size": (0, 0),
                "strip_sources": [], "strip_tendons": 0, "strip_slides": 0, "strip_unseen": [], "strip_note": "",
                "work_precision": work_precision(bench, out, name, sc.get("scene", "?"))}
        series = sc.get("series")
        if series and (out / series).is_file():
            target = f"figures/{name}.{view['scene']}.svg"
            try:
                text = (out / series).read_bytes()
                drawn(out / target, key("scene figure", text), lambda path: draw_scene_figure(json.loads(text), path))
                view["figure"] = target
                figures.add(target)
            except Exception as exc:  # noqa: BLE001 - a broken series file costs its figure, not the page
                view["figure_note"] = f"figure not drawn: {type(exc).__name__}: {exc}"
        elif series:
            view["figure_note"] = f"series file {series} not found"
        scenes.append(view)
    counts = Counter(c["classification"] for c in claims)
    confirmed = counts.pop("confirmed", 0)
    return {"name": name, "title": "", "lecture": record.get("lecture", ""), "outside": False,
            "passed": bool(record.get("passed")),
            "reason": record.get("failure") or "", "examples": record.get("examples", 0),
            "parameter_draws": record.get("parameter_draws"),
            "not_applicable": record.get("not_applicable") or {}, "checks": checks, "matrix": matrix,
            "checks_passed": sum(c["passed"] for c in checks), "scenes": scenes,
            "scenes_passed": sum(s["passed"] for s in scenes), "claims": claims, "claims_confirmed": confirmed,
            "claims_other": ", ".join(f"{n} {k}" for k, n in sorted(counts.items())), **NO_PICTURE}


def _add_equations(view: dict, model: dict, page: dict) -> None:
    """The derived equations and each printed equation beside its derived form (``page``:
    harness.report.equations.page_equations); the classification of claims.json joins by equation and quantity,
    in order."""
    model["equations"] = page["equations"]
    rows = page["claims"]
    records: dict[tuple, list] = {}
    for record in view["claims"]:
        records.setdefault((record.get("equation"), record.get("quantity")), []).append(record)
    for row in rows:
        queue = records.get((row["equation"], row["quantity"]), [])
        row["record"] = queue.pop(0) if queue else None
    model["claims"] = rows
    model["equation_notes"] = page["notes"]


def _add_pictures(view: dict, rendered: dict | None, figures: set) -> None:
    """The mechanism rendered by MuJoCo and a filmstrip per scene (harness.report.render), into the view."""
    if not rendered:
        return
    if rendered.get("error"):
        view["picture_note"] = f"picture not rendered: {rendered['error']}"
    shot = rendered.get("picture")
    if shot:
        figures.add(shot["target"])
        view.update(picture=shot["target"], picture_size=tuple(shot["size"]), picture_caption=shot["caption"])
    for sc in view["scenes"]:
        strip = rendered.get("strips", {}).get(sc["scene"])
        if not strip:
            continue
        if "error" in strip:
            sc["strip_note"] = f"filmstrip not rendered: {strip['error']}"
            continue
        figures.add(strip["target"])
        sc.update(strip=strip["target"], strip_size=tuple(strip["size"]), strip_sources=strip["sources"],
                  strip_tendons=strip.get("tendons", 0), strip_slides=strip.get("slides", 0),
                  strip_unseen=strip.get("unseen", []))


# --------------------------------------------------------------------------- generic JSON (optional pages)
def json_html(node, depth: int = 0) -> str:
    """Any JSON as HTML: a list of objects becomes a table, an object a two-column table."""
    esc = html.escape
    if isinstance(node, dict):
        if not node:
            return "<p>—</p>"
        rows = "".join(f"<tr><th>{esc(str(k))}</th><td>{json_html(v, depth + 1)}</td></tr>" for k, v in node.items())
        return f"<table>{rows}</table>"
    if isinstance(node, list):
        if node and all(isinstance(x, dict) for x in node):
            keys = list(dict.fromkeys(k for x in node for k in x))
            head = "".join(f"<th>{esc(str(k))}</th>" for k in keys)
            body = "".join("<tr>" + "".join(f"<td>{json_html(x.get(k), depth + 1)}</td>" for k in keys) + "</tr>"
                           for x in node)
            return f'<div class="wide"><table><tr>{head}</tr>{body}</table></div>'
        if all(not isinstance(x, (dict, list)) for x in node):
            return esc(", ".join(_scalar(x) for x in node))
        return "<ul>" + "".join(f"<li>{json_html(x, depth + 1)}</li>" for x in node) + "</ul>"
    return esc(_scalar(node))


def _scalar(x) -> str:
    if isinstance(x, float):
        return f"{x:.4g}"
    return "—" if x is None else str(x)


# --------------------------------------------------------------------------- one page per robot
ROBOT_QUANTITIES = ("M", "bias", "Cqd", "g", "qdd", "mass", "first moment of mass", "inertia")


def robot_view(record: dict, doc: dict) -> dict:
    """One robot of ``robots.json`` for its page: per pair the verdict, the worst recorded check of each quantity
    (robots.json keeps every failing check and the worst passing one per quantity), the cause, the counterexamples."""
    from harness.files import importer, robots

    labels = doc.get("engines") or {}
    pairs = []
    for p in record.get("pairs") or []:
        ref, other = p["pair"].split("-", 1)
        worst: dict = {}
        for c in p.get("checks") or []:
            if c["ratio"] >= worst.get(c["quantity"], {"ratio": -1.0})["ratio"]:
                worst[c["quantity"]] = c
        css = {"agree": "ok", "disagree-explained": "erratum", "not compared": "na"}.get(p["verdict"], "fail")
        pairs.append({
            "label": f"{labels.get(ref, ref)} – {labels.get(other, other)}", "verdict": robots.verdict_cell(p),
            "css": css, "why": (p.get("error") or "") if p.get("out_of_scope") else (robots.cause_cell(p) or (
                f"agrees within {doc.get('margin', robots.MARGIN):g} of the bound: nothing to explain"
                if p["verdict"] == robots.AGREE else "–")),
            "worst": {q: {"passed": c["passed"], "item": c["item"], **_error_bound(c)} for q, c in worst.items()},
            "failing": [{"finding": importer.finding(c),
                         "state": ", ".join(f"{k} = {v:.6g}"
                                            for k, v in (c.get("worst_state") or {}).get("theta", {}).items()),
                         "imported": _short(c.get("imported")), "reference": _short(c.get("reference"))}
                        for c in p.get("checks") or [] if not c["passed"]]})
    step = next((facts["step"] for facts in (record.get("engines") or {}).values() if facts.get("step")), None)
    engines = [(name, "; ".join(f"{k}: {_scalar(v) if not isinstance(v, (dict, list)) else json.dumps(v)}"
                                 for k, v in facts.items() if k != "step"))
               for name, facts in (record.get("engines") or {}).items() if facts]
    return {"r": record, "pairs": pairs, "labels": labels, "reference": doc.get("reference", "pinocchio"),
            "states": doc.get("states"), "seed": doc.get("seed"), "tolerance": f"{doc.get('tolerance', 0):.0e}",
            "verdicts": ", ".join(robots.VERDICTS), "quantities": [q for q in ROBOT_QUANTITIES
                                                                    if any(q in p["worst"] for p in pairs)],
            "step": step, "engines": engines}


def _error_bound(c: dict) -> dict:
    """Error, bound and their ratio of one check, as robots.md's worst cell writes them."""
    bound = c["max_error"] / c["ratio"] if c["ratio"] not in (0, float("inf")) else c["tolerance"]
    return {"error": f"{c['max_error']:.1e}", "bound": f"{bound:.0e}", "ratio": f"{c['ratio']:.2g}"}


def _short(values) -> str:
    if values is None:
        return "—"
    flat = [x for row in values for x in (row if isinstance(row, list) else [row])] if isinstance(values, list) \
        else [values]
    text = ", ".join(f"{x:.15g}" if isinstance(x, (int, float)) else str(x) for x in flat[:12])  # to the round-off
    return f"[{text}{', …' if len(flat) > 12 else ''}]"


def robot_pages(out: Path, env, common: dict) -> list[str]:
    """``robots/<robot>.html`` for every robot of ``out/robots.json`` (none without it), in the site's chrome."""
    from harness.files.robots import page

    doc = _read_json(out / "robots.json")
    if not isinstance(doc, dict):
        return []
    written = []
    template = env.get_template("robot")
    for record in doc.get("robots") or []:
        target = page(record["robot"])
        atomic_write_text(out / target, template.render(root="../", **robot_view(record, doc), **common))
        written.append(target)
    return written


# --------------------------------------------------------------------------- the site
def _inside(out: Path, target: str) -> bool:
    """A relative link that resolves to a file inside the report folder (others would break offline)."""
    if re.match(r"[a-zA-Z][a-zA-Z0-9+.-]*:", target) or target.startswith("/"):
        return False
    path = (out / target.split("#")[0]).resolve()
    return path.is_file() and out.resolve() in path.parents


def _stale(folder: Path, keep: set[str], pattern: str) -> None:
    """Remove pages/figures of an earlier run that this run did not write (only in the report's own folders)."""
    if folder.is_dir():
        for path in folder.glob(pattern):
            if f"{folder.name}/{path.name}" not in keep:
                path.unlink()


def _common(out: Path, versions: dict, claims: bool) -> dict:
    """What every page of the site shows around its own content: the navigation to the pages ``out`` holds (the
    errata where ``claims``) and the packages' versions."""
    extra_pages = [{"file": "errata.html", "title": "Errata"}] if claims else []
    extra_pages += [{"file": file, "title": title} for file, title, source, _, _ in OPTIONAL_PAGES
                    if (out / source).is_file()]
    return {"extra_pages": extra_pages, "versions_line": ", ".join(f"{k} {v}" for k, v in versions.items()),
            "bench_link": '<a href="../bench.html">Benchmarks</a>' if (out / "bench.json").is_file() else
            "Benchmarks: no bench.json in this folder, <code>harness bench --out</code> writes it"}


def write_errata(out: Path | str, claims: list[dict], lecture: set[str] | None, env=None, common=None) -> Path:
    """``out/errata.html``, the errata sheet (:func:`harness.report.errata.sheet`) as a page of the site, the one
    page ``harness claims --out`` and ``harness report`` both write (``env``, ``common``: the site's, where the
    report renders it; else made here from what ``out`` holds)."""
    from harness.report import errata
    from harness.report.results import load_results

    out = Path(out)
    if common is None:
        common = _common(out, (load_results(out) or {}).get("versions") or {}, True)
    page = (env or environment()).get_template("errata").render(
        records=claims, sheet=errata.sheet(claims, lecture), errata_title=errata.title(claims, lecture),
        style=errata.STYLE, root="", **common)
    atomic_write_text(out / "errata.html", page)
    return out / "errata.html"


def build_site(out: Path | str, catalogue=None, progress=None, jobs: int = 1) -> dict:
    """Render the site from ``out/results.json`` (+ claims.json, hard.json, bench.json, importer.json,
    robots.json); the
    model pages from ``catalogue`` (:class:`harness.catalogue.Catalogue`; without one, the recorded results
    only; ``jobs`` processes simplify the equations the cache lacks). Returns {"pages": [...],
    "failed": {system: reason}}."""
    progress = sys.stderr if progress is None else progress
    from harness.report.results import load_results

    out = Path(out)
    doc = load_results(out) or {"systems": [], "versions": {}, "tolerance_policy": "", "passed": False}
    claims_doc = _read_json(out / "claims.json")
    bench = _read_json(out / "bench.json")
    claims = claims_doc if isinstance(claims_doc, list) else []
    by_system: dict[str, list] = {}
    for c in claims:
        by_system.setdefault(c.get("system", "?"), []).append(c)
    env = environment()
    versions = doc.get("versions") or {}
    common = _common(out, versions, bool(claims))

    try:
        systems = {} if catalogue is None else catalogue.systems()
        catalogue_error = None if catalogue is not None else "no catalogue given: the recorded results only"
    except Exception as exc:  # noqa: BLE001 - the report still renders the recorded results
        systems, catalogue_error = {}, f"the catalogue does not load: {exc}"
    records = doc["systems"]
    order = {name: k for k, name in enumerate(systems)}
    records = sorted(records, key=lambda r: (order.get(r["system"], len(order)), r["system"]))
    written, figures, failed, views = [], set(), {}, []
    template = env.get_template("system")
    from harness.report.render import render_all

    print(f"rendering the mechanisms of {len(records)} system(s) with MuJoCo …", file=progress, flush=True)
    rendering = render_all([{"system": r["system"], "out": str(out), "catalogue": catalogue,
                             "scenes": [(sc.get("scene"), sc["series"]) for sc in r.get("scenes") or []
                                        if sc.get("series") and (out / sc["series"]).is_file()]}
                            for r in records if r["system"] in systems])
    from harness.report.equations import PageEquationsAhead

    # the scene figures are drawn here while the mechanisms render in their own process and the equations the
    # cache lacks are simplified in ``jobs`` others
    equations = PageEquationsAhead(catalogue, [r["system"] for r in records if r["system"] in systems], jobs)
    pages = []
    for k, record in enumerate(records, 1):
        name = record["system"]
        print(f"[{k}/{len(records)}] page {name}", file=progress, flush=True)
        try:
            view, model = system_view(record, by_system.get(name, []), out, figures, bench), None
            if name in systems:
                system = systems[name]
                model = model_view(system)
                model["scene_names"] = [s.name for s in catalogue.scenes(name)]
                view["title"] = system.title
                view["outside"] = not catalogue.from_lecture(name)   # one's own model: it names its source
                _add_equations(view, model, equations(name))
            else:
                view["reason"] = view["reason"] or catalogue_error or f"{name} is not in the catalogue any more"
            pages.append((record, view, model, None))
        except Exception as exc:  # noqa: BLE001 - one system raising never loses the others' pages
            pages.append((record, None, None, exc))
    equations.close()
    rendered = rendering()
    for record, view, model, error in pages:
        name = record["system"]
        try:
            if error is not None:
                raise error
            if model is not None:
                _add_pictures(view, rendered.get(name), figures)
            text = template.render(s=view, model=model, root="../", **common)
        except Exception as exc:  # noqa: BLE001 - one system raising never loses the others' pages
            reason = f"{name}: page not built: {type(exc).__name__}: {exc}"
            failed[name] = reason
            view = {"name": name, "title": "", "lecture": record.get("lecture", ""), "outside": False, "passed": False,
                    "reason": reason, "examples": 0, "not_applicable": {}, "checks": [], "matrix": {},
                    "checks_passed": 0, "scenes": [], "scenes_passed": 0, "claims": [], "claims_confirmed": 0,
                    "claims_other": "", **NO_PICTURE}
            text = template.render(s=view, model=None, root="../", **common)
        atomic_write_text(out / "systems" / f"{name}.html", text)
        written.append(f"systems/{name}.html")
        views.append(view)
    check_names = sorted({c for v in views for c in v["matrix"]})
    from harness.report import margins

    margin_figure = margins.figure_svg(doc)
    if margin_figure is not None:
        atomic_write_text(out / "figures" / "margins.svg", margin_figure)
        figures.add("figures/margins.svg")
    warnings = [{"system": r["system"], **w} for r in doc["systems"] for w in r.get("warnings") or []]
    hard_line = _hard_line(_read_json(out / "hard.json"))
    index = env.get_template("index").render(
        systems=views, passed=sum(v["passed"] for v in views), check_names=check_names,
        hypothesis=doc.get("hypothesis"), versions=versions, root="",
        policy=markdown_html(doc.get("tolerance_policy", "").replace("``", "`")),  # a docstring: RST's code marks
        margin_line=margins.summary_line(doc), margin_rows=margins.above(doc), margin_limit=margins.MARGIN,
        margin_figure="figures/margins.svg" if margin_figure else None, bounds=doc.get("bounds") or {},
        claim_margin_rows=margins.claim_rows(claims), claims_present=bool(claims),
        warnings=warnings, hard_line=hard_line, **common)
    atomic_write_text(out / "index.html", index)
    written.append("index.html")
    if claims:
        write_errata(out, claims, catalogue.lecture_claims() if catalogue else None, env, common)
        written.append("errata.html")
    written += robot_pages(out, env, common)   # before robots.html, whose table links them
    _profile_figure(out)
    for file, title, source, md, folder in OPTIONAL_PAGES:
        data = _read_json(out / source)
        if data is None:
            continue
        figs = sorted(f"{folder}/{p.name}" for p in (out / folder).glob("*.svg")) if folder else []
        if (out / md).is_file():  # the producer's own Markdown is the readable page; the JSON is linked
            text = (out / md).read_text()
            body = markdown_html(text, local=lambda target: _inside(out, target))
            figs = [f for f in figs if f not in text]
        else:
            body = json_html(data)
        atomic_write_text(out / file, env.get_template("generic").render(
            title=title, source=source, figures=figs, body=body, root="", **common))
        written.append(file)
    _stale(out / "systems", set(written), "*.html")
    _stale(out / "robots", set(written), "*.html")
    _stale(out / "figures", figures, "*.svg")
    _stale(out / "figures", figures, "*.png")
    return {"pages": written, "failed": failed}
