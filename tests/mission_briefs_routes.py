"""Route checks of mission briefs on real ground-truth scenes (issue 31), with independent references.

For a brief and a scene: the costmap is built by the pipeline (``run_costmap`` over the scene's
class raster, the prompt read offline), 8 seeded start/goal pairs are planned with the project's
rule-keeping planner, and each route is compared with the shortest path between the same points
on a flat costmap (every cell 0.5). "keeps" is judged against scikit-image's ``MCP_Geometric``, an
independent planner: it says whether any route can keep the distance (the zone and lethal cells
impassable) and, where none can, the least metres a route must run inside the zone
(lexicographically: zone metres first, then length). See ``tests/mission_briefs.py`` for the
relations.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from .invariants_data import SCENE_FILES, SCENES, Scene
from .mission_briefs import Brief, Route

N_PAIRS = 8
#: A pair's ends are at least this share of the scene's diagonal apart.
MIN_SEPARATION = 0.35

_SCENES: dict[str, Scene] = dict(SCENE_FILES)
_SCENES["massachusetts"] = Scene(
    SCENES / "massachusetts_22978945_buildings_1m" / "gt_buildings.tif",
    SCENES / "massachusetts_22978945_buildings_1m" / "classes.json",
)


def scene_available(scene: str) -> bool:
    s = _SCENES[scene]
    return s.labels.exists() and s.classes.exists()


@cache
def _labels(scene: str) -> np.ndarray:
    import rasterio

    with rasterio.open(_SCENES[scene].labels) as ds:
        return ds.read(1)


@cache
def class_present(scene: str, cls: str) -> bool:
    """Whether the scene holds any pixel of ``cls`` (a class its classes.json names may be empty
    on a clip: the New Brunswick clip nb1 has no railway). A route check on an absent class
    measures nothing (distances to an empty mask), so it is not scored."""
    try:
        return bool(class_mask(scene, cls).any())
    except KeyError:
        return False


@cache
def class_within_reach(scene: str, cls: str) -> bool:
    """Whether any seeded pair's route could run on ``cls`` at all: scikit-image's MCP_Geometric
    (an independent planner) on a costmap where ``cls`` is free and all else neutral, nothing
    impassable, for each pair. When even then no route touches the class (nb2's road is a strip
    at the clip's edge that no pair passes), "more on it" measures nothing, so it is not scored."""
    from skimage.graph import MCP_Geometric

    mask = class_mask(scene, cls)
    cost = np.where(mask, 1e-3, 0.5)
    for a, b in pairs(scene):
        mcp = MCP_Geometric(cost)
        mcp.find_costs([a], [b])
        px = np.array(mcp.traceback(b))
        if mask[px[:, 0], px[:, 1]].any():
            return True
    return False


@cache
def class_mask(scene: str, cls: str) -> np.ndarray:
    from overseec_core import evaluate

    table = evaluate.load_classes(_SCENES[scene].classes)
    ids = [cid for cid, name in table.names.items() if _is_class(name, cls)]
    if not ids:
        raise KeyError(f"{scene}: no class {cls!r}")
    return np.isin(_labels(scene), ids)


def _is_class(name: str, cls: str) -> bool:
    """Whether a scene's class label is the brief's ``cls``: the label without its
    parenthetical, or its head noun ("tree crown (bounding box)" is the scene's "tree")."""
    from overseec_core.interpret.matching import normalise

    label = normalise(name.split(" (")[0])
    return label == normalise(cls) or label.split()[0] == normalise(cls)


@cache
def pairs(scene: str) -> tuple[tuple[tuple[int, int], tuple[int, int]], ...]:
    """Seeded start/goal pairs on unlabelled ground (class 0), far enough apart to mean something."""
    labels = _labels(scene)
    free = labels == 0
    if free.mean() < 0.01:  # a scene labelled everywhere: any cell
        free = np.ones_like(free)
    rows, cols = np.nonzero(free)
    rng = np.random.default_rng(sum(map(ord, scene)))
    diag = float(np.hypot(*labels.shape))
    out: list[tuple[tuple[int, int], tuple[int, int]]] = []
    while len(out) < N_PAIRS:
        i, j = rng.integers(0, len(rows), size=2)
        a, b = (int(rows[i]), int(cols[i])), (int(rows[j]), int(cols[j]))
        if np.hypot(a[0] - b[0], a[1] - b[1]) >= MIN_SEPARATION * diag:
            out.append((a, b))
    return tuple(out)


@dataclass(frozen=True)
class RouteMeasure:
    share_on: float
    min_dist: float
    mean_dist: float
    length_m: float
    pixels: np.ndarray


def _measure(pixels: np.ndarray, mask: np.ndarray, dist: np.ndarray, pixel_size_m) -> RouteMeasure:
    """The invariant suite's own measures (``test_invariants.share_on`` / ``mean_distance``)."""
    from overseec_core.plan.paths import step_lengths_m

    from .test_invariants import mean_distance, share_on

    px = np.asarray(pixels, dtype=np.int64)
    total = float(step_lengths_m(px, *pixel_size_m).sum())
    closest = float(dist[px[:, 0], px[:, 1]].min())
    return RouteMeasure(share_on(px, mask, pixel_size_m), closest, mean_distance(px, dist, pixel_size_m), total, px)


def zone_metres(pixels: np.ndarray, zone: np.ndarray, pixel_size_m) -> float:
    """Ground metres of a route inside ``zone`` (``test_invariants.share_on`` times its length)."""
    from overseec_core.plan.paths import step_lengths_m

    from .test_invariants import share_on

    px = np.asarray(pixels, dtype=np.int64)
    return share_on(px, zone, pixel_size_m) * float(step_lengths_m(px, *pixel_size_m).sum())


def _least_in_zone(pixels, passable: np.ndarray, zone: np.ndarray, start, goal, pixel_size_m):
    """Whether a route (``pixels``) that must enter ``zone`` runs the fewest metres in it that any
    route can (the independent planner's, within 5 % and a cell's diagonal): (ok, its metres,
    the least possible or None when no route exists)."""
    least = reference_zone_metres(passable, zone, start, goal, pixel_size_m)
    got = zone_metres(pixels, zone, pixel_size_m)
    diag = float(np.hypot(*pixel_size_m))
    return least is not None and got <= 1.05 * least + diag, got, least


def reference_zone_metres(passable: np.ndarray, zone: np.ndarray, start, goal, pixel_size_m) -> float | None:
    """Least metres inside ``zone`` of any route from start to goal over passable cells
    (scikit-image MCP_Geometric; a tiny length term breaks ties), or None when unreachable."""
    from skimage.graph import MCP_Geometric

    dx, dy = pixel_size_m
    cost = np.where(zone, 1.0, 1e-6)
    cost = np.where(passable, cost, np.inf)
    mcp = MCP_Geometric(cost, sampling=(dy, dx))
    cum, _ = mcp.find_costs([start], [goal])
    if not np.isfinite(cum[goal]):
        return None
    return zone_metres(np.array(mcp.traceback(goal)), zone, pixel_size_m)


def _priors_program(layers: list[str]) -> str | None:
    """The cost program of the built-in priors alone over ``layers`` (what a costmap holds for
    classes no brief mentions), or None when no layer has a prior (the flat costmap)."""
    from dataclasses import replace

    from overseec_core.costlang import program_from_interpretation
    from overseec_core.interpret.merge import dense_ranks
    from overseec_core.interpret.priors import BUILT_IN
    from overseec_core.synthesize.fit import layer_priors

    prefs = layer_priors(layers, (), BUILT_IN)
    if not prefs:
        return None
    ranks = dense_ranks({n: (p.weight, p.lethal) for n, p in prefs.items()})
    return program_from_interpretation(list(prefs), [replace(p, rank=ranks[n]) for n, p in prefs.items()])


class RouteHarness:
    """Costmaps and routes per (scene, prompt), built once."""

    def __init__(self, root: Path | None = None) -> None:
        self.root = Path(root or tempfile.mkdtemp(prefix="briefs-routes-"))
        self._made = 0
        self._cache: dict = {}

    def grid(self, scene: str, prompt: str):
        from overseec_core.pipeline import run_costmap
        from overseec_core.plan import load_costmap
        from overseec_core.synthesize.options import CostmapOptions

        key = ("grid", scene, prompt)
        if key not in self._cache:
            self._made += 1
            out = self.root / f"cm{self._made:03d}" / "costmap.tif"
            out.parent.mkdir(parents=True)
            s = _SCENES[scene]
            run_costmap(CostmapOptions(out=out, labels=s.labels, classes=s.classes, prompt=prompt))
            self._cache[key] = load_costmap(out)
        return self._cache[key]

    def ablated_grid(self, scene: str, prompt: str, cls: str):
        """The costmap of the brief without its words on ``cls`` (its preferences and cues of
        the entities that match the scene's ``cls`` layer dropped, so that layer takes its
        prior as an unmentioned one does), or None when nothing else of the brief is read."""
        from dataclasses import replace

        from overseec_core import evaluate
        from overseec_core.errors import InputError
        from overseec_core.interpret.matching import match_entities
        from overseec_core.pipeline import interpret_for_costmap
        from overseec_core.plan import load_costmap
        from overseec_core.synthesize.options import CostmapOptions
        from overseec_core.synthesize.stage import run_synthesize

        key = ("ablated", scene, prompt, cls)
        if key not in self._cache:
            s = _SCENES[scene]
            layers = list(evaluate.load_classes(s.classes).names.values())
            options = CostmapOptions(out=self.root / "unused.tif", labels=s.labels, classes=s.classes, prompt=prompt)
            interp = interpret_for_costmap(options)
            assert interp is not None
            target = {layer for layer in layers if _is_class(layer, cls)}

            def about(entity: str | None) -> bool:
                return entity is not None and bool(set(match_entities([entity], layers)[0].layers) & target)

            ablated = replace(
                interp,
                preferences=tuple(p for p in interp.preferences if not about(p.entity)),
                cues=tuple(c for c in interp.cues if not (about(c.entity) or about(c.other))),
                program="",
            )
            self._made += 1
            out = self.root / f"cm{self._made:03d}" / "costmap.tif"
            out.parent.mkdir(parents=True)
            try:
                run_synthesize(replace(options, out=out), interpretation=ablated)
            except InputError:  # the brief says nothing else this tool reads: the priors alone
                text = _priors_program(layers)
                if text is None:
                    self._cache[key] = None
                    return None
                run_synthesize(replace(options, out=out, prompt=None, program_text=text))
            self._cache[key] = load_costmap(out)
        return self._cache[key]

    def baseline_routes(self, scene: str, prompt: str, cls: str, pixel_size_m) -> tuple[list, str]:
        """The routes of the brief without its words on ``cls`` and what they are called; the
        flat routes where nothing else of the brief is read."""
        grid = self.ablated_grid(scene, prompt, cls)
        if grid is None:
            return self.flat_routes(scene, pixel_size_m), "flat"
        return self._plan(("ablated-routes", scene, prompt, cls), grid), f"without its words on {cls}"

    def routes(self, scene: str, prompt: str) -> list[np.ndarray | None]:
        return self._plan(("routes", scene, prompt), self.grid(scene, prompt))

    def _plan(self, key: tuple, grid) -> list[np.ndarray | None]:
        from overseec_core.errors import PlanError
        from overseec_core.plan.stage import plan_keeping_rules

        scene = key[1]
        if key not in self._cache:
            out: list[np.ndarray | None] = []
            for a, b in pairs(scene):
                try:
                    res, _ = plan_keeping_rules(grid, [a, b])
                    out.append(res.pixels)
                except PlanError:
                    out.append(None)
            self._cache[key] = out
        return self._cache[key]

    def flat_routes(self, scene: str, pixel_size_m: tuple[float, float]) -> list[np.ndarray]:
        from overseec_core.plan import Planner, PlanningGrid

        key = ("flat", scene)
        if key not in self._cache:
            flat = PlanningGrid.from_array(np.full(_labels(scene).shape, 0.5, np.float32), pixel_size_m=pixel_size_m)
            planner = Planner(flat)
            self._cache[key] = [planner.plan([a, b]).pixels for a, b in pairs(scene)]
        return self._cache[key]

    def check(self, brief: Brief, route: Route, baseline: str = "flat") -> list[str | None]:  # noqa: C901
        """One verdict per seeded pair (None = the route does what the brief means).

        ``baseline``: what a route is compared with -- ``"flat"`` (the contract: the shortest
        path on a flat costmap) or ``"ablated"`` (the route of the same brief without its words
        on the class: what those words changed, with the brief's other rules and the priors
        held, so a route that skirts a pond the priors avoid is not blamed for being nearer
        the water than a flat route straight across it). Where no route exists without what
        the brief forbids (the independent planner finds none either), no route is right, and
        (against that baseline) a route with no metre on a class it should be less on is."""
        from scipy.ndimage import distance_transform_edt

        scene = route.scene
        grid = self.grid(scene, brief.prompt)
        psm = grid.pixel_size_m
        mask = class_mask(scene, route.cls)
        dist = distance_transform_edt(~mask, sampling=(psm[1], psm[0]))
        mine = self.routes(scene, brief.prompt)
        if baseline == "ablated":
            flat, _called = self.baseline_routes(scene, brief.prompt, route.cls, psm)
        else:
            flat = self.flat_routes(scene, psm)
        # cells a route may use at all: passable, or keep-out (entered only where it must)
        passable = np.isfinite(grid.cost) | (grid.keep_out if grid.keep_out is not None else False)
        verdicts: list[str | None] = []
        ms = [None if p is None else _measure(p, mask, dist, psm) for p in mine]
        # a baseline pair with no route (the brief's other rules forbid it) is measured flat
        flat_all = self.flat_routes(scene, psm)
        fs = [_measure(p if p is not None else q, mask, dist, psm) for p, q in zip(flat, flat_all)]
        rel = route.relation
        if rel in ("more_on", "less_on", "beside"):
            done = [(m, f) for m, f in zip(ms, fs) if m is not None]
            if rel == "more_on":
                total_ok = sum(m.share_on for m, _ in done) > sum(f.share_on for _, f in done) + 1e-9
            elif rel == "less_on":
                total_ok = sum(m.share_on for m, _ in done) < sum(f.share_on for _, f in done) - 1e-9
                # against the brief without those words, none of the class is as little as can be
                nothing = baseline == "ablated" and sum(m.share_on for m, _ in done) <= 1e-9
                total_ok = total_ok or nothing
            else:
                band = (dist > 0) & (dist <= float(route.metres))
                total_ok = sum(m.share_on for m, _ in done) < sum(f.share_on for _, f in done) + 1e-9 and sum(
                    zone_metres(m.pixels, band, psm) for m, _ in done
                ) > sum(zone_metres(f.pixels, band, psm) for _, f in done)
        else:
            total_ok = True
        diag = float(np.hypot(*psm))
        for i, (m, f) in enumerate(zip(ms, fs)):
            a, b = pairs(scene)[i]
            if m is None:
                # no route is right only where none exists without what the brief forbids
                free = reference_zone_metres(passable, np.zeros_like(mask), a, b, psm)
                none_right = free is None and (rel == "zero_on" or baseline == "ablated")
                verdicts.append(None if none_right else "no route planned")
                continue
            if rel == "more_on":
                ok = m.share_on >= f.share_on - 1e-9 and total_ok
                why = f"share on {route.cls} {m.share_on:.3f} vs flat {f.share_on:.3f}"
            elif rel == "less_on":
                ok = m.share_on <= f.share_on + 1e-9 and total_ok
                why = f"share on {route.cls} {m.share_on:.3f} vs flat {f.share_on:.3f}"
            elif rel == "zero_on":
                ok = m.share_on == 0.0
                why = f"share on {route.cls} {m.share_on:.3f}"
                if not ok and reference_zone_metres(passable & ~mask, np.zeros_like(mask), a, b, psm) is None:
                    # no route avoids it (a never-cross rule where the class separates the
                    # points): the rule bends as little as possible, the least metres on it
                    ok, got, least = _least_in_zone(m.pixels, passable, mask, a, b, psm)
                    why = f"{got:.1f} m on {route.cls}, which no route avoids; least possible {least}"
            elif rel in ("closer", "farther"):
                ok = m.mean_dist <= f.mean_dist + 1e-9 if rel == "closer" else m.mean_dist >= f.mean_dist - 1e-9
                why = f"mean distance to {route.cls} {m.mean_dist:.2f} m vs flat {f.mean_dist:.2f} m"
            elif rel == "beside":
                ok = total_ok
                why = f"share on {route.cls} {m.share_on:.3f} vs flat {f.share_on:.3f} (beside, in total)"
            elif rel == "keeps":
                metres = float(route.metres)
                zone = dist < metres
                ref_free = reference_zone_metres(passable & ~zone, np.zeros_like(zone), a, b, psm)
                if ref_free is not None:
                    ok = m.min_dist >= metres - diag / 2
                    why = f"closest approach {m.min_dist:.2f} m, a route keeping {metres} m exists"
                else:
                    ok, got, least = _least_in_zone(m.pixels, passable, zone, a, b, psm)
                    why = f"{got:.1f} m inside the {metres} m zone; least possible {least}"
            else:
                ok, why = False, f"unknown relation {rel}"
            verdicts.append(None if ok else why)
        return verdicts
