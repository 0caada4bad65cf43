"""The dock's Environment box: check the worker's Python environment and model weights, set it up
with pip, open the options page; one message-bar warning stays until a check passes."""

from __future__ import annotations

from pathlib import Path

from qgis.core import Qgis, QgsApplication
from qgis.gui import QgsMessageBarItem
from qgis.PyQt.QtCore import Qt, pyqtSignal
from qgis.PyQt.QtWidgets import QGroupBox, QHBoxLayout, QLabel, QPushButton, QVBoxLayout

from .. import jobs
from ..options import PAGE_NAME
from ..settings import PluginSettings
from ..setup_env import SetupEnvTask, default_venv, install_target
from ..task import PipelineTask, log
from .common import DockSettings, JobSlot, detach

#: Settings whose change means another environment (checked again if it was checked before).
ENV_FIELDS = ("worker_path", "venv")
MODEL_FIELDS = ("segmenter", "model", "clipseg_model", "sam_model", "device")


def environment_changed(before: PluginSettings, after: PluginSettings) -> bool:
    """Whether ``after`` names another worker environment or other models than ``before``."""
    return any(getattr(before, f) != getattr(after, f) for f in ENV_FIELDS) or any(
        getattr(before.params, f) != getattr(after.params, f) for f in MODEL_FIELDS
    )


class EnvironmentSection(QGroupBox):
    """The "Environment" box."""

    #: the EnvReport of an environment check
    env_checked = pyqtSignal(object)
    #: Set up environment changed the settings (the dock shows them again)
    settings_changed = pyqtSignal()

    def __init__(self, iface, settings: DockSettings, slot: JobSlot) -> None:
        super().__init__("Environment")
        self.iface = iface
        self.settings = settings
        self.slot = slot
        #: the environment check in flight
        self.task: PipelineTask | None = None
        self.report = None
        #: whether this session checked the environment already (the first show checks it once)
        self.checked_once = False
        self._automatic = False  # the running check is the one the dock starts by itself
        #: the message-bar warning of the last environment check (removed once it passes)
        self._message: QgsMessageBarItem | None = None
        v = QVBoxLayout(self)
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
        slot.busy_changed.connect(lambda busy: self.setup_button.setEnabled(not busy))

    def check_environment(self, *_args, automatic: bool = False) -> None:
        """Check both Python environments and the model weights in a background task.

        ``automatic`` is the check the dock runs by itself when first shown: it warns in the
        message bar only when the core cannot work (no costmap, no route); what only
        segmentation lacks (model packages, weights) stays in the panel and the log, and the
        check is not repeated next session for it: an analyst who works from class rasters is
        not told every session, and Segment names every missing model when it is clicked. A
        check the user asks for (Check environment, changed options) warns about everything."""
        if self.task is not None:
            return
        self._automatic = automatic
        self.checked_once = True
        settings = self.settings.save()
        self.env_label.setText("Checking the Python environment…")
        self.task = PipelineTask("overseec: environment check", jobs.environment_report, settings)
        self.task.succeeded.connect(self._report_ready)
        self.task.failed.connect(self._check_failed)
        QgsApplication.taskManager().addTask(self.task)

    def check_if_changed(self, before: PluginSettings) -> None:
        """The options page was applied: check again if it changed the environment this session
        already checked."""
        if environment_changed(before, self.settings.current) and self.checked_once:
            self.check_environment()

    def clear_message(self) -> None:
        """Remove the last check's message-bar warning (if the user has not closed it)."""
        if self._message is not None and self.iface is not None:
            try:
                self.iface.messageBar().popWidget(self._message)
            except RuntimeError:  # the bar already deleted it (the user closed it)
                pass
        self._message = None

    def _report_ready(self, report) -> None:
        self.task = None
        self.report = report
        self.env_label.setText(report.text())
        self.setup_button.setDefault(report.setup_helps)
        log("environment check:\n" + report.text(), Qgis.Info if report.all_ok else Qgis.Warning)
        self.clear_message()  # a fixed problem's warning goes away
        automatic, self._automatic = self._automatic, False
        if report.all_ok or (automatic and report.ok):
            self.settings.current.env_checked = jobs.core_version()
            PluginSettings.save_fields(env_checked=self.settings.current.env_checked)
        if not report.all_ok and self.iface is not None and not (automatic and report.ok):
            self._warn(report)
        self.env_checked.emit(report)

    def _warn(self, report) -> None:
        """One message-bar warning: the first problem and the first advice."""
        problem = report.problems[0] if report.problems else "environment problem"
        more = f" (+{len(report.problems) - 1} more in the overseec panel)" if len(report.problems) > 1 else ""
        first = report.advice[0] if report.advice else ""
        self._message = QgsMessageBarItem(
            "overseec environment", problem + more + (f" -- {first}" if first else ""), Qgis.Warning, 0
        )
        self.iface.messageBar().pushItem(self._message)

    def _check_failed(self, message: str, _details: str) -> None:
        self.task = None
        self.env_label.setText(f"environment check failed: {message}")

    def set_up_environment(self, venv: str | Path | None = None, pip_args=()) -> None:
        """Create the worker's venv (the settings' venv, else the default place) and pip-install
        overseec[models] into it in a background task; on success the settings point at it and
        the environment is checked again."""
        settings = self.settings.save()
        plugin_dir = Path(__file__).parent.parent
        target_venv = Path(venv or settings.venv or default_venv(plugin_dir, QgsApplication.qgisSettingsDirPath()))
        try:
            target = install_target(settings.install_source, plugin_dir)
        except jobs.OverseecError as exc:
            self.slot.fail("set up", str(exc))
            return
        self.env_label.setText(f"Setting up {target_venv}: pip install {target.requirement} (see the log panel)…")
        task = SetupEnvTask(target_venv, target, pip_args=pip_args)
        self.slot.start("set up", task, self._environment_made)

    def _environment_made(self, result) -> None:
        self.settings.current = PluginSettings.save_fields(venv=str(result.venv), worker_path="", env_checked="")
        self.settings_changed.emit()
        self.slot.say(f"set up: {result.worker} is ready")
        self.check_environment()

    def show_options(self) -> None:
        """Settings › Options, on the overseec page."""
        if self.iface is not None:
            self.iface.showOptionsDialog(self.iface.mainWindow(), PAGE_NAME)

    def shutdown(self) -> None:
        """Detach the check in flight and remove the warning (the dock is going away)."""
        detach(self.task)
        self.task = None
        self.clear_message()
