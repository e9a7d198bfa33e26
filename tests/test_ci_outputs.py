"""CI outputs of ``harness check``: the JUnit file (validated against the common JUnit XML schema, the one
Jenkins' xunit plugin and most CI systems read) and the changes since a baseline results.json."""

from __future__ import annotations

import copy
import json

import pytest
from lxml import etree

from harness import cli
from harness.report import baseline
from harness.report.junit import junit_xml

# The common JUnit XML schema (Jenkins xunit junit-10.xsd), the parts a report uses: testsuites of testsuite of
# testcase; a testcase holds at most failure/error/skipped and output; counts on suites.
JUNIT_XSD = b"""<?xml version="1.0" encoding="UTF-8"?>
<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema" elementFormDefault="qualified">
  <xs:complexType name="problem" mixed="true">
    <xs:attribute name="type" type="xs:string"/>
    <xs:attribute name="message" type="xs:string"/>
  </xs:complexType>
  <xs:element name="failure" type="problem"/>
  <xs:element name="error" type="problem"/>
  <xs:element name="skipped" type="problem"/>
  <xs:element name="system-out" type="xs:string"/>
  <xs:element name="system-err" type="xs:string"/>
  <xs:element name="property">
    <xs:complexType><xs:attribute name="name" type="xs:string" use="required"/>
      <xs:attribute name="value" type="xs:string" use="required"/></xs:complexType>
  </xs:element>
  <xs:element name="properties">
    <xs:complexType><xs:sequence><xs:element ref="property" maxOccurs="unbounded"/></xs:sequence></xs:complexType>
  </xs:element>
  <xs:element name="testcase">
    <xs:complexType>
      <xs:sequence><xs:choice minOccurs="0" maxOccurs="unbounded">
        <xs:element ref="skipped"/><xs:element ref="error"/><xs:element ref="failure"/>
        <xs:element ref="system-out"/><xs:element ref="system-err"/>
      </xs:choice></xs:sequence>
      <xs:attribute name="name" type="xs:string" use="required"/>
      <xs:attribute name="assertions" type="xs:string"/>
      <xs:attribute name="time" type="xs:decimal"/>
      <xs:attribute name="classname" type="xs:string"/>
      <xs:attribute name="status" type="xs:string"/>
    </xs:complexType>
  </xs:element>
  <xs:element name="testsuite">
    <xs:complexType>
      <xs:sequence>
        <xs:element ref="properties" minOccurs="0"/>
        <xs:element ref="testcase" minOccurs="0" maxOccurs="unbounded"/>
        <xs:element ref="system-out" minOccurs="0"/>
        <xs:element ref="system-err" minOccurs="0"/>
      </xs:sequence>
      <xs:attribute name="name" type="xs:string" use="required"/>
      <xs:attribute name="tests" type="xs:nonNegativeInteger" use="required"/>
      <xs:attribute name="failures" type="xs:nonNegativeInteger"/>
      <xs:attribute name="errors" type="xs:nonNegativeInteger"/>
      <xs:attribute name="skipped" type="xs:nonNegativeInteger"/>
      <xs:attribute name="disabled" type="xs:nonNegativeInteger"/>
      <xs:attribute name="time" type="xs:decimal"/>
      <xs:attribute name="timestamp" type="xs:string"/>
      <xs:attribute name="hostname" type="xs:string"/>
      <xs:attribute name="id" type="xs:string"/>
      <xs:attribute name="package" type="xs:string"/>
    </xs:complexType>
  </xs:element>
  <xs:element name="testsuites">
    <xs:complexType>
      <xs:sequence><xs:element ref="testsuite" minOccurs="0" maxOccurs="unbounded"/></xs:sequence>
      <xs:attribute name="name" type="xs:string"/>
      <xs:attribute name="time" type="xs:decimal"/>
      <xs:attribute name="tests" type="xs:nonNegativeInteger"/>
      <xs:attribute name="failures" type="xs:nonNegativeInteger"/>
      <xs:attribute name="errors" type="xs:nonNegativeInteger"/>
      <xs:attribute name="skipped" type="xs:nonNegativeInteger"/>
      <xs:attribute name="disabled" type="xs:nonNegativeInteger"/>
    </xs:complexType>
  </xs:element>
</xs:schema>
"""

FAILURE = ("spring: M from mujoco differs from the symbolic model by 3.000e-09 (relative; tolerance 1.0e-12) at "
           "q=[0.5], qd=[0.0], u={}, params={m=1.0}")


def check(name, source, value, bound=1e-12, basis="float64 round-off"):
    return {"check": name, "source": source, "value": value, "bound": bound, "ratio": value / bound,
            "basis": basis, "passed": value <= bound}


