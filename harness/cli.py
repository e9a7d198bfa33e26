"""The ``harness`` command: ``list``, ``eval``, ``check``, ``claims``, ``export``, ``main`` (all of the main job), ….

Exit codes: 0 success, 1 a check failed (or exported files are stale), 2 bad input (one line on stderr).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import re
import sys
import threading
import time
from collections import Counter
from pathlib import Path

import numpy as np

from harness import limits, pool, profiling, run
from harness.engines import SOURCES
from harness.errors import HarnessError, InputError
from harness.io import writable_folder
from harness.report import margins
from harness.report.markdown import CHECK_HEADER, check_rows
from harness.report.results import dumps, split_timings
from harness.settings import load_hypothesis_profile

PROJECT_ROOT = Path(__file__).resolve().parent.parent


# counts a user may give, each bounded by its limit in harness/limits.py (0 or too many: one line, exit 2)
EXAMPLES = limits.bounded_int(1, limits.EXAMPLES, "harness.limits.EXAMPLES")
JOBS = limits.bounded_int(1, limits.JOBS, "harness.limits.JOBS")
STATES = limits.bounded_int(1, limits.STATES, "harness.limits.STATES")


class _Parser(argparse.ArgumentParser):
    # a value such as -1e-3 or -inf is a number, not an option: argparse's own pattern takes -1 and -.5 alone, and
    # `--q -1e-3 0` failed with "expected at least one argument" (no option of ours starts with a digit or "inf")
    NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|infinity|nan)$", re.IGNORECASE)

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = self.NEGATIVE_NUMBER

    def error(self, message):  # one line, exit 2, like every other bad input
        raise InputError(f"{self.prog}: {message}")


def _assignments(items, what: str) -> dict[str, float]:
    out = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise InputError(f"--{what} takes NAME=VALUE, got {item!r}")
        if name in out:
            raise InputError(f"--{what} {name} is given twice ({name}={out[name]:g} and {item}): give it once")
        try:
            out[name] = float(value)
        except ValueError:
            raise InputError(f"--{what} {name}: {value!r} is not a number") from None
    return out


def _catalogue(creating=None):
    """The catalogue of ``models/`` and ``HARNESS_MODELS_PATH`` (:func:`harness.catalogue.repository`); the
    library is handed it. ``creating``: the folder ``new --dir`` creates, on the path before it exists."""
    from harness.catalogue import check_search_path, repository

    check_search_path(creating=creating)
    return repository()


def cmd_list(args) -> int:
    rows = run.listing(_catalogue())
    widths = [max(len(r[i]) for r in rows + [("system", "dof", "lecture", "status")]) for i in range(4)]
    for row in [("system", "dof", "lecture", "status")] + rows:
        print("  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip())
    return 0


def cmd_eval(args) -> int:
    out = run.evaluate(_catalogue(), args.system, args.engine, args.q, args.qd, _assignments(args.param, "param"),
                       _assignments(args.input, "input"))
    if args.json:
        print(json.dumps(out))
    else:
        for key in ("M", "C", "Cqd", "g", "qdd"):
            print(f"{key} =\n{np.array2string(np.asarray(out[key]), precision=15)}")
    return 0


def cmd_check(args, claims: dict | None = None) -> int:
    """Conformance of each system; ``--out`` writes results.json, timings.json and summary.md (harness.run);
    ``--junit`` and ``--baseline`` the CI outputs (harness.report.ci). ``claims`` (the main job): a dict the
    systems' printed equations, classified in the same jobs, are put in (:func:`harness.run.check`)."""
    from harness.report import ci

    baseline = ci.prepare(args.junit, args.baseline)  # bad flags fail before the work
    result = run.check(_catalogue(), args.systems, examples=args.examples, seed=args.seed, jobs=args.jobs,
                       scenes=not args.no_scenes, out=args.out, profile=args.profile, scheduler=args.scheduler,
                       claims=claims)
    if result.profile is not None:  # stderr: --json keeps stdout for the document
        print(profiling.markdown(result.profile, systems=False), file=sys.stderr)
    if args.json:
        print(dumps(split_timings(result.document)[0]), end="")
    else:
        _print_table(result.document)
    if result.written:
        print(f"wrote {', '.join(map(str, result.written))}", file=sys.stderr)
    records = result.document["systems"]
    ci.finish(records, {r["system"]: (r.get("timings") or {}).get("seconds") for r in records}, junit=args.junit,
              baseline=baseline, baseline_path=args.baseline, out=args.out,
              stream=sys.stderr if args.json else sys.stdout)
    return 0 if result.passed else 1


