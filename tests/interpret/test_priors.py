"""Common-sense priors: the table, the merge rules, replacing and switching them off."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import rasterio

from overseec_core.cli import main
from overseec_core.costlang.scale import NEUTRAL, OBSTACLE_LEVEL, is_obstacle
from overseec_core.errors import InputError
from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.offline import interpret_offline
from overseec_core.interpret.priors import BUILT_IN, NONE, load_priors, parse_priors, resolve_priors
from overseec_core.synthesize.fit import fit_program

REPO = Path(__file__).resolve().parents[2]
SAMPLE = REPO / "resources" / "sample"
HEADLINE = "Prefer the roads and trails, grass should be fine, try to avoid the baseball field as much as possible"


def levels(prompt: str, priors=None) -> dict:
    return {p.entity: p for p in interpret_offline(prompt, priors=priors).preferences}


def test_the_schemas_neutral_level_is_the_scales():
    from overseec_core.schema import NEUTRAL_LEVEL

    assert NEUTRAL_LEVEL == NEUTRAL == lx.NEUTRAL


def test_the_built_in_table_orders_hazards_as_the_paper_does():
    by = {p.entity: p for p in BUILT_IN.priors}
    assert by["tree"].level < by["railway"].level < by["building"].level == by["water"].level == OBSTACLE_LEVEL
    assert all(NEUTRAL < p.level <= 1.0 and not p.lethal for p in BUILT_IN.priors)
    # stated avoid tiers stay below the priors of the physical hazards: a field is not a house
    assert lx.TOLERABLE < lx.AVOID < lx.STRONG_AVOID < by["tree"].level


@pytest.mark.parametrize(
    "name, prior",
    [("lake", "water"), ("house", "building"), ("woods", "tree"), ("forest", "tree"), ("railroad", "railway")],
)
def test_entities_take_their_own_or_their_ancestors_prior(name, prior):
    assert BUILT_IN.for_name(name).entity == prior


@pytest.mark.parametrize("name", ["vegetation", "grass", "road", "sand", "baseball field"])
def test_non_hazards_have_no_prior(name):
    assert BUILT_IN.for_name(name) is None


def test_the_headline_prompt_ranks_as_the_paper_does():
    p = levels(HEADLINE)
    ranks = {n: x.rank for n, x in p.items()}
    assert [ranks[n] for n in ("road", "trail", "grass", "baseball field", "tree", "building")] == [1, 1, 2, 3, 4, 5]
    assert (p["tree"].band, p["building"].band, p["water"].band) == ("prior", "prior", "prior")
    assert is_obstacle(p["building"]) and is_obstacle(p["water"]) and not is_obstacle(p["baseball field"])


@pytest.mark.parametrize(
    "prompt, entity, band, level",
    [
        ("avoid the buildings", "building", "avoided", 1.0),  # never below the prior
        ("avoid the trees", "tree", "avoided", 0.85),
        ("prefer the trees", "tree", "preferred", 0.0),  # prefer goes below neutral
        ("the trees are fine", "tree", "neutral", NEUTRAL),  # permission: neutral
        ("you can wade through the water", "water", "neutral", NEUTRAL),
        ("trees are a last resort", "tree", "avoided", lx.LAST_RESORT),  # a last resort stands
        ("the river is off limits", "river", "lethal", 1.0),
        ("avoid the railway", "railway", "avoided", 0.9),
    ],
)
def test_merge_rules(prompt, entity, band, level):
    p = levels(prompt)[entity]
    assert (p.band, p.weight, p.prior) == (band, pytest.approx(level), False)


def test_an_avoid_lifted_to_its_prior_says_so():
    notes = interpret_offline("avoid the buildings").notes
    assert any("'building': avoided, and kept at its prior" in n for n in notes)


def test_no_priors_leaves_the_unsaid_neutral():
    p = levels(HEADLINE, priors=NONE)
    assert all(not x.prior for x in p.values())
    assert (p["building"].weight, p["water"].weight, p["tree"].weight) == (NEUTRAL, NEUTRAL, NEUTRAL)


def test_a_replaced_table_is_used_and_avoid_still_never_lowers():
    table = parse_priors({"building": 0.9, "sand": "obstacle", "water": "lethal"}, "mine.json")
    p = levels("avoid the buildings and the sand, prefer the road", priors=table)
    assert p["building"].weight == pytest.approx(0.9) and p["sand"].weight == 1.0 and is_obstacle(p["sand"])
    assert p["water"].lethal and p["water"].band == "lethal" and p["tree"].weight == NEUTRAL


@pytest.mark.parametrize(
    "data, fragment",
    [
        ([1, 2], "must be a JSON object"),
        ({"building": 0.5}, "priors lie in the avoided band"),
        ({"building": 1.5}, "priors lie in the avoided band"),
        ({"building": "high"}, 'must be a level in (0.5, 1], "obstacle" or "lethal"'),
        ({"building": True}, "must be a level"),
        ({"building": float("nan")}, "must be a level"),
        ({" ": 0.9}, "an entity name is empty"),
    ],
)
def test_bad_prior_tables_are_one_line_input_errors(data, fragment):
    with pytest.raises(InputError) as info:
        parse_priors(data, "p.json")
    assert fragment in str(info.value) and "\n" not in str(info.value)


def test_priors_files_and_switches(tmp_path):
    path = tmp_path / "p.json"
    path.write_text('{"Tree": 0.6}')
    assert [(p.entity, p.level) for p in load_priors(path).priors] == [("tree", 0.6)]
    assert resolve_priors(None) is BUILT_IN and resolve_priors(None, enabled=False) is NONE
    with pytest.raises(InputError, match="contradict"):
        resolve_priors(path, enabled=False)
    path.write_text("{not json")
    with pytest.raises(InputError, match="not JSON"):
        load_priors(path)


def test_layers_no_entity_stands_for_take_their_priors_and_trees_never_price_vegetation():
    fitted = fit_program(interpret_offline(HEADLINE), ["road", "vegetation", "building", "water", "railway"])
    assert any("at their priors: railway 0.9" in n for n in fitted.notes)
    assert '0.4 * P["railway"]' in fitted.text  # 0.9 - neutral
    assert '"vegetation"' not in fitted.text.split("acc = ")[1]  # grass is fine; the tree prior stays on trees
    assert 'keep_out = OR(M["building"], M["water"])' in fitted.text


def test_a_vegetation_layer_is_not_priced_as_trees_when_the_prompt_is_silent_about_it():
    """trees' prior belongs to trees: a broader ``vegetation`` layer (grass, bushes, crops) stays
    neutral when the prompt says nothing of it."""
    fitted = fit_program(interpret_offline("prefer the roads"), ["road", "vegetation"])
    assert '"vegetation"' not in fitted.text


def _costmap(tmp_path: Path, *extra: str) -> tuple[np.ndarray, np.ndarray, dict]:
    tmp_path.mkdir(exist_ok=True)
    out = tmp_path / "costmap.tif"
    args = ["-q", "costmap", "--labels", str(SAMPLE / "sample_labels.tif"), "--classes", str(SAMPLE / "classes.json")]
    assert main([*args, "--prompt", "avoid the baseball field", *extra, "--out", str(out)]) == 0
    with rasterio.open(out) as ds:
        cost = ds.read(1)
    with rasterio.open(tmp_path / "lethal.tif") as ds:
        flags = ds.read(1)
    return cost, flags, json.loads((tmp_path / "manifest.json").read_text())


def _labels() -> np.ndarray:
    with rasterio.open(SAMPLE / "sample_labels.tif") as ds:
        return ds.read(1)


def test_cli_priors_default_file_and_off(tmp_path):
    building = _labels() == 6  # classes.json: 6 building
    cost, flags, manifest = _costmap(tmp_path / "a")
    assert np.all(cost[building] == 1.0) and np.all(flags[building] == 2)  # an obstacle: keep-out
    assert manifest["parameters"]["costmap"]["priors"]["source"] == "built-in"
    cost, flags, manifest = _costmap(tmp_path / "b", "--no-priors")
    assert np.all(cost[building] == NEUTRAL) and not flags[building].any()
    table = tmp_path / "priors.json"
    table.write_text('{"building": 0.9}')
    cost, flags, manifest = _costmap(tmp_path / "c", "--priors", str(table))
    assert np.allclose(cost[building], 0.9) and not flags[building].any()
    assert manifest["parameters"]["costmap"]["priors"]["priors"][0]["entity"] == "building"


def test_cli_refuses_both_switches_and_bad_files(tmp_path, capsys):
    table = tmp_path / "priors.json"
    table.write_text('{"building": 2}')
    base = ["-q", "costmap", "--labels", str(SAMPLE / "sample_labels.tif"), "--classes", str(SAMPLE / "classes.json")]
    out = ["--prompt", "avoid the field", "--out", str(tmp_path / "c.tif")]
    with pytest.raises(SystemExit) as info:
        main([*base, *out, "--priors", str(table), "--no-priors"])
    assert info.value.code == 2
    capsys.readouterr()
    assert main([*base, *out, "--priors", str(table)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "priors lie in the avoided band" in err[0]
    assert not (tmp_path / "c.tif").exists()
