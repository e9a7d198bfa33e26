"""File output that never leaves a half-written file: write a temporary file, then rename.

A destination is checked before the work (:func:`writable_folder`: a folder we can create files in, or one
we can create), and a failure while writing (a full disk, a file size limit, a folder removed meanwhile) is
one :class:`~harness.errors.OutputError` line; the temporary file is removed and the old file, if any, kept.
"""

from __future__ import annotations

import errno
import os
import tempfile
from pathlib import Path

from harness.errors import InputError, OutputError


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _why(exc: OSError) -> str:
    return exc.strerror or errno.errorcode.get(exc.errno or 0, type(exc).__name__)


def existing_folder(path: Path | str, what: str) -> Path:
    """``path`` if it is a folder that exists (one a command reads from); else one :class:`InputError` line naming
    ``what`` (the option or variable): ``no such folder`` or ``is not a folder``."""
    path = Path(path)
    if not path.is_dir():
        raise InputError(f"{what} {path}: " + ("is not a folder" if path.exists() else "no such folder"))
    return path


def writable_folder(path: Path | str, what: str = "--out") -> Path:
    """``path`` if it is a folder we can write files into, or could be created as one; else one
    :class:`OutputError` line naming ``what`` (the option or variable). Nothing is created: the nearest
    existing ancestor is probed with a temporary file that is removed at once."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise OutputError(f"{what} {path}: exists and is not a folder")
    probe = path
    while not probe.exists():
        if probe.parent == probe:
            break
        probe = probe.parent
    if not probe.is_dir():
        raise OutputError(f"{what} {path}: {probe} is not a folder")
    try:
        fd, tmp = tempfile.mkstemp(prefix=".write-probe.", dir=probe)
        os.close(fd)
        os.unlink(tmp)
    except OSError as exc:
        raise OutputError(f"{what} {path}: cannot write into {probe}: {_why(exc)}") from None
    return path


def atomic_write_bytes(path: Path | str, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically, with the permissions a plain ``open`` would give (``mkstemp``
    creates 0600, which a web server could not serve). An ``OSError`` becomes one :class:`OutputError` line."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise OutputError(f"{path}: cannot write: {_why(exc)}") from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise OutputError(f"{path}: cannot write: {_why(exc)}; the file was left as it was") from None
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def atomic_write_text(path: Path | str, text: str) -> None:
    atomic_write_bytes(path, text.encode())
