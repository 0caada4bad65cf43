"""The dock's "Routes" box: the least-cost corridor of the current route, and many routes at once.

* **Corridor** runs ``overseec corridor`` (a :class:`WorkerTask`) between the map tool's start
  and goal (its vias are not part of a corridor) on the costmap it plans on, within the box's
  percentage of the optimum, into the costmap's run folder (``corridor.tif``, ``corridor-2.tif``
  ...; the mask beside it). Both rasters load styled (``corridor.qml`` with its ramp stretched to
  the percentage, ``corridor_mask.qml``) in a group right below the routes group.
* **Plan pairs** runs ``overseec plan --pairs`` (a WorkerTask) on the same costmap for every
  start/goal pair of a CSV file, a layer of lines (first vertex -> last vertex), or a point
  layer of starts with a point layer of goals (paired by ``id`` or by order). A layer's pairs are
  written as the CLI's CSV in the costmap's CRS on the task's thread (from a feature-source
  snapshot), so a large layer never blocks QGIS. ``routes.gpkg`` (``routes-2.gpkg`` ...) loads
  into the routes group, named by the costmap's prompt.

Both apply the saved overrides beside the costmap (``overrides.gpkg``), as the map tool's plans
do, and share the dock's one job slot (one overseec job at a time, Cancel stops the worker).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from qgis.core import (
    QgsMapLayerProxyModel,
    QgsProject,
    QgsRasterLayer,
    QgsVectorLayer,
    QgsWkbTypes,
)
from qgis.gui import QgsFileWidget, QgsMapLayerComboBox
from qgis.PyQt.QtWidgets import (
    QDoubleSpinBox,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QVBoxLayout,
)

from overseec_core import defaults, runfiles

from .. import jobs, pairsfile
from ..layers import Provenance, apply_style, run_group, set_provenance, style_route
from ..legend import add_to_routes, layer_name
from ..task import WorkerTask
from .common import DockSettings, JobSlot

#: The corridor's default percentage over the optimum (Processing's dialog offers the same).
DEFAULT_WITHIN_PCT = 10.0
#: The routes GeoPackage of Plan pairs: named after the layer the CLI writes in it.
ROUTES_FILE = f"{runfiles.PAIRS_LAYER}.gpkg"
#: The costmap layer's property holding its prompt (layers.set_provenance).
PROMPT_PROPERTY = "overseec/prompt"


def next_free(folder: Path, name: str, suffix: str = "") -> Path:
    """``folder/name``, else ``name-2``, ``name-3`` ... (stem + n), the first free one; with
    ``suffix`` the companion file ``stem + suffix`` must be free too (a corridor's mask)."""
    first = Path(name)

    def taken(path: Path) -> bool:
        return path.exists() or (bool(suffix) and path.with_name(path.stem + suffix).exists())

    candidate, n = folder / first, 2
    while taken(candidate):
        candidate = folder / f"{first.stem}-{n}{first.suffix}"
        n += 1
    return candidate


def saved_overrides(costmap: Path) -> tuple[Path, ...]:
    """The saved overrides beside the costmap (the dock's Draw overrides file), if any."""
    path = costmap.with_name(runfiles.OVERRIDES_LAYER)
    return (path,) if path.is_file() else ()


class RoutesSection(QGroupBox):
    """The "Routes" box: Corridor (for the map tool's route) and Plan pairs (many routes)."""

    def __init__(self, iface, settings: DockSettings, slot: JobSlot, map_tool: Callable[[], Any], parent=None) -> None:
        super().__init__("Routes", parent)
        self.iface = iface
        self.settings = settings
        self.slot = slot
        #: the plugin's map tool (None until the plugin shares it with the dock)
        self.map_tool = map_tool
        self._build()
        slot.busy_changed.connect(self._set_busy)

    def _build(self) -> None:
        v = QVBoxLayout(self)
        row = QHBoxLayout()
        self.within_spin = QDoubleSpinBox()
        self.within_spin.setRange(0.1, 1000.0)
        self.within_spin.setDecimals(1)
        self.within_spin.setSuffix(" %")
        self.within_spin.setValue(DEFAULT_WITHIN_PCT)
        self.within_spin.setToolTip("The corridor's mask holds the cells of routes at most this much dearer")
        self.corridor_button = QPushButton("Corridor")
        self.corridor_button.setToolTip(
            "The least-cost corridor between the planned route's start and goal: each cell's best "
            "route cost over the optimum, and the cells within the percentage (`overseec corridor`)"
        )
        self.corridor_button.clicked.connect(lambda _checked=False: self.corridor())
        row.addWidget(QLabel("Within"))
        row.addWidget(self.within_spin)
        row.addWidget(self.corridor_button)
        v.addLayout(row)
        form = QFormLayout()
        self.pairs_combo = QgsMapLayerComboBox()
        self.pairs_combo.setFilters(QgsMapLayerProxyModel.LineLayer | QgsMapLayerProxyModel.PointLayer)
        self.pairs_combo.setAllowEmptyLayer(True)
        self.pairs_combo.setLayer(None)
        self.pairs_combo.setToolTip("Lines from start to goal, or points: the starts (goals in the next box)")
        self.pairs_combo.layerChanged.connect(self._pairs_layer_changed)
        self.goals_combo = QgsMapLayerComboBox()
        self.goals_combo.setFilters(QgsMapLayerProxyModel.PointLayer)
        self.goals_combo.setAllowEmptyLayer(True)
        self.goals_combo.setLayer(None)
        self.goals_combo.setToolTip("The goals of the start points, paired by an 'id' field, else by order")
        self.pairs_file = QgsFileWidget()
        self.pairs_file.setFilter("CSV (*.csv);;All files (*)")
        self.pairs_file.setToolTip(
            "Or a CSV file start_x,start_y,goal_x,goal_y[,id] in the costmap's CRS (used instead of a layer)"
        )
        form.addRow("Pairs layer", self.pairs_combo)
        form.addRow("Goal points", self.goals_combo)
        form.addRow("or CSV", self.pairs_file)
        v.addLayout(form)
        self.pairs_button = QPushButton("Plan pairs")
        self.pairs_button.setToolTip(
            "One route per start/goal pair on the map tool's costmap, into routes.gpkg in its run folder "
            "(`overseec plan --pairs`)"
        )
        self.pairs_button.clicked.connect(lambda _checked=False: self.plan_pairs())
        v.addWidget(self.pairs_button)
        self._pairs_layer_changed(None)

    def _set_busy(self, busy: bool) -> None:
        for b in (self.corridor_button, self.pairs_button):
            b.setEnabled(not busy)

    def _pairs_layer_changed(self, layer) -> None:
        """Goal points are asked for only when the pairs layer is a point layer (the starts)."""
        self.goals_combo.setEnabled(self._is_points(layer))

    @staticmethod
    def _is_points(layer) -> bool:
        return isinstance(layer, QgsVectorLayer) and layer.geometryType() == QgsWkbTypes.PointGeometry

    def _costmap(self, stage: str) -> tuple[Any, Path] | None:
        """The map tool and the file of the costmap it plans on; None (and a message) without."""
        tool = self.map_tool()
        path = tool.costmap_path() if tool is not None else None
        if not path:
            self.slot.fail(stage, "no costmap to plan on: build one (or add a costmap layer) first")
            return None
        return tool, Path(path)

    # -- Corridor ----------------------------------------------------------------------------

    def corridor(self) -> None:
        """The corridor of the map tool's route (start and goal) as a worker task."""
        found = self._costmap("corridor")
        if found is None:
            return
        tool, costmap = found
        if not tool.complete or len(tool.points) < 2:
            self.slot.fail("corridor", "plan a route on the map first (Plan on map: click start, then goal)")
            return
        start, goal = tool.points[0], tool.points[-1]
        crs = jobs.crs_text(tool.canvas.mapSettings().destinationCrs())
        within = float(self.within_spin.value())
        out = next_free(costmap.parent, runfiles.CORRIDOR, runfiles.CORRIDOR_MASK_SUFFIX)
        try:
            argv, env = jobs.corridor_command(
                self.settings.worker(),
                costmap,
                (start.x(), start.y()),
                (goal.x(), goal.y()),
                within,
                out,
                crs,
                saved_overrides(costmap),
            )
        except (LookupError, OSError, jobs.OverseecError) as exc:
            self.slot.fail("corridor", str(exc))
            return
        mask = Path(argv[argv.index("--mask-out") + 1])
        prov = Provenance(run_dir=str(costmap.parent), prompt=self._prompt(tool), stage="corridor")
        task = WorkerTask(
            "overseec: corridor", argv, env=env, weights={"corridor": 1.0}, capture=True, after=self._document
        )
        steps = int(getattr(tool, "neighbours", 8))
        self.slot.start("corridor", task, lambda doc: self._add_corridor(out, mask, within, doc, prov, steps))

    @staticmethod
    def _document(printed: list[str]) -> dict[str, Any]:
        """The command's ``--json`` document (on the task's thread)."""
        doc = jobs.result_document(printed)
        if not doc:
            raise jobs.InputError("the worker printed no result document")
        return doc

    def _add_corridor(
        self, out: Path, mask: Path, within: float, doc: dict[str, Any], prov: Provenance, steps: int = 8
    ) -> None:
        """Both rasters, styled, in a group right below the routes group; ``steps`` the map tool's
        (the corridor steps to 8 neighbours, which the message says when the route used 16)."""
        from ..processing.corridor import corridor_name, stretch_corridor_style

        optimum, cells = float(doc["optimum"]), int(doc["cells_within"])
        project = QgsProject.instance()
        group = run_group(f"overseec corridor: {out.parent.name}/{out.stem}", project)
        ratio = QgsRasterLayer(str(out), layer_name(corridor_name(within, optimum), project=project), "gdal")
        mask_name = layer_name(f"corridor mask — within {within:g} %", project=project)
        within_mask = QgsRasterLayer(str(mask), mask_name, "gdal")
        for layer, style in ((ratio, "corridor"), (within_mask, "corridor_mask")):  # the ratio on top
            if not layer.isValid():
                raise ValueError(f"QGIS cannot open {layer.source()}")
            apply_style(layer, style)
            set_provenance(layer, prov, "corridor")
            project.addMapLayer(layer, False)
            group.addLayer(layer)
        stretch_corridor_style(ratio, within)
        said = f"corridor: optimum {optimum:.6g}, {cells} cells within {within:g} % ({out.name})"
        if steps != 8:
            said += f"; the corridor steps to 8 neighbours, the route on the map to {steps}"
        self.slot.say(said)

    # -- Plan pairs ----------------------------------------------------------------------------

    def plan_pairs(self) -> None:
        """One route per pair (the CSV, or the chosen layer(s)) as a worker task."""
        found = self._costmap("pairs")
        if found is None:
            return
        tool, costmap = found
        out = next_free(costmap.parent, ROUTES_FILE)
        try:
            pairs, precheck = self._pairs_input(tool, out)
            argv, env = jobs.pairs_command(
                self.settings.worker(),
                costmap,
                pairs,
                out,
                getattr(tool, "mode", defaults.PLAN_MODE),
                overrides=saved_overrides(costmap),
                neighbours=getattr(tool, "neighbours", defaults.PLAN_NEIGHBOURS[0]),
            )
        except (LookupError, OSError, jobs.OverseecError) as exc:
            self.slot.fail("pairs", str(exc))
            return
        prov = Provenance(run_dir=str(costmap.parent), prompt=self._prompt(tool), stage="plan")
        task = WorkerTask(
            "overseec: plan pairs",
            argv,
            env=env,
            weights={"pairs": 1.0},
            precheck=precheck,
            capture=True,
            after=self._document,
        )
        self.slot.start("pairs", task, lambda doc: self._add_routes(out, doc, prov))

    def _pairs_input(self, tool, out: Path) -> tuple[Path, Callable[[], str] | None]:
        """The pairs file for the CLI and, for a layer, the precheck that writes it on the
        task's thread. The pairs are read and transformed to the costmap's CRS here, on the GUI
        thread (see :mod:`..pairsfile` for why); a pair of layers that does not pair up is
        reported by the precheck, as the task's failure, like any other reason not to plan."""
        csv_file = self.pairs_file.filePath().strip()
        if csv_file:
            if not Path(csv_file).is_file():
                raise jobs.InputError(f"no such pairs file: {csv_file}")
            return Path(csv_file), None
        layer = self.pairs_combo.currentLayer()
        if not isinstance(layer, QgsVectorLayer):
            raise jobs.InputError("choose a pairs layer (lines, or start points with goal points) or a CSV file")
        crs = tool.costmap_layer.crs()
        context = QgsProject.instance().transformContext()
        target = out.with_name(f"{out.stem}.pairs.csv")
        points = self._is_points(layer)
        goals = self.goals_combo.currentLayer()
        if points and not self._is_points(goals):
            raise jobs.InputError("start points need goal points: choose the goals' point layer")
        pairs: list[pairsfile.Pair] = []
        problem = ""
        try:
            if points:
                to_costmap = pairsfile.transform_to(layer, crs, context)
                pairs = pairsfile.point_pairs(layer, goals, to_costmap, pairsfile.transform_to(goals, crs, context))
            else:
                pairs = pairsfile.line_pairs(layer, pairsfile.transform_to(layer, crs, context))
        except jobs.OverseecError as exc:
            problem = str(exc)

        def write() -> str:  # the task's thread: "" to go ahead, else why not
            if problem:
                return problem
            try:
                pairsfile.write_pairs(pairs, target)
            except (jobs.OverseecError, OSError) as exc:
                return str(exc)
            return ""

        return target, write

    def _add_routes(self, out: Path, doc: dict[str, Any], prov: Provenance) -> None:
        """The routes GeoPackage into the routes group, named by the costmap's prompt."""
        routes = doc.get("routes") or []
        planned = [r for r in routes if r.get("total_cost") is not None]
        for route in routes:
            if route.get("error"):
                self.slot.warn("pairs", str(route["error"]))
        project = QgsProject.instance()
        name = layer_name("routes", prov.prompt, f"routes — {out.stem}", project)
        layer = QgsVectorLayer(f"{out}|layername={runfiles.PAIRS_LAYER}", name, "ogr")
        if not layer.isValid():
            raise ValueError(f"QGIS cannot open {out}")
        style_route(layer, project)
        set_provenance(layer, prov, "path")
        add_to_routes(layer, project)
        self.slot.say(f"pairs: {len(planned)} of {len(routes)} routes planned ({out.name})")

    @staticmethod
    def _prompt(tool) -> str:
        layer = getattr(tool, "costmap_layer", None)
        return str(layer.customProperty(PROMPT_PROPERTY, "") or "") if layer is not None else ""
