"""The overseec dock panel: input, mission prompt, entities, cost program, parameters, runs.

Widgets are built in code (no .ui file) so the layout is reviewable in one place. The dock holds
no logic of its own: every stage (the image reading check, interpret, segment, build costmap)
runs the ``overseec`` CLI of the overseec environment as a worker process, built by
:mod:`overseec_qgis.jobs` and read back from its ``--json`` document, so QGIS's own Python needs
neither rasterio nor the planner kernel (Windows and macOS QGIS have neither). Results become
layers through :mod:`overseec_qgis.layers`.

The current run directory is kept between stages, so re-prompting (Interpret, edit, Build
costmap) re-uses the masks already segmented for that image: seconds, not minutes.

Runs persist: run folders go under the runs folder of Settings › Options › overseec, by default
``overseec-runs`` beside the saved project (an unsaved project asks once per session); every
layer the dock adds points at a file of its run folder, and the project remembers the current
run folder (``overseec/run_dir``), so a reopened project shows the same masks, costmaps and paths
and the dock carries on with that run.

Machine-wide settings (environment, models, device, runs folder, LLM) are on the options page
(``options.py``); the dock's Environment box checks the environment, offers "Set up environment"
(``setup_env.py``) and keeps one message-bar warning that goes away once the check passes.
"""

from __future__ import annotations

import datetime as _dt
import tempfile
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any

from qgis.core import Qgis, QgsApplication, QgsMapLayerProxyModel, QgsProject, QgsRasterLayer
from qgis.gui import QgsDockWidget, QgsFileWidget, QgsMapLayerComboBox, QgsMessageBarItem
from qgis.PyQt.QtCore import Qt, QTimer, pyqtSignal
from qgis.PyQt.QtGui import QColor, QFontDatabase, QTextCursor, QTextFormat
from qgis.PyQt.QtWidgets import (
    QCheckBox,
    QComboBox,
    QDoubleSpinBox,
    QFileDialog,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QPlainTextEdit,
    QProgressBar,
    QPushButton,
    QScrollArea,
    QSpinBox,
    QTableWidget,
    QTableWidgetItem,
    QTextEdit,
    QVBoxLayout,
    QWidget,
)

from . import envcheck, jobs
from .extent_tool import ExtentMapTool
from .extract import ExtractTask, plan_extraction
from .layers import (
    Provenance,
    add_costmap,
    add_path,
    add_run_outputs,
    apply_style,
    open_overrides,
    run_group,
    set_provenance,
)
from .options import PAGE_NAME
from .settings import PluginSettings
from .setup_env import SetupEnvTask, default_venv, install_target
from .task import PipelineTask, WorkerTask, log

ENTITY_COLUMNS = ("name", "geometry", "threshold", "extra prompts")
#: The runs folder beside a saved project, when the settings name none.
RUNS_FOLDER = "overseec-runs"
#: The operator overrides the dock draws, in the run folder (applied by Build costmap and the map tool).
OVERRIDES_FILE = "overrides.gpkg"
#: Project entry (scope, key) that remembers the dock's current run folder.
PROJECT_SCOPE, PROJECT_RUN_KEY = "overseec", "run_dir"
#: Project entries (keys in PROJECT_SCOPE) of the mission's aliases and priors.
PROJECT_ALIASES_KEY, PROJECT_PRIORS_KEY, PROJECT_NO_PRIORS_KEY = "aliases", "priors", "no_priors"
#: How long information messages stay in the message bar (s).
INFO_S = 6
#: The image an extraction writes into its run folder.
EXTRACTED_IMAGE = "image.tif"
#: Ground resolution the Imagery box starts with (m per pixel).
DEFAULT_GSD_M = 0.5


def runs_root(setting: str, project_dir: str) -> Path | None:
    """Where run folders go: the setting, else ``overseec-runs`` beside the saved project
    (``project_dir``: ``QgsProject.absolutePath()``, "" for an unsaved project or one stored in a
    database), else None (the dock asks)."""
    if setting:
        return Path(setting).expanduser()
    if project_dir:
        return Path(project_dir) / RUNS_FOLDER
    return None


def add_lethal(path: str | Path, group, prov: Provenance, name: str) -> QgsRasterLayer | None:
    """The costmap's lethal sidecar above it: lethal cells black, keep-out zones purple, the rest
    transparent. The costmap gives lethal cells 1.0 like the most avoided ground, so only the
    sidecar tells them apart."""
    layer = QgsRasterLayer(str(path), name, "gdal")
    if not layer.isValid():
        log(f"costmap: QGIS cannot open {path}", Qgis.Warning)
        return None
    apply_style(layer, "lethal")
    set_provenance(layer, prov, "lethal")
    QgsProject.instance().addMapLayer(layer, False)
    group.addLayer(layer)
    return layer


def ask_runs_folder(parent) -> str:
    """Ask where runs go for an unsaved project ("" when the user declines)."""
    return QFileDialog.getExistingDirectory(
        parent,
        "overseec: where should runs be kept? (save the project first to keep them beside it)",
        str(Path.home()),
    )