def records():
    ok = {"system": "pendulum", "passed": True, "examples": 5, "failure": None, "not_applicable": {},
          "checks": [check("M", "pinocchio", 1e-16), check("M", "mujoco", 2e-16)],
          "scenes": [{"scene": "swing", "passed": True, "failure": None,
                      "checks": [check("trajectory", "mujoco", 1e-9, 1e-6, "integrator")]}]}
    bad = {"system": "spring", "passed": False, "examples": 3, "failure": FAILURE,
           "not_applicable": {"pinocchio": "no follower forces"}, "checks": [check("M", "mujoco", 3e-9)]}
    crashed = {"system": "broken", "passed": False, "examples": 0, "checks": [], "not_applicable": {},
               "failure": "broken: worker process failed: RuntimeError: boom"}
    return [ok, bad, crashed]


def validate(text: str) -> etree._Element:
    schema = etree.XMLSchema(etree.fromstring(JUNIT_XSD))
    doc = etree.fromstring(text.encode())
    assert schema.validate(doc), schema.error_log
    return doc


def test_junit_validates_and_counts():
    doc = validate(junit_xml(records(), {"pendulum": 1.5}))
    assert (doc.get("tests"), doc.get("failures"), doc.get("errors"), doc.get("skipped")) == ("6", "1", "1", "1")
    suites = {s.get("name"): s for s in doc.findall("testsuite")}
    assert suites["pendulum"].get("time") == "1.500"
    names = [c.get("name") for c in suites["pendulum"].findall("testcase")]
    assert names == ["M [pinocchio]", "M [mujoco]", "scene swing: trajectory [mujoco]"]
    failure = suites["spring"].find("testcase/failure")
    assert "3.00e-09" in failure.get("message") and "q=[0.5]" in failure.text  # the shrunk counterexample
    assert suites["spring"].find("testcase/skipped").get("message").startswith("pinocchio does not apply")
    assert "boom" in suites["broken"].find("testcase/error").get("message")
    for suite in suites.values():  # per-suite counts agree with the cases
        assert int(suite.get("tests")) == len(suite.findall("testcase"))
        assert int(suite.get("failures")) == len(suite.findall("testcase/failure"))


def test_baseline_reports_new_failures_fixed_and_growth():
    old = {"systems": records()}
    new = copy.deepcopy(records())
    new[0]["checks"][0] = check("M", "pinocchio", 2e-15)        # ratio grown 20x
    new[0]["checks"][1] = check("M", "mujoco", 2e-11)           # newly failing
    new[0]["passed"] = False
    new[1]["checks"][0] = check("M", "mujoco", 1e-13)           # fixed
    new[1]["passed"], new[1]["failure"] = True, None
    changes = baseline.compare(old, new)
    where = lambda key: [(r["system"], r["check"], r["source"]) for r in changes[key]]  # noqa: E731
    assert where("new_failures") == [("pendulum", "M", "mujoco")]
    assert where("fixed") == [("spring", "M", "mujoco")]
    assert where("grown") == [("pendulum", "M", "pinocchio")] and changes["grown"][0]["factor"] == pytest.approx(20)
    assert changes["systems_failing"] == ["pendulum"] and changes["systems_fixed"] == ["spring"]
    assert any(line.startswith("NEW FAILURE pendulum M [mujoco]") for line in baseline.lines(changes))
    assert not baseline.compare(old, records())["changed"]


def test_baseline_reads_the_former_schema():
    old = {"systems": [{"system": "pendulum", "passed": True, "checks": [
        {"check": "M", "engine": "pinocchio", "max_error": 1e-18, "tolerance": 1e-12, "passed": True},
        {"check": "M", "engine": "mujoco", "max_error": 2e-16, "tolerance": 1e-12, "passed": True}]}]}
    changes = baseline.compare(old, records()[:1])
    assert [r["source"] for r in changes["grown"]] == ["pinocchio"]
    assert not changes["new_failures"] and not changes["fixed"]


def test_check_writes_junit_and_changes(tmp_path, capsys):
    out = tmp_path / "run"
    old = tmp_path / "old.json"
    old.write_text(json.dumps({"systems": [{"system": "pendulum", "passed": False, "checks": [
        {"check": "M", "source": "pinocchio", "value": 1.0, "bound": 1e-12, "ratio": 1e12, "passed": False}]}]}))
    junit = tmp_path / "ci" / "junit.xml"
    code = cli.main(["check", "pendulum", "--examples", "3", "--no-scenes", "--out", str(out), "--junit", str(junit),
                     "--baseline", str(old)])
    assert code == 0
    doc = validate(junit.read_text())
    assert int(doc.get("tests")) >= 10 and doc.get("failures") == "0"
    printed = capsys.readouterr().out
    assert "FIXED       pendulum M [pinocchio]" in printed
    assert json.loads((out / "changes.json").read_text())["fixed"][0]["check"] == "M"
    assert "## Fixed" in (out / "changes.md").read_text()


@pytest.mark.parametrize("flag", ["--baseline", "--junit"])
def test_bad_ci_flags_are_one_line_errors(tmp_path, capsys, flag):
    target = tmp_path / "missing.json" if flag == "--baseline" else tmp_path
    assert cli.main(["check", "pendulum", "--no-scenes", flag, str(target)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {flag}")
