"""What changed since an earlier run (``harness check --baseline OLD/results.json``).

Checks are matched by (system, scene, check, source); a scene check's scene is its name, a conformance check's
is empty. Reported:

* **new failures**: a check that passed in the baseline (or was not there) and fails now; a system that fails
  now and passed before;
* **fixed**: a check (or system) that failed in the baseline and passes now;
* **grown**: an error ratio (value / bound) that grew by more than :data:`GROWTH` times, from a non-zero
  baseline ratio, or from an exact zero to above :data:`harness.checks.MARGIN` of the bound (a ratio grown from
  0 to round-off is no finding);
* systems and checks that appeared or disappeared.

Only the systems of the current run are compared (a run over some systems says nothing of the others, a run
with ``--no-scenes`` nothing of the scenes).
Results of the former schema (``engine``, ``max_error``, ``tolerance``) are read as well.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from harness.checks import MARGIN
from harness.errors import InputError
from harness.report.junit import _source, _value

GROWTH = 10.0


def load_baseline(path: Path | str) -> dict:
    """The baseline results document; a missing or malformed file is bad input (one line)."""
    path = Path(path)
    try:
        doc = json.loads(path.read_text())
    except OSError as exc:
        raise InputError(f"--baseline {path}: cannot be read: {exc.strerror or exc}") from None
    except ValueError as exc:
        raise InputError(f"--baseline {path}: not JSON: {exc}") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("systems"), list):
        raise InputError(f"--baseline {path}: not a results.json (no list 'systems')")
    return doc


def _ratio(check: dict) -> float | None:
    ratio = _value(check)[2]
    if isinstance(ratio, str):
        try:
            return float(ratio)
        except ValueError:
            return math.inf
    return None if ratio is None else float(ratio)


def _checks(record: dict, scenes: bool = True) -> dict[tuple, dict]:
    out = {}
    for c in record.get("checks") or []:
        out[("", str(c.get("check")), _source(c))] = c
    for sc in (record.get("scenes") or []) if scenes else []:
        for c in sc.get("checks") or []:
            out[(str(sc.get("scene")), str(c.get("check")), _source(c))] = c
    return out


def _row(system: str, key: tuple, old: dict | None, new: dict | None) -> dict:
    scene, check, source = key
    return {"system": system, "scene": scene, "check": check, "source": source,
            "old_ratio": None if old is None else _ratio(old), "new_ratio": None if new is None else _ratio(new),
            "old_passed": None if old is None else bool(old.get("passed")),
            "new_passed": None if new is None else bool(new.get("passed"))}


def compare(baseline: dict, records: list[dict]) -> dict:
    """The changes from ``baseline`` (a results document) to ``records`` (this run's system records)."""
    old_systems = {r.get("system"): r for r in baseline.get("systems", []) if isinstance(r, dict)}
    out = {"new_failures": [], "fixed": [], "grown": [], "appeared": [], "disappeared": [],
           "systems_new": [], "systems_failing": [], "systems_fixed": [], "growth": GROWTH}
    for record in records:
        name = record["system"]
        old = old_systems.get(name)
        if old is None:
            out["systems_new"].append(name)
            old = {}
        elif old.get("passed") and not record.get("passed"):
            out["systems_failing"].append(name)
        elif not old.get("passed") and record.get("passed"):
            out["systems_fixed"].append(name)
        # a run without scenes (--no-scenes) says nothing about the baseline's scene checks
        before, now = _checks(old, scenes="scenes" in record), _checks(record)
        for key, c in now.items():
            b = before.get(key)
            row = _row(name, key, b, c)
            if not c.get("passed") and (b is None or b.get("passed")):
                out["new_failures"].append(row)
            elif c.get("passed") and b is not None and not b.get("passed"):
                out["fixed"].append(row)
            elif b is not None:
                r_old, r_new = row["old_ratio"], row["new_ratio"]
                if r_old is None or r_new is None:
                    continue
                if (r_old > 0 and r_new > GROWTH * r_old) or (r_old == 0 and r_new > MARGIN):
                    out["grown"].append({**row, "factor": math.inf if r_old == 0 else r_new / r_old})
            if b is None and old:
                out["appeared"].append(row)
        if old:
            out["disappeared"] += [_row(name, key, b, None) for key, b in before.items() if key not in now]
    out["changed"] = any(out[k] for k in ("new_failures", "fixed", "grown", "systems_failing", "systems_fixed"))
    return out


def _where(row: dict) -> str:
    scene = f"/{row['scene']}" if row["scene"] else ""
    return f"{row['system']}{scene} {row['check']} [{row['source']}]"


def _r(value) -> str:
    return "—" if value is None else f"{value:.3g}"


def lines(changes: dict) -> list[str]:
    """The changes as console lines (empty when nothing changed)."""
    out = [f"NEW FAILURE {_where(r)}: ratio {_r(r['old_ratio'])} -> {_r(r['new_ratio'])}"
           for r in changes["new_failures"]]
    out += [f"FIXED       {_where(r)}: ratio {_r(r['old_ratio'])} -> {_r(r['new_ratio'])}" for r in changes["fixed"]]
    out += [f"GROWN       {_where(r)}: ratio {_r(r['old_ratio'])} -> {_r(r['new_ratio'])} "
            f"(x{_r(r['factor'])})" for r in changes["grown"]]
    out += [f"system now failing: {n}" for n in changes["systems_failing"]]
    out += [f"system fixed: {n}" for n in changes["systems_fixed"]]
    out += [f"system not in the baseline: {n}" for n in changes["systems_new"]]
    if changes["appeared"] or changes["disappeared"]:
        out.append(f"{len(changes['appeared'])} check(s) new, {len(changes['disappeared'])} gone since the baseline")
    return out


def markdown(changes: dict, baseline: str) -> str:
    """``changes.md``: the changes as Markdown (rendered as the report's Changes page)."""
    text = ["# Changes since the baseline", "", f"Baseline: `{baseline}`. Error ratios are value / bound; "
            f"'grown' means more than {GROWTH:g}× the baseline's ratio.", ""]
    if not changes["changed"]:
        text += ["Nothing changed: no new failure, nothing fixed, no ratio grown.", ""]
    for key, title in (("new_failures", "New failures"), ("fixed", "Fixed"), ("grown", "Error ratios grown")):
        rows = changes[key]
        if not rows:
            continue
        text += [f"## {title}", "", "| system | scene | check | source | old ratio | new ratio |", "|---|---|---|---|---|---|"]
        text += [f"| {r['system']} | {r['scene'] or '—'} | {r['check']} | {r['source']} | {_r(r['old_ratio'])} | "
                 f"{_r(r['new_ratio'])} |" for r in rows]
        text.append("")
    for key, title in (("systems_failing", "Systems now failing"), ("systems_fixed", "Systems fixed"),
                       ("systems_new", "Systems not in the baseline")):
        if changes[key]:
            text += [f"## {title}", "", ", ".join(changes[key]), ""]
    if changes["appeared"] or changes["disappeared"]:
        text += ["## Checks new or gone", ""]
        text += [f"- new: {_where(r)}" for r in changes["appeared"]]
        text += [f"- gone: {_where(r)}" for r in changes["disappeared"]]
        text.append("")
    return "\n".join(text)
