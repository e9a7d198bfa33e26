"""The ``harness`` command: ``list``, ``eval``, ``check``, ``claims``, ``export``.

Exit codes: 0 success, 1 a check failed (or exported files are stale), 2 bad input (one line on stderr).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

import numpy as np

from harness.errors import HarnessError, InputError

PROJECT_ROOT = Path(__file__).resolve().parent.parent


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2, like every other bad input
        raise InputError(f"{self.prog}: {message}")


def _assignments(items, what: str) -> dict[str, float]:
    out = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise InputError(f"--{what} takes NAME=VALUE, got {item!r}")
        try:
            out[name] = float(value)
        except ValueError:
            raise InputError(f"--{what} {name}: {value!r} is not a number") from None
    return out


def cmd_list(args) -> int:
    from models import catalogue, failures

    rows = [(s.name, str(len(s.coordinates)), s.lecture, s.status) for s in catalogue().values()]
    rows += [(name, "?", "—", "does not load (harness check shows why)") for name in failures()]
    widths = [max(len(r[i]) for r in rows + [("system", "dof", "lecture", "status")]) for i in range(4)]
    for row in [("system", "dof", "lecture", "status")] + rows:
        print("  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip())
    return 0


def cmd_eval(args) -> int:
    import models
    from harness.engines import evaluate
    from harness.engines.base import State

    system = models.get(args.system)
    state = State.make(system, args.q, args.qd, _assignments(args.param, "param"), _assignments(args.input, "input"))
    ev = evaluate(args.engine, state)
    out = {"system": system.name, "engine": ev.engine,
           "coordinates": [c.name for c in system.coordinates],
           "q": state.q.tolist(), "qd": state.qd.tolist(), "params": state.params, "inputs": state.u,
           "M": ev.M.tolist(), "C": None if ev.C is None else ev.C.tolist(), "Cqd": ev.Cqd.tolist(),
           "g": ev.g.tolist(), "qdd": ev.qdd.tolist(), "calls": ev.calls}
    if args.json:
        print(json.dumps(out))
    else:
        for key in ("M", "C", "Cqd", "g", "qdd"):
            print(f"{key} =\n{np.array2string(np.asarray(out[key]), precision=15)}")
    return 0


def cmd_check(args) -> int:
    """Conformance of each system; ``--out`` writes results.json, timings.json and summary.md (harness.report)."""
    import models
    from harness.report.results import (check_folder, load_results, merge_records, read_timings, results_document,
                                        run_checks, timings_of, write_results)

    names = args.systems or models.names()   # a module that does not load is reported as that system's failure
    for name in args.systems or []:
        models.get(name)  # unknown or broken names given by the user fail before any work
    if args.out:
        check_folder(args.out)
    results, seconds = run_checks(names, examples=args.examples, seed=args.seed, jobs=args.jobs,
                                  scenes=not args.no_scenes, series_dir=args.out)
    doc = results_document(results, args.examples, args.seed)
    if args.json:
        print(json.dumps(doc, indent=1))
    else:
        _print_table(results)
    if args.out:  # merged by system into what the folder holds: other systems' results are kept
        merged = results_document(merge_records(load_results(args.out), results), args.examples, args.seed)
        timings = {**read_timings(args.out), **timings_of(seconds)}
        written = write_results(merged, args.out, timings=timings)
        print(f"wrote {', '.join(map(str, written))}", file=sys.stderr)
    return 0 if doc["passed"] else 1


def _print_table(results):
    from harness.report.markdown import CHECK_HEADER, check_rows

    header = ("system", "check", "source", *CHECK_HEADER)
    rows = [header] + list(check_rows(results))
    widths = [max(len(r[i]) for r in rows) for i in range(len(header))]
    for row in rows:
        print("  ".join(c.ljust(w) for c, w in zip(row, widths)))
    for r in results:
        for engine, reason in r.get("not_applicable", {}).items():
            print(f"n/a    {r['system']} in {engine}: {reason}")
        if r["failure"]:
            print(f"FAILED {r['failure']}")
        for sc in r.get("scenes", []):
            worst = max(sc["checks"], key=_ratio, default=None)
            detail = sc["failure"] or ("" if worst is None else
                                       f"worst: {worst['check']} ({worst['source']}) {worst['value']:.2e}"
                                       f" / {worst['bound']:.0e} (ratio {_ratio(worst):.2g})")
            print(f"scene  {r['system']}/{sc['scene']}: {'ok' if sc['passed'] else 'FAIL'}  {detail}")
    from harness.report import margins
    from harness.report.results import bounds_used

    doc = {"systems": results, "bounds": bounds_used(results)}
    print(margins.summary_line(doc))
    for row in margins.above(doc):
        if not row["derived"]:
            print(f"thin margin: {row['system']}/{row['scene']} {row['check']} ({row['source']}) ratio "
                  f"{row['ratio']:.2g} on {row['basis']}")
    for r in results:  # explained engine warnings are in the report (#warnings), never on the console
        for w in r.get("warnings") or []:
            if not w["explained"]:
                print(f"UNEXPLAINED {w['engine']} warning: {r['system']} {w['where']} ({w['count']}x): {w['message']}")
    print(f"{sum(r['passed'] for r in results)} of {len(results)} systems conformant")


def _ratio(check: dict) -> float:
    ratio = check.get("ratio", 0.0)
    return float(ratio) if not isinstance(ratio, str) else float("inf")


def cmd_report(args) -> int:
    """Checks the systems results.json lacks, then writes summary.md and the static site (harness.report)."""
    from harness.report import build_report

    result = build_report(args.out, names=args.systems, jobs=args.jobs, examples=args.examples, seed=args.seed,
                          rerun=args.rerun, scenes=not args.no_scenes)
    for name, reason in result["failed"].items():
        print(f"FAILED {reason}", file=sys.stderr)
    print(f"wrote {Path(args.out) / 'index.html'} ({len(result['pages'])} pages)", file=sys.stderr)
    return 0 if result["passed"] else 1


def cmd_new(args) -> int:
    """Scaffold ``models/NAME.py`` (harness.scaffold)."""
    from harness.scaffold import scaffold

    import models

    path = scaffold(args.name, args.dir)
    print(f"wrote {path}: follow the checklist in its docstring, then run `harness check {args.name}`")
    if str(path.parent.resolve()) not in {str(Path(p).resolve()) for p in models.__path__}:
        print(f"note: add {path.parent} to {models.MODELS_PATH_VARIABLE} so that the catalogue finds it",
              file=sys.stderr)
    return 0


def _classify_system(job) -> dict:
    """Classify the claims of one system (runs in a worker process with --jobs): ``{"system", "failure",
    "records"}``; a module that does not load, or a claim that cannot be evaluated, is a failure of its own."""
    from harness.compare import claims
    from harness.settings import draws_from_seed_only, load_hypothesis_profile

    name, examples = job
    load_hypothesis_profile()
    with draws_from_seed_only():  # the examples depend on the seed only, not on our source's literals
        return _classify(name, examples, claims)


def _classify(name: str, examples, claims) -> dict:
    import models

    try:
        system, printed = models.get(name), models.claims(name)
    except HarnessError as exc:
        return {"system": name, "failure": str(exc), "records": []}
    out, failures = [], []
    for claim in printed:
        print(f"classifying {name} {claim.equation} …", file=sys.stderr, flush=True)
        try:
            v = claims.classify(system, claim, examples=examples, claims=printed)
            extra = claims.record_fields(system, v, printed)
        except Exception as exc:  # noqa: BLE001 - one claim that cannot be evaluated does not lose the others
            failures.append(f"{name} {claim.equation}: cannot be evaluated: {type(exc).__name__}: {exc}")
            continue
        out.append({"system": v.system, "equation": v.claim.equation, "quantity": v.claim.quantity,
                    "description": v.claim.description, "classification": v.classification,
                    "printed": str(v.claim.printed), "corrected": v.corrected, "convention": v.convention,
                    "counterexample": v.counterexample, "note": v.claim.note, "examples": v.examples,
                    "errors_over_tolerance": v.errors, **extra})
    from harness.engines import warnings_log

    failures += [f"{name}: unexplained {w['engine']} warning in {w['where']} ({w['count']}x): {w['message']}"
                 for w in warnings_log.drain(name) if not w["explained"]]
    return {"system": name, "failure": "; ".join(failures) or None, "records": out}


def cmd_claims(args) -> int:
    """Classify every printed equation; errata are findings (reported, exit 0), 'engines disagree' fails."""
    import multiprocessing

    import models
    from harness.io import atomic_write_text

    names = args.systems or models.names()
    for name in args.systems or []:
        models.get(name)  # unknown or broken names given by the user fail before any work
    if args.out:
        from harness.report.results import check_folder

        check_folder(args.out)
    jobs = [(name, args.examples) for name in names]
    if args.jobs > 1 and len(jobs) > 1:
        with multiprocessing.get_context("spawn").Pool(args.jobs) as pool:
            per_system = pool.map(_classify_system, jobs, chunksize=1)
    else:
        per_system = [_classify_system(job) for job in jobs]
    records = [r for result in per_system for r in result["records"]]
    failed = [result["failure"] for result in per_system if result["failure"]]
    if args.json:
        print(json.dumps(records, indent=1))
    else:
        for r in records:
            print(f"{r['system']:22s} {r['equation']:30s} {r['quantity']:16s} {r['classification']}")
    for reason in failed:
        print(f"FAILED {reason}", file=sys.stderr)
    if args.out:  # merged by system: the classified systems replace their records, the others are kept
        path = Path(args.out) / "claims.json"
        ran = {result["system"] for result in per_system}
        kept = [r for r in _read_claims(path) if r.get("system") not in ran]
        order = {name: k for k, name in enumerate(models.names())}
        merged = sorted(kept + records, key=lambda r: order.get(r["system"], len(order)))  # stable: equation order
        atomic_write_text(path, json.dumps(merged, indent=1) + "\n")
        from harness.report import errata

        atomic_write_text(Path(args.out) / "errata.md", errata.markdown(merged))
        atomic_write_text(Path(args.out) / "errata.html", errata.html(merged))
    return 1 if failed or any(r["classification"] == "engines disagree" for r in records) else 0


def _read_claims(path: Path) -> list[dict]:
    try:
        records = json.loads(path.read_text())
    except (OSError, ValueError):
        return []
    return [r for r in records if isinstance(r, dict) and "system" in r] if isinstance(records, list) else []


def cmd_scenes(args) -> int:
    """List the scenes; with --run, simulate them and check the trajectories (harness/scenes/trajectories.py)."""
    import models
    from harness.scenes.trajectories import run_scene

    names = args.systems or list(models.catalogue())
    failed = False
    for name in names:
        system = models.get(name)
        chosen = models.scenes(name)
        if args.scene:
            known = [s.name for s in chosen]
            if args.scene not in known:
                raise InputError(f"unknown scene {args.scene!r} of {name}; known scenes: {', '.join(known) or 'none'}")
            chosen = [s for s in chosen if s.name == args.scene]
        for scene in chosen:
            print(f"{name:22s} {scene.name:12s} {scene.horizon:6.2f} s  {', '.join(sorted(scene.effects)):40s} "
                  f"{scene.description}")
            if not args.run:
                continue
            result = run_scene(system, scene)
            for c in result.checks:
                print(f"    {c.name:45s} {c.source:10s} {c.value:.2e} / {c.bound:.0e}  "
                      f"ratio {c.ratio:.2g}  {'ok' if c.passed else 'FAIL'}")
            for key, value in result.notes.items():
                print(f"    {key}: {value:.3g}" if isinstance(value, float) else f"    {key}: {value}")
            failed |= not result.passed
    return 1 if failed else 0


def cmd_export(args) -> int:
    import models
    from harness.export.files import export_files
    from harness.io import atomic_write_text

    out = Path(args.dir)
    files = export_files(models.catalogue().values())
    stale = [name for name, text in files.items()
             if not (out / name).exists() or (out / name).read_text() != text]
    if args.check:
        for name in stale:
            print(f"stale: {out / name} (run `harness export`)", file=sys.stderr)
        return 1 if stale else 0
    for name, text in files.items():
        atomic_write_text(out / name, text)
    print(f"wrote {len(files)} files to {out}/ ({len(stale)} changed)")
    return 0


def cmd_validate(args) -> int:
    """A user's own URDF/MJCF: safe parse, checks, load in the engines (harness/files/validate.py)."""
    from harness.files.validate import validate

    result = validate(args.file, root=args.root, states=args.states)
    if args.json:
        print(json.dumps(result.to_json(), indent=1))
    else:
        print("\n".join(result.lines()))
    return 0 if result.passed else 1