def _print_table(doc: dict):
    results = doc["systems"]
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
    """Checks the systems results.json lacks, then writes summary.md and the static site (harness.run)."""
    result = run.report(_catalogue(), args.out, names=args.systems, jobs=args.jobs, examples=args.examples,
                        seed=args.seed, rerun=args.rerun, scenes=not args.no_scenes)
    for name, reason in result["failed"].items():
        print(f"FAILED {reason}", file=sys.stderr)
    print(f"wrote {Path(args.out) / 'index.html'} ({len(result['pages'])} pages)", file=sys.stderr)
    return 0 if result["passed"] else 1


def cmd_new(args) -> int:
    """Scaffold ``models/NAME.py`` (harness.scaffold)."""
    from harness.catalogue import MODELS_PATH_VARIABLE

    path, on_path = run.new(_catalogue(creating=args.dir), args.name, args.dir)
    print(f"wrote {path}: follow the checklist in its docstring, then run `harness check {args.name}`")
    if not on_path:
        print(f"note: add {path.parent} to {MODELS_PATH_VARIABLE} so that the catalogue finds it", file=sys.stderr)
    return 0


def cmd_claims(args, classified: dict | None = None) -> int:
    """Classify every printed equation; errata are findings (reported, exit 0), 'engines disagree' fails.
    ``classified`` (the main job): what the check's jobs classified, by system (:func:`harness.run.claims`)."""
    result = run.claims(_catalogue(), args.systems, examples=args.examples, jobs=args.jobs, out=args.out,
                        profile=args.profile, scheduler=args.scheduler, classified=classified)
    if result.profile is not None:  # stderr: --json keeps stdout for the records
        print(profiling.markdown(result.profile, systems=False), file=sys.stderr)
    if args.json:
        print(json.dumps(result.records, indent=1))
    else:
        for r in result.records:
            print(f"{r['system']:22s} {r['equation']:30s} {r['quantity']:16s} {r['classification']}")
            if r["classification"] != "confirmed" and r.get("sentence"):  # what is wrong, as the errata say it
                print(f"{'':23s}{r['sentence']}")
    for reason in result.failed:
        print(f"FAILED {reason}", file=sys.stderr)
    return 0 if result.passed else 1


def cmd_scenes(args) -> int:
    """List the scenes; with --run, simulate them and check the trajectories (harness/scenes/trajectories.py)."""
    catalogue = _catalogue()
    failed = False
    for system, scene in run.select_scenes(catalogue, args.systems, args.scene):
        print(f"{system.name:22s} {scene.name:12s} {scene.horizon:6.2f} s  {', '.join(sorted(scene.effects)):40s} "
              f"{scene.description}")
        if not args.run:
            continue
        result = run.run_scene(catalogue, system, scene)
        for c in result.checks:
            print(f"    {c.name:45s} {c.source:10s} {c.value:.2e} / {c.bound:.0e}  "
                  f"ratio {c.ratio:.2g}  {'ok' if c.passed else 'FAIL'}")
        for key, value in result.notes.items():
            print(f"    {key}: {value:.3g}" if isinstance(value, float) else f"    {key}: {value}")
        failed |= not result.passed
    return 1 if failed else 0


def _stale(stale: list[str]) -> int:
    for path in stale:
        print(f"stale: {path} (run `harness export`)", file=sys.stderr)
    return 1 if stale else 0


def _unloaded(catalogue) -> int:
    """The model modules that do not load, one line each: exported files of a system whose module does not load
    are neither written nor compared (they may be stale), so the export fails (2) beside what it did."""
    failures = catalogue.failures()
    for line in failures.values():
        print(f"error: {line} (its files in urdf/ are not exported)", file=sys.stderr)
    return 2 if failures else 0


