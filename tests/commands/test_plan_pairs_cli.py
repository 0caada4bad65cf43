"""`overseec plan --pairs / --matrix`: many routes from one costmap load, equal to single plans."""

from __future__ import annotations

import json
from pathlib import Path

import fiona
import numpy as np
import pytest

from overseec_core.cli import EXIT_USER, main
from overseec_core.errors import Cancelled, InputError
from overseec_core.plan.pairs import PairsOptions, run_pairs
from overseec_core.progress import NullProgress

from ..plan.conftest import smooth_costmap, write_costmap

#: (id, start, goal) in the costmap's CRS (UTM 33N, 0.5 m pixels from (500000, 4000000)).
PAIRS = [
    ("a", (500000.75, 3999999.25), (500039.25, 3999970.25)),
    ("b", (500001.25, 3999998.75), (500020.25, 3999980.25)),
    ("c", (500035.25, 3999972.75), (500002.25, 3999990.25)),
]
POINTS = [("p1", 500000.75, 3999999.25), ("p2", 500039.25, 3999970.25), ("p3", 500020.25, 3999980.25)]


@pytest.fixture
def costmap(tmp_path: Path) -> Path:
    cost = smooth_costmap((60, 80), seed=3, lethal_fraction=0.08)
    for r, c in ((1, 1), (2, 2), (59, 78), (39, 40), (5, 70), (19, 4), (1, 2)):
        cost[max(0, r - 1) : r + 2, max(0, c - 1) : c + 2] = 0.5
    cost[30, 30] = np.inf
    return write_costmap(tmp_path / "costmap.tif", cost)


