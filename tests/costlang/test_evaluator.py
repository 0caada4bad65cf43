"""What programs compute: operator semantics on small hand-checkable grids (metres, non-square pixels)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from overseec_core.costlang import check_program, evaluate_program

ENTITIES = ("road", "grass", "water", "building")


def run(text: str, masks: dict, probs: dict | None = None, sampling=(1.0, 1.0), shape=None):
    program = check_program(text, ENTITIES)
    return evaluate_program(program, masks, probs, sampling=sampling, shape=shape)


def empty(shape=(11, 11)) -> np.ndarray:
    return np.zeros(shape, dtype=bool)


def point(shape=(11, 11), at=(5, 5)) -> np.ndarray:
    m = empty(shape)
    m[at] = True
    return m


def test_distance_is_in_metres_with_non_square_pixels_and_saturates():
    masks = {"road": point()}
    # sampling is (y, x): rows 2 m apart, columns 1 m apart
    cost = run('d = distance(M["road"], 4.5)\ncost = d / 4.5', masks, sampling=(2.0, 1.0)).cost
    d = cost * 4.5
    assert d[5, 5] == 0.0
    assert d[5, 8] == pytest.approx(3.0)  # 3 columns
    assert d[6, 5] == pytest.approx(2.0)  # 1 row
    assert d[6, 7] == pytest.approx(math.hypot(2.0, 2.0), rel=1e-6)
    assert d[7, 5] == pytest.approx(4.0)
    assert d[8, 5] == pytest.approx(4.5)  # 6 m, saturated at the cap
    assert d[0, 0] == pytest.approx(4.5)


def test_distance_default_cap_is_100_m_and_empty_masks_are_far():
    masks = {"road": empty((5, 5))}
    cost = run('cost = distance(M["road"]) / 100', masks).cost
    assert np.all(cost == 1.0)


def test_near_far_include_exclude_the_exact_radius():
    masks = {"road": point()}
    near = run('cost = 1.0 * near(M["road"], 3)', masks).cost
    far = run('cost = 1.0 * far(M["road"], 3)', masks).cost
    assert near[5, 8] == 1.0 and near[5, 9] == 0.0 and near[8, 5] == 1.0
    assert near[7, 7] == 1.0 and near[8, 8] == 0.0  # 2.83 m in, 4.24 m out
    assert np.array_equal(near + far, np.ones_like(near))


def test_borders_keeps_pixels_of_a_near_b():
    grass = np.zeros((5, 8), bool)
    grass[:, :4] = True
    water = np.zeros((5, 8), bool)
    water[:, 6:] = True
    out = run('cost = 1.0 * borders(M["grass"], M["water"], 3)', {"grass": grass, "water": water}).cost
    assert out[:, 3].all() and out[:, 4:].sum() == 0 and out[:, :3].sum() == 0


def test_inside_erodes_by_metres():
    grass = np.zeros((9, 9), bool)
    grass[1:8, 1:8] = True
    out = run('cost = 1.0 * inside(M["grass"], 2)', {"grass": grass}).cost
    expected = np.zeros((9, 9))
    expected[2:7, 2:7] = 1.0  # 2 m or more from the nearest non-grass pixel
    assert np.array_equal(out, expected)


def road_band(shape=(11, 15), rows=(3, 8)) -> np.ndarray:
    m = np.zeros(shape, bool)
    m[rows[0] : rows[1]] = True
    return m


def test_centre_is_zero_on_the_centre_line_and_rises_to_the_border():
    c = run('cost = centre(M["road"], 10)', {"road": road_band()}).cost
    col = c[:, 7]
    assert col[5] == 0.0
    assert col[4] == pytest.approx(1 / 3) and col[6] == pytest.approx(1 / 3)
    assert col[3] == pytest.approx(2 / 3) and col[7] == pytest.approx(2 / 3)
    assert np.all(col[:3] == 1.0) and np.all(col[8:] == 1.0)
    assert np.allclose(c[3:8], c[3:8, :1])  # the road leaves the image: no border at the sides


def test_edge_is_low_on_the_borders_and_one_on_the_centre_line():
    e = run('cost = edge(M["road"], 10)', {"road": road_band()}).cost
    col = e[:, 7]
    assert col[3] == pytest.approx(1 / 3) and col[7] == pytest.approx(1 / 3)
    assert col[4] == pytest.approx(2 / 3) and col[5] == 1.0
    assert np.all(col[:3] == 1.0)


def test_centre_adapts_to_the_local_width_of_roads_narrower_than_the_width():
    road = np.zeros((20, 20), bool)
    road[2:5] = True  # 3 px wide
    road[10:17] = True  # 7 px wide
    c = run('cost = centre(M["road"], 20)', {"road": road}).cost
    assert c[3, 10] == 0.0 and c[13, 10] == 0.0
    assert c[2, 10] > 0 and c[10, 10] > 0


def test_p_is_gated_by_the_mask_and_defaults_to_the_mask():
    road = point((3, 3), (1, 1))
    prob = np.full((3, 3), 0.8)
    gated = run('cost = P["road"]', {"road": road}, {"road": prob}).cost
    assert gated[1, 1] == pytest.approx(0.8) and gated.sum() == pytest.approx(0.8)
    ungated = run('cost = P["road"]', {"road": road}).cost
    assert ungated[1, 1] == 1.0 and ungated.sum() == 1.0


def test_cost_is_clipped_and_lethal_pixels_cost_one():
    road = point((3, 3), (0, 0))
    water = point((3, 3), (2, 2))
    r = run('cost = 2 * M["road"] - 0.5\nlethal = M["water"]', {"road": road, "water": water})
    assert r.cost[0, 0] == 1.0 and r.cost[1, 1] == 0.0 and r.cost[2, 2] == 1.0
    assert r.lethal.sum() == 1 and r.lethal[2, 2]
    assert r.cost.dtype == np.float64 and r.lethal.dtype == bool


def test_scalar_programs_broadcast_to_the_block():
    r = run("cost = 0.25", {}, shape=(4, 6))
    assert r.cost.shape == (4, 6) and np.all(r.cost == 0.25) and not r.lethal.any()
    r = run("cost = 0.25\nlethal = True", {}, shape=(2, 2))
    assert r.lethal.all() and np.all(r.cost == 1.0)


def test_logic_comparisons_and_conditionals():
    road = np.array([[True, False], [True, False]])
    grass = np.array([[True, True], [False, False]])
    probs = {"grass": np.array([[0.2, 0.9], [0.5, 0.5]])}
    text = (
        'a = M["road"] & ~M["grass"]\nb = M["road"] and not M["grass"]\n'
        'c = AND(a, b) | REMOVE(M["grass"], M["road"])\n'
        'd = 0.1 < P["grass"] <= 0.5\n'
        "cost = (0.3 if c else 0.7) + 0.1 * d"
    )
    cost = run(text, {"road": road, "grass": grass}, probs).cost
    assert np.allclose(cost, [[0.8, 0.3], [0.3, 0.7]])


def test_normalize_uses_the_static_range_not_the_data():
    road = point((3, 3), (1, 1))
    probs = {"road": np.full((3, 3), 0.5)}
    cost = run('cost = normalize(2 * P["road"] + 1)', {"road": road}, probs).cost
    # static range of 2P+1 is [1, 3]; the pixel value 2 maps to 0.5, the rest (1) to 0
    assert cost[1, 1] == 0.5 and cost[0, 0] == 0.0
    cost = run('cost = normalize(P["road"], 0.25, 0.75)', {"road": road}, probs).cost
    assert cost[1, 1] == 0.5


def test_min_max_sum_abs_sqrt_exp_clip_and_powers():
    road = np.array([[True, False]])
    text = (
        'x = 0.64 * M["road"]\n'
        "a = min(x, 0.5, 1)\nb = max(x, 0.1)\nc = sum(x, x, 0.1)\nd = abs(x - 1)\n"
        "e = sqrt(x)\nf = exp(-x)\ng = clip(x, 0.2, 0.3)\nh = (x + 1) ** -2\n"
        "cost = a"
    )
    program = check_program(text, ENTITIES)
    from overseec_core.costlang.evaluator import _Block

    block = _Block({"road": road}, None, (1.0, 1.0))
    for s in program.statements:
        block.env[s.target] = block.value(s.value)
    env = block.env
    assert np.allclose(env["a"], [[0.5, 0]])
    assert np.allclose(env["b"], [[0.64, 0.1]])
    assert np.allclose(env["c"], [[1.38, 0.1]])
    assert np.allclose(env["d"], [[0.36, 1.0]])
    assert np.allclose(env["e"], [[0.8, 0.0]])
    assert np.allclose(env["f"], [[math.exp(-0.64), 1.0]])
    assert np.allclose(env["g"], [[0.3, 0.2]])
    assert np.allclose(env["h"], [[1 / 1.64**2, 1.0]])


def test_missing_layer_is_a_cost_program_error():
    from overseec_core.errors import CostProgramError

    with pytest.raises(CostProgramError, match="no mask for entity 'grass'"):
        run('cost = M["grass"] * 1.0', {"road": empty((2, 2))}, shape=(2, 2))