def _exported_folder(folder) -> None:
    """The folder ``export --check`` compares (the main job's too) exists, before any work: one line, exit 2."""
    if not Path(folder).is_dir():
        raise InputError(f"--dir {folder}: is not a folder of exported files")


def cmd_export(args) -> int:
    catalogue = _catalogue()
    if args.check:
        _exported_folder(args.dir)
        stale = run.stale_exports(catalogue, args.dir)
        if not stale:
            print(f"the exported files in {args.dir}/ (and beside added models) are current")
        return max(_stale(stale), _unloaded(catalogue))
    files, stale = run.export(catalogue, args.dir)
    folders = Counter(path.parent for path in files)   # the repository's first, then each added folder's
    print(f"exported {', '.join(f'{n} files to {folder}/' for folder, n in folders.items())}: {len(stale)} changed "
          f"and written, {len(files) - len(stale)} current and left as they are")
    return _unloaded(catalogue)


def cmd_main(args) -> int:
    """The main job (``make check``): ``export --check``, ``check --profile``, ``claims --profile``, ``robots
    --symbolic``, ``hard`` (the hard cases at their full horizons), ``report``, each as its own command would run it
    (the profiles: where the time went, on the report's profile page), on one pool of ``--jobs`` processes kept for
    all of them (:func:`harness.pool.workers_kept`); the exported files are compared by one of those processes while
    the check starts. A check job also classifies its system's printed equations, on the states its conformance run
    evaluated (their numbers kept: :mod:`harness.compare.evaluations`); the claims phase writes what they found, as
    ``harness claims`` would. With more than one process the robots and the hard cases run beside them
    (:func:`_side_by_side`: the pool takes their jobs after the check's, no worker waits for a phase's last job),
    the report after them. Each phase's output follows a line naming its command, phase after phase; the last line
    says how each ended and took. A phase that fails does not stop the later ones (the report shows the failure);
    the exit code is the largest of the phases' (Ctrl-C stops at once, 130)."""
    jobs, out, parser = str(args.jobs), args.out, build_parser()
    run.check_folder(out)   # bad input before any phase: one line, not one per phase
    _exported_folder(args.dir)
    start, ended = time.perf_counter(), []  # (phase, exit code, seconds or None)
    side_by_side = args.jobs > 1

    def phase(*argv, **extra) -> None:
        sys.stdout.flush()
        print(f"== harness {' '.join(argv)}", file=sys.stderr, flush=True)
        began, command = time.perf_counter(), parser.parse_args(argv)
        try:
            code = command.func(command, **extra)
        except HarnessError as exc:
            print(f"error: {exc}", file=sys.stderr)
            code = getattr(exc, "exit_code", 2)
        except Exception:  # noqa: BLE001 - a crash of one phase is reported in its place; the later ones run
            import traceback

            traceback.print_exc()
            code = 1
        ended.append((argv[0], code, time.perf_counter() - (start if side_by_side and argv[0] != "report" else began)))

    def exported(future) -> None:
        try:
            code = max(_stale(future.result()), _unloaded(_catalogue()))
        except Exception as exc:  # noqa: BLE001 - reported like the command's own failure; the phases go on
            print(f"error: export --check: {type(exc).__name__}: {exc}", file=sys.stderr)
            code = getattr(exc, "exit_code", 2 if isinstance(exc, HarnessError) else 1)
        ended.append(("export --check", code, None))

    classified: dict = {}  # the printed equations, classified in the check's jobs on the states each checked
    checked = threading.Event()

    def check_phase():
        try:
            phase("check", "--jobs", jobs, "--profile", "--out", out, claims=classified)
            exported(comparing)
        finally:
            checked.set()

    def claims_phase():  # writes what the check's jobs classified (a system they did not is classified here)
        checked.wait()
        if not any(code == 130 for _, code, _ in ended):
            phase("claims", "--jobs", jobs, "--profile", "--out", out, classified=classified)

    def robots_phase():
        phase("robots", "--symbolic", "--jobs", jobs, "--out", out)

    def hard_phase():
        phase("hard", "--jobs", jobs, "--out", out)

    try:
        with pool.workers_kept(args.jobs) if args.jobs > 1 else contextlib.nullcontext():  # --jobs 1: all here
            comparing = pool.submit(run.stale_exports, _catalogue(), args.dir)
            if side_by_side:  # in the pool, the robots' jobs follow the check's; in the log, the claims do
                _side_by_side([(check_phase, 0), (claims_phase, None), (robots_phase, 1), (hard_phase, 2)])
            else:
                for work in (check_phase, claims_phase, robots_phase, hard_phase):
                    if any(code == 130 for _, code, _ in ended):
                        break
                    work()
            if not any(code == 130 for _, code, _ in ended):
                _profile_main(out, sorted(ended, key=lambda e: ORDER.index(e[0])), args.jobs,
                              time.perf_counter() - start, side_by_side, ["main", "--jobs", jobs, "--out", out])
                phase("report", "--jobs", jobs, "--out", out)
    except KeyboardInterrupt:  # between the phases' own handling (the workers are ended by workers_kept)
        print("error: interrupted", file=sys.stderr)
        return 130
    codes = [code for _, code, _ in ended]
    status = 130 if 130 in codes else max(codes)
    sys.stdout.flush()
    print("main job: " + ", ".join(
        f"{name} {'ok' if code == 0 else f'exit {code}'}"
        + ("" if seconds is None else f" (ended at {seconds:.1f} s)" if side_by_side and name != "report"
           else f" ({seconds:.1f} s)") for name, code, seconds in sorted(ended, key=lambda e: ORDER.index(e[0])))
        + f"; exit {status} after {time.perf_counter() - start:.1f} s", file=sys.stderr, flush=True)
    return status


