"""Faults that must not lose or corrupt anything: a damaged derivation cache is detected and rebuilt (never
trusted), and an interrupted write leaves the previous file intact (temporary file, then rename)."""

import json
import os
import signal
import subprocess
import sys
import textwrap

import pytest
import sympy as sp

import models
from harness.derivation import cache
from harness.derivation.derive import derive
from harness.io import atomic_write_text


def _entry(tmp_path):
    (path,) = tmp_path.glob("pendulum-*.json")
    return path


@pytest.mark.parametrize("damage", ["truncated", "garbage", "edited entry", "edited checksum", "empty"])
def test_corrupted_derivation_cache_is_rebuilt_not_trusted(monkeypatch, tmp_path, damage):
    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path))
    system = models.get("pendulum")
    fresh = derive(system)
    assert not fresh.from_cache
    path = _entry(tmp_path)
    text = path.read_text()
    doc = json.loads(text)
    if damage == "truncated":
        path.write_text(text[: len(text) // 2])
    elif damage == "garbage":
        path.write_bytes(os.urandom(256))
    elif damage == "edited entry":  # valid JSON, a plausible expression: only the checksum tells
        doc["entries"]["M"] = sp.srepr(sp.Matrix([[2 * sp.Symbol("m")]]))
        path.write_text(json.dumps(doc))
    elif damage == "edited checksum":
        doc["sha256"] = "0" * 64
        path.write_text(json.dumps(doc))
    else:
        path.write_text("")
    assert cache.load(path.stem) is None and not path.exists()  # detected and discarded
    rebuilt = derive(system)
    assert not rebuilt.from_cache and rebuilt.M == fresh.M
    assert json.loads(_entry(tmp_path).read_text()) == json.loads(text)  # written again, intact
    assert derive(system).from_cache


class _Interrupted(Exception):
    pass


def test_interrupted_write_keeps_the_old_file(monkeypatch, tmp_path):
    target = tmp_path / "reports" / "importer.json"
    atomic_write_text(target, '{"old": true}\n')
    real_fdopen = os.fdopen

    class HalfWriter:
        def __init__(self, fh):
            self.fh = fh

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.fh.close()

        def write(self, data):
            self.fh.write(data[: len(data) // 2])
            self.fh.flush()
            raise _Interrupted("disk full half-way")

    monkeypatch.setattr(os, "fdopen", lambda fd, mode: HalfWriter(real_fdopen(fd, mode)))
    with pytest.raises(_Interrupted):
        atomic_write_text(target, json.dumps({"new": list(range(1000))}))
    assert target.read_text() == '{"old": true}\n'
    assert [p.name for p in target.parent.iterdir()] == ["importer.json"]  # the temporary file is removed


def test_killed_writer_keeps_the_old_file(tmp_path):
    """A process killed (SIGKILL, no clean-up) in the middle of writing: the old file is still whole; at most
    a hidden ``.importer.json.*.tmp`` is left behind."""
    target = tmp_path / "importer.json"
    atomic_write_text(target, '{"old": true}\n')
    child = textwrap.dedent(f"""
        import os, sys, time
        from harness import io
        real = os.fdopen
        class Slow:
            def __init__(self, fh): self.fh = fh
            def __enter__(self): return self
            def __exit__(self, *a): self.fh.close()
            def write(self, data):
                self.fh.write(data[: len(data) // 2]); self.fh.flush()
                print("half", flush=True); time.sleep(60)
        os.fdopen = lambda fd, mode: Slow(real(fd, mode))
        io.atomic_write_text({str(target)!r}, "x" * 100000)
    """)
    proc = subprocess.Popen([sys.executable, "-c", child], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "half"
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert target.read_text() == '{"old": true}\n'
    leftovers = [p.name for p in tmp_path.iterdir() if p.name != "importer.json"]
    assert all(n.startswith(".importer.json.") and n.endswith(".tmp") for n in leftovers) and len(leftovers) == 1