def cmd_importer(args) -> int:
    """MuJoCo's URDF importer vs our MJCF and Pinocchio (harness/files/importer.py): importer.json, importer.md."""
    from harness.files import importer

    doc = importer.run(args.systems or None, states=args.states, seed=args.seed)
    if args.out:
        for path in importer.write(doc, Path(args.out)):
            print(f"wrote {path}", file=sys.stderr)
    print(json.dumps(doc, indent=1) if args.json else importer.markdown(doc), end="")
    return 0 if doc["summary"]["differ"] == 0 and all(c["detected"] for c in doc["controls"]) else 1


def cmd_bench(args) -> int:
    """The performance studies (harness/bench/); writes bench.json, bench.md and the figures."""
    from harness.bench import merge, render, run_bench

    if args.render:
        render(args.out)
        return 0
    if args.merge:
        merge(args.out, args.merge)
        return 0
    run_bench(out=args.out, quick=args.quick, scheduler=args.scheduler, systems=args.systems, scenes=args.scenes,
              workers=args.workers, parts=tuple(args.parts), command="harness bench " + " ".join(sys.argv[2:]))
    return 0


def cmd_hard(args) -> int:
    """The hard cases (harness/hard/): reports/hard.json and reports/hard/*.svg; exit 1 if a bound fails."""
    from harness.hard import run

    doc = run(Path(args.out), quick=args.quick, only=args.cases or None,
              echo=lambda line: print(line, file=sys.stderr))
    print(f"wrote {Path(args.out) / 'hard.json'}", file=sys.stderr)
    return 0 if doc["passed"] else 1


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="harness", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    sub.add_parser("list", help="every system with its lecture reference").set_defaults(func=cmd_list)

    p = sub.add_parser("eval", help="M, C, Cqd, g, qdd of one system at one state")
    p.add_argument("system")
    p.add_argument("--engine", default="symbolic", choices=("symbolic", "pinocchio", "mujoco"))
    p.add_argument("--q", nargs="+", type=float, required=True)
    p.add_argument("--qd", nargs="+", type=float)
    p.add_argument("--param", nargs="*", action="extend", metavar="NAME=VALUE")
    p.add_argument("--input", nargs="*", action="extend", metavar="NAME=VALUE")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_eval)

    p = sub.add_parser("check", help="conformance checks against Pinocchio and MuJoCo")
    p.add_argument("systems", nargs="*")
    p.add_argument("--examples", type=int, default=None, help="hypothesis examples per system (default: profile)")
    p.add_argument("--json", action="store_true")
    p.add_argument("--no-scenes", action="store_true", help="skip the trajectory checks of the scenes")
    p.add_argument("--out", help="folder for results.json, timings.json and summary.md")
    p.add_argument("--jobs", type=int, default=1, help="systems checked in parallel processes")
    p.add_argument("--seed", type=int, default=None, help="hypothesis seed (default: the profile's fixed seeds)")
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("report", help="readable reports: index.html, summary.md, results.json")
    p.add_argument("systems", nargs="*", help="default: every system")
    p.add_argument("--out", default="reports", help="report folder (default: reports)")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="systems checked in parallel")
    p.add_argument("--examples", type=int, default=None, help="hypothesis examples per system (default: profile)")
    p.add_argument("--seed", type=int, default=None, help="hypothesis seed (default: the profile's fixed seeds)")
    p.add_argument("--rerun", action="store_true", help="check every system again, even if results.json has it")
    p.add_argument("--no-scenes", action="store_true", help="skip the trajectory checks of the scenes")
    p.set_defaults(func=cmd_report)

    p = sub.add_parser("new", help="scaffold models/NAME.py for a new system")
    p.add_argument("name", help="system name: a lower-case Python identifier, e.g. pendulum_rod")
    p.add_argument("--dir", default=None, help="folder for the module (default: models/)")
    p.set_defaults(func=cmd_new)

    p = sub.add_parser("claims", help="check the lecture's printed equations (errata report)")
    p.add_argument("systems", nargs="*")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="systems classified in parallel")
    p.add_argument("--examples", type=int, default=None)
    p.add_argument("--json", action="store_true")
    p.add_argument("--out", help="folder for claims.json and errata.md")
    p.set_defaults(func=cmd_claims)

    p = sub.add_parser("scenes", help="list the scenes; --run simulates and checks them")
    p.add_argument("systems", nargs="*")
    p.add_argument("--run", action="store_true")
    p.add_argument("--scene", default=None, help="only the scene with this name")
    p.set_defaults(func=cmd_scenes)

    p = sub.add_parser("export", help="regenerate urdf/ (URDF, MJCF, coordinate maps)")
    p.add_argument("--dir", default=str(PROJECT_ROOT / "urdf"))
    p.add_argument("--check", action="store_true", help="only report stale files (exit 1)")
    p.set_defaults(func=cmd_export)

    p = sub.add_parser("bench", help="work-precision, evaluation and derivation cost (harness/bench/)")
    p.add_argument("--out", default=str(PROJECT_ROOT / "reports"), help="folder for bench.json, bench.md, bench/")
    p.add_argument("--quick", action="store_true", help="small grids and a representative set (about 2 min)")
    p.add_argument("--scheduler", default=None, metavar="ADDR", help="run the sweeps on this Dask scheduler")
    p.add_argument("--workers", type=int, default=None, help="local processes (default: one per CPU)")
    p.add_argument("--systems", nargs="+", default=None)
    p.add_argument("--scenes", nargs="+", default=None, help="scene names (stiff variants: SCENE_PARAM_xFACTOR…)")
    p.add_argument("--parts", nargs="+", default=["workprecision", "evaluation", "derivation", "pruning"],
                   choices=["workprecision", "evaluation", "derivation", "pruning"])
    p.add_argument("--render", action="store_true", help="only redraw bench.md and the figures from bench.json")
    p.add_argument("--merge", default=None, metavar="BENCH_JSON",
                   help="take the parts another run measured (its bench.json) into OUT/bench.json, recorded")
    p.set_defaults(func=cmd_bench)

    p = sub.add_parser("validate", help="check a URDF or MJCF file of your own and load it in the engines")
    p.add_argument("file", help="a .urdf or MJCF .xml file")
    p.add_argument("--root", default=None, help="folder its mesh/package/include files must stay in "
                   "(default: the file's folder)")
    p.add_argument("--states", type=int, default=20, help="random states for the importer comparison")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_validate)

    p = sub.add_parser("importer", help="MuJoCo's URDF importer vs our MJCF and Pinocchio")
    p.add_argument("systems", nargs="*", help="default: every system (the test models are always included)")
    p.add_argument("--out", default=None, help="folder for importer.json and importer.md")
    p.add_argument("--states", type=int, default=20)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_importer)

    p = sub.add_parser("hard", help="hard cases: singularities, stiffness, chaos, long horizons (harness/hard/)")
    p.add_argument("cases", nargs="*", help="default: the whole catalogue")
    p.add_argument("--out", default="reports", help="folder for hard.json and hard/*.svg")
    p.add_argument("--quick", action="store_true", help="the shortened horizons of the test suite")
    p.set_defaults(func=cmd_hard)
    return parser


def main(argv=None) -> int:
    from harness.settings import load_hypothesis_profile

    load_hypothesis_profile()
    try:
        args = build_parser().parse_args(argv)
        return args.func(args)
    except HarnessError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