ORDER = ["check", "export --check", "claims", "robots", "hard", "report"]
"""The main job's phases in the order its last line (and the profile page) lists them."""


def _profile_main(out, ended: list, jobs: int, seconds: float, side_by_side: bool, argv: list) -> None:
    """The main job's overview on the profile page (the ``main`` section of ``out/profile.json``), written before
    the report renders it; a folder that cannot be written is reported, the report still runs."""
    try:
        profiling.write(profiling.main_section(ended, jobs, seconds, argv, side_by_side), out)
    except HarnessError as exc:
        print(f"error: the main job's profile: {exc}", file=sys.stderr)


def _side_by_side(phases) -> None:
    """Run ``phases`` (``(function, turn)``) in threads side by side, their output printed phase after phase in the
    order given (:class:`_InOrder`), the jobs they give the kept pool taken in the order of their ``turn``
    (:func:`harness.pool.phases_in_order`; None: a phase that waits for another's results and submits nothing in
    turn). Ctrl-C reaches this thread: it is raised here (the kept pool is then ended and the phases stop)."""
    ordered = _InOrder(len(phases))

    def running(number, work, turn):
        with ordered.phase(number), pool.phase(turn) if turn is not None else contextlib.nullcontext():
            work()

    threads = [threading.Thread(target=running, args=(k, work, turn), daemon=True, name=f"phase {k}")
               for k, (work, turn) in enumerate(phases)]
    with ordered, pool.phases_in_order():
        for thread in threads:
            thread.start()
        for thread in threads:
            while thread.is_alive():
                thread.join(0.1)  # a bounded wait: Ctrl-C reaches this thread


