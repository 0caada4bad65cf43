"""Errors raised by overseec.

One root, :class:`OverseecError`, so callers (CLI, QGIS task, Processing) can tell a user mistake
or an environment problem from a bug. Each subclass also inherits the builtin it resembles, as
rasterio's errors do, so generic handlers keep working. Messages are one line and say what to
change: the CLI prints them as they are, without a traceback.
"""

from __future__ import annotations


class OverseecError(Exception):
    """Root of every error overseec raises on purpose."""


class InputError(OverseecError, ValueError):
    """A user-supplied argument or file is unusable (bad value, missing file, wrong kind)."""


class RasterError(OverseecError, OSError):
    """A raster cannot be opened or read: not a raster, corrupt, no CRS, unsupported bands."""


class OutputError(OverseecError, OSError):
    """An output cannot be written: not writable, would overwrite an input, disk full."""


class TilingError(OverseecError, ValueError):
    """Invalid tile geometry (tile size, overlap) or a model returned maps of the wrong shape."""


class ModelError(OverseecError, RuntimeError):
    """A model cannot be loaded or run (missing weights, unsupported type, unknown device)."""


class InterpretError(OverseecError, ValueError):
    """A mission prompt cannot be turned into entities and preferences."""


class LLMError(OverseecError, RuntimeError):
    """The LLM endpoint failed: unreachable, timed out, HTTP error or unusable reply."""


class CostProgramError(OverseecError, ValueError):
    """A cost program is invalid; carries the 1-based line and 0-based column of the problem."""

    def __init__(self, message: str, line: int | None = None, col: int | None = None):
        self.message = message
        self.line = line
        self.col = col
        where = f"line {line}, column {col}: " if line is not None else ""
        super().__init__(f"{where}{message}")


class PlanError(OverseecError, ValueError):
    """No path can be planned: point outside the raster, on a lethal cell, or unreachable."""


class EvaluateError(OverseecError, ValueError):
    """Evaluation inputs are inconsistent (grids differ, unknown class, no reference paths)."""


class Cancelled(OverseecError):
    """The user cancelled a running job; partial outputs were discarded."""
