"""Errors the harness reports to a user as one clear line (the CLI prints them without a traceback)."""


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