class _InOrder:
    """``sys.stdout`` and ``sys.stderr`` while phases run side by side (:func:`_side_by_side`): what a phase's thread
    writes goes out as it comes while every phase before it has ended, else it is kept and written when they have;
    the log reads as if the phases had run one after the other. Other threads write through."""

    def __init__(self, count: int):
        self._lock, self._local = threading.RLock(), threading.local()
        self._kept: list[list] = [[] for _ in range(count)]
        self._ended, self._current = [False] * count, 0
        self._real: dict = {}

    def __enter__(self):
        self._real = {"stdout": sys.stdout, "stderr": sys.stderr}
        sys.stdout, sys.stderr = _Stream(self, "stdout"), _Stream(self, "stderr")
        return self

    def __exit__(self, *exc):
        sys.stdout, sys.stderr = self._real["stdout"], self._real["stderr"]

    @contextlib.contextmanager
    def phase(self, number: int):
        self._local.number = number
        try:
            yield
        finally:
            self._local.number = None
            with self._lock:
                self._ended[number] = True
                while self._current < len(self._ended) and self._ended[self._current]:
                    self._current += 1
                    if self._current < len(self._kept):
                        for which, text in self._kept[self._current]:
                            self._real[which].write(text)
                        self._kept[self._current] = []
                for stream in self._real.values():
                    stream.flush()

    def write(self, which: str, text: str) -> None:
        number = getattr(self._local, "number", None)
        with self._lock:
            if number is None or number <= self._current:
                self._real[which].write(text)
            else:
                self._kept[number].append((which, text))

    def flush(self, which: str) -> None:
        number = getattr(self._local, "number", None)
        if number is None or number <= self._current:
            self._real[which].flush()


class _Stream:
    """One of the standard streams seen through :class:`_InOrder`."""

    def __init__(self, ordered: _InOrder, which: str):
        self._ordered, self._which = ordered, which

    def write(self, text: str) -> int:
        self._ordered.write(self._which, text)
        return len(text)

    def flush(self) -> None:
        self._ordered.flush(self._which)

    def __getattr__(self, name):  # encoding, isatty, fileno … of the real stream
        return getattr(self._ordered._real[self._which], name)


def cmd_validate(args) -> int:
    """A user's own URDF/MJCF: safe parse, checks, load in the engines (harness/files/validate.py)."""
    result = run.validate(args.file, root=args.root, states=args.states)
    if args.json:
        print(json.dumps(result.to_json(), indent=1))
    else:
        print("\n".join(result.lines()))
    return 0 if result.passed else 1


def cmd_importer(args) -> int:
    """MuJoCo's URDF importer vs our MJCF and Pinocchio (harness/files/importer.py): importer.json, importer.md."""
    from harness.files import importer

    doc, written = run.importer(_catalogue(), args.systems, states=args.states, seed=args.seed, out=args.out)
    for path in written:
        print(f"wrote {path}", file=sys.stderr)
    print(json.dumps(doc, indent=1) if args.json else importer.markdown(doc), end="")
    return 0 if doc["summary"]["differ"] == 0 and all(c["detected"] for c in doc["controls"]) else 1


def cmd_robots(args) -> int:
    """Every robot of example-robot-data in every engine (harness/files/robots.py): robots.json, robots.md."""
    doc, written = run.robots(args.robots, out=args.out, states=args.states, seed=args.seed, jobs=args.jobs,
                              echo=lambda line: print(line, flush=True),
                              command="harness robots " + " ".join(sys.argv[2:]), scheduler=args.scheduler,
                              symbolic=args.symbolic)
    for path in written:
        print(f"wrote {path}", file=sys.stderr)
    for pair, counts in doc["summary"].items():
        print(f"{pair}: " + ", ".join(f"{n} {verdict}" for verdict, n in counts.items() if n))
    print(f"{len(doc['robots'])} robots in {doc['seconds']} s")
    if doc["open"]:
        print("open (no cause proven): " + ", ".join(doc["open"]))
    return 1 if doc["open"] else 0


def cmd_bench(args) -> int:
    """The performance studies (harness/bench/); writes bench.json, bench.md and the figures."""
    if args.render:
        run.bench_render(args.out)
        return 0
    if args.merge:
        run.bench_merge(args.out, args.merge)
        return 0
    run.bench(_catalogue(), out=args.out, quick=args.quick, scheduler=args.scheduler, systems=args.systems,
              scenes=args.scenes, workers=args.workers, parts=tuple(args.parts) if args.parts else None,
              command="harness bench " + " ".join(sys.argv[2:]))
    return 0


def cmd_hard(args) -> int:
    """The hard cases (harness/hard/): reports/hard.json and reports/hard/*.svg; exit 1 if a bound fails."""
    doc = run.hard(_catalogue(), args.out, quick=args.quick, only=args.cases or None,
                   echo=lambda line: print(line, file=sys.stderr), jobs=args.jobs)
    print(f"wrote {Path(args.out) / 'hard.json'}", file=sys.stderr)
    return 0 if doc["passed"] else 1


