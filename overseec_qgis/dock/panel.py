"""The overseec dock: a scrollable panel over its sections, wired together.

The panel builds the sections (imagery, mission, parameters, runs, environment), hands them the
three things they share (:mod:`.common`: the settings, the current run, the job slot), connects
their signals, and follows the project (a reopened project carries on with its run folder). Every
thing the dock does lives in a section.
"""

from __future__ import annotations

from typing import Any

from qgis.core import QgsProject
from qgis.gui import QgsDockWidget
from qgis.PyQt.QtCore import QTimer, pyqtSignal
from qgis.PyQt.QtWidgets import QScrollArea, QVBoxLayout, QWidget

from .. import jobs
from ..settings import PluginSettings
from .common import CurrentRun, DockSettings, JobSlot, ask_runs_folder, detach
from .environment import EnvironmentSection
from .imagery import ImagerySection
from .mission import MissionSection
from .parameters import ParametersSection
from .routes import RoutesSection
from .runs import RunsSection


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
        self.settings = DockSettings(self._dock_fields)
        self.slot = JobSlot(iface, self)
        self.run = CurrentRun(self.slot, lambda: ask_runs_folder(self), changed=lambda: self._show_settings())
        self.imagery = ImagerySection(iface, self.settings, self.run, self.slot)
        self.mission = MissionSection(self.run, self.slot)
        self.parameters = ParametersSection()
        self.runs = RunsSection(iface, self.settings, self.run, self.slot, self.imagery, self.mission)
        self.environment = EnvironmentSection(iface, self.settings, self.slot)
        self.routes = RoutesSection(iface, self.settings, self.slot, lambda: self.runs.map_tool)
        self._layout()
        self.mission.offline_check.setChecked(self.settings.current.offline)
        self.parameters.load(self.settings.current.params)
        self._show_settings()
        self._wire()
        self.slot.set_busy(False)
        project = QgsProject.instance()
        self._project_slots = (
            (project.readProject, self._project_read),
            (project.cleared, self._project_cleared),
            (project.writeProject, self._project_writing),
            # the default runs folder moves with the project file: `write(path)` says so only
            # through projectSaved, Save As through fileNameChanged
            (project.fileNameChanged, self._show_settings),
            (project.projectSaved, self._show_settings),
        )
        for signal, slot in self._project_slots:
            signal.connect(slot)

    def _layout(self) -> None:
        body = QWidget()
        col = QVBoxLayout(body)
        for section in (self.imagery, self.mission, self.parameters, self.runs, self.routes, self.environment):
            col.addWidget(section)
        col.addStretch(1)
        scroll = QScrollArea()
        scroll.setWidgetResizable(True)
        scroll.setWidget(body)
        self.setWidget(scroll)

    def _wire(self) -> None:
        """The sections' signals: to each other and out of the panel."""
        self.slot.task_done.connect(self.task_done)
        self.runs.run_done.connect(self.run_done)
        self.environment.env_checked.connect(self.env_checked)
        self.environment.settings_changed.connect(self._show_settings)
        self.imagery.run_changed.connect(self.mission.masks_updated)
        self.mission.interpret_button.clicked.connect(lambda _checked=False: self.runs.interpret())

    def _dock_fields(self) -> dict[str, Any]:
        """The settings the dock edits: the offline switch and the run parameters."""
        return {"offline": self.mission.offline_check.isChecked(), **self.parameters.fields()}

    def _show_settings(self) -> None:
        """The options-page settings the dock's work depends on, as one line each."""
        s = self.settings.current
        self.mission.show_settings(s)
        self.parameters.show_settings(s, self.run.describe())

    def reload_settings(self, saved: PluginSettings | None = None) -> None:
        """The options page was applied: show its settings, re-check a changed environment."""
        before = self.settings.current
        self.settings.current = saved or PluginSettings.load()
        self._show_settings()
        self.environment.check_if_changed(before)

    def set_map_tool(self, tool, action) -> None:
        """Share the plugin's map tool: the Plan button drives the same (checkable) action."""
        self.runs.map_tool = tool
        self.runs.plan_button.clicked.connect(lambda _checked: action.trigger())
        action.toggled.connect(self.runs.plan_button.setChecked)
        self.parameters.mode_combo.currentTextChanged.connect(lambda m: setattr(tool, "mode", m))
        tool.mode = self.parameters.mode_combo.currentText()
        steps = self.parameters.steps_combo
        steps.currentIndexChanged.connect(lambda _i: setattr(tool, "neighbours", int(steps.currentData())))
        tool.neighbours = int(steps.currentData())  # the next click or drag plans with them, as with the mode

    # -- The project -------------------------------------------------------------------------

    def _project_read(self, *_args) -> None:
        """A project was opened: carry on with the run folder it was saved with (if it is still
        there); its layers already point at that folder's files. The mission (prompt, entities,
        program, aliases, priors, entity layers) and the input image come back as saved."""
        project = QgsProject.instance()
        self.mission.restore(project)
        image = self.run.restore(project)
        self.imagery.restore(project, image)
        self.mission.masks_updated()
        self._show_settings()

    def _project_writing(self, *_args) -> None:
        """The project is being saved: the dock's mission and input image go into it."""
        project = QgsProject.instance()
        self.mission.save_to(project)
        self.imagery.save_to(project)
        self.run.save_to(project)

    def _project_cleared(self) -> None:
        self.run.forget()
        self.mission.show_mission()
        self.imagery.clear()
        self.mission.masks_updated()
        self._show_settings()

    # -- Showing and unloading ---------------------------------------------------------------

    def showEvent(self, event) -> None:
        """The first show checks the environment, unless this core version passed before."""
        super().showEvent(event)
        if not self.environment.checked_once and self.settings.current.env_checked != jobs.core_version():
            QTimer.singleShot(0, lambda: self.environment.check_environment(automatic=True))

    def shutdown(self) -> None:
        """Plugin unload: detach running tasks from this widget (it is about to be deleted),
        cancel the job (a worker is terminated), save the form."""
        self.slot.shutdown()
        self.environment.shutdown()
        detach(self.imagery.info_task)
        self.imagery.info_task = None
        detach(self.mission.names_task)
        self.mission.names_task = None
        self.mission.program_timer.stop()
        self.imagery.drop_extent_tool()
        for signal, slot in self._project_slots:
            try:
                signal.disconnect(slot)
            except TypeError:
                pass
        self.settings.save()
