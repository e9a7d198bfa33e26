"""Errors the harness reports to a user as one clear line (the CLI prints them without a traceback), and
:class:`NotApplicable`, which a caller reports as a note."""


class HarnessError(Exception):
    """Base class: a problem with the user's input or a model, stated in one line."""


class ModelError(HarnessError):
    """A modeling mistake or a non-physical parameter (names the field and the fix)."""


class InputError(HarnessError):
    """Bad command-line input: unknown system, engine or parameter; a vector of the wrong length."""


class ExportError(HarnessError):
    """A URDF/MJCF that cannot be written or read back faithfully."""


class EngineError(HarnessError):
    """An engine refused a model or produced non-finite numbers."""


class OutputError(HarnessError):
    """A destination that cannot be written (not a folder, no permission, a full disk)."""


class NotApplicable(ValueError):
    """A source or method that does not apply to a system or scene (MuJoCo's own integrator through a map that is not
    affine, MuJoCo's own run of a motion with events, a pruning that leaves the same model): raised where that is
    found, and reported by the one caller that asks (a note, a skipped run) with this message. Only this is caught
    there: any other error, a ``ValueError`` of a bug among them, is a failure, not a skip (a wrong unpacking in the
    loads' code had read "skipped: not enough values to unpack" in the pruning bench)."""
