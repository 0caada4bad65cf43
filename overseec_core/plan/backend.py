"""Which planner this environment plans with: the compiled kernel, or scikit-image's fallback.

The kernel (``_kernel.c``) is optional: where it was not compiled (no compiler when pip built the
sdist) or does not load, a :class:`~overseec_core.plan.planner.Planner` plans with scikit-image's
``MCP_Geometric`` instead (:mod:`.fallback`: the same step rule and path costs, several times
slower, fast mode = exact), and every result says so in its notes. :func:`planner_backend` tells
which one this environment uses; ``OVERSEEC_PLANNER=fallback`` forces the fallback (tests),
``=kernel`` refuses to plan without the kernel.
"""

from __future__ import annotations

import importlib.util
import os
from dataclasses import dataclass

from overseec_core import defaults, install
from overseec_core.errors import InputError, PlanError
from overseec_core.plan import fallback

try:
    from overseec_core.plan import _kernel

    KERNEL_ERROR: str | None = None
except Exception as exc:  # not compiled (no compiler at install time), or built for another NumPy ABI
    _kernel = None  # type: ignore[assignment]
    KERNEL_ERROR = " ".join(f"{type(exc).__name__}: {exc}".split())[:300]
if _kernel is not None and getattr(_kernel, "SLOPE_MODEL_IDS", None) != defaults.SLOPE_MODEL_IDS:
    # a kernel compiled from another version of _kernel.c: its slope model ids are not the table's
    _kernel = None  # type: ignore[assignment]
    KERNEL_ERROR = "the compiled kernel is out of date (its slope models differ from this version's); reinstall"

#: Which planner to use: "auto" (default: the compiled kernel when it loads, else the fallback),
#: "kernel" (the kernel, or an error saying why not) or "fallback" (scikit-image, even with a kernel).
PLANNER_ENV = "OVERSEEC_PLANNER"
PLANNER_CHOICES = ("auto", "kernel", "fallback")


@dataclass(frozen=True)
class PlannerBackend:
    """Which planner this environment plans with, and why.

    ``name`` is 'kernel' (the compiled kernel) or 'fallback' (scikit-image's MCP_Geometric);
    ``reason`` says why the fallback is used and how to get the kernel ("" with the kernel);
    ``kernel_file`` is the compiled module's path when one is installed (loaded or not),
    ``kernel_error`` why it did not load.
    """

    name: str
    reason: str = ""
    kernel_file: str | None = None
    kernel_error: str | None = None
    #: True when OVERSEEC_PLANNER chose it.
    forced: bool = False

    @property
    def note(self) -> str:
        """The note a result planned by this backend carries ("" for the kernel)."""
        if self.name == "kernel":
            return ""
        return fallback.NOTE.format(slowdown=fallback.SLOWDOWN, reason=self.reason)

    def describe(self) -> str:
        """One line for ``overseec doctor`` and the plugin's environment check."""
        if self.name == "kernel":
            return f"compiled kernel ({self.kernel_file})"
        return f"fallback (scikit-image MCP_Geometric, {fallback.SLOWDOWN} slower): {self.reason}"

    def to_json(self) -> dict:
        """The backend as plain JSON types (``overseec doctor --json``)."""
        return {
            "planner": self.name,
            "reason": self.reason,
            "kernel_file": self.kernel_file,
            "kernel_error": self.kernel_error,
            "forced": self.forced,
        }


def planner_backend(choice: str | None = None) -> PlannerBackend:
    """The planner a :class:`Planner` made now would use: ``choice`` ('auto', 'kernel' or
    'fallback'), by default ``OVERSEEC_PLANNER`` (read at each call; unset = 'auto').

    Raises :class:`InputError` for an unknown choice and :class:`PlanError` when it asks for the
    kernel and there is none that loads."""
    from_env = choice is None
    if choice is None:
        choice = os.environ.get(PLANNER_ENV, "").strip().lower() or "auto"
    if choice not in PLANNER_CHOICES:
        where = f"{PLANNER_ENV}={choice!r}" if from_env else f"planner {choice!r}"
        raise InputError(f"{where}: use one of {', '.join(PLANNER_CHOICES)}")
    if _kernel is not None:
        kernel_file: str | None = getattr(_kernel, "__file__", None)
    else:
        try:
            spec = importlib.util.find_spec(f"{__package__}._kernel")
        except (ImportError, ValueError):
            spec = None
        kernel_file = spec.origin if spec is not None else None
    asked = f"{PLANNER_ENV}={choice}" if from_env else f"planner={choice!r}"
    if choice == "fallback":
        return PlannerBackend("fallback", f"{asked} asks for it", kernel_file, KERNEL_ERROR, forced=True)
    if _kernel is not None:
        return PlannerBackend("kernel", "", kernel_file, None, forced=choice == "kernel")
    how = install.detect()
    if kernel_file is None:
        reason = f"the compiled kernel is not installed (no C compiler when overseec was built?); {how.kernel_advice()}"
    else:
        reason = f"the compiled kernel {kernel_file} does not load ({KERNEL_ERROR}); {how.reinstall_advice()}"
    if choice == "kernel":
        raise PlanError(f"{asked}, but {reason}")
    return PlannerBackend("fallback", reason, kernel_file, KERNEL_ERROR)
