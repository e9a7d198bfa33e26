"""Fuzzing the model-loading path (``harness validate``: safe parse, checks, Pinocchio, MuJoCo's importer or
compiler, 1 s of stepping, the importer comparison) with hypothesis-made variations of valid URDF and MJCF:
mutated numbers, deleted attributes and elements, junk text, deep nesting. Whatever the file, the outcome is
a report or one of our errors with a one-line message — never another exception, never a hang (each example
is bounded by hypothesis' deadline). What the long profile found and what was fixed: an unknown ``encoding=``
(LookupError, now a ModelError), a finite but absurd number (1.8e308: engines overflow to NaN, now bounded by
``untrusted.MAX_MAGNITUDE``), a centre of mass 5.7e5 m away (float64 cancellation, now the scale of the
terms), a fixed link of mass 1e-16 kg with an inertia tensor (MuJoCo's importer drops the inertia: a finding,
see ``harness importer``'s edge cases)."""

import os
import re
from datetime import timedelta
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from harness.errors import HarnessError
from harness.files.validate import Validation, validate

ROOT = Path(__file__).resolve().parent.parent
SEEDS = [ROOT / "harness/files/fixtures/rotated_inertials.urdf", ROOT / "urdf/planar_manipulator.urdf",
         ROOT / "urdf/planar_manipulator.xml", ROOT / "urdf/cart_pendulum.xml"]
DEADLINE = timedelta(seconds=5)
"""One example parses, loads in two engines and steps 500 times: a few 10 ms; 5 s means a hang."""
EXAMPLES = 1000 if os.environ.get("HYPOTHESIS_PROFILE") == "long" else 40
"""Per seed file: 40 in the default run (~1 s each file), 1000 with ``HYPOTHESIS_PROFILE=long``."""

NUMBER = re.compile(r'(?<=["\s])-?\d+(?:\.\d+)?(?:e-?\d+)?(?=["\s])')
ATTRIBUTE = re.compile(r'\s[a-z_]+="[^"]*"')
ELEMENT = re.compile(r"<([a-z_]+)\b[^>]*/>")

junk_number = st.one_of(
    st.sampled_from(["nan", "inf", "-inf", "1e999", "1,5", "0x1p3", "1_0", "", " ", "1.5kg", "--1", "1e", "."]),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.floats(-1e6, 1e6).map(lambda x: f"{x:.6g}"),
    st.text(max_size=8),
)


def _pick(pattern, text, data):
    matches = list(pattern.finditer(text))
    return data.draw(st.sampled_from(matches)) if matches else None


def mutate(text: str, data) -> str:
    kind = data.draw(st.sampled_from(["number", "number", "attribute", "element", "junk", "nest", "truncate"]))
    if kind == "number" and (m := _pick(NUMBER, text, data)):
        return text[:m.start()] + data.draw(junk_number).replace('"', "") + text[m.end():]
    if kind == "attribute" and (m := _pick(ATTRIBUTE, text, data)):
        return text[:m.start()] + text[m.end():]
    if kind == "element" and (m := _pick(ELEMENT, text, data)):
        return text[:m.start()] + text[m.end():]
    if kind == "nest":
        depth = data.draw(st.integers(1, 400))
        at = text.rfind("</") if "</" in text else len(text)
        return text[:at] + "<x>" * depth + "</x>" * depth + text[at:]
    if kind == "truncate":
        return text[: data.draw(st.integers(0, len(text)))]
    at = data.draw(st.integers(0, len(text)))
    return text[:at] + data.draw(st.text(max_size=12)) + text[at:]


@pytest.mark.parametrize("seed", SEEDS, ids=lambda p: p.name)
@settings(deadline=DEADLINE, max_examples=EXAMPLES, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                                       HealthCheck.too_slow])
@given(data=st.data())
def test_mutated_model_gives_a_report_or_one_clear_error(tmp_path, seed, data):
    text = seed.read_text()
    for _ in range(data.draw(st.integers(1, 3))):
        text = mutate(text, data)
    path = tmp_path / seed.name
    path.write_text(text, errors="surrogatepass")
    try:
        result = validate(path, states=2)
    except HarnessError as exc:
        message = str(exc)
        assert message and "\n" not in message and "Traceback" not in message
    else:  # accepted: a report; findings (the engines disagree on this model) are one line each
        assert isinstance(result, Validation) and result.lines()[-1] in ("valid", f"{len(result.findings)} finding(s)")
        assert all(f and "\n" not in f for f in result.findings)
