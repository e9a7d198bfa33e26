"""The ``harness`` command: ``list``, ``eval``, ``check``, ``claims``, ``export``.

Exit codes: 0 success, 1 a check failed (or exported files are stale), 2 bad input (one line on stderr).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
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
    from models import catalogue

    rows = [(s.name, str(len(s.coordinates)), s.lecture, s.status) for s in catalogue().values()]
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


def _versions() -> dict:
    import mujoco
    import pinocchio
    import sympy
    import hypothesis

    return {"python": platform.python_version(), "platform": platform.platform(), "pinocchio": pinocchio.__version__,
            "mujoco": mujoco.__version__, "sympy": sympy.__version__, "numpy": np.__version__,
            "hypothesis": hypothesis.__version__}


def cmd_check(args) -> int:
    import models
    from harness import conformance
    from harness.io import atomic_write_text

    systems = [models.get(name) for name in args.systems] if args.systems else list(models.catalogue().values())
    results = []
    for k, system in enumerate(systems, 1):
        print(f"[{k}/{len(systems)}] checking {system.name} …", file=sys.stderr, flush=True)
        start = time.perf_counter()
        try:
            summary = conformance.run(system, examples=args.examples)
            record = {"system": system.name, "passed": summary.passed, "examples": summary.examples,
                      "failure": summary.failure, "not_applicable": summary.not_applicable,
                      "checks": [{"check": f.check, "engine": f.engine, "max_error": f.error,
                                  "tolerance": f.tolerance, "passed": f.passed}
                                 for f in sorted(summary.worst.values(), key=lambda f: (f.check, f.engine))]}
        except Exception as exc:  # noqa: BLE001 - one system raising never loses the others' results
            reason = str(exc) if isinstance(exc, HarnessError) else f"{type(exc).__name__}: {exc}"
            record = {"system": system.name, "passed": False, "examples": 0, "failure": f"{system.name}: {reason}",
                      "checks": []}
        record["seconds"] = round(time.perf_counter() - start, 2)
        record["lecture"], record["status"] = system.lecture, system.status
        results.append(record)
    doc = {"tolerance_policy": conformance.__doc__.split("Tolerance policy")[1].strip(" -\n"),
           "versions": _versions(), "systems": results,
           "passed": all(r["passed"] for r in results)}
    if args.json:
        print(json.dumps(doc, indent=1))
    else:
        _print_table(results)
    if args.out:
        out = Path(args.out)
        atomic_write_text(out / "results.json", json.dumps(doc, indent=1) + "\n")
        atomic_write_text(out / "summary.md", _markdown(doc))
        print(f"wrote {out / 'results.json'} and {out / 'summary.md'}", file=sys.stderr)
    return 0 if doc["passed"] else 1


def _rows(results):
    for r in results:
        for c in r["checks"]:
            yield (r["system"], c["check"], c["engine"], f"{c['max_error']:.2e}", f"{c['tolerance']:.1e}",
                   "ok" if c["passed"] else "FAIL")


def _print_table(results):
    header = ("system", "check", "engine", "max error", "tolerance", "verdict")
    rows = [header] + list(_rows(results))
    widths = [max(len(r[i]) for r in rows) for i in range(len(header))]
    for row in rows:
        print("  ".join(c.ljust(w) for c, w in zip(row, widths)))
    for r in results:
        for engine, reason in r.get("not_applicable", {}).items():
            print(f"n/a    {r['system']} in {engine}: {reason}")
        if r["failure"]:
            print(f"FAILED {r['failure']}")
    print(f"{sum(r['passed'] for r in results)} of {len(results)} systems conformant")


def _markdown(doc) -> str:
    lines = ["# Conformance summary", "",
             "Largest relative error over all hypothesis examples (random states and parameters), per check and "
             "engine. Generated by `harness check --out reports`.", "",
             "| system | check | engine | max error | tolerance | verdict |", "|---|---|---|---|---|---|"]
    lines += ["| " + " | ".join(row) + " |" for row in _rows(doc["systems"])]
    treated = [r for r in doc["systems"] if r.get("status", "modeled") != "modeled"]
    if treated:
        lines += ["", "## What the engines check where the system is not a plain rigid-body tree", ""]
        lines += [f"- {r['system']} ({r['lecture']}): {r['status']}" for r in treated]
    notes = [(r["system"], e, why) for r in doc["systems"] for e, why in r.get("not_applicable", {}).items()]
    if notes:
        lines += ["", "## Engines that do not apply", ""] + [f"- {s} in {e}: {why}" for s, e, why in notes]
    failures = [r for r in doc["systems"] if r["failure"]]
    if failures:
        lines += ["", "## Failures", ""] + [f"- {r['failure']}" for r in failures]
    lines += ["", "Versions: " + ", ".join(f"{k} {v}" for k, v in doc["versions"].items()), ""]
    return "\n".join(lines)


def _classify_system(job) -> list[dict]:
    """Classify the claims of one system (runs in a worker process with --jobs)."""
    import models
    from harness import claims
    from harness.settings import load_hypothesis_profile

    name, examples = job
    load_hypothesis_profile()
    system = models.get(name)
    out = []
    for claim in models.claims(name):
        print(f"classifying {name} {claim.equation} …", file=sys.stderr, flush=True)
        v = claims.classify(system, claim, examples=examples)
        out.append({"system": v.system, "equation": v.claim.equation, "quantity": v.claim.quantity,
                    "description": v.claim.description, "classification": v.classification,
                    "printed": str(v.claim.printed), "corrected": v.corrected, "convention": v.convention,
                    "counterexample": v.counterexample, "note": v.claim.note, "examples": v.examples,
                    "errors_over_tolerance": v.errors})
    return out


def cmd_claims(args) -> int:
    """Classify every printed equation; errata are findings (reported, exit 0), 'engines disagree' fails."""
    import multiprocessing

    import models
    from harness.io import atomic_write_text

    names = args.systems or list(models.catalogue())
    for name in names:
        models.get(name)  # unknown names fail before any work
    jobs = [(name, args.examples) for name in names]
    if args.jobs > 1 and len(jobs) > 1:
        with multiprocessing.get_context("spawn").Pool(args.jobs) as pool:
            per_system = pool.map(_classify_system, jobs, chunksize=1)
    else:
        per_system = [_classify_system(job) for job in jobs]
    records = [r for rs in per_system for r in rs]
    if args.json:
        print(json.dumps(records, indent=1))
    else:
        for r in records:
            print(f"{r['system']:22s} {r['equation']:30s} {r['quantity']:16s} {r['classification']}")
    if args.out:
        atomic_write_text(Path(args.out) / "claims.json", json.dumps(records, indent=1) + "\n")
        atomic_write_text(Path(args.out) / "errata.md", _errata_markdown(records))
    return 1 if any(r["classification"] == "engines disagree" for r in records) else 0


def _errata_markdown(records) -> str:
    lines = ["# Printed equations of the lecture, checked", "",
             "Each printed equation is evaluated on hypothesis states (random states and parameters) against our "
             "derivation and, where an engine gives the quantity, Pinocchio and MuJoCo. Generated by "
             "`harness claims --out reports`.", "",
             "| system | equation | quantity | classification |", "|---|---|---|---|"]
    lines += [f"| {r['system']} | {r['equation']} | {r['quantity']} | {r['classification']} |" for r in records]
    errata = [r for r in records if r["classification"] != "confirmed"]
    if errata:
        lines += ["", "## Not confirmed", ""]
        for r in errata:
            lines += [f"### {r['system']} {r['equation']}: {r['classification']}", "",
                      f"- printed: `{r['printed']}`", f"- derived: `{r['corrected']}`"]
            if r["convention"]:
                lines.append(f"- holds with the convention: {r['convention']}")
            lines += [f"- minimal counterexample: {r['counterexample']}"]
            if r["note"]:
                lines.append(f"- transcription note: {r['note']}")
            lines.append("")
    return "\n".join(lines) + "\n"


def cmd_scenes(args) -> int:
    """List the scenes; with --run, simulate them and check the trajectories (harness/trajectories.py)."""
    import models
    from harness.trajectories import run_scene

    names = args.systems or list(models.catalogue())
    failed = False
    for name in names:
        system = models.get(name)
        for scene in models.scenes(name):
            print(f"{name:22s} {scene.name:12s} {scene.horizon:6.2f} s  {', '.join(sorted(scene.effects)):40s} "
                  f"{scene.description}")
            if not args.run:
                continue
            result = run_scene(system, scene)
            for check, source, error, tolerance in result.checks:
                verdict = "ok" if error <= tolerance else "FAIL"
                print(f"    {check:45s} {source:10s} {error:.2e} / {tolerance:.0e}  {verdict}")
            for key, value in result.notes.items():
                print(f"    {key}: {value:.3g}" if isinstance(value, float) else f"    {key}: {value}")
            failed |= not result.passed
    return 1 if failed else 0


def cmd_export(args) -> int:
    from harness.export import export_files
    from harness.io import atomic_write_text

    out = Path(args.dir)
    files = export_files()
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
    p.add_argument("--out", help="folder for results.json and summary.md")
    p.set_defaults(func=cmd_check)

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
    p.set_defaults(func=cmd_scenes)

    p = sub.add_parser("export", help="regenerate urdf/ (URDF, MJCF, coordinate maps)")
    p.add_argument("--dir", default=str(PROJECT_ROOT / "urdf"))
    p.add_argument("--check", action="store_true", help="only report stale files (exit 1)")
    p.set_defaults(func=cmd_export)
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
