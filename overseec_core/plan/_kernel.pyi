"""Type stub of the planner's C kernel (_kernel.c, built by setup.py); the C file documents each call."""

from typing import Any

import numpy as np

#: Most buckets in the bucket ring; beyond it the planner uses the radix heap.
MAX_RING: int
#: The slope model ids the kernel knows, by name (the planner's table: defaults.SLOPE_MODEL_IDS).
SLOPE_MODEL_IDS: dict[str, int]

def workspace() -> Any: ...  # an opaque capsule holding the priority queues
def workspace_bytes(workspace: Any, /) -> int: ...
def search(
    *,
    cost: np.ndarray,
    dist: np.ndarray,
    state: np.ndarray,
    workspace: Any,
    dx: float,
    dy: float,
    base: float,
    start: int,
    cancel: np.ndarray,
    bbox: np.ndarray,
    hscale: float = 0.0,
    width: float = 0.0,
    ring: int = 0,
    goal: int = -1,
    region: np.ndarray | None = None,
    region_k: int = 1,
    neighbours: int = 8,
    elevation: np.ndarray | None = None,
    slope_model: int = 0,
) -> tuple[int, float, int, int]: ...
def trace(state: np.ndarray, h: int, w: int, end: int, /) -> np.ndarray: ...
def reset(
    dist: np.ndarray, state: np.ndarray, h: int, w: int, bbox: np.ndarray, region: np.ndarray | None, region_k: int, /
) -> None: ...
def hop_bound(
    mu: np.ndarray,
    valid: np.ndarray,
    dist: np.ndarray,
    state: np.ndarray,
    workspace: Any,
    offsets: np.ndarray,
    lengths: np.ndarray,
    start: int,
    target: np.ndarray,
    /,
) -> float: ...
def expand_many(
    cost: np.ndarray,
    dist: np.ndarray,
    state: np.ndarray,
    workspace: Any,
    dx: float,
    dy: float,
    base: float,
    sources: np.ndarray,
    cancel: np.ndarray,
    bbox: np.ndarray,
    /,
) -> tuple[int, int]: ...