def _scheduler_option(p, what: str) -> None:
    p.add_argument("--scheduler", default=None, metavar="ADDR", help=f"run the {what} on this Dask scheduler "
                   "(tcp://HOST:8786; instead of --jobs); the results are written here, as with --jobs")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="harness", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    sub.add_parser("list", help="every system with its lecture reference").set_defaults(func=cmd_list)

    p = sub.add_parser("eval", help="M, C, Cqd, g, qdd of one system at one state")
    p.add_argument("system")
    p.add_argument("--engine", default="symbolic", choices=SOURCES)
    p.add_argument("--q", nargs="+", type=float, required=True)
    p.add_argument("--qd", nargs="+", type=float)
    p.add_argument("--param", nargs="*", action="extend", metavar="NAME=VALUE")
    p.add_argument("--input", nargs="*", action="extend", metavar="NAME=VALUE")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_eval)

    p = sub.add_parser("check", help="conformance checks against Pinocchio and MuJoCo")
    p.add_argument("systems", nargs="*")
    p.add_argument("--examples", type=EXAMPLES, default=None, help="hypothesis examples (states) per system (default: profile), two per parameter draw")
    p.add_argument("--json", action="store_true")
    p.add_argument("--no-scenes", action="store_true", help="skip the trajectory checks of the scenes")
    p.add_argument("--profile", action="store_true", help="print where the time goes per phase (and with --out "
                   "write profile.json and profile.md)")
    p.add_argument("--out", help="folder for results.json, timings.json and summary.md")
    p.add_argument("--jobs", type=JOBS, default=1, help="systems checked in parallel processes")
    _scheduler_option(p, "systems")
    p.add_argument("--seed", type=int, default=None, help="hypothesis seed (default: the profile's fixed seeds)")
    p.add_argument("--junit", metavar="FILE", help="also write the results as JUnit XML (one test case per "
                   "system x check x engine)")
    p.add_argument("--baseline", metavar="RESULTS_JSON", help="print (and with --out write changes.json, "
                   "changes.md) what changed since this earlier results.json")
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("report", help="readable reports: index.html, summary.md, results.json")
    p.add_argument("systems", nargs="*", help="default: every system")
    p.add_argument("--out", default="reports", help="report folder (default: reports)")
    p.add_argument("--jobs", type=JOBS, default=os.cpu_count() or 1, help="systems checked in parallel")
    p.add_argument("--examples", type=EXAMPLES, default=None, help="hypothesis examples (states) per system (default: profile), two per parameter draw")
    p.add_argument("--seed", type=int, default=None, help="hypothesis seed (default: the profile's fixed seeds)")
    p.add_argument("--rerun", action="store_true", help="check every system again, even if results.json has it")
    p.add_argument("--no-scenes", action="store_true", help="skip the trajectory checks of the scenes")
    p.set_defaults(func=cmd_report)

    p = sub.add_parser("new", help="scaffold models/NAME.py for a new system")
    p.add_argument("name", help="system name: a lower-case Python identifier, e.g. my_rod")
    p.add_argument("--dir", default=None, help="folder for the module (default: models/)")
    p.set_defaults(func=cmd_new)

    p = sub.add_parser("claims", help="check the lecture's printed equations (errata report)")
    p.add_argument("systems", nargs="*")
    p.add_argument("--jobs", type=JOBS, default=os.cpu_count() or 1, help="systems classified in parallel")
    _scheduler_option(p, "systems")
    p.add_argument("--examples", type=EXAMPLES, default=None)
    p.add_argument("--json", action="store_true")
    p.add_argument("--out", help="folder for claims.json and errata.md")
    p.add_argument("--profile", action="store_true", help="print where the time goes per phase (and with --out "
                   "write the claims section of profile.json)")
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
    p.add_argument("--workers", type=JOBS, default=None, help="local processes (default: one per CPU)")
    p.add_argument("--systems", nargs="+", default=None)
    p.add_argument("--scenes", nargs="+", default=None, help="scene names (stiff variants: SCENE_PARAM_xFACTOR…)")
    parts = ["workprecision", "evaluation", "derivation", "pruning", "lightweight_robot"]   # harness.bench.RUNS
    p.add_argument("--parts", nargs="+", default=None, choices=parts,
                   help="default: every part; with --systems or --scenes those measured per system or scene")
    p.add_argument("--render", action="store_true", help="only redraw bench.md and the figures from bench.json")
    p.add_argument("--merge", default=None, metavar="BENCH_JSON",
                   help="take the parts another run measured (its bench.json) into OUT/bench.json, recorded")
    p.set_defaults(func=cmd_bench)

    p = sub.add_parser("main", help="the main job of `make check`: export --check, check, claims, robots "
                       "--symbolic, hard and report, on one pool of worker processes")
    p.add_argument("--out", default="reports", help="report folder (default: reports)")
    p.add_argument("--jobs", type=JOBS, default=os.cpu_count() or 1, help="worker processes for every phase")
    p.add_argument("--dir", default=str(PROJECT_ROOT / "urdf"), help="the exported files to compare")
    p.set_defaults(func=cmd_main)

    p = sub.add_parser("validate", help="check a URDF or MJCF file of your own and load it in the engines")
    p.add_argument("file", help="a .urdf or MJCF .xml file")
    p.add_argument("--root", default=None, help="folder its mesh/package/include files must stay in "
                   "(default: the file's folder)")
    p.add_argument("--states", type=STATES, default=20, help="random states for the importer comparison")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_validate)

    p = sub.add_parser("importer", help="MuJoCo's URDF importer vs our MJCF and Pinocchio")
    p.add_argument("systems", nargs="*", help="default: every system (the test models are always included)")
    p.add_argument("--out", default=None, help="folder for importer.json and importer.md")
    p.add_argument("--states", type=STATES, default=20)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_importer)

    p = sub.add_parser("robots", help="every robot of example-robot-data: Pinocchio vs MuJoCo's URDF importer")
    p.add_argument("robots", nargs="*", help="robot names (URDF file stems; default: every robot)")
    p.add_argument("--out", default=None, help="folder for robots.json and robots.md")
    p.add_argument("--states", type=STATES, default=None, help="random states per robot (default 10)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--jobs", type=JOBS, default=1, help="robots compared in parallel processes")
    _scheduler_option(p, "robots")
    p.add_argument("--symbolic", action="store_true", help="also our symbolic derivation (fixed-base trees up to 7 "
                   "DoF; reads and writes the derivation cache, HARNESS_CACHE_DIR)")
    p.set_defaults(func=cmd_robots)

    p = sub.add_parser("hard", help="hard cases: singularities, stiffness, chaos, long horizons (harness/hard/)")
    p.add_argument("cases", nargs="*", help="default: the whole catalogue")
    p.add_argument("--out", default="reports", help="folder for hard.json and hard/*.svg")
    p.add_argument("--quick", action="store_true", help="the shortened horizons of the test suite")
    p.add_argument("--jobs", type=JOBS, default=1, help="cases run at a time in worker processes")
    p.set_defaults(func=cmd_hard)
    return parser


NO_DERIVATION = frozenset({"list", "new", "validate", "robots"})
"""Commands that never read or write the derivation cache (``robots`` only with ``--symbolic``)."""


def main(argv=None) -> int:
    load_hypothesis_profile()
    try:
        args = build_parser().parse_args(argv)
        derives = args.command not in NO_DERIVATION or getattr(args, "symbolic", False)
        if derives and os.environ.get("HARNESS_CACHE_DIR"):
            from harness.derivation.cache import cache_dir

            writable_folder(cache_dir(), "HARNESS_CACHE_DIR")  # before the work, not after it
        return args.func(args)
    except HarnessError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return getattr(exc, "exit_code", 2)
    except BrokenPipeError:  # the reader stopped early (`harness list | head`): not an error of ours
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no second error when stdout is flushed
        return 1


if __name__ == "__main__":
    sys.exit(main())
