"""The CI outputs of ``harness check``: ``--junit FILE`` (harness.report.junit) and ``--baseline OLD`` (what
changed, harness.report.baseline; written to ``changes.json``/``changes.md`` of ``--out``, shown on the
report's Changes page)."""

from __future__ import annotations


import sys
from pathlib import Path

from harness.errors import InputError


def prepare(junit: str | None, baseline: str | None) -> dict | None:
    """Validate the flags before any work (bad input: one line, no partial file); the baseline document."""
    if junit is not None and Path(junit).is_dir():
        raise InputError(f"--junit {junit}: is a folder, give a file name")
    if junit is not None:  # its folder writable before the work: not a check run whose results then cannot be kept
        from harness.io import writable_folder

        writable_folder(Path(junit).parent, "--junit")
    if baseline is None:
        return None
    from harness.report.baseline import load_baseline

    return load_baseline(baseline)


def finish(records: list[dict], seconds: dict, *, junit: str | None, baseline: dict | None,
           baseline_path: str | None, out: str | None, stream=None) -> dict | None:
    """Write the JUnit file, print (to ``stream``, default stdout) and write the changes since the baseline;
    returns the changes."""
    from harness.io import atomic_write_text

    if junit is not None:
        from harness.report.junit import junit_xml

        atomic_write_text(junit, junit_xml(records, seconds))
        print(f"wrote {junit}", file=sys.stderr)
    if baseline is None:
        return None
    from harness.report import baseline as changes_of
    from harness.report.results import dumps

    changes = changes_of.compare(baseline, records)
    text = changes_of.lines(changes)
    stream = stream or sys.stdout
    print(f"changes since {baseline_path}:" if text else f"nothing changed since {baseline_path}", file=stream)
    for line in text:
        print(f"  {line}", file=stream)
    if out:
        atomic_write_text(Path(out) / "changes.json", dumps({"baseline": str(baseline_path), **changes}))
        atomic_write_text(Path(out) / "changes.md", changes_of.markdown(changes, str(baseline_path)))
    return changes
