"""JUnit XML of a conformance run (``harness check --junit FILE``), the format CI systems read.

Layout (the common JUnit schema: ``<testsuites>`` of ``<testsuite>`` of ``<testcase>``, each with at most one
``<failure>``, ``<error>`` or ``<skipped>``):

* one ``<testsuite>`` per system (``name`` the system, ``time`` its wall clock when known);
* one ``<testcase>`` per check × engine (``classname`` ``harness.<system>``, ``name`` ``<check> [<engine>]``),
  and per scene check (``name`` ``scene <scene>: <check> [<source>]``);
* a failed check carries ``<failure>``: its value against its bound and, when hypothesis shrank it, the
  minimal counterexample (q, q̇, inputs, parameters) of the system's failure message;
* an engine that does not apply to the system is one skipped test case with the reason;
* a system that failed without a failed check (it does not load, a worker crashed, an unexplained engine
  warning) gets one test case ``verdict`` with an ``<error>`` holding the reason, so that the failure
  count of the file is never zero for a failed run.
"""

from __future__ import annotations

from xml.etree import ElementTree as ET

from harness.report.markdown import fmt_bound, fmt_error, fmt_ratio


def _value(check: dict):
    """(value, bound, ratio) of a check record of any schema version (``value``/``bound`` or the former
    ``max_error``/``tolerance``)."""
    value = check.get("value", check.get("max_error"))
    bound = check.get("bound", check.get("tolerance"))
    ratio = check.get("ratio")
    if ratio is None and isinstance(value, (int, float)) and isinstance(bound, (int, float)):
        ratio = 0.0 if value == 0 else (value / bound if bound > 0 else float("inf"))
    return value, bound, ratio


def _source(check: dict) -> str:
    return str(check.get("source", check.get("engine", "?")))


def _measured(check: dict) -> str:
    value, bound, ratio = _value(check)
    value_text = value if isinstance(value, str) else fmt_error(value)
    basis = f" ({check['basis']})" if check.get("basis") else ""
    detail = f" at {check['detail']}" if check.get("detail") else ""
    return f"{check.get('check', '?')} from {_source(check)}: {value_text} against the bound " \
           f"{fmt_bound({'bound': bound})}{basis}, ratio {fmt_ratio(ratio)}{detail}"


def _mentions(failure: str | None, check: dict) -> bool:
    """Whether the system's failure message (hypothesis' shrunk counterexample) is about this check."""
    return bool(failure) and f"{check.get('check')}" in failure and _source(check) in failure


def _case(suite, classname: str, name: str, check: dict | None = None, failure: str | None = None):
    case = ET.SubElement(suite, "testcase", {"classname": classname, "name": name, "time": "0"})
    if check is not None and not check.get("passed"):
        message = _measured(check)
        body = message
        if _mentions(failure, check):
            body = f"{message}\nminimal counterexample: {failure}"
        node = ET.SubElement(case, "failure", {"message": message, "type": "ConformanceFailure"})
        node.text = body
    return case


def junit_tree(records: list[dict], seconds: dict | None = None, name: str = "harness check") -> ET.Element:
    """The ``<testsuites>`` element of ``records`` (results.json system records)."""
    seconds = seconds or {}
    root = ET.Element("testsuites", {"name": name})
    totals = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
    total_time = 0.0
    for record in records:
        system = str(record.get("system", "?"))
        classname = f"harness.{system}"
        suite = ET.SubElement(root, "testsuite", {"name": system})
        failure = record.get("failure")
        for check in record.get("checks") or []:
            _case(suite, classname, f"{check.get('check', '?')} [{_source(check)}]", check, failure)
        for scene in record.get("scenes") or []:
            scene_name = scene.get("scene", "?")
            for check in scene.get("checks") or []:
                _case(suite, classname, f"scene {scene_name}: {check.get('check', '?')} [{_source(check)}]",
                      check, scene.get("failure"))
            if not scene.get("passed", True) and all(c.get("passed") for c in scene.get("checks") or []):
                case = _case(suite, classname, f"scene {scene_name}: verdict")
                ET.SubElement(case, "error", {"message": str(scene.get("failure") or "scene failed"),
                                              "type": "SceneError"}).text = str(scene.get("failure") or "")
        for engine, reason in sorted((record.get("not_applicable") or {}).items()):
            case = _case(suite, classname, f"all checks [{engine}]")
            ET.SubElement(case, "skipped", {"message": f"{engine} does not apply: {reason}"})
        failed_cases = [c for c in suite if c.find("failure") is not None or c.find("error") is not None]
        if not record.get("passed", False) and not failed_cases:
            case = _case(suite, classname, "verdict")
            reason = str(failure or "the system failed without a failed check")
            ET.SubElement(case, "error", {"message": reason.splitlines()[0][:500], "type": "SystemError"}).text = reason
        counts = {"tests": len(suite), "failures": sum(c.find("failure") is not None for c in suite),
                  "errors": sum(c.find("error") is not None for c in suite),
                  "skipped": sum(c.find("skipped") is not None for c in suite)}
        wall = seconds.get(system)
        suite.set("time", f"{float(wall):.3f}" if isinstance(wall, (int, float)) else "0")
        total_time += float(wall) if isinstance(wall, (int, float)) else 0.0
        for key, n in counts.items():
            suite.set(key, str(n))
            totals[key] += n
    for key, n in totals.items():
        root.set(key, str(n))
    root.set("time", f"{total_time:.3f}")
    return root


def junit_xml(records: list[dict], seconds: dict | None = None) -> str:
    """``records`` as a JUnit XML document (UTF-8 text with declaration)."""
    tree = junit_tree(records, seconds)
    ET.indent(tree, " ")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(tree, encoding="unicode") + "\n"