def pairs_csv(path: Path, rows=PAIRS) -> Path:
    lines = ["id,start_x,start_y,goal_x,goal_y"] + [f"{i},{s[0]},{s[1]},{g[0]},{g[1]}" for i, s, g in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def single_plan(costmap: Path, start, goal, tmp_path: Path, capsys, extra: tuple[str, ...] = ()) -> dict:
    out = tmp_path / "single" / "path.geojson"
    argv = ["-q", "plan", str(costmap), "--start", *map(str, start), "--goal", *map(str, goal), *extra]
    assert main([*argv, "--out", str(out), "--native-crs", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    with fiona.open(out.with_name("path.native.gpkg"), layer="path") as src:
        doc["coords"] = list(next(iter(src))["geometry"]["coordinates"])
    return doc


def read_routes(path: Path) -> dict[str, dict]:
    with fiona.open(path, layer="routes") as src:
        return {
            f["properties"]["id"]: {**dict(f["properties"]), "coords": f["geometry"] and f["geometry"]["coordinates"]}
            for f in src
        }


def test_pair_routes_equal_single_plans(costmap: Path, tmp_path: Path, capsys) -> None:
    out = tmp_path / "out" / "routes.gpkg"
    assert (
        main(["-q", "plan", str(costmap), "--pairs", str(pairs_csv(tmp_path / "p.csv")), "--out", str(out), "--json"])
        == 0
    )
    doc = json.loads(capsys.readouterr().out)
    assert doc["planned"] == 3 and doc["failed"] == 0
    routes = read_routes(out)
    assert list(routes) == ["a", "b", "c"]
    for ident, start, goal in PAIRS:
        single = single_plan(costmap, start, goal, tmp_path, capsys)
        got = routes[ident]
        assert got["total_cost"] == single["total_cost"] and got["length_m"] == single["length_m"]
        assert [tuple(c) for c in got["coords"]] == [tuple(c) for c in single["coords"]]
        assert (got["start_x"], got["goal_y"]) == (start[0], goal[1])
    manifest = json.loads((out.parent / "manifest.json").read_text())
    assert manifest["plan_pairs"]["outputs"] == {"routes": "routes.gpkg"}
    assert (manifest["plan_pairs"]["planned"], manifest["plan_pairs"]["failed"]) == (3, 0)
    assert any(k.startswith("plan_pairs_") for k in manifest["inputs"])


def test_a_bad_pair_keeps_its_row_and_the_others(costmap: Path, tmp_path: Path, capsys) -> None:
    rows = [*PAIRS[:1], ("far", (600000.0, 3999999.0), PAIRS[0][2]), ("wall", PAIRS[0][1], (500015.25, 3999984.75))]
    out = tmp_path / "routes.gpkg"
    assert (
        main(["-q", "plan", str(costmap), "--pairs", str(pairs_csv(tmp_path / "p.csv", rows)), "--out", str(out)]) == 0
    )
    printed = capsys.readouterr().out
    routes = read_routes(out)
    assert routes["a"]["coords"] and routes["a"]["error"] is None
    assert routes["far"]["coords"] is None and "outside the costmap" in routes["far"]["error"]
    assert routes["wall"]["coords"] is None and "lethal" in routes["wall"]["error"]
    assert "1 planned, 2 without a route" in printed


def test_pairs_from_a_line_layer_in_another_crs(costmap: Path, tmp_path: Path, capsys) -> None:
    from pyproj import Transformer

    to_ll = Transformer.from_crs("EPSG:32633", "EPSG:4326", always_xy=True)
    layer = tmp_path / "pairs.gpkg"
    schema = {"geometry": "LineString", "properties": {"id": "str"}}
    with fiona.open(layer, "w", driver="GPKG", schema=schema, crs="EPSG:4326") as dst:
        for ident, s, g in PAIRS:
            coords = [to_ll.transform(*s), to_ll.transform(*g)]
            dst.write({"geometry": {"type": "LineString", "coordinates": coords}, "properties": {"id": ident}})
    out = tmp_path / "routes.gpkg"
    assert main(["-q", "plan", str(costmap), "--pairs", str(layer), "--out", str(out)]) == 0
    capsys.readouterr()
    routes = read_routes(out)
    for ident, start, goal in PAIRS:
        single = single_plan(costmap, start, goal, tmp_path, capsys)
        assert routes[ident]["total_cost"] == single["total_cost"]


def test_matrix_equals_pairwise_plans(costmap: Path, tmp_path: Path, capsys) -> None:
    pts = tmp_path / "pts.csv"
    pts.write_text("x,y,id\n" + "".join(f"{x},{y},{i}\n" for i, x, y in POINTS))
    out = tmp_path / "m" / "costs.csv"
    assert main(["-q", "plan", str(costmap), "--points", str(pts), "--matrix", str(out)]) == 0
    capsys.readouterr()
    lines = [line.split(",") for line in out.read_text().splitlines()]
    assert lines[0] == ["from", "p1", "p2", "p3"]
    for i, (_, x0, y0) in enumerate(POINTS):
        assert lines[i + 1][0] == POINTS[i][0]
        for j, (_, x1, y1) in enumerate(POINTS):
            value = float(lines[i + 1][j + 1])
            if i == j:
                assert value == 0.0
                continue
            single = single_plan(costmap, (x0, y0), (x1, y1), tmp_path, capsys)
            assert value == pytest.approx(single["total_cost"], rel=1e-12)
    # one-to-many: --sources with one point is the first row
    one = tmp_path / "one.csv"
    one.write_text(f"x,y,id\n{POINTS[0][1]},{POINTS[0][2]},s\n")
    out2 = tmp_path / "m" / "one.csv"
    assert main(["-q", "plan", str(costmap), "--sources", str(one), "--points", str(pts), "--matrix", str(out2)]) == 0
    row = out2.read_text().splitlines()[1].split(",")
    assert row[0] == "s" and row[1:] == lines[1][1:]


def test_sixteen_neighbours_pairs_and_matrix_equal_single_plans_with_16(costmap: Path, tmp_path: Path, capsys) -> None:
    """--neighbours 16 reaches every pair route and every matrix search: each equals the single
    plan with 16 (cost, length, vertices), and knight moves make some routes cheaper than with 8."""
    sixteen = ("--neighbours", "16")
    out = tmp_path / "out" / "routes.gpkg"
    pairs = str(pairs_csv(tmp_path / "p.csv"))
    assert main(["-q", "plan", str(costmap), "--pairs", pairs, "--out", str(out), *sixteen]) == 0
    capsys.readouterr()
    routes = read_routes(out)
    cheaper = 0
    for ident, start, goal in PAIRS:
        single = single_plan(costmap, start, goal, tmp_path, capsys, sixteen)
        got = routes[ident]
        assert (got["total_cost"], got["length_m"]) == (single["total_cost"], single["length_m"])
        assert [tuple(c) for c in got["coords"]] == [tuple(c) for c in single["coords"]]
        cheaper += single["total_cost"] < single_plan(costmap, start, goal, tmp_path, capsys)["total_cost"] - 1e-9
    assert cheaper >= 2, "16 neighbours should beat 8 on these diagonal-ish pairs"
    manifest = json.loads((out.parent / "manifest.json").read_text())
    assert manifest["parameters"]["plan_pairs"]["neighbours"] == 16
    pts = tmp_path / "pts.csv"
    pts.write_text("x,y,id\n" + "".join(f"{x},{y},{i}\n" for i, x, y in POINTS))
    matrix = tmp_path / "m" / "costs.csv"
    assert main(["-q", "plan", str(costmap), "--points", str(pts), "--matrix", str(matrix), *sixteen]) == 0
    capsys.readouterr()
    rows = [line.split(",")[1:] for line in matrix.read_text().splitlines()[1:]]
    for i, (_, x0, y0) in enumerate(POINTS):
        for j, (_, x1, y1) in enumerate(POINTS):
            if i != j:
                single = single_plan(costmap, (x0, y0), (x1, y1), tmp_path, capsys, sixteen)
                assert float(rows[i][j]) == pytest.approx(single["total_cost"], rel=1e-12)


def test_sixteen_neighbours_on_the_fallback_is_one_line_and_writes_nothing(costmap: Path, tmp_path: Path) -> None:
    from overseec_core.errors import PlanError
    from overseec_core.plan import planner as planner_module

    out = tmp_path / "routes.gpkg"
    options = PairsOptions(costmap=costmap, pairs=pairs_csv(tmp_path / "p.csv"), out=out, neighbours=16)
    real = planner_module.Planner

    def fallback_planner(*args, **kwargs):
        return real(*args, planner="fallback", **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr("overseec_core.plan.pairs.Planner", fallback_planner)
        with pytest.raises(PlanError, match="16") as err:
            run_pairs(options)
    assert "\n" not in str(err.value) and not out.exists()
    with pytest.raises(InputError, match="8 or 16"):
        PairsOptions(costmap=costmap, pairs=out, out=out, neighbours=4)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--pairs", "P", "--out", "r.gpkg", "--start", "1", "2"], "--start: single-route options"),
        (["--pairs", "P", "--out", "r.geojson"], "ROUTES.gpkg"),
        (["--matrix", "m.csv"], "--matrix needs --points"),
        (["--matrix", "m.csv", "--points", "P", "--out", "r.gpkg"], "--out names the routes"),
        (["--out", "x.geojson"], "plan needs --start"),
        (["--pairs", "BAD", "--out", "r.gpkg"], "needs the columns"),
    ],
)
def test_bad_combinations_are_one_line_errors(costmap: Path, tmp_path: Path, capsys, argv, message) -> None:
    bad = tmp_path / "bad.csv"
    bad.write_text("sx,sy\n1,2\n")
    argv = [str(pairs_csv(tmp_path / "p.csv")) if a == "P" else str(bad) if a == "BAD" else a for a in argv]
    argv = [str(tmp_path / a) if a.endswith((".gpkg", ".geojson", ".csv")) and "/" not in a else a for a in argv]
    assert main(["-q", "plan", str(costmap), *argv]) == EXIT_USER
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1


class CancelAfter(NullProgress):
    """Cancelled once ``n`` routes were counted."""

    def __init__(self, n: int) -> None:
        super().__init__()
        self.n, self.done = n, 0

    def advance(self, n: int = 1) -> None:
        self.done += n

    def cancelled(self) -> bool:
        return self.done >= self.n


def test_cancel_between_routes_writes_nothing(costmap: Path, tmp_path: Path) -> None:
    out = tmp_path / "routes.gpkg"
    options = PairsOptions(costmap=costmap, pairs=pairs_csv(tmp_path / "p.csv"), out=out)
    with pytest.raises(Cancelled):
        run_pairs(options, CancelAfter(1))
    assert not out.exists() and not (tmp_path / "manifest.json").exists()


def test_pairs_json_names_each_routes_cost_as_plan_does(costmap: Path, tmp_path: Path, capsys) -> None:
    """`plan --pairs --json` says ``total_cost`` as `plan --json` and the routes GeoPackage do;
    the old ``cost`` key stays, the same figure, for scripts written against it (deprecated)."""
    out = tmp_path / "routes.gpkg"
    assert (
        main(["-q", "plan", str(costmap), "--pairs", str(pairs_csv(tmp_path / "p.csv")), "--out", str(out), "--json"])
        == 0
    )
    doc = json.loads(capsys.readouterr().out)
    layer = read_routes(out)
    for route in doc["routes"]:
        assert route["total_cost"] == layer[route["id"]]["total_cost"] and route["cost"] == route["total_cost"]


def test_a_matrix_prices_the_good_points_and_names_every_blocked_one(tmp_path: Path, capsys) -> None:
    """Two of four points on impassable cells: the others are priced as single plans price them,
    the blocked ones' rows and columns are empty, and one note names both (issue 33 rule 6)."""
    cost = smooth_costmap((60, 80), seed=3, lethal_fraction=0.0)
    cost[30, 30] = cost[10, 60] = np.inf
    costmap = write_costmap(tmp_path / "costmap.tif", cost)
    centre = lambda r, c: (500000.0 + (c + 0.5) * 0.5, 4000000.0 - (r + 0.5) * 0.5)  # noqa: E731
    named = {"a": centre(2, 2), "wall1": centre(30, 30), "b": centre(50, 70), "wall2": centre(10, 60)}
    pts = tmp_path / "pts.csv"
    pts.write_text("id,x,y\n" + "".join(f"{k},{x},{y}\n" for k, (x, y) in named.items()))
    out = tmp_path / "m.csv"
    assert main(["-q", "plan", str(costmap), "--points", str(pts), "--matrix", str(out), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["notes"] == ["2 of the points lie on impassable cells, their costs left empty: 'wall1', 'wall2'"]
    rows = {r[0]: r[1:] for r in (line.split(",") for line in out.read_text().splitlines())}
    header = rows.pop("from")
    assert header == list(named)
    for blocked in ("wall1", "wall2"):
        assert rows[blocked] == ["", "", "", ""]
        assert all(rows[k][header.index(blocked)] == "" for k in rows)
    single = single_plan(costmap, named["a"], named["b"], tmp_path, capsys)
    assert float(rows["a"][header.index("b")]) == pytest.approx(single["total_cost"], rel=1e-12)
