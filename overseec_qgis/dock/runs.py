"""The dock's runs: Interpret, Segment, Build costmap and Run all as worker tasks into the current
run folder, their results as layers, and the map tool's paths and overrides saved beside the
costmap. The Run box also shows the job's progress and status line."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from qgis.core import Qgis, QgsProject, QgsRasterLayer
from qgis.PyQt.QtCore import pyqtSignal
from qgis.PyQt.QtWidgets import QGroupBox, QHBoxLayout, QLabel, QProgressBar, QPushButton, QVBoxLayout

from overseec_core import runfiles

from .. import envcheck, jobs
from ..layers import (
    Provenance,
    add_costmap,
    add_run_outputs,
    apply_style,
    run_group,
    set_provenance,
)
from ..override_layer import open_overrides
from ..task import WorkerTask, log
from .common import CurrentRun, DockSettings, JobSlot
from .imagery import ImagerySection
from .mission import MissionSection

#: The operator overrides the dock draws, in the run folder (applied by Build costmap and the map tool).


def add_lethal(path: str | Path, group, prov: Provenance, name: str) -> QgsRasterLayer | None:
    """The costmap's lethal sidecar above it: lethal cells black, keep-out zones purple, the rest
    transparent. The costmap gives lethal cells 1.0 like the most avoided ground, so only the
    sidecar tells them apart."""
    from ..legend import unique_name

    layer = QgsRasterLayer(str(path), unique_name(name), "gdal")
    if not layer.isValid():
        log(f"costmap: QGIS cannot open {path}", Qgis.Warning)
        return None
    apply_style(layer, "lethal")
    set_provenance(layer, prov, "lethal")
    QgsProject.instance().addMapLayer(layer, False)
    group.addLayer(layer)
    return layer


def overrides_layers(source: str) -> list:
    """The project's overrides layers drawn from ``source`` (the gpkg's path)."""
    return [
        lyr
        for lyr in QgsProject.instance().mapLayers().values()
        if lyr.customProperty("overseec/role") == "overrides" and lyr.source().split("|")[0] == source
    ]


class RunsSection(QGroupBox):
    """The "Run" box and the stages it runs (Interpret too: its button is in the Mission box)."""

    #: Run all has finished every stage (the run directory)
    run_done = pyqtSignal(str)

    def __init__(
        self,
        iface,
        settings: DockSettings,
        run: CurrentRun,
        slot: JobSlot,
        imagery: ImagerySection,
        mission: MissionSection,
    ) -> None:
        super().__init__("Run")
        self.iface = iface
        self.settings = settings
        self.run = run
        self.slot = slot
        self.imagery = imagery
        self.mission = mission
        #: the plugin's map tool (None until the plugin shares it)
        self.map_tool = None
        self._build()
        slot.said.connect(self.status_label.setText)
        slot.progress.connect(self.progress_bar.setValue)
        slot.busy_changed.connect(self._set_busy)

    def _build(self) -> None:
        v = QVBoxLayout(self)
        row = QHBoxLayout()
        self.segment_button = QPushButton("Segment")
        self.segment_button.setToolTip("Find the entities in the image (worker process)")
        self.segment_button.clicked.connect(lambda _checked=False: self.segment())
        self.costmap_button = QPushButton("Build costmap")
        self.costmap_button.setToolTip("Cost program + the current run's masks -> costmap")
        self.costmap_button.clicked.connect(lambda _checked=False: self.build_costmap())
        self.plan_button = QPushButton("Plan on map")
        self.plan_button.setCheckable(True)
        self.plan_button.setToolTip("Click start, Shift+click vias, click goal; Esc cancels")
        self.run_button = QPushButton("Run all")
        self.run_button.setToolTip(
            "Interpret (if the prompt changed), segment (unless a class raster "
            "is chosen), build the costmap: into a new run folder"
        )
        self.run_button.clicked.connect(lambda _checked=False: self.run_to_costmap())
        for b in (self.run_button, self.segment_button, self.costmap_button):
            row.addWidget(b)
        v.addLayout(row)
        row = QHBoxLayout()
        self.save_paths_button = QPushButton("Save planned paths")
        self.save_paths_button.setToolTip(
            "Write the map tool's paths as GeoJSON into the run folder and add them as a layer that the project keeps"
        )
        self.save_paths_button.clicked.connect(lambda _checked=False: self.save_paths())
        self.overrides_button = QPushButton("Draw overrides")
        self.overrides_button.setToolTip(
            f"Edit {runfiles.OVERRIDES_LAYER} beside the costmap: polygons with cost (0-1), prefer or lethal, "
            "applied while planning (each edit re-plans the route) and by `overseec costmap "
            "--override`"
        )
        self.overrides_button.clicked.connect(lambda _checked=False: self.edit_overrides())
        row.addWidget(self.plan_button)
        row.addWidget(self.save_paths_button)
        row.addWidget(self.overrides_button)
        v.addLayout(row)
        row = QHBoxLayout()
        self.progress_bar = QProgressBar()
        self.progress_bar.setRange(0, 100)
        self.cancel_button = QPushButton("Cancel")
        self.cancel_button.clicked.connect(self.slot.cancel)
        row.addWidget(self.progress_bar)
        row.addWidget(self.cancel_button)
        v.addLayout(row)
        self.status_label = QLabel("")
        self.status_label.setWordWrap(True)
        v.addWidget(self.status_label)

    def _set_busy(self, busy: bool) -> None:
        for b in (self.segment_button, self.costmap_button, self.run_button):
            b.setEnabled(not busy)
        self.cancel_button.setEnabled(busy)
        if not busy:
            self.progress_bar.setValue(0)

    def _require_image(self) -> str | None:
        image = self.imagery.image_path()
        if not image:
            self.slot.fail("input", "choose an input raster layer or file first")
            return None
        return image

    # -- The stages --------------------------------------------------------------------------

    def interpret(self, then: Callable[[], None] | None = None) -> None:
        """Interpret the mission prompt in the worker, then show it in the table and program box."""
        prompt = self.mission.prompt()
        if not prompt:
            self.slot.fail("interpret", "write a mission prompt first")
            return
        priors, terrain = self.mission.priors(), bool(self.mission.dem_path())
        try:
            argv, env = jobs.interpret_command(
                self.settings.worker(), prompt, self.settings.llm_config(), priors, terrain=terrain
            )
        except (LookupError, jobs.OverseecError) as exc:
            self.slot.fail("interpret", str(exc))
            return
        task = WorkerTask(
            "overseec: interpret",
            argv,
            env=env,
            weights={"interpret": 1.0},
            capture=True,
            after=self.mission.fit_job(priors),  # reading the layers' names stays off the GUI thread
        )
        self.slot.start(
            "interpret",
            task,
            lambda result: self.mission.show_interpretation(result[0], priors, result[1], terrain=terrain),
            then,
        )

    def segment(self, then: Callable[[], None] | None = None) -> None:
        """Find the (edited) interpretation's entities in the image: masks in the run folder."""
        image = self._require_image()
        if image is None:
            return
        try:
            interp = self.mission.current_interpretation()
        except (ValueError, jobs.OverseecError) as exc:
            self.slot.fail("segment", str(exc))
            return
        if not interp.entities:
            self.slot.fail("segment", "no entities: interpret a prompt or add entities to the table")
            return
        run_dir = self.run.ensure_run_dir(image)
        try:
            params = self.settings.params()
            argv, env = jobs.segment_command(
                self.settings.worker(), image, run_dir, interp, params, self.imagery.bands()
            )
        except (LookupError, jobs.OverseecError) as exc:
            self.slot.fail("segment", str(exc))
            return
        worker = Path(argv[0])

        def models_present() -> str:  # on the task thread: names every missing model at once
            return envcheck.segment_problem(
                worker,
                params.clipseg_model,
                params.sam_model,
                params.refine,
                refiner=params.refiner,
                segmenter=params.segmenter,
                model=params.model,
            )

        task = WorkerTask(
            "overseec: segment",
            argv,
            env=env,
            weights=jobs.stage_weights("segment", params),
            precheck=models_present,
        )
        self.slot.start(
            "segment", task, lambda _r: self._add_outputs(run_dir, "segment", ("mask", "probability")), then
        )

    def build_costmap(self, then: Callable[[], None] | None = None) -> None:
        """The cost program over the entity layers (and the run's overrides): a new costmap."""
        src = self.mission.layer_sources()
        if not src["masks_dir"] and not (src["labels"] and src["classes"]):
            self.slot.fail(
                "costmap",
                "no entity layers: run Segment (or Run all) first, or choose a class raster and its classes.json",
            )
            return
        if not self.mission.names_known():  # read in a task: opening the layers never blocks QGIS
            self.slot.say("costmap: reading the entity layers' names…")
            self.mission.load_names(lambda: self.build_costmap(then))
            return
        if not self.mission.validate_program():
            self.slot.fail("costmap", "fix the cost program first (" + self.mission.program_status.text() + ")")
            return
        run_dir = self.run.run_dir if self.run.run_dir is not None else self.run.ensure_run_dir(src["labels"])
        out = jobs.next_costmap_path(run_dir)
        prompt = self.mission.prompt()
        program = self.mission.program_edit.toPlainText()
        try:
            overrides = self._run_overrides(run_dir)
            argv, env = jobs.costmap_command(self.settings.worker(), out, program, overrides=overrides, **src)
        except (LookupError, OSError, jobs.OverseecError) as exc:
            self.slot.fail("costmap", str(exc))
            return
        task = WorkerTask("overseec: costmap", argv, env=env, weights={"costmap": 1.0}, capture=True)
        if self.map_tool is not None:
            self.map_tool.warm_up()  # the planner worker starts while the costmap is built
        self.slot.start(
            "costmap",
            task,
            lambda _r: self._add_costmap(
                run_dir, jobs.CostmapSummary.from_json(jobs.result_document(task.printed)), prompt
            ),
            then,
        )

    def _run_overrides(self, run_dir: Path) -> tuple[Path, ...]:
        """The project's overrides -- every overrides layer in it, whatever run folder is current
        (they belong to the project, not to a folder) -- as Processing and `overseec costmap
        --override` apply them: unsaved edits included, never ignored; a feature the core would
        refuse (an all-NULL polygon from QGIS's own Add Polygon) skipped with one warning that
        names it, never an error that stops the costmap.

        A saved layer whose every feature is usable is applied as its own file. Otherwise the
        layer as it is now (saved features and edit buffer, usable features only) is written to
        a snapshot beside the costmap about to be built (``costmap-2.tif`` ->
        ``costmap-2-overrides.gpkg``, then ``-overrides-2.gpkg`` ...) and that is applied. A
        snapshot rather than committing the layer: the analyst's own file is saved only when
        they save it (QGIS's rule), committing would also clear the layer's undo history, and
        the snapshot records exactly which polygons this costmap applied. A snapshot that cannot
        be written raises OSError (one line): the costmap is not built without them."""
        from .. import overridetool
        from ..overridecheck import project_overrides_layers, push_skipped, usable_features

        costmap = jobs.next_costmap_path(run_dir)
        applied: list[Path] = []
        skipped_all = []
        for n, layer in enumerate(project_overrides_layers(), start=1):
            source = Path(layer.source().split("|")[0])
            usable, skipped = usable_features(layer)
            skipped_all += skipped
            if not usable:
                continue
            if not layer.isModified() and not skipped and source.is_file():
                applied.append(source)
                continue
            suffix = "" if n == 1 else f"-{n}"
            snapshot = costmap.with_name(f"{costmap.stem}-{Path(runfiles.OVERRIDES_LAYER).stem}{suffix}.gpkg")
            written = overridetool.write_overrides_snapshot(layer, snapshot)
            if written is not None:
                log(f"costmap: applying {layer.name()} ({source}) as it is now, as {written}")
                applied.append(written)
        push_skipped(self.iface, skipped_all)
        for s in skipped_all:
            log(f"costmap: {s.describe()}")
        if applied:
            self.slot.say(f"costmap: applying the overrides in {', '.join(p.name for p in applied)}")
            log(f"costmap: applying the overrides in {', '.join(str(p) for p in applied)}")
        return tuple(applied)

    def run_to_costmap(self) -> None:
        """Every stage in order, as the buttons would run them, into a new run directory:
        interpret (unless the table already holds this prompt's interpretation, possibly
        edited), segment (skipped when a class raster provides the entity layers), costmap.
        The form's parameters and the user's edits to entities and program all apply."""
        image = self._require_image()
        if image is None:
            return
        if not self.mission.prompt():
            self.slot.fail("run", "write a mission prompt first")
            return
        src = self.mission.layer_sources()
        use_labels = bool(src["labels"] and src["classes"])
        self.run.ensure_run_dir(image, new=True)
        self.mission.masks_updated()

        def after_interpret() -> None:
            if use_labels:
                self.build_costmap(then=self._run_finished)
            else:
                self.segment(then=lambda: self.build_costmap(then=self._run_finished))

        if self.mission.needs_interpreting():
            self.interpret(then=after_interpret)
        else:
            after_interpret()

    def _run_finished(self) -> None:
        self.slot.say(f"run: done, outputs in {self.run.run_dir}")
        self.run_done.emit(str(self.run.run_dir))

    # -- Results -> layers -------------------------------------------------------------------

    def _add_outputs(self, run_dir: Path, stage: str, roles) -> None:
        """A stage's outputs as a new group, below the routes group (layers.run_group)."""
        self.mission.masks_updated()
        _group, layers = add_run_outputs(run_dir, f"overseec {stage}: {run_dir.name}", roles=roles)
        self.slot.say(f"{stage}: done, {len(layers)} layer(s) added")

    def _add_costmap(self, run_dir: Path, result, prompt: str) -> None:
        """The new costmap and its lethal sidecar as a group below the routes group, the costmap
        named by its prompt (unique in the project; the file's name without a prompt)."""
        from ..legend import layer_name

        prov = Provenance(
            run_dir=str(run_dir),
            prompt=prompt,
            program=result.program,
            entities=tuple(result.entities),
            stage="costmap",
            extra=(("program file", str(result.program_file)),),
        )
        group = run_group(f"overseec costmap: {run_dir.name}/{result.costmap.stem}")
        if Path(result.lethal).is_file():
            add_lethal(result.lethal, group, prov, name=f"{result.costmap.stem} lethal / keep-out")
        layer = add_costmap(
            result.costmap, group, prov, name=layer_name("costmap", prompt, result.costmap.stem, QgsProject.instance())
        )
        if self.map_tool is not None:
            self.map_tool.set_costmap(layer)
        for note in tuple(result.notes) + tuple(result.warnings):
            log(f"costmap: {note}")
        self.slot.say(
            f"costmap: done ({result.costmap}, mean cost "
            f"{result.mean_cost if result.mean_cost is None else round(result.mean_cost, 3)})"
        )

    # -- The map tool's paths and overrides ------------------------------------------------

    def save_paths(self) -> Path | None:
        """The planned paths -> ``paths-N.geojson`` beside their costmap, then a layer in the
        routes group. The paths are the project's paths layer of the map tool's costmap (or the
        map tool's layer, the active one, the topmost): a reopened project's loaded layers do, and
        nothing here waits for the planner worker. The routes are copied here; the file is
        written and opened by a task (:attr:`save_task` until it is done), so the GUI never waits
        on the disk. Returns the file being written."""
        from qgis.core import QgsApplication

        from ..savedpaths import SavePathsTask, paths_costmap, paths_snapshot

        layer = self._paths_to_save()
        if layer is None:
            self.slot.fail("save paths", "no planned paths yet: use Plan on map first")
            return None
        costmap = paths_costmap(layer)
        folder = costmap.parent if costmap is not None else Path(layer.source().split("|")[0]).parent
        n = 1
        while (folder / f"paths-{n}.geojson").exists() or (folder / f".paths-{n}.partial.geojson").exists():
            n += 1
        path = folder / f"paths-{n}.geojson"
        snapshot = paths_snapshot(layer)
        extra = (("costmap", str(costmap)),) if costmap is not None else ()
        prov = Provenance(run_dir=str(folder), prompt=snapshot.prompt, stage="plan", extra=extra)
        task = SavePathsTask(snapshot, path, lambda saved, error: self._paths_saved(path, saved, error, prov))
        self.save_task: SavePathsTask | None = task
        QgsApplication.taskManager().addTask(task)
        self.slot.say(f"saving the paths to {path} ...")
        return path

    def _paths_saved(self, path: Path, layer, error: str, prov: Provenance) -> None:
        """The save task is done: the saved paths as a layer in the routes group, or why not."""
        from ..legend import layer_name
        from ..savedpaths import adopt_path_layer

        self.save_task = None
        if layer is None:
            self.slot.fail("save paths", error)
            return
        adopt_path_layer(layer, prov, layer_name("saved paths", prov.prompt, path.stem, QgsProject.instance()))
        self.slot.say(f"paths saved to {path}")

    def _paths_to_save(self):
        """The paths layer Save planned paths writes: the one of the map tool's costmap, else the
        tool's own, the active layer, then the topmost; only one holding a route."""
        from ..savedpaths import paths_costmap, paths_layers

        project = QgsProject.instance()
        loaded = {lyr.id(): lyr for lyr in paths_layers(project) if lyr.featureCount()}

        def loaded_id(layer) -> str | None:  # the tool's layers may be gone with a closed project
            try:
                return layer.id() if layer is not None and layer.id() in loaded else None
            except RuntimeError:
                return None

        tool = self.map_tool
        preferred = []
        costmap = getattr(tool, "costmap_layer", None)
        try:
            alive = costmap is not None and project.mapLayer(costmap.id()) is costmap
            source = Path(costmap.source().split("|")[0]) if alive and costmap is not None else None
        except RuntimeError:
            source = None
        if source is not None:
            preferred += [key for key, lyr in loaded.items() if paths_costmap(lyr, project) == source]
        preferred.append(loaded_id(getattr(tool, "paths_layer", None)))
        if self.iface is not None:
            preferred.append(loaded_id(self.iface.activeLayer()))
        return next((loaded[key] for key in [*preferred, *loaded] if key is not None), None)

    def edit_overrides(self, start_editing: bool = True):
        """Open (or create) ``overrides.gpkg`` beside the current costmap, in edit mode, and have
        the map tool plan with it: drawing or editing a polygon re-plans the route.

        The folder is the costmap layer's (the map tool's, else the project's topmost): found
        from the layer alone, so opening the overrides never waits for the planner worker to
        load the costmap. The override tool opens its layer through here too, with
        ``start_editing=False``: it turns editing on itself on the next turn of the event loop,
        so no single step holds the GUI long (QGIS updates every editing action then)."""
        tool = self.map_tool
        if tool is None:
            self.slot.fail("overrides", "no map tool: the plugin is not loaded")
            return None
        import os

        from ..maptool import find_costmap_layer

        costmap = tool.costmap_layer
        if costmap is None or not costmap.isValid() or QgsProject.instance().mapLayer(costmap.id()) is None:
            costmap = find_costmap_layer()
        if costmap is None:
            self.slot.fail("overrides", f"no costmap layer: build a costmap first (or add {runfiles.COSTMAP})")
            return None
        folder = Path(os.path.abspath(costmap.dataProvider().dataSourceUri().split("|")[0])).parent
        source = str(folder / runfiles.OVERRIDES_LAYER)
        layer = next(iter(overrides_layers(source)), None)
        if layer is None:
            try:
                layer = open_overrides(folder)  # into the routes group (legend.add_to_routes)
            except ValueError as exc:
                self.slot.fail("overrides", str(exc))
                return None
        tool.set_overrides_layer(layer)
        if start_editing:
            layer.startEditing()
        if self.iface is not None:
            from qgis.PyQt.QtCore import QTimer

            layer_id, iface = layer.id(), self.iface

            def make_current() -> None:
                current = QgsProject.instance().mapLayer(layer_id)
                if current is not None:
                    iface.setActiveLayer(current)

            QTimer.singleShot(0, make_current)  # on the next turn of the event loop: each step stays short
        self.slot.say(
            f"overrides: draw polygons in {source}; set cost, prefer or lethal; the route re-plans on each edit"
        )
        return layer
