"""Which planner this environment plans with: the compiled kernel, or scikit-image's fallback.

The kernel (``_kernel.c``) is optional: where it was not compiled (no compiler when pip built the
sdist) or does not load, a :class:`~overseec_core.plan.planner.Planner` plans with scikit-image's
``MCP_Geometric`` instead (:mod:`.fallback`: the same step rule and path costs, several times
slower, fast mode = exact), and every result says so in its notes. :func:`planner_backend` tells
which one this environment uses; ``OVERSEEC_PLANNER=fallback`` forces the fallback (tests),
``=kernel`` refuses to plan without the kernel.

What each backend can plan is checked here too (:func:`checked_neighbours`: 16 neighbours are the
kernel's; :func:`checked_terrain`: so is the slope model), with :func:`run_cancellable`, which runs
a kernel call a user may cancel, and :data:`UNVISITED`, the kernel's "not reached".
"""

from __future__ import annotations

import importlib.util
import os
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import TypeVar

import numpy as np

from overseec_core import defaults, install
from overseec_core.errors import InputError, PlanError
from overseec_core.plan import fallback
from overseec_core.plan.paths import check_slope_model
from overseec_core.progress import Progress

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
#: Steps a planner may take: 8 neighbours, or 16 (plus the knight moves (+-1, +-2), (+-2, +-1)).
NEIGHBOURS = defaults.PLAN_NEIGHBOURS
#: The float64 whose bytes are all 0x7F (~1.38e306): "not reached" in the distance buffer.
UNVISITED = float(np.frombuffer(b"\x7f" * 8, dtype=np.float64)[0])
_T = TypeVar("_T")


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


# ------------------------------------------------------------------------------------------------
# What each backend plans, and running its calls
# ------------------------------------------------------------------------------------------------


def check_neighbours(neighbours: object) -> int:
    """``neighbours`` as an int when it is one of :data:`NEIGHBOURS`, else a one-line InputError
    (options, worker requests and the planner check a value with this one rule)."""
    if isinstance(neighbours, bool) or neighbours not in NEIGHBOURS:
        raise InputError(f"neighbours must be 8 or 16, not {neighbours!r}")
    return int(neighbours)


def checked_neighbours(neighbours: int, backend: str) -> int:
    """``neighbours`` when the backend can plan with it: InputError unless 8 or 16, PlanError
    for 16 on the fallback (its one-line reason names the kernel)."""
    neighbours = check_neighbours(neighbours)
    if neighbours == 16 and backend == "fallback":
        raise PlanError(fallback.NO_KNIGHTS)
    return int(neighbours)


def checked_terrain(
    elevation: np.ndarray | None, slope_model: str | None, shape: tuple[int, int], backend: str
) -> tuple[np.ndarray | None, str | None]:
    """(flat float32 elevations, model name) for the anisotropic mode, or (None, None) without
    one: InputError for a model without elevations (or the reverse), an unknown model or a wrong
    shape; PlanError on the fallback (:data:`.fallback.NO_TERRAIN`)."""
    if elevation is None and slope_model is None:
        return None, None
    if elevation is None or slope_model is None:
        raise InputError("the slope model needs an elevation grid (--dem) and the DEM a slope model (--slope-model)")
    check_slope_model(slope_model)
    z = np.asarray(elevation)
    if z.shape != shape:
        raise InputError(
            f"the elevation grid is {z.shape}, the costmap {shape}: resample the DEM onto the costmap grid"
        )
    if backend == "fallback":
        raise PlanError(fallback.NO_TERRAIN)
    return np.ascontiguousarray(z, dtype=np.float32).ravel(), slope_model


def run_cancellable(
    call: Callable[[], _T],
    cancel: np.ndarray,
    progress: Progress | None,
    on_cancel: Callable[[], None] | None = None,
) -> _T:
    """Run a kernel call that polls the flag ``cancel[0]``: the flag is set from ``progress``
    first, and while the call runs a watcher thread sets it (then calls ``on_cancel``) once
    ``progress`` asks to cancel."""
    cancel[0] = 1 if progress is not None and progress.cancelled() else 0
    if progress is None or cancel[0]:
        return call()
    stop = threading.Event()

    def watch() -> None:
        while not stop.wait(0.05):
            if progress.cancelled():
                cancel[0] = 1
                if on_cancel is not None:
                    on_cancel()
                return

    watcher = threading.Thread(target=watch, name="overseec-plan-cancel", daemon=True)
    watcher.start()
    try:
        return call()
    finally:
        stop.set()
        watcher.join()
