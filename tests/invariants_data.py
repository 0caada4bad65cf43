"""Data for tests/test_invariants.py: scenes, fixed start/goal pixels, prompt pairs, RRPI ranks.

Every case is a pair of prompts and the effect prompt A must have on the planned route compared
with prompt B, measured between one fixed pair of pixels of one scene:

- ``less_on`` / ``more_on``: the share of route length (ground metres) on the class is strictly
  lower / higher under A than under B (B is the baseline; its route must touch the class for
  ``less_on``, and leave some of it unused for ``more_on``);
- ``zero_on``: A's route has no length on the class (B's route must touch it);
- ``min_distance>=N or warn``: A's route stays at least N m from the class, or, when no route
  can (checked: the strict plan has none), the result carries the "cannot be met" note;
  B's route comes closer than N m (else the case proves nothing);
- ``max_distance<=N or warn``: A's route stays within N m of the class, or warns as above;
- ``farther``: A's closest approach to the class is strictly farther than B's;
- ``closer``: A's mean distance (per metre of route) to the class is strictly lower than B's;
- ``moves``: the symmetric Hausdorff distance between the two routes is > 0.

Points are (row, col) pixels of the class raster, chosen so that the comparison means something
(usually the straight line between them crosses or runs along the class in question).

Baselines and priors: a class with a common-sense prior (buildings, water, trees, railways:
``interpret.priors``) is avoided even when the prompt is silent about it, so a case that measures
what "avoid X" does to such a class takes a baseline that allows X ("you can wade through the
water", "the buildings are fine"): silence is no longer indifference.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
SCENES = Path(os.environ.get("OVERSEEC_SCENES", REPO.parent / "shared" / "scenes"))
SAMPLE = REPO / "resources" / "sample"


@dataclass(frozen=True)
class Scene:
    labels: Path
    classes: Path
    #: True for the bundled sample (always present); the others need ../shared/scenes.
    bundled: bool = False


_NB = SCENES / "nrcan_newbrunswick_bakerlake_5class"
SCENE_FILES: dict[str, Scene] = {
    # New Brunswick five-class clips, 0.5 m: building, road, water (Hydro), vegetation, railway (Train)
    "nb1": Scene(_NB / "gt_1of2.tif", _NB / "classes.json"),
    "nb2": Scene(_NB / "gt_2of2.tif", _NB / "classes.json"),
    # Las Vegas roads, ~0.24 x 0.30 m, EPSG:4326: paved road, unpaved road (no unpaved pixels)
    "vegas": Scene(
        SCENES / "spacenet_vegas_img0_roads_rgb" / "gt_roads.tif",
        SCENES / "spacenet_vegas_img0_roads_rgb" / "classes.json",
    ),
    "vegas_pan": Scene(
        SCENES / "solaris_vegas_roads_pan" / "gt_roads.tif", SCENES / "solaris_vegas_roads_pan" / "classes.json"
    ),
    # Kampala OSM building footprints, 7.5 cm, EPSG:3857, 3072 x 2048
    "kampala": Scene(
        SCENES / "kampala_oam_z21_osm_buildings" / "gt_buildings.tif",
        SCENES / "kampala_oam_z21_osm_buildings" / "classes.json",
    ),
    # NEON tree crowns (boxes), 10 cm
    "neon": Scene(
        SCENES / "neon_osbs029_trees_10cm" / "gt_trees.tif", SCENES / "neon_osbs029_trees_10cm" / "classes.json"
    ),
    # the bundled sample, 0.5 m, 1024 x 1024: grass, road, trail, tree, water, building, baseball field
    "sample": Scene(SAMPLE / "sample_labels.tif", SAMPLE / "classes.json", bundled=True),
}

#: Fixed start/goal pixels (row, col) per scene.
POINTS: dict[str, dict[str, tuple[tuple[int, int], tuple[int, int]]]] = {
    "nb1": {
        "on_road": ((10, 154), (280, 154)),  # both on the north-south road, line along it
        "beside_road": ((20, 140), (290, 140)),  # 3-7 m west of the road, line parallel to it
        "west_of_road": ((20, 125), (160, 120)),  # 12-14 m west of the road (beyond "near"'s 10 m)
        "past_lake": ((5, 215), (260, 250)),  # line cuts the west shore of the eastern lake
        "across_lake": ((20, 20), (150, 60)),  # NW corner cut off by a water channel
        "through_yard": ((200, 60), (290, 60)),  # line through the buildings in the south-west
        "veg_edge": ((215, 5), (320, 140)),  # line partly in the south-western vegetation
    },
    "nb2": {
        "on_rail": ((268, 2), (378, 300)),  # both on the railway, line along it
        "above_rail": ((258, 5), (362, 300)),  # north of the railway; the line dips onto it
        "north_of_rail": ((250, 5), (362, 300)),  # 5-6 m north of the railway at both ends
        "across_rail": ((200, 60), (330, 60)),  # on both sides of the railway (it spans the clip)
        "clearing": ((60, 90), (160, 200)),  # through the clearing and its buildings
    },
    "sample": {
        "river_diag": ((100, 50), (950, 500)),  # crosses the river slantwise, then the field
        "on_road": ((20, 640), (600, 640)),  # along the north-south road
        "trail_to_road": ((80, 790), (680, 630)),  # top of the trail to the road junction
        "trees": ((60, 560), (420, 980)),  # through the wood in the north-east
        "field": ((780, 330), (990, 540)),  # across the baseball field
        "past_houses": ((760, 330), (1000, 520)),  # >= 17 m from buildings at both ends; line passes 2
        "river_far_from_road": ((100, 60), (600, 450)),  # crosses the river 350 px north of the road
    },
    "vegas": {
        "blocks": ((600, 250), (1000, 1050)),  # across several streets
        "south_blocks": ((900, 120), (1150, 1000)),  # 1.9 / 2.4 m from a street, across the blocks
    },
    "vegas_pan": {
        "blocks": ((600, 250), (1000, 1050)),
    },
    "kampala": {
        "east_west": ((1100, 120), (1100, 3000)),  # crosses several buildings
        "north_south": ((200, 1266), (1900, 1947)),  # >= 1.9 m from buildings at both ends
    },
    "neon": {
        "west_east": ((190, 5), (190, 395)),  # line 40 % on crowns
        "north_south": ((0, 200), (399, 200)),  # both ends 0.1 m from a crown; line 60 % on crowns
    },
}


@dataclass(frozen=True)
class InvariantCase:
    scene: str
    points: str  # key into POINTS[scene]
    prompt_a: str
    prompt_b: str
    classes: tuple[str, ...]  # class names (classes.json) the relation is measured on
    relation: str
    family: str  # phrasing family, for the ids and the report
    aliases: tuple[tuple[str, str], ...] = ()
    #: for "... or warn": False = a route keeping the rule exists (so it must be kept), True = no
    #: route can keep it (so the "cannot be met" note must come); None = either (not used)
    expect_warning: bool | None = None
    extra: dict = field(default_factory=dict)

    @property
    def id(self) -> str:
        return f"{self.scene}-{self.points}-{self.family}-{self.relation.split()[0]}-" + "_".join(
            self.prompt_a.lower().replace(",", "").split()[:6]
        )


C = InvariantCase
CASES: list[InvariantCase] = [
    # ---------------------------------------------------------------- New Brunswick clip 1
    C("nb1", "on_road", "avoid the roads", "avoid the buildings", ("road",), "less_on", "plain"),
    C("nb1", "on_road", "stay off the road", "avoid the lake", ("road",), "less_on", "stay_off"),
    C(
        "nb1",
        "on_road",
        "use the roads only as a last resort",
        "avoid the buildings",
        ("road",),
        "less_on",
        "last_resort",
    ),
    C("nb1", "beside_road", "prefer the roads", "avoid the buildings", ("road",), "more_on", "plain"),
    C(
        "nb1",
        "beside_road",
        "stick to the paved road as much as possible",
        "avoid the water",
        ("road",),
        "more_on",
        "synonym+strength",
    ),
    C("nb1", "west_of_road", "stay near the road", "avoid the buildings", ("road",), "closer", "near"),
    C(
        "nb1",
        "beside_road",
        "stay within 3 m of the road",
        "avoid the buildings",
        ("road",),
        "max_distance<=3 or warn",
        "distance",
        expect_warning=False,
    ),
    C(
        "nb1",
        "past_lake",
        "avoid the lake",
        "avoid the buildings, you can wade through the lake",
        ("water (Hydro)",),
        "less_on",
        "synonym",
    ),
    C(
        "nb1",
        "past_lake",
        "the water is impassable",
        "avoid the buildings, the water is fine",
        ("water (Hydro)",),
        "zero_on",
        "impassable",
    ),
    C(
        "nb1",
        "past_lake",
        "keep at least 5 m from the water",
        "avoid the buildings",
        ("water (Hydro)",),
        "min_distance>=5 or warn",
        "distance",
        expect_warning=False,
    ),
    C(
        "nb1",
        "past_lake",
        "you can wade through the water, avoid the buildings",
        "avoid the water and the buildings",
        ("water (Hydro)",),
        "moves",
        "permission",
    ),
    C(
        "nb1",
        "past_lake",
        "avoid the water at all costs",
        "avoid the buildings, you can wade through the water",
        ("water (Hydro)",),
        "less_on",
        "strength",
    ),
    C(
        "nb1",
        "across_lake",
        "never come within 4 m of the lake",
        "avoid the buildings",
        ("water (Hydro)",),
        "min_distance>=4 or warn",
        "distance",
        expect_warning=True,
    ),
    C(
        "nb1",
        "through_yard",
        "avoid the buildings",
        "avoid the water, the buildings are fine",
        ("building",),
        "less_on",
        "plain",
    ),
    C(
        "nb1",
        "through_yard",
        "never walk through the buildings",
        "avoid the water, walking through the buildings is fine",
        ("building",),
        "zero_on",
        "strength",
    ),
    C(
        "nb1",
        "through_yard",
        "keep 6 m away from the houses",
        "avoid the water",
        ("building",),
        "farther",
        "distance_soft+synonym",
    ),
    C(
        "nb1",
        "through_yard",
        "buildings are fine, avoid the water",
        "avoid the buildings and the water",
        ("building",),
        "moves",
        "permission",
    ),
    C("nb1", "veg_edge", "stay in the woods", "avoid the buildings", ("vegetation",), "more_on", "synonym+concealment"),
    C("nb1", "veg_edge", "stay under the trees", "avoid the water", ("vegetation",), "more_on", "concealment"),
    C("nb1", "veg_edge", "keep out of the vegetation", "avoid the water", ("vegetation",), "less_on", "plain"),
    # ---------------------------------------------------------------- New Brunswick clip 2
    C(
        "nb2",
        "on_rail",
        "stay off the tracks",
        "avoid the buildings, the railway is fine",
        ("railway (Train)",),
        "less_on",
        "stay_off+synonym",
    ),
    C("nb2", "on_rail", "walk along the railway", "avoid the railway", ("railway (Train)",), "more_on", "plain"),
    C(
        "nb2",
        "above_rail",
        "the railway is off limits",
        "avoid the buildings, crossing the railway is fine",
        ("railway (Train)",),
        "zero_on",
        "impassable",
    ),
    C(
        "nb2",
        "north_of_rail",
        "keep at least 3 m from the railroad",
        "avoid the lake",
        ("railway (Train)",),
        "min_distance>=3 or warn",
        "distance+synonym",
        expect_warning=False,
    ),
    C(
        "nb2",
        "across_rail",
        "keep at least 5 m from the railway",
        "avoid the buildings",
        ("railway (Train)",),
        "min_distance>=5 or warn",
        "distance",
        expect_warning=True,
    ),
    C(
        "nb2",
        "across_rail",
        "go cross-country through the forest",
        "avoid the buildings",
        ("vegetation",),
        "more_on",
        "cross_country",
    ),
    C(
        "nb2",
        "clearing",
        "avoid the buildings as much as possible",
        "avoid the water, the buildings are fine",
        ("building",),
        "less_on",
        "strength",
    ),
    C(
        "nb2",
        "clearing",
        "vegetation is better than open ground",
        "avoid the buildings",
        ("vegetation",),
        "more_on",
        "comparative",
    ),
    C(
        "nb2",
        "clearing",
        "the woods are better than the buildings",
        "the buildings are better than the woods",
        ("vegetation",),
        "more_on",
        "comparative+synonym",
    ),
    # ---------------------------------------------------------------- the bundled sample
    C(
        "sample",
        "river_diag",
        "avoid the water",
        "avoid the buildings, you can wade through the water",
        ("water",),
        "less_on",
        "plain",
    ),
    C(
        "sample",
        "river_diag",
        "stay out of the river",
        "avoid the buildings, you can wade through the river",
        ("water",),
        "less_on",
        "stay_off+synonym",
    ),
    C(
        "sample",
        "river_diag",
        "avoid the baseball field",
        "avoid the buildings",
        ("baseball field",),
        "less_on",
        "plain",
    ),
    C(
        "sample",
        "field",
        "the baseball field is impassable",
        "avoid the water",
        ("baseball field",),
        "zero_on",
        "impassable",
    ),
    C(
        "sample",
        "past_houses",
        "keep at least 8 m from the buildings",
        "avoid the water",
        ("building",),
        "min_distance>=8 or warn",
        "distance",
        expect_warning=False,
    ),
    C(
        "sample",
        "river_far_from_road",
        "do not cross the water except at the road",
        "avoid the buildings, you can wade through the water",
        ("water",),
        "less_on",
        "negation+exception",
    ),
    C(
        "sample",
        "river_far_from_road",
        "you can wade through the river, avoid the trees",
        "avoid the river, avoid the trees",
        ("water",),
        "moves",
        "permission",
    ),
    C("sample", "on_road", "roads are a last resort", "avoid the buildings", ("road",), "less_on", "last_resort"),
    C("sample", "on_road", "do not walk on the road", "avoid the water", ("road",), "less_on", "negation"),
    C(
        "sample",
        "trail_to_road",
        "the trail is better than the road",
        "the road is better than the trail",
        ("trail",),
        "more_on",
        "comparative",
    ),
    C(
        "sample",
        "trail_to_road",
        "prefer the trail over the grass",
        "prefer the grass over the trail",
        ("trail",),
        "more_on",
        "comparative",
    ),
    C("sample", "trees", "stay under the trees", "avoid the buildings", ("tree",), "more_on", "concealment"),
    C("sample", "trees", "keep to the tree cover", "avoid the water", ("tree",), "more_on", "concealment+synonym"),
    C("sample", "trees", "avoid the woods", "avoid the water, the woods are fine", ("tree",), "less_on", "synonym"),
    # ---------------------------------------------------------------- Las Vegas roads
    C("vegas", "blocks", "prefer the paved roads", "avoid the unpaved roads", ("paved road",), "more_on", "synonym"),
    C("vegas", "blocks", "stay off the streets", "prefer the roads", ("paved road",), "less_on", "stay_off+synonym"),
    C(
        "vegas",
        "south_blocks",
        "stay within 5 m of the road",
        "avoid the roads",
        ("paved road",),
        "max_distance<=5 or warn",
        "distance",
        expect_warning=False,
    ),
    C(
        "vegas",
        "south_blocks",
        "keep at least 2 m from the roads",
        "prefer the roads",
        ("paved road",),
        "min_distance>=2 or warn",
        "distance",
        expect_warning=True,
    ),
    C("vegas_pan", "blocks", "follow the road", "avoid the roads", ("paved road", "unpaved road"), "more_on", "plain"),
    # ---------------------------------------------------------------- Kampala buildings
    C(
        "kampala",
        "east_west",
        "avoid the houses",
        "prefer the buildings",
        ("building (OSM footprint)",),
        "less_on",
        "synonym",
    ),
    C(
        "kampala",
        "east_west",
        "buildings are impassable",
        "prefer the buildings",
        ("building (OSM footprint)",),
        "zero_on",
        "impassable",
    ),
    C(
        "kampala",
        "east_west",
        "avoid the compounds",
        "prefer the buildings",
        ("building (OSM footprint)",),
        "less_on",
        "alias",
        aliases=(("compound", "building"),),
    ),
    C(
        "kampala",
        "north_south",
        "keep at least 1 m from the buildings",
        "prefer the buildings",
        ("building (OSM footprint)",),
        "min_distance>=1 or warn",
        "distance",
        expect_warning=False,
    ),
    # ---------------------------------------------------------------- NEON tree crowns
    C(
        "neon",
        "west_east",
        "stay under the tree canopy",
        "avoid the trees",
        ("tree crown (bounding box)",),
        "more_on",
        "concealment",
    ),
    C(
        "neon",
        "north_south",
        "avoid the trees",
        "stay under the trees",
        ("tree crown (bounding box)",),
        "less_on",
        "plain",
    ),
    C(
        "neon",
        "north_south",
        "never within 1 m of the trees",
        "stay under the trees",
        ("tree crown (bounding box)",),
        "min_distance>=1 or warn",
        "distance",
        expect_warning=True,
    ),
]

# ---------------------------------------------------------------- RRPI against the rank optimum
#: Prompts whose ranks are stated by hand (neutral ground ranks between preferred and avoided).
#: case id -> (scene, prompt, ranks stated by hand from the prompt's intent). "sym" prompts have
#: as many ranks below neutral as above (costs exactly affine in rank); "asym" ones do not (one
#: preferred rank, two avoided ones), so the planner's costs only approximate the ranks.
RRPI_CASES: dict[str, tuple[str, str, dict[str, int]]] = {
    "nb1-sym": (
        "nb1",
        "prefer the roads, stay off the railway and avoid buildings and the lake",
        {"road": 1, "unlabeled": 2, "vegetation": 2, "building": 3, "water": 3, "railway": 3},
    ),
    "nb2-sym": (
        "nb2",
        "prefer the roads, stay off the railway and avoid buildings and the lake",
        {"road": 1, "unlabeled": 2, "vegetation": 2, "building": 3, "water": 3, "railway": 3},
    ),
    "sample-sym": (
        "sample",
        "prefer the roads and the trails, avoid the water and the buildings",
        {"road": 1, "trail": 1, "grass": 2, "tree": 2, "baseball field": 2, "water": 3, "building": 3},
    ),
    "nb1-asym": (
        "nb1",
        "prefer the roads, avoid the buildings, avoid the railway and the lake as much as possible",
        {"road": 1, "unlabeled": 2, "vegetation": 2, "building": 3, "water": 4, "railway": 4},
    ),
    "nb2-asym": (
        "nb2",
        "prefer the roads, avoid the buildings, avoid the railway and the lake as much as possible",
        {"road": 1, "unlabeled": 2, "vegetation": 2, "building": 3, "water": 4, "railway": 4},
    ),
    "sample-asym": (
        "sample",
        "prefer the roads and the trails, avoid the trees, avoid the water and the buildings as much as possible",
        {"road": 1, "trail": 1, "grass": 2, "baseball field": 2, "tree": 3, "water": 4, "building": 4},
    ),
}
RRPI_PAIRS = 100
RRPI_SEED = 20240917
RRPI_TOLERANCE = 1.05
RRPI_PASS_SHARE = 0.90


def all_prompts() -> set[str]:
    out = {c.prompt_a for c in CASES} | {c.prompt_b for c in CASES}
    return out | {p for _, p, _ in RRPI_CASES.values()}
