"""Bounds on the work one command may be asked to do, in one place, each with its reason.

Input beyond a bound is refused before any work with one line (:class:`~harness.errors.InputError` for a
command-line value, :class:`~harness.errors.ModelError` for a model file), exit 2. The bounds are far beyond
any lecture system or public robot description: they exist so that a small file or a typo cannot make a
command run for hours or take all memory.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import signal
import threading

# ------------------------------------------------------------------------------------------- model files
MODEL_BYTES = 8 * 2**20
"""Largest model file read (8 MiB): the largest public robot descriptions are a few hundred kB of XML."""

XML_DEPTH = 200
"""Deepest element nesting accepted. A URDF is flat (depth ≤ 5); an MJCF nests one ``<body>`` per link of a
chain. 200 is far beyond any robot, keeps the engines' recursive parsers away from stack exhaustion and
stays below libxml2's own limit (256)."""

INCLUDE_DEPTH = 16
"""MJCF ``<include>`` nesting depth followed by the checks."""

MAGNITUDE = 1e12
"""Largest magnitude of a geometric, inertial or force-element number (SI: kg, m, kg m², N/m, N s/m), in a
model file and in a ``--param``: beyond any mechanism, and products of a few such numbers stay far from
float64 overflow. A mass of 1.79e308 passes "finite" yet overflows every engine to NaN or Infinity."""

MJCF_ELEMENTS = 20_000
"""Most MJCF elements after ``<replicate>`` expansion (and counting the bodies a ``<composite>`` or
``<flexcomp>`` generates). The largest public MJCF models (humanoids, hands, MuJoCo Menagerie scenes) have a
few thousand; MuJoCo's compile time and memory grow with the count (a 300-byte file of nested
``<replicate count="1000">`` ran past 90 s at 2.8 GB before this bound)."""

REPLICATE_COPIES = 1_000
"""Most copies nested ``<replicate>`` elements make of one element (the product of their counts): an array
of a thousand bodies is a granular medium, not a mechanism to validate."""

HFIELD_CELLS = 1_000_000
"""Largest height field (``nrow * ncol``, 4 MB of float32): 1000 x 1000 samples; 200000² ended in MuJoCo's
"Caught an unknown exception!" after allocating for minutes."""

TEXTURE_PIXELS = 16 * 2**20
"""Largest texture MuJoCo may be asked to generate (width x height, six faces for a cube): 48 MB of RGB."""

MJCF_MEMORY_BYTES = 2**30
"""Largest ``<size memory=…>`` (MuJoCo's arena, allocated with every ``MjData``): 1 GiB."""

URDF_LINKS = 128
"""Most links (and joints) of a URDF: the 7-DoF arms and the humanoids of example-robot-data have 10 to 60.
Validation time grows with the cube of the count (500 links took 8.5 min)."""

MJCF_STEPS = 20_000
"""At most this many ``mj_step`` calls in ``harness validate`` (a model's own ``timestep`` below 50 µs
shortens the 1 s run): a file cannot make ``validate`` hang."""

COMPILE_SECONDS = 120
"""Wall-clock limit of loading and stepping an untrusted model in the engines (``harness validate``, run in a
child process): the largest accepted models load in a few seconds."""

COMPILE_MEMORY_BYTES = 4 * 2**30
"""Address-space limit of that child process (4 GiB): the engines and their libraries map about 1 GiB."""

# ------------------------------------------------------------------------------------------- command line
EXAMPLES = 10_000
"""Most hypothesis examples per system (``--examples``): five times the ``long`` profile (2000); a check of
one system at 10 000 examples already takes many minutes."""

STATES = 10_000
"""Most random states of the importer comparison (``--states``; default 20): each state is a few engine
calls per model, so 10 000 is minutes, not hours."""

JOBS = 256
"""Most parallel processes (``--jobs``, ``--workers``): each imports SymPy and both engines (~300 MB)."""

SCENE_HORIZON = 1_000.0
"""Longest scene horizon in seconds (a model's ``Scene(horizon=…)``): the lecture's scenes last at most a
few seconds; the reference integrates at 1e-13, so 1000 s is already hours."""


def bounded_int(low: int, high: int, reason: str):
    """An argparse ``type``: an integer in ``[low, high]``; anything else is a one-line error naming the
    bound and ``reason``."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"{value} must be at least {low}")
        if value > high:
            raise argparse.ArgumentTypeError(f"{value} exceeds the limit of {high} ({reason})")
        return value
    parse.__name__ = "integer"
    return parse


def check_magnitude(what: str, value: float) -> None:
    """A finite number not larger than :data:`MAGNITUDE` in size; ``ValueError`` naming ``what`` otherwise."""
    if not math.isfinite(value):
        raise ValueError(f"{what}={value!r}: must be a finite number")
    if abs(value) > MAGNITUDE:
        raise ValueError(f"{what}={value!r}: exceeds {MAGNITUDE:g} in magnitude (results would overflow)")


# ------------------------------------------------------------------------------------------- symbolic work
class OutOfTime(BaseException):
    """A CPU budget ran out (a BaseException: library code such as SymPy that catches ``Exception`` must not
    swallow it)."""


def _in_collector_callback(frame, depth: int = 3) -> bool:
    """Whether the interrupted ``frame`` (or one of its ``depth`` callers) is a callback of the garbage collector or
    of a weak reference (only the innermost frames: the budgeted work itself may run below such a module)."""
    for _ in range(depth):
        if frame is None:
            return False
        code = frame.f_code
        if code.co_name in ("gc_callback", "__del__") or code.co_filename.endswith(("weakref.py", "_weakrefset.py")):
            return True
        frame = frame.f_back
    return False


@contextlib.contextmanager
def cpu_budget(seconds: float):
    """Raises :class:`OutOfTime` inside the block after ``seconds`` of this process's CPU time (``ITIMER_VIRTUAL``:
    other processes on a loaded machine do not shorten it; main thread only, elsewhere the cascade runs its bounded
    steps without the expensive ones)."""
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "setitimer"):
        yield False
        return

    active = [True]

    def stop(signum, frame):
        # not inside a callback the garbage collector runs (a gc callback, a weak reference's or a finalizer): an
        # exception cannot propagate from there (Python prints "Exception ignored"); the timer repeats every 0.05 s
        if active[0] and not _in_collector_callback(frame):
            raise OutOfTime

    previous = signal.signal(signal.SIGVTALRM, stop)
    signal.setitimer(signal.ITIMER_VIRTUAL, seconds, 0.05)  # repeats: an interrupt swallowed elsewhere comes again
    try:
        yield True
    finally:
        while active[0]:  # an interrupt arriving here is retried until the handler is disarmed
            try:
                active[0] = False
            except OutOfTime:
                pass
        signal.setitimer(signal.ITIMER_VIRTUAL, 0)
        signal.signal(signal.SIGVTALRM, previous)
