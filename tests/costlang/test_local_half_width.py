"""centre()/edge()'s local half width: the fast kernel equals the step-by-step definition exactly,
and long kernels poll for a cancel between units of work (issue 13)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from overseec_core.costlang import check_program, evaluate_program, kernels
from overseec_core.costlang.kernels import (
    _footprint_radius,
    _inner_distance,
    centre_field,
    geodesic_dilation,
    local_half_width,
)
from overseec_core.errors import Cancelled


def reference_dilation(values: np.ndarray, mask: np.ndarray, steps: tuple[int, int]) -> np.ndarray:
    """The definition as it was first written: every one of the max(steps) full-array steps."""
    ry, rx = steps
    h = values
    for step in range(max(ry, rx)):
        size = (3 if step < ry else 1, 3 if step < rx else 1)
        h = np.where(mask, ndimage.maximum_filter(h, size=size, mode="constant", cval=0.0), 0.0)
    return h


def reference_centre(mask: np.ndarray, width: float, sampling: tuple[float, float], edge: bool = False) -> np.ndarray:
    """centre_field with the reference dilation (what costmaps were before the fast kernel)."""
    half = width / 2.0
    d = _inner_distance(mask, sampling, half)
    h = reference_dilation(d, mask, _footprint_radius(half, sampling))
    ratio = np.divide(d, h, out=np.zeros_like(d), where=h > 0)
    return np.where(mask, ratio if edge else 1.0 - ratio, 1.0)


def random_mask(seed: int, shape: tuple[int, int], density: float) -> np.ndarray:
    """Blobs, thin lines and single pixels: components of every size and shape."""
    rng = np.random.default_rng(seed)
    mask = ndimage.binary_dilation(rng.random(shape) < density / 10, iterations=int(rng.integers(0, 3)))
    for _ in range(int(rng.integers(0, 4))):  # thin winding lines: far from their peak
        r, c = rng.integers(0, shape[0]), rng.integers(0, shape[1])
        for _ in range(int(rng.integers(5, 60))):
            mask[r, c] = True
            r = int(np.clip(r + rng.integers(-1, 2), 0, shape[0] - 1))
            c = int(np.clip(c + rng.integers(-1, 2), 0, shape[1] - 1))
    return mask | (rng.random(shape) < density / 20)


def serpentine(height: int, width: int, blob: int = 40) -> np.ndarray:
    """A square blob (high distance to the outside) feeding a long 3-pixel winding corridor."""
    mask = np.zeros((height, width), bool)
    mask[:blob, :blob] = True
    for i, r in enumerate(range(blob + 2, height - 3, 6)):
        mask[r : r + 3, 2 : width - 2] = True
        c = slice(width - 5, width - 2) if i % 2 == 0 else slice(2, 5)
        if i:
            mask[r - 3 : r, c] = True  # joins this row to the one above
    mask[blob : blob + 2, 2:5] = True
    return mask


@settings(max_examples=120, deadline=None)
@given(
    seed=st.integers(0, 2**31),
    h=st.integers(1, 40),
    w=st.integers(1, 40),
    density=st.floats(0.05, 0.9),
    ry=st.integers(0, 12),
    rx=st.integers(0, 12),
)
def test_fast_kernel_equals_the_step_definition_exactly(seed, h, w, density, ry, rx):
    mask = random_mask(seed, (h, w), density)
    values = _inner_distance(mask, (1.0, 1.3), 6.0)
    expected = reference_dilation(values, mask, (ry, rx))
    assert np.array_equal(geodesic_dilation(values, mask, (ry, rx)), expected)
    with pytest.MonkeyPatch.context() as m:
        m.setattr(kernels, "LOOP_STEPS", 0)  # the component path even for few steps
        assert np.array_equal(local_half_width(values, mask, (ry, rx)), expected)


@pytest.mark.parametrize("sampling", [(0.1, 0.1), (0.1, 0.07), (0.05, 0.12)])
@pytest.mark.parametrize("width", [1.0, 5.0, 12.0])
def test_centre_and_edge_equal_the_reference_on_wide_and_winding_features(sampling, width):
    mask = serpentine(90, 70) | random_mask(7, (90, 70), 0.4)
    for edge in (False, True):
        assert np.array_equal(
            centre_field(mask, width, sampling, edge=edge), reference_centre(mask, width, sampling, edge=edge)
        )


def test_a_corridor_beyond_the_reach_of_its_peak_keeps_its_own_half_width():
    mask = serpentine(60, 60)
    values = _inner_distance(mask, (1.0, 1.0), 30.0)
    h = local_half_width(values, mask, (30, 30))
    assert h[0, 0] == values.max()  # the blob
    assert h[-5, 30] < values.max()  # far down the corridor
    assert np.array_equal(h, reference_dilation(values, mask, (30, 30)))


def test_empty_and_full_masks():
    for mask in (np.zeros((20, 30), bool), np.ones((20, 30), bool)):
        for width in (1.0, 40.0):
            assert np.array_equal(centre_field(mask, width, (0.5, 0.5)), reference_centre(mask, width, (0.5, 0.5)))


class CancelAfter:
    """A poll that raises Cancelled on its n-th call (and counts the calls)."""

    def __init__(self, n: int) -> None:
        self.n, self.calls = n, 0

    def __call__(self) -> None:
        self.calls += 1
        if self.calls >= self.n:
            raise Cancelled("cancelled")


@pytest.mark.parametrize("loop_steps", [0, 10**6])
def test_long_kernels_poll_between_steps(loop_steps, monkeypatch):
    monkeypatch.setattr(kernels, "LOOP_STEPS", loop_steps)
    mask = serpentine(200, 200)
    program = check_program('cost = centre(M["road"], 40)', ["road"])
    counter = CancelAfter(10**9)
    evaluate_program(program, {"road": mask}, sampling=(0.1, 0.1), poll=counter)
    assert counter.calls > 20  # within the one centre() call, not only before it
    with pytest.raises(Cancelled):
        evaluate_program(program, {"road": mask}, sampling=(0.1, 0.1), poll=CancelAfter(counter.calls // 2))


def test_the_evaluator_polls_before_every_operation():
    program = check_program('a = M["road"] * 0.5\nb = a + 1\ncost = min(b, 1)', ["road"])
    counter = CancelAfter(10**9)
    evaluate_program(program, {"road": np.ones((4, 4), bool)}, poll=counter)
    assert counter.calls == 3
    with pytest.raises(Cancelled):
        evaluate_program(program, {"road": np.ones((4, 4), bool)}, poll=CancelAfter(2))
