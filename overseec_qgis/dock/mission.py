"""The dock's mission: the prompt, the entities table, the entity layers the costmap reads (masks
or a class raster, aliases, priors, and a DEM for the terrain fields) and the cost program,
checked as it is typed."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from qgis.core import QgsApplication, QgsMapLayerProxyModel, QgsProject, QgsRasterLayer, QgsTask
from qgis.gui import QgsFileWidget, QgsMapLayerComboBox
from qgis.PyQt.QtCore import QTimer
from qgis.PyQt.QtGui import QColor, QFontDatabase, QTextCursor, QTextFormat
from qgis.PyQt.QtWidgets import (
    QCheckBox,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QPlainTextEdit,
    QPushButton,
    QTextEdit,
    QVBoxLayout,
    QWidget,
)

from overseec_core import runfiles

from .. import jobs, params
from ..settings import PluginSettings
from ..task import PipelineTask, log
from .common import CurrentRun, JobSlot, detach
from .entity_table import EntityTable
from .fitting import DEM_FIELD, Fitted, Names, fit_for_dock, names_key, read_names, terrain_error
from .mission_state import Mission, read_mission, write_mission

#: How long the program box waits after the last keystroke before checking the program (ms).
PROGRAM_CHECK_MS = 300


class MissionSection(QWidget):
    """The "Mission", "Entities", "Entity layers for the costmap" and "Cost program" boxes.

    Holds the interpretation last shown, so Run all knows whether to interpret again."""

    def __init__(self, run: CurrentRun, slot: JobSlot) -> None:
        super().__init__()
        self.run = run
        self.slot = slot
        self.interpretation = None  # overseec_core Interpretation from the last Interpret
        #: the priors the last Interpret ran with (Run all interprets again when they changed)
        self.interpretation_priors: params.Priors | None = None
        #: whether that interpretation was asked with a DEM (the LLM is offered slope, roughness);
        #: None: not known (a restored project), which forces no new interpretation
        self.interpretation_terrain: bool | None = None
        #: set while a project's mission fields are restored (not written back to it)
        self._restoring = False
        #: the entity layers' names, read on the task thread (opening rasters takes time)
        self._names: Names | None = None
        #: the task reading them, and what waits for them
        self.names_task: PipelineTask | None = None
        self._names_waiting: list[Callable[[], object]] = []
        self._names_sources: dict = {}
        col = QVBoxLayout(self)
        col.setContentsMargins(0, 0, 0, 0)
        for box in (self._build_prompt_box(), self._build_entities_box(), self._build_layers_box()):
            col.addWidget(box)
        col.addWidget(self._build_program_box())
        self.program_timer = QTimer(self)
        self.program_timer.setSingleShot(True)
        self.program_timer.setInterval(PROGRAM_CHECK_MS)
        self.program_timer.timeout.connect(self.validate_program)
        self.program_edit.textChanged.connect(self.program_timer.start)
        self.labels_combo.layerChanged.connect(self._layers_changed)
        self.classes_widget.fileChanged.connect(self._layers_changed)
        for signal in (
            self.prompt_edit.textChanged,
            self.program_edit.textChanged,
            self.entities_table.edited,
            self.aliases_edit.textChanged,
            self.priors_widget.fileChanged,
            self.no_priors_check.toggled,
            self.classes_widget.fileChanged,
            self.dem_combo.layerChanged,
            self.dem_file_widget.fileChanged,
        ):
            signal.connect(self._edited)
        self.dem_combo.layerChanged.connect(self._dem_changed)
        self.dem_file_widget.fileChanged.connect(self._dem_changed)
        self.offline_check.toggled.connect(self._llm_enabled)
        self.slot.busy_changed.connect(lambda busy: self.interpret_button.setEnabled(not busy))

    def _build_prompt_box(self) -> QGroupBox:
        box = QGroupBox("Mission")
        v = QVBoxLayout(box)
        self.prompt_edit = QPlainTextEdit()
        self.prompt_edit.setPlaceholderText("e.g. Prefer the roads and trails, grass is fine, avoid the baseball field")
        self.prompt_edit.setMaximumHeight(80)
        self.unread: tuple[str, ...] = ()  # the last interpretation's unread parts (highlighted)
        self.prompt_edit.textChanged.connect(self._prompt_edited)
        v.addWidget(self.prompt_edit)
        self.offline_check = QCheckBox("Offline interpreter (no LLM)")
        v.addWidget(self.offline_check)
        self.llm_label = QLabel("")
        self.llm_label.setWordWrap(True)
        self.llm_label.setToolTip("The LLM endpoint, model and API key are set in Settings › Options › overseec")
        v.addWidget(self.llm_label)
        self.interpret_button = QPushButton("Interpret prompt")
        v.addWidget(self.interpret_button)
        return box

    def _build_entities_box(self) -> QGroupBox:
        box = QGroupBox("Entities")
        v = QVBoxLayout(box)
        self.entities_table = EntityTable()
        v.addWidget(self.entities_table)
        row = QHBoxLayout()
        add = QPushButton("Add entity")
        add.clicked.connect(lambda: self.add_entity_row("", "areal", None, ()))
        remove = QPushButton("Remove selected")
        remove.clicked.connect(self.entities_table.remove_selected)
        row.addWidget(add)
        row.addWidget(remove)
        v.addLayout(row)
        return box

    def _build_layers_box(self) -> QGroupBox:
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
        self._build_dem_rows(form)
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
        return box

    def _build_dem_rows(self, form: QFormLayout) -> None:
        """The DEM: a raster layer (or "none") and, when none is chosen, a file (``--dem``)."""
        self.dem_combo = QgsMapLayerComboBox()
        self.dem_combo.setFilters(QgsMapLayerProxyModel.RasterLayer)
        self.dem_combo.setAllowEmptyLayer(True, "none")
        self.dem_combo.setLayer(None)
        self.dem_combo.setToolTip(
            "An elevation raster in metres (any CRS and resolution; resampled onto the costmap's grid): "
            "the cost program may then read slope (degrees) and roughness (metres)"
        )
        form.addRow(DEM_FIELD, self.dem_combo)
        self.dem_file_widget = QgsFileWidget()
        self.dem_file_widget.setFilter("Rasters (*.tif *.tiff *.vrt *.img *.asc *.dem);;All files (*)")
        self.dem_file_widget.setToolTip("A DEM file, used when no DEM layer is chosen above")
        form.addRow("or DEM file", self.dem_file_widget)

    def _build_program_box(self) -> QGroupBox:
        box = QGroupBox("Cost program")
        v = QVBoxLayout(box)
        self.program_edit = QPlainTextEdit()
        self.program_edit.setFont(QFontDatabase.systemFont(QFontDatabase.FixedFont))
        self.program_edit.setLineWrapMode(QPlainTextEdit.NoWrap)
        self.program_edit.setMinimumHeight(120)
        v.addWidget(self.program_edit)
        self.program_status = QLabel("")
        self.program_status.setWordWrap(True)
        v.addWidget(self.program_status)
        self.fit_label = QLabel("")
        self.fit_label.setWordWrap(True)
        self.fit_label.setStyleSheet("color: #8a6d00")
        self.fit_label.setVisible(False)
        v.addWidget(self.fit_label)
        return box

    # -- Settings ----------------------------------------------------------------------------

    def show_settings(self, s: PluginSettings) -> None:
        """The LLM the options page sets, as one line."""
        llm = f"{s.llm_endpoint}" + (f", model {s.llm_model}" if s.llm_model else "") if s.llm_endpoint else "none set"
        self.llm_label.setText(f"LLM: {llm}" + (" (API key stored)" if s.llm_authcfg else ""))

    def _llm_enabled(self, offline: bool) -> None:
        self.llm_label.setEnabled(not offline)

    def prompt(self) -> str:
        """The mission prompt, stripped."""
        return self.prompt_edit.toPlainText().strip()

    # -- Entities ----------------------------------------------------------------------------

    def add_entity_row(self, name: str, geometry: str, threshold: float | None, prompts) -> None:
        """Append an entity to the table (``prompts``: its prompts; the name itself is implied)."""
        self.entities_table.add_row(name, geometry, threshold, prompts)

    def entity_rows(self) -> list[dict]:
        """The table as plain dicts (name, geometry, threshold or None, prompts)."""
        return self.entities_table.entity_rows()

    def priors(self) -> params.Priors:
        """The mission's priors: none when "No priors" is ticked, else the file's, else built-in."""
        if self.no_priors_check.isChecked():
            return params.Priors(off=True)
        return params.Priors(path=self.priors_widget.filePath().strip())

    def show_interpretation(
        self,
        interp,
        priors: params.Priors | None = None,
        fitted: Fitted | None = None,
        terrain: bool | None = None,
    ) -> None:
        """Fill the table and program box (``priors``: those it was interpreted with, default
        the dock's; ``fitted``: its program fitted to the entity layers on the task thread,
        :meth:`fit_job`; without it the fitting runs here; ``terrain``: whether it was asked with
        a DEM, default whether one is chosen now)."""
        self.interpretation = interp
        self.interpretation_priors = self.priors() if priors is None else priors
        self.interpretation_terrain = bool(self.dem_path()) if terrain is None else terrain
        if fitted is None:
            fitted = fit_for_dock(
                interp, self.layer_sources(), self._names, self.aliases_edit.text(), self.interpretation_priors
            )
        if fitted.names.key is not None:
            self._names = fitted.names
        self.entities_table.setRowCount(0)
        for e in interp.entities:
            self.add_entity_row(e.name, e.geometry, e.threshold, e.prompts)
        self.program_edit.setPlainText(fitted.program)
        for note in interp.notes:
            log(f"interpret: {note}")
        for line, level in fitted.log:
            log(line, level)
        self.show_advice(fitted.advice)
        unread = tuple(interp.unparsed)
        self.mark_unread(unread)
        if unread:  # never "Interpreted" alone when part of the brief was dropped
            log("interpret: not understood: " + "; ".join(unread))
            said = (
                f"Interpreted ({interp.source}), but {len(unread)} part(s) of the prompt were not understood"
                " and have no effect (highlighted): " + "; ".join(repr(u) for u in unread)
            )
        else:
            said = f"Interpreted ({interp.source})"
        self.slot.say(said + ("; " + "; ".join(fitted.advice) if fitted.advice else "."))
        if unread:
            self.slot.warn(
                "interpret",
                f"not understood, so it has no effect: {'; '.join(repr(u) for u in unread)} "
                "(highlighted in the prompt; reword it, or edit the program)",
            )
        if fitted.advice:
            self.slot.warn("interpret", fitted.advice[0])

    def mark_unread(self, unread: Sequence[str]) -> None:
        """Highlight the prompt's words that were not understood (a yellow background in the
        prompt box, the text itself untouched); the marks go as soon as the prompt is edited."""
        from qgis.PyQt.QtGui import QColor, QTextCursor, QTextDocument

        selections = []
        document = self.prompt_edit.document()
        for fragment in unread:
            cursor = document.find(fragment, 0, QTextDocument.FindFlags())
            while not cursor.isNull():
                sel = QTextEdit.ExtraSelection()
                sel.cursor = QTextCursor(cursor)
                sel.format.setBackground(QColor(255, 214, 0, 160))
                sel.format.setToolTip("not understood: this has no effect on the costmap")
                selections.append(sel)
                cursor = document.find(fragment, cursor)
        self.prompt_edit.setExtraSelections(selections)
        self.unread = tuple(unread)

    def _prompt_edited(self) -> None:
        """The prompt changed: the marks of the last interpretation no longer apply."""
        if self.prompt_edit.extraSelections():
            self.prompt_edit.setExtraSelections([])

    def show_advice(self, advice: Sequence[str] = ()) -> None:
        """What the last fitting could not match, phrased for the dock's fields (or nothing)."""
        self.fit_label.setText("\n".join(f"⚠ {a}" for a in advice))
        self.fit_label.setVisible(bool(advice))

    def fit_job(self, priors: params.Priors) -> Callable[[list[str]], tuple]:
        """For Interpret's task: a function of the worker's printed lines, run on the task thread,
        that reads the interpretation and fits its program to the entity layers chosen now."""
        sources, names, aliases = self.layer_sources(), self._names, self.aliases_edit.text()

        def job(printed: list[str]) -> tuple:
            interp = jobs.interpretation_from_json(jobs.result_document(printed))
            return interp, fit_for_dock(interp, sources, names, aliases, priors)

        return job

    def needs_interpreting(self) -> bool:
        """Whether the table does not hold this prompt's interpretation with these priors (and
        with a DEM chosen or not, as when it was interpreted: the LLM is offered slope then)."""
        return (
            self.interpretation is None
            or self.interpretation.prompt != self.prompt()
            or self.interpretation_priors != self.priors()
            or (self.interpretation_terrain is not None and self.interpretation_terrain != bool(self.dem_path()))
        )

    def current_interpretation(self):
        """The interpretation as edited in the table and program box."""
        return jobs.edited_interpretation(
            self.interpretation, self.prompt(), self.entity_rows(), self.program_edit.toPlainText()
        )

    # -- Entity layers -----------------------------------------------------------------------

    def layer_sources(self) -> dict:
        """The costmap's entity layers: the current run's masks and/or a class raster."""
        labels_layer = self.labels_combo.currentLayer()
        labels = jobs.layer_file(labels_layer) if isinstance(labels_layer, QgsRasterLayer) else ""
        classes = self.classes_widget.filePath().strip()
        run_dir = self.run.run_dir
        masks = str(run_dir) if run_dir is not None and runfiles.first_existing(run_dir, "mask") is not None else ""
        return {
            "masks_dir": masks or None,
            "labels": labels or None,
            "classes": classes if labels and classes else None,
            "dem": self.dem_path() or None,
        }

    def dem_path(self) -> str:
        """The DEM's file: the chosen layer's, else the file field's ('' for none, or for a
        layer that is not a file, :meth:`dem_problem`)."""
        layer = self.dem_combo.currentLayer()
        if layer is not None:
            return jobs.layer_file(layer) if isinstance(layer, QgsRasterLayer) else ""
        return self.dem_file_widget.filePath().strip()

    def dem_problem(self) -> str:
        """Why the chosen DEM layer cannot be handed to the worker ('' when it can, or none is chosen)."""
        layer = self.dem_combo.currentLayer()
        if layer is None or self.dem_path():
            return ""
        return f"the layer '{layer.name()}' in {DEM_FIELD} is not a raster file; choose a file layer or a DEM file"

    def _dem_changed(self, *_args) -> None:
        """The DEM changed: check the program again (whether it may read slope and roughness)."""
        if self.program_edit.toPlainText().strip():
            self.program_timer.start()

    def masks_updated(self) -> None:
        """The current run's masks may have changed: show them, read the names again."""
        self._names = None
        run_dir = self.run.run_dir
        masks = runfiles.first_existing(run_dir, "mask") if run_dir is not None else None
        self.masks_label.setText(f"Masks: {masks}" if masks else "Masks: none yet (Segment or Run all)")
        self.load_names()

    def _layers_changed(self, *_args) -> None:
        self._names = None
        self.load_names(self.validate_program if self.program_edit.toPlainText().strip() else None)

    def names_known(self) -> bool:
        """Whether the entity layers' names are at hand (no layers, or read for these ones)."""
        key = names_key(self.layer_sources())
        return key is None or (self._names is not None and self._names.key == key)

    def load_names(self, then: Callable[[], object] | None = None) -> None:
        """Read the entity layers' names on the task thread (opening rasters never blocks QGIS),
        then call ``then``; at once when they are known already."""
        if self.names_known():
            if then is not None:
                then()
            return
        if then is not None:
            self._names_waiting.append(then)
        sources = self.layer_sources()
        if self._names_pending() and self._names_sources == sources:
            return
        detach(self.names_task)
        task = PipelineTask("overseec: entity layer names", read_names, sources)
        self._names_sources = sources
        task.succeeded.connect(lambda names: self._names_read(task, names))
        task.failed.connect(lambda message, _details: self._names_read(task, Names(names_key(sources), error=message)))
        self.names_task = task
        QgsApplication.taskManager().addTask(task)

    def _names_pending(self) -> bool:
        """Whether the names task can still report: it exists and has not ended. One that ended
        (or whose C++ object is gone) without reporting here would leave the callbacks waiting
        for ever, so it counts as none and a new one starts."""
        task = self.names_task
        if task is None:
            return False
        try:
            return QgsTask.status(task) not in (QgsTask.Complete, QgsTask.Terminated)  # .status is a signal here
        except RuntimeError:  # the C++ task is already deleted
            return False

    def _names_read(self, task, names: Names) -> None:
        if task is not self.names_task:
            return
        self.names_task = None
        self._names = names
        waiting, self._names_waiting = self._names_waiting, []
        for then in waiting:
            then()

    def entity_names(self) -> tuple[str, ...]:
        """Names a program may use: those of the layer sources, else the entities table. Reads
        them here when they are not known yet (:meth:`load_names` reads them in a task);
        OverseecError when the layers are unusable."""
        src = self.layer_sources()
        if names_key(src) is None:
            return tuple(r["name"] for r in self.entity_rows())
        if not self.names_known():
            self._names = read_names(src)
        assert self._names is not None
        if self._names.error:
            raise jobs.InputError(self._names.error)
        if self._names.names is None:  # QGIS's Python cannot read rasters: the worker's costmap checks
            return tuple(r["name"] for r in self.entity_rows())
        return self._names.names

    # -- The cost program --------------------------------------------------------------------

    def validate_program(self) -> bool:
        """Check the program against the entity names; mark an error at its line."""
        text = self.program_edit.toPlainText()
        self.program_edit.setExtraSelections([])
        if not text.strip():
            self.program_status.setText("")
            return False
        if not self.names_known():  # checked once the task has read them
            self.program_status.setStyleSheet("")
            self.program_status.setText("checking the program against the entity layers…")
            self.load_names(self.validate_program)
            return False
        try:
            names = self.entity_names()
        except jobs.OverseecError as exc:  # the entity layers themselves are unusable
            self.program_status.setStyleSheet("color: #b00020")
            self.program_status.setText(f"✗ entity layers: {exc}")
            return False
        try:
            program = jobs.check_program(text, names)
            problem = terrain_error(program, self.dem_path(), self.dem_problem())
            if problem is not None:
                raise problem
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

    # -- The project -------------------------------------------------------------------------

    def _edited(self, *_args) -> None:
        """The user changed the mission: the project has unsaved changes (the mission itself is
        written when the project is saved, :meth:`save_to`)."""
        if not self._restoring:
            QgsProject.instance().setDirty(True)

    def mission(self) -> Mission:
        """The mission as the dock shows it now (what the project saves)."""
        labels, dem = self.labels_combo.currentLayer(), self.dem_combo.currentLayer()
        with_priors = self.interpretation_priors
        return Mission(
            prompt=self.prompt_edit.toPlainText(),
            rows=self.entities_table.cells(),
            program=self.program_edit.toPlainText(),
            aliases=self.aliases_edit.text().strip(),
            priors=self.priors_widget.filePath().strip(),
            no_priors=self.no_priors_check.isChecked(),
            interpretation=self.interpretation.to_json() if self.interpretation is not None else None,
            interpreted_with=(with_priors.path, with_priors.off) if with_priors is not None else None,
            labels_layer=labels.id() if labels is not None else "",
            classes=self.classes_widget.filePath().strip(),
            dem_layer=dem.id() if dem is not None else "",
            dem_file=self.dem_file_widget.filePath().strip(),
        )

    def save_to(self, project: QgsProject) -> None:
        """The project is being written: the mission goes into its entries."""
        write_mission(project, self.mission())

    def show_mission(self, mission: Mission | None = None) -> None:
        """Show a project's mission (blank fields for none) without marking the project changed;
        the interpretation the table came from comes back with it, so nothing is interpreted
        again over the user's edits. A mission from an older plugin (``complete`` False) brings
        back only its aliases and priors."""
        m = mission or Mission()
        self._restoring = True
        try:
            self.aliases_edit.setText(m.aliases)
            self.priors_widget.setFilePath(m.priors)
            self.no_priors_check.setChecked(m.no_priors)
            if m.complete:
                self._show_fields(m)
        finally:
            self._restoring = False

    def _show_fields(self, m: Mission) -> None:
        self.show_advice(())  # the last fitting's advice was about another mission
        self.prompt_edit.setPlainText(m.prompt)
        self.entities_table.show_cells(m.rows)
        self.interpretation, self.interpretation_priors, self.interpretation_terrain = None, None, None
        if m.interpretation is not None and m.interpreted_with is not None:
            try:
                self.interpretation = jobs.interpretation_from_json(m.interpretation)
                self.interpretation_priors = params.Priors(*m.interpreted_with)
            except (KeyError, TypeError, ValueError) as exc:  # a hand-edited project: interpret again
                log(f"project: the saved interpretation cannot be read ({exc}); Run all interprets again")
        layer = QgsProject.instance().mapLayer(m.labels_layer) if m.labels_layer else None
        self.labels_combo.setLayer(layer if isinstance(layer, QgsRasterLayer) else None)
        self.classes_widget.setFilePath(m.classes)
        dem = QgsProject.instance().mapLayer(m.dem_layer) if m.dem_layer else None
        self.dem_combo.setLayer(dem if isinstance(dem, QgsRasterLayer) else None)
        self.dem_file_widget.setFilePath(m.dem_file)
        self.program_edit.setPlainText(m.program)

    def restore(self, project: QgsProject) -> None:
        """A project was opened: its mission comes back as it was saved."""
        self.show_mission(read_mission(project))