class OverseecDock(QgsDockWidget):
    """The panel; its signals say when work finishes (the tests, and anything scripting the
    dock, wait on them)."""

    #: emitted after a task: (stage, ok)
    task_done = pyqtSignal(str, bool)
    #: emitted when Run all has finished every stage (the run directory)
    run_done = pyqtSignal(str)
    #: emitted with the EnvReport of an environment check
    env_checked = pyqtSignal(object)

    def __init__(self, iface, parent=None) -> None:
        super().__init__("overseec", parent)
        self.iface = iface
        self.settings = PluginSettings.load()
        self.interpretation = None  # overseec_core Interpretation from the last Interpret
        #: the priors the last Interpret ran with (Run all interprets again when they changed)
        self.interpretation_priors: jobs.Priors | None = None
        #: set while a project's mission fields are restored (not written back to it)
        self._restoring = False
        self.run_dir: Path | None = None
        self.run_image: str | None = None
        self.task = None
        self.env_task: PipelineTask | None = None
        #: the image reading check in flight (the latest one wins; older results are dropped)
        self.info_task: WorkerTask | None = None
        self.env_report = None
        self.map_tool = None
        self.plan_action = None
        self.extent_tool: ExtentMapTool | None = None
        #: the area to extract, in ``extract_crs`` (the canvas CRS when it was chosen)
        self.extract_extent = None
        self.extract_crs = None
        self.extract_plan = None
        self._env_checked = False
        #: the message-bar warning of the last environment check (removed once it passes)
        self._env_message: QgsMessageBarItem | None = None
        #: runs folder chosen for unsaved projects in this session (asked once)
        self._session_runs: Path | None = None
        #: asks where runs go when the project is unsaved and no runs folder is set
        self.ask_runs_folder: Callable[[], str] = lambda: ask_runs_folder(self)
        self._build()
        self._load_settings()
        self._program_timer = QTimer(self)
        self._program_timer.setSingleShot(True)
        self._program_timer.setInterval(300)
        self._program_timer.timeout.connect(self.validate_program)
        self.program_edit.textChanged.connect(self._program_timer.start)
        self.layer_combo.layerChanged.connect(self._input_changed)
        self.file_widget.fileChanged.connect(self._input_changed)
        self.bands_edit.editingFinished.connect(self._input_changed)
        self.labels_combo.layerChanged.connect(self._layers_changed)
        self.source_combo.layerChanged.connect(self.update_extract_plan)
        self.gsd_spin.valueChanged.connect(self.update_extract_plan)
        self.classes_widget.fileChanged.connect(self._layers_changed)
        self._names_cache: tuple | None = None
        self.aliases_edit.textChanged.connect(self._save_mission)
        self.priors_widget.fileChanged.connect(self._save_mission)
        self.no_priors_check.toggled.connect(self._save_mission)
        self.offline_check.toggled.connect(self._llm_enabled)
        self._llm_enabled(self.offline_check.isChecked())
        self._set_busy(False)
        project = QgsProject.instance()
        self._project_slots = (
            (project.readProject, self._project_read),
            (project.cleared, self._project_cleared),
            (project.fileNameChanged, self._show_settings),  # the default runs folder moves with it
        )
        for signal, slot in self._project_slots:
            signal.connect(slot)

    # ----------------------------------------------------------------------------------------
    # Layout
    # ----------------------------------------------------------------------------------------

    def _build(self) -> None:
        body = QWidget()
        col = QVBoxLayout(body)
        mono = QFontDatabase.systemFont(QFontDatabase.FixedFont)

        box = QGroupBox("Imagery from a layer")
        form = QFormLayout(box)
        self.source_combo = QgsMapLayerComboBox()
        self.source_combo.setFilters(QgsMapLayerProxyModel.RasterLayer)
        self.source_combo.setAllowEmptyLayer(True)
        self.source_combo.setLayer(None)
        self.source_combo.setToolTip(
            "Any raster layer QGIS draws (a file, a basemap, WMS or XYZ tiles), rendered at the GSD below"
        )
        form.addRow("Source layer", self.source_combo)
        row = QHBoxLayout()
        self.draw_area_button = QPushButton("Draw area")
        self.draw_area_button.setCheckable(True)
        self.draw_area_button.setToolTip("Drag a rectangle on the map (right click or Esc cancels)")
        self.draw_area_button.toggled.connect(self.draw_area)
        self.canvas_extent_button = QPushButton("Canvas extent")
        self.canvas_extent_button.setToolTip("Use what the map shows now")
        self.canvas_extent_button.clicked.connect(lambda _checked=False: self.use_canvas_extent())
        row.addWidget(self.draw_area_button)
        row.addWidget(self.canvas_extent_button)
        form.addRow("Area", row)
        self.gsd_spin = QDoubleSpinBox()
        self.gsd_spin.setRange(0.01, 1000.0)
        self.gsd_spin.setDecimals(2)
        self.gsd_spin.setSingleStep(0.1)
        self.gsd_spin.setSuffix(" m")
        self.gsd_spin.setValue(DEFAULT_GSD_M)
        self.gsd_spin.setToolTip("Ground size of one pixel of the extracted image")
        form.addRow("GSD", self.gsd_spin)
        self.extract_label = QLabel("Choose a source layer and an area")
        self.extract_label.setWordWrap(True)
        form.addRow(self.extract_label)
        self.extract_button = QPushButton("Extract")
        self.extract_button.setToolTip(
            "Write image.tif into a new run folder (a background task; Cancel stops it) and use it as the image"
        )
        self.extract_button.clicked.connect(lambda _checked=False: self.extract())
        form.addRow(self.extract_button)
        col.addWidget(box)

        box = QGroupBox("Input image")
        form = QFormLayout(box)
        self.layer_combo = QgsMapLayerComboBox()
        self.layer_combo.setFilters(QgsMapLayerProxyModel.RasterLayer)
        self.layer_combo.setAllowEmptyLayer(True)
        form.addRow("Layer", self.layer_combo)
        self.file_widget = QgsFileWidget()
        self.file_widget.setFilter("Rasters (*.tif *.tiff *.vrt *.img *.jp2 *.png);;All files (*)")
        form.addRow("or file", self.file_widget)
        self.bands_edit = QLineEdit()
        self.bands_edit.setPlaceholderText("auto; or R,G,B bands e.g. 4,3,2; or one band")
        form.addRow("Bands", self.bands_edit)
        self.info_view = QPlainTextEdit()
        self.info_view.setReadOnly(True)
        self.info_view.setMaximumHeight(110)
        self.info_view.setFont(mono)
        form.addRow(self.info_view)
        col.addWidget(box)

        box = QGroupBox("Mission")
        v = QVBoxLayout(box)
        self.prompt_edit = QPlainTextEdit()
        self.prompt_edit.setPlaceholderText("e.g. Prefer the roads and trails, grass is fine, avoid the baseball field")
        self.prompt_edit.setMaximumHeight(80)
        v.addWidget(self.prompt_edit)
        self.offline_check = QCheckBox("Offline interpreter (no LLM)")
        v.addWidget(self.offline_check)
        self.llm_label = QLabel("")
        self.llm_label.setWordWrap(True)
        self.llm_label.setToolTip("The LLM endpoint, model and API key are set in Settings › Options › overseec")
        v.addWidget(self.llm_label)
        self.interpret_button = QPushButton("Interpret prompt")
        self.interpret_button.clicked.connect(lambda _checked=False: self.interpret())
        v.addWidget(self.interpret_button)
        col.addWidget(box)

        box = QGroupBox("Entities")
        v = QVBoxLayout(box)
        self.entities_table = QTableWidget(0, len(ENTITY_COLUMNS))
        self.entities_table.setHorizontalHeaderLabels(ENTITY_COLUMNS)
        self.entities_table.horizontalHeader().setSectionResizeMode(QHeaderView.Stretch)
        self.entities_table.setMinimumHeight(120)
        v.addWidget(self.entities_table)
        row = QHBoxLayout()
        add = QPushButton("Add entity")
        add.clicked.connect(lambda: self.add_entity_row("", "areal", None, ()))
        remove = QPushButton("Remove selected")
        remove.clicked.connect(self._remove_entity_rows)
        row.addWidget(add)
        row.addWidget(remove)
        v.addLayout(row)
        col.addWidget(box)

        box = QGroupBox("Entity layers for the costmap")
        form = QFormLayout(box)
        self.masks_label = QLabel("Masks: none yet (Segment or Run all)")
        self.masks_label.setWordWrap(True)
        form.addRow(self.masks_label)
        self.labels_combo = QgsMapLayerComboBox()
        self.labels_combo.setFilters(QgsMapLayerProxyModel.RasterLayer)
        self.labels_combo.setAllowEmptyLayer(True)
        self.labels_combo.setLayer(None)
        self.labels_combo.setToolTip(
            "A class raster (integer ids) to use as entity layers, e.g. ground truth or a land-cover map"
        )
        form.addRow("and/or class raster", self.labels_combo)
        self.classes_widget = QgsFileWidget()
        self.classes_widget.setFilter("classes.json (*.json)")
        form.addRow("classes.json", self.classes_widget)
        self.aliases_edit = QLineEdit()
        self.aliases_edit.setPlaceholderText("e.g. lake=water, compound=building")
        self.aliases_edit.setToolTip(
            "Which layer a prompt entity stands for when the names differ "
            "and the built-in matching (plurals, synonyms, broader classes) "
            "misses it; applied when the prompt is interpreted"
        )
        form.addRow("Entity aliases", self.aliases_edit)
        row = QHBoxLayout()
        self.priors_widget = QgsFileWidget()
        self.priors_widget.setFilter("Priors (*.json)")
        self.priors_widget.lineEdit().setPlaceholderText("built-in")
        self.priors_widget.setToolTip(
            "What hazards the prompt leaves unsaid cost: a JSON object of entity -> level in (0.5, 1], "
            '"obstacle" or "lethal", e.g. {"building": 0.9}, replacing the built-in priors '
            '(see "What the prompt leaves unsaid" in the README); applied when the prompt is interpreted'
        )
        self.no_priors_check = QCheckBox("No priors")
        self.no_priors_check.setToolTip(
            "What the prompt does not mention is neutral ground (no built-in or file priors); "
            "applied when the prompt is interpreted"
        )
        self.no_priors_check.toggled.connect(self.priors_widget.setDisabled)
        row.addWidget(self.priors_widget, 1)
        row.addWidget(self.no_priors_check)
        form.addRow("Priors", row)
        col.addWidget(box)

        box = QGroupBox("Cost program")
        v = QVBoxLayout(box)
        self.program_edit = QPlainTextEdit()
        self.program_edit.setFont(mono)
        self.program_edit.setLineWrapMode(QPlainTextEdit.NoWrap)
        self.program_edit.setMinimumHeight(120)
        v.addWidget(self.program_edit)
        self.program_status = QLabel("")
        self.program_status.setWordWrap(True)
        v.addWidget(self.program_status)
        col.addWidget(box)

        box = QGroupBox("Parameters")
        form = QFormLayout(box)
        self.tile_spin = QSpinBox()
        self.tile_spin.setRange(32, 4096)
        self.tile_spin.setSingleStep(32)
        form.addRow("Tile size (px)", self.tile_spin)
        self.overlap_spin = QSpinBox()
        self.overlap_spin.setRange(0, 2048)
        form.addRow("Tile overlap (px)", self.overlap_spin)
        self.tau_linear_spin = QDoubleSpinBox()
        self.tau_areal_spin = QDoubleSpinBox()
        for s in (self.tau_linear_spin, self.tau_areal_spin):
            s.setRange(0.0, 1.0)
            s.setSingleStep(0.05)
            s.setDecimals(2)
        form.addRow("Threshold, linear", self.tau_linear_spin)
        form.addRow("Threshold, areal", self.tau_areal_spin)
        self.refine_check = QCheckBox("Refine masks with SAM")
        form.addRow(self.refine_check)
        self.mode_combo = QComboBox()
        self.mode_combo.addItems(["fast", "exact"])
        form.addRow("Planner", self.mode_combo)
        self.models_label = QLabel("")
        self.models_label.setWordWrap(True)
        self.models_label.setToolTip("Models, device and the runs folder are set in Settings › Options › overseec")
        form.addRow(self.models_label)
        col.addWidget(box)

        box = QGroupBox("Run")
        v = QVBoxLayout(box)
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
            "Edit overrides.gpkg beside the costmap: polygons with cost (0-1), prefer or lethal, "
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
        self.cancel_button.clicked.connect(self.cancel)
        row.addWidget(self.progress_bar)
        row.addWidget(self.cancel_button)
        v.addLayout(row)
        self.status_label = QLabel("")
        self.status_label.setWordWrap(True)
        v.addWidget(self.status_label)
        col.addWidget(box)

        box = QGroupBox("Environment")
        v = QVBoxLayout(box)
        row = QHBoxLayout()
        self.env_button = QPushButton("Check environment")
        self.env_button.setToolTip("Check QGIS's Python, the worker environment and the model weights")
        self.env_button.clicked.connect(lambda _checked=False: self.check_environment())
        self.setup_button = QPushButton("Set up environment")
        self.setup_button.setToolTip(
            "Create the worker's Python environment and install overseec[models] into it with pip "
            "(a background task; Cancel stops it)"
        )
        self.setup_button.clicked.connect(lambda _checked=False: self.set_up_environment())
        self.options_button = QPushButton("Settings…")
        self.options_button.setToolTip("Settings › Options › overseec: environment, models, device, runs folder, LLM")
        self.options_button.clicked.connect(lambda _checked=False: self.show_options())
        for b in (self.env_button, self.setup_button, self.options_button):
            row.addWidget(b)
        v.addLayout(row)
        self.env_label = QLabel("")
        self.env_label.setWordWrap(True)
        self.env_label.setTextInteractionFlags(Qt.TextSelectableByMouse)
        v.addWidget(self.env_label)
        col.addWidget(box)
        col.addStretch(1)

        scroll = QScrollArea()
        scroll.setWidgetResizable(True)
        scroll.setWidget(body)
        self.setWidget(scroll)

    def _load_settings(self) -> None:
        s = self.settings
        self.offline_check.setChecked(s.offline)
        p = s.params
        self.tile_spin.setValue(p.tile_size)
        self.overlap_spin.setValue(p.overlap)
        self.tau_linear_spin.setValue(p.tau_linear)
        self.tau_areal_spin.setValue(p.tau_areal)
        self.refine_check.setChecked(p.refine)
        self.mode_combo.setCurrentText(p.plan_mode)
        self._show_settings()

    def _show_settings(self) -> None:
        """The options-page settings the dock's work depends on, as one line each."""
        s = self.settings
        llm = f"{s.llm_endpoint}" + (f", model {s.llm_model}" if s.llm_model else "") if s.llm_endpoint else "none set"
        self.llm_label.setText(f"LLM: {llm}" + (" (API key stored)" if s.llm_authcfg else ""))
        p = s.params
        root = runs_root(s.runs_dir, QgsProject.instance().absolutePath())
        self.models_label.setText(
            f"CLIPSeg: {p.clipseg_model or 'default'}; SAM: {p.sam_model or 'default'}; device: {p.device}\n"
            f"Runs: {root if root is not None else 'asked on the first run (project not saved)'}"
        )

    def save_settings(self) -> PluginSettings:
        """Save the dock's own fields (the offline switch and run parameters) over the current
        settings, so the options page's fields are never overwritten; returns all settings."""
        self.settings = PluginSettings.save_fields(
            offline=self.offline_check.isChecked(),
            tile_size=self.tile_spin.value(),
            overlap=self.overlap_spin.value(),
            tau_linear=self.tau_linear_spin.value(),
            tau_areal=self.tau_areal_spin.value(),
            refine=self.refine_check.isChecked(),
            plan_mode=self.mode_combo.currentText(),
        )
        return self.settings

    def reload_settings(self, saved: PluginSettings | None = None) -> None:
        """The options page was applied: show its settings, re-check a changed environment."""
        before = self.settings
        self.settings = saved or PluginSettings.load()
        self._show_settings()
        env_fields = ("worker_path", "venv")
        model_fields = ("clipseg_model", "sam_model", "device")
        changed = any(getattr(before, f) != getattr(self.settings, f) for f in env_fields) or any(
            getattr(before.params, f) != getattr(self.settings.params, f) for f in model_fields
        )
        if changed and self._env_checked:
            self.check_environment()

    def _llm_enabled(self, offline: bool) -> None:
        self.llm_label.setEnabled(not offline)

    # ----------------------------------------------------------------------------------------
    # Wiring with the plugin
    # ----------------------------------------------------------------------------------------

    def set_map_tool(self, tool, action) -> None:
        """Share the plugin's map tool: the Plan button drives the same (checkable) action."""
        self.map_tool, self.plan_action = tool, action
        self.plan_button.clicked.connect(lambda _checked: action.trigger())
        action.toggled.connect(self.plan_button.setChecked)
        self.mode_combo.currentTextChanged.connect(lambda m: setattr(tool, "mode", m))
        tool.mode = self.mode_combo.currentText()

    # ----------------------------------------------------------------------------------------
    # Imagery: extract any raster layer into the run folder
    # ----------------------------------------------------------------------------------------

    def _canvas(self):
        return self.iface.mapCanvas() if self.iface is not None else None

    def _extent_tool(self, canvas) -> ExtentMapTool:
        if self.extent_tool is None:
            self.extent_tool = ExtentMapTool(canvas)
            self.extent_tool.extent_drawn.connect(self._area_drawn)
            self.extent_tool.deactivated.connect(lambda: self.draw_area_button.setChecked(False))
        return self.extent_tool

    def draw_area(self, on: bool = True) -> None:
        """Switch the rectangle tool on (or off): the drawn rectangle is the area to extract."""
        canvas = self._canvas()
        if canvas is None:
            return
        tool = self._extent_tool(canvas)
        if on and canvas.mapTool() is not tool:
            canvas.setMapTool(tool)
        elif not on and canvas.mapTool() is tool:
            canvas.unsetMapTool(tool)

    def _drop_extent_tool(self) -> None:
        """Unload: the rectangle tool off the canvas, its rubber band removed."""
        tool, canvas = self.extent_tool, self._canvas()
        if tool is None or canvas is None:
            return
        if canvas.mapTool() is tool:
            canvas.unsetMapTool(tool)
        tool.reset()
        canvas.scene().removeItem(tool.band)  # a canvas item, not a child of the tool
        tool.deleteLater()
        self.extent_tool = None

    def _area_drawn(self, extent) -> None:
        canvas = self._canvas()
        self.set_extract_area(extent, canvas.mapSettings().destinationCrs())
        self.draw_area(False)

    def use_canvas_extent(self) -> None:
        canvas = self._canvas()
        if canvas is None:
            return
        self.draw_area(False)
        self._extent_tool(canvas).show_extent(canvas.extent())  # its rubber band shows the area
        self.set_extract_area(canvas.extent(), canvas.mapSettings().destinationCrs())

    def set_extract_area(self, extent, crs) -> None:
        """The area to extract (``extent`` in ``crs``)."""
        self.extract_extent, self.extract_crs = extent, crs
        self.update_extract_plan()

    def update_extract_plan(self, *_args):
        """Work out the output grid for the form (no pixel is fetched) and show its size, or the
        one-line reason it cannot be made (no area, too large, outside the layer ...)."""
        self.extract_plan = None
        layer = self.source_combo.currentLayer()
        if not isinstance(layer, QgsRasterLayer) or self.extract_extent is None:
            self.extract_label.setText("Choose a source layer and an area (Draw area or Canvas extent)")
            return None
        try:
            self.extract_plan = plan_extraction(layer, self.extract_extent, self.extract_crs, self.gsd_spin.value())
        except jobs.OverseecError as exc:
            self.extract_label.setText(f"✗ {exc}")
            return None
        self.extract_label.setText(self.extract_plan.describe())
        return self.extract_plan

    def extract(self) -> None:
        """Render the source layer over the area into ``image.tif`` of a new run folder (a
        cancellable background task), then use that file as the input image."""
        layer = self.source_combo.currentLayer()
        plan = self.update_extract_plan()
        if plan is None:
            self._fail("extract", self.extract_label.text().lstrip("✗ ") or "choose a source layer and an area")
            return
        stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S-%f")
        name = "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in layer.name())[:40] or "imagery"
        run_dir = self.runs_folder() / f"{name}-{stamp}"
        run_dir.mkdir(parents=True, exist_ok=True)
        out = run_dir / EXTRACTED_IMAGE
        task = ExtractTask(layer, plan, out)
        self._start("extract", task, lambda path: self._use_extracted(run_dir, Path(path), layer.name()))

    def _use_extracted(self, run_dir: Path, image: Path, source_name: str) -> None:
        self.set_run_dir(run_dir, str(image))
        group = run_group(f"overseec imagery: {run_dir.name}")
        layer = QgsRasterLayer(str(image), f"{EXTRACTED_IMAGE} ({source_name})", "gdal")
        if not layer.isValid():
            raise ValueError(f"QGIS cannot open {image}")
        set_provenance(layer, Provenance(run_dir=str(run_dir), stage="extract"), "image")
        QgsProject.instance().addMapLayer(layer, False)
        group.addLayer(layer)
        self.layer_combo.setLayer(None)
        self.file_widget.setFilePath(str(image))
        self._masks_updated()
        self.status_label.setText(f"extract: done, {image} is the input image")

    def showEvent(self, event) -> None:  # noqa: N802 -- Qt API
        super().showEvent(event)
        if not self._env_checked and self.settings.env_checked != jobs.core_version():
            QTimer.singleShot(0, self.check_environment)

    def shutdown(self) -> None:
        """Plugin unload: detach running tasks from this widget (it is about to be deleted),
        cancel the job (a worker is terminated), save the form."""
        for task in (self.task, self.env_task, self.info_task):
            if task is None:
                continue
            try:
                for signal in (task.succeeded, task.failed, task.status, task.progressChanged):
                    try:
                        signal.disconnect()
                    except TypeError:  # nothing connected
                        pass
                task.cancel()
            except RuntimeError:  # the C++ task is already gone
                pass
        self.task = self.env_task = self.info_task = None
        self._program_timer.stop()
        self._clear_env_message()
        self._drop_extent_tool()
        for signal, slot in self._project_slots:
            try:
                signal.disconnect(slot)
            except TypeError:
                pass
        self.save_settings()

    # ----------------------------------------------------------------------------------------
    # Input
    # ----------------------------------------------------------------------------------------

    def image_path(self) -> str:
        """The chosen image file: the file box if set, else the layer's file."""
        path = self.file_widget.filePath().strip()
        if path:
            return path
        layer = self.layer_combo.currentLayer()
        if isinstance(layer, QgsRasterLayer):
            return jobs.layer_file(layer)
        return ""

    def _input_changed(self, *_args) -> None:
        """Read the chosen image's description in the worker (``overseec info --json``), in a
        background task: picking an image never blocks QGIS while the worker starts."""
        self._drop_info_task()
        path = self.image_path()
        if not path:
            self.info_view.setPlainText("")
            return
        if self.run_image is not None and Path(self.run_image).resolve() != Path(path).resolve():
            self.set_run_dir(None)  # masks belong to the old image
            self._masks_updated()
        worker = jobs.find_worker_for(self.settings)
        if worker is None:
            self.info_view.setPlainText(f"cannot use this image: {jobs.no_worker_message()}")
            return
        argv, env = jobs.info_command(worker, path, self.bands_edit.text().strip() or None)
        task = WorkerTask("overseec: read image", argv, env=env, capture=True)
        task.succeeded.connect(lambda _r: self._show_info(task))
        task.failed.connect(lambda message, _details: self._show_info(task, message))
        self.info_task = task
        self.info_view.setPlainText(f"reading {Path(path).name}…")
        QgsApplication.taskManager().addTask(task)

    def _drop_info_task(self) -> None:
        """Cancel a reading check still in flight (its image is no longer the chosen one)."""
        task, self.info_task = self.info_task, None
        if task is not None:
            try:
                task.cancel()
            except RuntimeError:  # the C++ task is already gone
                pass

    def _show_info(self, task: WorkerTask, error: str = "") -> None:
        """The reading check's outcome, if ``task`` is still the latest one."""
        if task is not self.info_task:
            return
        self.info_task = None
        info = {} if error else jobs.result_document(task.printed)
        if not info:
            self.info_view.setPlainText(f"cannot use this image: {error or 'the worker printed no description'}")
            return
        self.info_view.setPlainText(jobs.describe_info(info))

    # ----------------------------------------------------------------------------------------
    # Entities and program
    # ----------------------------------------------------------------------------------------

    def add_entity_row(self, name: str, geometry: str, threshold: float | None, prompts) -> None:
        t = self.entities_table
        r = t.rowCount()
        t.insertRow(r)
        t.setItem(r, 0, QTableWidgetItem(name))
        combo = QComboBox()
        combo.addItems(["linear", "areal"])
        combo.setCurrentText(geometry)
        t.setCellWidget(r, 1, combo)
        t.setItem(r, 2, QTableWidgetItem("" if threshold is None else f"{threshold:g}"))
        extra = [p for p in prompts if p != name]
        t.setItem(r, 3, QTableWidgetItem(", ".join(extra)))

    def _remove_entity_rows(self) -> None:
        for r in sorted({i.row() for i in self.entities_table.selectedIndexes()}, reverse=True):
            self.entities_table.removeRow(r)

    def entity_rows(self) -> list[dict]:
        """The table as plain dicts (name, geometry, threshold or None, prompts)."""
        rows = []
        t = self.entities_table
        for r in range(t.rowCount()):
            name = (t.item(r, 0).text() if t.item(r, 0) else "").strip()
            if not name:
                continue
            geometry = t.cellWidget(r, 1).currentText()
            thr_text = (t.item(r, 2).text() if t.item(r, 2) else "").strip()
            try:
                threshold = float(thr_text) if thr_text else None
            except ValueError:
                raise ValueError(f"entity {name!r}: threshold {thr_text!r} is not a number") from None
            extra = [p.strip() for p in (t.item(r, 3).text() if t.item(r, 3) else "").split(",") if p.strip()]
            rows.append(
                {
                    "name": name,
                    "geometry": geometry,
                    "threshold": threshold,
                    "prompts": [name] + [p for p in extra if p != name] if extra else [],
                }
            )
        return rows

    def priors(self) -> jobs.Priors:
        """The mission's priors: none when "No priors" is ticked, else the file's, else built-in."""
        if self.no_priors_check.isChecked():
            return jobs.Priors(off=True)
        return jobs.Priors(path=self.priors_widget.filePath().strip())

    def show_interpretation(self, interp, priors: jobs.Priors | None = None) -> None:
        """Fill the table and program box (``priors``: those it was interpreted with; default
        the dock's)."""
        self.interpretation = interp
        self.interpretation_priors = self.priors() if priors is None else priors
        self.entities_table.setRowCount(0)
        for e in interp.entities:
            self.add_entity_row(e.name, e.geometry, e.threshold, e.prompts)
        self.program_edit.setPlainText(self._program_for_layers(interp))
        for note in interp.notes:
            log(f"interpret: {note}")
        if interp.unparsed:
            log("interpret: not understood: " + "; ".join(interp.unparsed))
            self.status_label.setText(
                "Interpreted (" + interp.source + "); not understood: " + "; ".join(interp.unparsed)
            )
        else:
            self.status_label.setText(f"Interpreted ({interp.source}).")

    def _program_for_layers(self, interp) -> str:
        """The interpretation's program fitted to the entity layers when there are any (names
        matched as `overseec costmap --prompt` matches them, with the dock's aliases)."""
        src = self.layer_sources()
        if not (src["masks_dir"] or (src["labels"] and src["classes"])):
            return interp.program
        try:
            fitted = jobs.fit_to_layers(
                interp, self.entity_names(), self.aliases_edit.text(), self.interpretation_priors or jobs.Priors()
            )
        except jobs.OverseecError as exc:
            log(f"interpret: {exc}", Qgis.Warning)
            return interp.program
        except ImportError as exc:  # QGIS's Python cannot read rasters: the worker checks the names
            log(f"interpret: the program is not fitted to the layers' names in QGIS ({exc})", Qgis.Warning)
            return interp.program
        for note in fitted.notes:
            if note.startswith("entities -> layers"):
                log(f"interpret: {note}")
        for warning in fitted.warnings:
            log(f"interpret: {warning}", Qgis.Warning)
        return fitted.text

    def layer_sources(self) -> dict:
        """The costmap's entity layers: the current run's masks and/or a class raster."""
        labels_layer = self.labels_combo.currentLayer()
        labels = jobs.layer_file(labels_layer) if isinstance(labels_layer, QgsRasterLayer) else ""
        classes = self.classes_widget.filePath().strip()
        masks = (
            str(self.run_dir)
            if self.run_dir is not None and jobs.first_existing(self.run_dir, "mask") is not None
            else ""
        )
        return {
            "masks_dir": masks or None,
            "labels": labels or None,
            "classes": classes if labels and classes else None,
        }

    def _layers_changed(self, *_args) -> None:
        self._names_cache = None
        if self.program_edit.toPlainText().strip():
            self.validate_program()

    def entity_names(self) -> tuple[str, ...]:
        """Names a program may use: those of the layer sources, else the entities table."""
        src = self.layer_sources()
        if src["masks_dir"] or (src["labels"] and src["classes"]):
            key = tuple(sorted((k, str(v)) for k, v in src.items()))
            if self._names_cache is None or self._names_cache[0] != key:
                try:
                    self._names_cache = (key, jobs.layer_names(**src))
                except ImportError:  # QGIS's Python cannot read rasters: the worker's costmap checks
                    return tuple(r["name"] for r in self.entity_rows())
            return self._names_cache[1]
        return tuple(r["name"] for r in self.entity_rows())

    def validate_program(self) -> bool:
        """Check the program against the entity names; mark an error at its line."""
        text = self.program_edit.toPlainText()
        self.program_edit.setExtraSelections([])
        if not text.strip():
            self.program_status.setText("")
            return False
        try:
            names = self.entity_names()
        except jobs.OverseecError as exc:  # the entity layers themselves are unusable
            self.program_status.setStyleSheet("color: #b00020")
            self.program_status.setText(f"✗ entity layers: {exc}")
            return False
        try:
            program = jobs.check_program(text, names)
        except jobs.CostProgramError as exc:
            self._mark_line(exc.line, exc.col)
            where = f"line {exc.line}, column {exc.col}: " if exc.line else ""
            self.program_status.setStyleSheet("color: #b00020")
            self.program_status.setText(f"✗ {where}{exc.message}")
            return False
        warnings = list(program.warnings)
        self.program_status.setStyleSheet("color: #1b5e20" if not warnings else "color: #8a6d00")
        self.program_status.setText("✓ valid" + ("; " + "; ".join(warnings) if warnings else ""))
        return True

    def _mark_line(self, line: int | None, col: int | None) -> None:
        if not line:
            return
        block = self.program_edit.document().findBlockByLineNumber(line - 1)
        if not block.isValid():
            return
        sel = QTextEdit.ExtraSelection()
        sel.format.setBackground(QColor(255, 205, 210))
        sel.format.setProperty(QTextFormat.FullWidthSelection, True)
        cursor = QTextCursor(block)
        if col:
            cursor.movePosition(QTextCursor.Right, QTextCursor.MoveAnchor, min(col, block.length() - 1))
        sel.cursor = cursor
        self.program_edit.setExtraSelections([sel])

    # ----------------------------------------------------------------------------------------
    # Running
    # ----------------------------------------------------------------------------------------

    def _set_busy(self, busy: bool) -> None:
        for b in (
            self.interpret_button,
            self.segment_button,
            self.costmap_button,
            self.run_button,
            self.setup_button,
            self.extract_button,
        ):
            b.setEnabled(not busy)
        self.cancel_button.setEnabled(busy)
        if not busy:
            self.progress_bar.setValue(0)

    def _fail(self, title: str, message: str, details: str = "") -> None:
        self.status_label.setText(f"{title}: {message}")
        log(f"{title}: {message}" + (f"\n{details}" if details else ""), Qgis.Critical)
        if self.iface is not None:
            self.iface.messageBar().pushMessage(f"overseec {title}", message, Qgis.Critical, 0)

    def _inform(self, title: str, message: str) -> None:
        """What the user asked for happened (a cancel, a folder chosen): information that
        goes away by itself, never a red error."""
        self.status_label.setText(f"{title}: {message}")
        log(f"{title}: {message}", Qgis.Info)
        if self.iface is not None:
            self.iface.messageBar().pushMessage(f"overseec {title}", message, Qgis.Info, INFO_S)

    def _start(
        self, stage: str, task, on_success: Callable[[Any], None], then: Callable[[], None] | None = None
    ) -> None:
        """Run ``task`` in the task manager; route its outcome to ``on_success`` (and then to the
        next stage, ``then``) or to the message bar."""
        if self.task is not None:
            self._fail(stage, "another overseec job is running; cancel it first")
            return
        self.task = task
        task.progressChanged.connect(lambda p: self.progress_bar.setValue(int(p)))
        task.status.connect(lambda s: self.status_label.setText(f"{stage}: {s}…"))

        def done_ok(result) -> None:
            self.task = None
            self._set_busy(False)
            try:
                on_success(result)
            except Exception as exc:  # adding layers failed: report, keep what is there
                self._fail(stage, f"the run finished but its outputs could not be shown: {exc}", traceback.format_exc())
                self.task_done.emit(stage, False)
                return
            self.task_done.emit(stage, True)
            if then is not None:
                try:
                    then()
                except Exception as exc:  # never let an exception escape a Qt slot
                    self._fail(stage, f"could not start the next stage: {exc}", traceback.format_exc())

        def done_fail(message: str, details: str) -> None:
            self.task = None
            self._set_busy(False)
            if task.was_cancelled:
                self._inform(stage, message)
            else:
                self._fail(stage, message, details)
            self.task_done.emit(stage, False)

        task.succeeded.connect(done_ok)
        task.failed.connect(done_fail)
        self.status_label.setText(f"{stage}…")
        self._set_busy(True)
        QgsApplication.taskManager().addTask(task)

    def cancel(self) -> None:
        if self.task is not None:
            self.status_label.setText("cancelling…")
            self.task.cancel()

    def runs_folder(self) -> Path:
        """Where new run folders go (see :func:`runs_root`); for an unsaved project without a
        runs folder setting the user is asked once per session, and a temporary folder (said so
        in the message bar) is used if they decline."""
        root = runs_root(PluginSettings.load().runs_dir, QgsProject.instance().absolutePath())
        if root is not None:
            return root
        if self._session_runs is None:
            answer = self.ask_runs_folder()
            if answer:
                self._session_runs = Path(answer)
            else:
                self._session_runs = Path(tempfile.gettempdir()) / RUNS_FOLDER
                self._inform(
                    "runs",
                    f"runs go to {self._session_runs}, which is temporary: save the project (runs then go "
                    f"beside it) or set a runs folder in Settings › Options › overseec to keep them",
                )
        return self._session_runs

    def ensure_run_dir(self, image: str, new: bool = False) -> Path:
        """The run directory for ``image``: the current one, or a new one under the runs folder."""
        if (
            not new
            and self.run_dir is not None
            and self.run_image is not None
            and Path(self.run_image).resolve() == Path(image).resolve()
        ):
            return self.run_dir
        stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S-%f")
        run_dir = self.runs_folder() / f"{Path(image).stem}-{stamp}"
        run_dir.mkdir(parents=True, exist_ok=True)
        self.set_run_dir(run_dir, image)
        return run_dir

    def set_run_dir(self, run_dir: Path | None, image: str | None = None) -> None:
        """Make ``run_dir`` the current run and remember it in the project."""
        self.run_dir, self.run_image = run_dir, image
        project = QgsProject.instance()
        if run_dir is None:
            project.removeEntry(PROJECT_SCOPE, PROJECT_RUN_KEY)
            project.removeEntry(PROJECT_SCOPE, "run_image")
        else:
            project.writeEntry(PROJECT_SCOPE, PROJECT_RUN_KEY, str(run_dir))
            project.writeEntry(PROJECT_SCOPE, "run_image", image or "")

    def _require_image(self) -> str | None:
        image = self.image_path()
        if not image:
            self._fail("input", "choose an input raster layer or file first")
            return None
        return image

    def llm_config(self) -> jobs.LlmSettings:
        s = self.save_settings()
        if s.offline:
            return jobs.LlmSettings()
        return jobs.LlmSettings(endpoint=s.llm_endpoint, model=s.llm_model, api_key=s.api_key())

    def interpret(self, then: Callable[[], None] | None = None) -> None:
        prompt = self.prompt_edit.toPlainText().strip()
        if not prompt:
            self._fail("interpret", "write a mission prompt first")
            return
        priors = self.priors()
        try:
            argv, env = jobs.interpret_command(self.worker(), prompt, self.llm_config(), priors)
        except (LookupError, jobs.OverseecError) as exc:
            self._fail("interpret", str(exc))
            return
        task = WorkerTask("overseec: interpret", argv, env=env, weights={"interpret": 1.0}, capture=True)
        self._start(
            "interpret",
            task,
            lambda _r: self.show_interpretation(
                jobs.interpretation_from_json(jobs.result_document(task.printed)), priors
            ),
            then,
        )

    def current_interpretation(self):
        """The interpretation as edited in the table and program box."""
        return jobs.edited_interpretation(
            self.interpretation,
            self.prompt_edit.toPlainText().strip(),
            self.entity_rows(),
            self.program_edit.toPlainText(),
        )

    def segment(self, then: Callable[[], None] | None = None) -> None:
        image = self._require_image()
        if image is None:
            return
        try:
            interp = self.current_interpretation()
        except (ValueError, jobs.OverseecError) as exc:
            self._fail("segment", str(exc))
            return
        if not interp.entities:
            self._fail("segment", "no entities: interpret a prompt or add entities to the table")
            return
        run_dir = self.ensure_run_dir(image)
        try:
            params = self.params()
            argv, env = jobs.segment_command(
                self.worker(), image, run_dir, interp, params, self.bands_edit.text().strip() or None
            )
        except (LookupError, jobs.OverseecError) as exc:
            self._fail("segment", str(exc))
            return
        worker = Path(argv[0])

        def models_present() -> str:  # on the task thread: names every missing model at once
            return envcheck.segment_problem(worker, params.clipseg_model, params.sam_model, params.refine)

        task = WorkerTask(
            "overseec: segment",
            argv,
            env=env,
            weights=jobs.stage_weights("segment", params),
            precheck=models_present,
        )
        self._start("segment", task, lambda _r: self._add_outputs(run_dir, "segment", ("mask", "probability")), then)

    def build_costmap(self, then: Callable[[], None] | None = None) -> None:
        src = self.layer_sources()
        if not src["masks_dir"] and not (src["labels"] and src["classes"]):
            self._fail(
                "costmap",
                "no entity layers: run Segment (or Run all) first, or choose a class raster and its classes.json",
            )
            return
        if not self.validate_program():
            self._fail("costmap", "fix the cost program first (" + self.program_status.text() + ")")
            return
        run_dir = self.run_dir if self.run_dir is not None else self.ensure_run_dir(src["labels"])
        out = jobs.next_costmap_path(run_dir)
        prompt = self.prompt_edit.toPlainText().strip()
        program = self.program_edit.toPlainText()
        overrides = self._run_overrides(run_dir)
        try:
            argv, env = jobs.costmap_command(self.worker(), out, program, overrides=overrides, **src)
        except (LookupError, OSError, jobs.OverseecError) as exc:
            self._fail("costmap", str(exc))
            return
        task = WorkerTask("overseec: costmap", argv, env=env, weights={"costmap": 1.0}, capture=True)
        self._start(
            "costmap",
            task,
            lambda _r: self._add_costmap(
                run_dir, jobs.CostmapResult.from_json(jobs.result_document(task.printed)), prompt
            ),
            then,
        )

    def _run_overrides(self, run_dir: Path) -> tuple[Path, ...]:
        """The run folder's ``overrides.gpkg`` (the dock's Draw overrides layer), as Processing
        and `overseec costmap --override` apply it; edits not yet saved are not in the file."""
        path = run_dir / OVERRIDES_FILE
        if not path.is_file():
            return ()
        for layer in QgsProject.instance().mapLayers().values():
            if layer.customProperty("overseec/role") == "overrides" and layer.source().split("|")[0] == str(path):
                if layer.isModified():
                    log(f"costmap: {path} has unsaved edits; the costmap applies the saved overrides", Qgis.Warning)
        log(f"costmap: applying the overrides in {path}")
        return (path,)

    def run_to_costmap(self) -> None:
        """Every stage in order, as the buttons would run them, into a new run directory:
        interpret (unless the table already holds this prompt's interpretation, possibly
        edited), segment (skipped when a class raster provides the entity layers), costmap.
        The form's parameters and the user's edits to entities and program all apply."""
        image = self._require_image()
        if image is None:
            return
        prompt = self.prompt_edit.toPlainText().strip()
        if not prompt:
            self._fail("run", "write a mission prompt first")
            return
        src = self.layer_sources()
        use_labels = bool(src["labels"] and src["classes"])
        self.ensure_run_dir(image, new=True)
        self._masks_updated()

        def after_interpret() -> None:
            if use_labels:
                self.build_costmap(then=self._run_finished)
            else:
                self.segment(then=lambda: self.build_costmap(then=self._run_finished))

        if (
            self.interpretation is None
            or self.interpretation.prompt != prompt
            or self.interpretation_priors != self.priors()
        ):
            self.interpret(then=after_interpret)
        else:
            after_interpret()

    def _run_finished(self) -> None:
        self.status_label.setText(f"run: done, outputs in {self.run_dir}")
        self.run_done.emit(str(self.run_dir))

    def params(self) -> jobs.Params:
        """The form's run parameters (saved as the new defaults)."""
        return self.save_settings().params

    def worker(self) -> Path:
        worker = jobs.find_worker_for(self.save_settings())
        if worker is None:
            report = jobs.check_worker_env(None)
            raise LookupError(report.problems[0] + "; " + "; ".join(report.advice))
        return worker

    # ----------------------------------------------------------------------------------------
    # Results -> layers
    # ----------------------------------------------------------------------------------------

    def _title(self, run_dir: Path, stage: str) -> str:
        return f"overseec {stage}: {run_dir.name}"

    def _masks_updated(self) -> None:
        self._names_cache = None
        masks = jobs.first_existing(self.run_dir, "mask") if self.run_dir is not None else None
        self.masks_label.setText(f"Masks: {masks}" if masks else "Masks: none yet (Segment or Run all)")

    def _add_outputs(self, run_dir: Path, stage: str, roles) -> None:
        self._masks_updated()
        _group, layers = add_run_outputs(run_dir, self._title(run_dir, stage), roles=roles)
        self.status_label.setText(f"{stage}: done, {len(layers)} layer(s) added")

    def _add_costmap(self, run_dir: Path, result, prompt: str) -> None:
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
        layer = add_costmap(result.costmap, group, prov, name=result.costmap.stem)
        if self.map_tool is not None:
            self.map_tool.set_costmap(layer)
        for note in tuple(result.notes) + tuple(result.warnings):
            log(f"costmap: {note}")
        self.status_label.setText(
            f"costmap: done ({result.costmap}, mean cost "
            f"{result.mean_cost if result.mean_cost is None else round(result.mean_cost, 3)})"
        )

    def save_paths(self) -> Path | None:
        """The map tool's planned paths -> ``paths-N.geojson`` beside the costmap, as a layer."""
        tool = self.map_tool
        if tool is None or tool.paths_layer is None or not tool.paths_layer.featureCount():
            self._fail("save paths", "no planned paths yet: use Plan on map first")
            return None
        folder = Path(tool.session().path).parent  # beside the costmap, as `overseec plan` writes
        n = 1
        while (folder / f"paths-{n}.geojson").exists():
            n += 1
        try:
            path = tool.save_paths(folder / f"paths-{n}.geojson")
        except (OSError, LookupError) as exc:
            self._fail("save paths", str(exc))
            return None
        prov = Provenance(run_dir=str(folder), stage="plan", extra=(("costmap", tool.session().path),))
        add_path(path, run_group(f"overseec paths: {folder.name}"), prov, name=path.stem)
        self.status_label.setText(f"paths saved to {path}")
        return path

    def edit_overrides(self):
        """Open (or create) ``overrides.gpkg`` beside the current costmap, in edit mode, and have
        the map tool plan with it: drawing or editing a polygon re-plans the route."""
        tool = self.map_tool
        try:
            folder = Path(tool.session().path).parent if tool is not None else None
        except (LookupError, OSError) as exc:
            self._fail("overrides", str(exc))
            return None
        if folder is None:
            self._fail("overrides", "no map tool: the plugin is not loaded")
            return None
        source = str(folder / OVERRIDES_FILE)
        layer = next(
            (
                lyr
                for lyr in QgsProject.instance().mapLayers().values()
                if lyr.customProperty("overseec/role") == "overrides" and lyr.source().split("|")[0] == source
            ),
            None,
        )
        if layer is None:
            try:
                layer = open_overrides(folder, run_group(f"overseec overrides: {folder.name}"))
            except ValueError as exc:
                self._fail("overrides", str(exc))
                return None
        tool.set_overrides_layer(layer)
        layer.startEditing()
        if self.iface is not None:
            self.iface.setActiveLayer(layer)
        self.status_label.setText(
            f"overrides: draw polygons in {source}; set cost, prefer or lethal; the route re-plans on each edit"
        )
        return layer

    # ----------------------------------------------------------------------------------------
    # Environment
    # ----------------------------------------------------------------------------------------

    def check_environment(self) -> None:
        """Check both Python environments and the model weights in a background task."""
        if self.env_task is not None:
            return
        self._env_checked = True
        settings = self.save_settings()
        self.env_label.setText("Checking the Python environment…")
        self.env_task = PipelineTask("overseec: environment check", jobs.environment_report, settings)
        self.env_task.succeeded.connect(self._env_report_ready)
        self.env_task.failed.connect(self._env_check_failed)
        QgsApplication.taskManager().addTask(self.env_task)

    def _clear_env_message(self) -> None:
        if self._env_message is not None and self.iface is not None:
            try:
                self.iface.messageBar().popWidget(self._env_message)
            except RuntimeError:  # the bar already deleted it (the user closed it)
                pass
        self._env_message = None

    def _env_report_ready(self, report) -> None:
        self.env_task = None
        self.env_report = report
        self.env_label.setText(report.text())
        self.setup_button.setDefault(report.setup_helps)
        log("environment check:\n" + report.text(), Qgis.Info if report.all_ok else Qgis.Warning)
        self._clear_env_message()  # a fixed problem's warning goes away
        if report.all_ok:
            self.settings.env_checked = jobs.core_version()
            PluginSettings.save_fields(env_checked=self.settings.env_checked)
        elif self.iface is not None:
            problem = report.problems[0] if report.problems else "environment problem"
            more = f" (+{len(report.problems) - 1} more in the overseec panel)" if len(report.problems) > 1 else ""
            first = report.advice[0] if report.advice else ""
            self._env_message = QgsMessageBarItem(
                "overseec environment", problem + more + (f" -- {first}" if first else ""), Qgis.Warning, 0
            )
            self.iface.messageBar().pushItem(self._env_message)
        self.env_checked.emit(report)

    def _env_check_failed(self, message: str, _details: str) -> None:
        self.env_task = None
        self.env_label.setText(f"environment check failed: {message}")

    def set_up_environment(self, venv: str | Path | None = None, pip_args=()) -> None:
        """Create the worker's venv (the settings' venv, else the default place) and pip-install
        overseec[models] into it in a background task; on success the settings point at it and
        the environment is checked again."""
        settings = self.save_settings()
        plugin_dir = Path(__file__).parent
        target_venv = Path(venv or settings.venv or default_venv(plugin_dir, QgsApplication.qgisSettingsDirPath()))
        try:
            target = install_target(settings.install_source, plugin_dir)
        except jobs.OverseecError as exc:
            self._fail("set up", str(exc))
            return
        self.env_label.setText(f"Setting up {target_venv}: pip install {target.requirement} (see the log panel)…")
        task = SetupEnvTask(target_venv, target, pip_args=pip_args)
        self._start("set up", task, self._environment_made)

    def _environment_made(self, result) -> None:
        self.settings = PluginSettings.save_fields(venv=str(result.venv), worker_path="", env_checked="")
        self._show_settings()
        self.status_label.setText(f"set up: {result.worker} is ready")
        self.check_environment()

    def show_options(self) -> None:
        """Settings › Options, on the overseec page."""
        if self.iface is not None:
            self.iface.showOptionsDialog(self.iface.mainWindow(), PAGE_NAME)

    # ----------------------------------------------------------------------------------------
    # The project
    # ----------------------------------------------------------------------------------------

    def _save_mission(self, *_args) -> None:
        """Remember the mission's aliases and priors in the project (saved with it)."""
        if self._restoring:
            return
        project = QgsProject.instance()
        project.writeEntry(PROJECT_SCOPE, PROJECT_ALIASES_KEY, self.aliases_edit.text().strip())
        project.writeEntry(PROJECT_SCOPE, PROJECT_PRIORS_KEY, self.priors_widget.filePath().strip())
        project.writeEntry(PROJECT_SCOPE, PROJECT_NO_PRIORS_KEY, self.no_priors_check.isChecked())

    def _show_mission(self, aliases: str = "", priors: str = "", no_priors: bool = False) -> None:
        """Show a project's aliases and priors (without writing them back)."""
        self._restoring = True
        try:
            self.aliases_edit.setText(aliases)
            self.priors_widget.setFilePath(priors)
            self.no_priors_check.setChecked(no_priors)
        finally:
            self._restoring = False

    def _project_read(self, *_args) -> None:
        """A project was opened: carry on with the run folder it was saved with (if it is still
        there); its layers already point at that folder's files. Its mission's aliases and priors
        come back too."""
        project = QgsProject.instance()
        self._show_mission(
            project.readEntry(PROJECT_SCOPE, PROJECT_ALIASES_KEY, "")[0],
            project.readEntry(PROJECT_SCOPE, PROJECT_PRIORS_KEY, "")[0],
            project.readBoolEntry(PROJECT_SCOPE, PROJECT_NO_PRIORS_KEY, False)[0],
        )
        run_dir, found = project.readEntry(PROJECT_SCOPE, PROJECT_RUN_KEY, "")
        image, _ = project.readEntry(PROJECT_SCOPE, "run_image", "")
        if found and run_dir and Path(run_dir).is_dir():
            self.run_dir, self.run_image = Path(run_dir), image or None
            if image and Path(image).is_file():
                self.layer_combo.setLayer(None)
                self.file_widget.setFilePath(image)  # the run's input image again
        else:
            self.run_dir, self.run_image = None, None
        self._masks_updated()
        self._show_settings()

    def _project_cleared(self) -> None:
        self.run_dir, self.run_image = None, None
        self._show_mission()
        self._masks_updated()
        self._show_settings()
