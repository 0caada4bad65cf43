"""What the dock's sections share: the settings as the dock saves them, the current run folder,
and the one job slot with its status line.

Each section gets these three objects from the panel instead of reaching into its siblings, so a
section reads as its widgets plus what it does with them.
"""

from __future__ import annotations

import datetime as _dt
import tempfile
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any

from qgis.core import Qgis, QgsApplication, QgsProject
from qgis.PyQt.QtCore import QObject, pyqtSignal
from qgis.PyQt.QtWidgets import QFileDialog

from .. import jobs
from ..params import LlmSettings, Params
from ..settings import PluginSettings
from ..task import log

#: The runs folder beside a saved project, when the settings name none.
RUNS_FOLDER = "overseec-runs"
#: Project entry (scope, key) that remembers the dock's current run folder.
PROJECT_SCOPE, PROJECT_RUN_KEY = "overseec", "run_dir"
#: Project entry (in PROJECT_SCOPE) of the current run's input image.
PROJECT_IMAGE_KEY = "run_image"
#: Project entry (in PROJECT_SCOPE) of the runs folder chosen for the project while it was unsaved.
PROJECT_RUNS_KEY = "runs_folder"
#: How long information messages stay in the message bar (s).
INFO_S = 6
#: How long warnings stay in the message bar (s).
WARN_S = 15


def runs_root(setting: str, project_dir: str) -> Path | None:
    """Where run folders go: the setting, else ``overseec-runs`` beside the saved project
    (``project_dir``: ``QgsProject.absolutePath()``, "" for an unsaved project or one stored in a
    database), else None (the dock asks)."""
    if setting:
        return Path(setting).expanduser()
    if project_dir:
        return Path(project_dir) / RUNS_FOLDER
    return None


def ask_runs_folder(parent) -> str:
    """Ask where runs go for an unsaved project ("" when the user declines)."""
    return QFileDialog.getExistingDirectory(
        parent,
        "overseec: where should runs be kept? (save the project first to keep them beside it)",
        str(Path.home()),
    )


def stamped_folder(root: Path, name: str) -> Path:
    """A new folder ``root/name-<timestamp>`` (made, with its parents): one per run."""
    stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S-%f")
    folder = root / f"{name}-{stamp}"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def detach(task) -> None:
    """Disconnect everything from ``task`` and cancel it (the dock is going away; a worker
    process is terminated)."""
    if task is None:
        return
    try:
        for signal in (task.succeeded, task.failed, task.status, task.progressChanged):
            try:
                signal.disconnect()
            except TypeError:  # nothing connected
                pass
        task.cancel()
    except RuntimeError:  # the C++ task is already gone
        pass


class DockSettings:
    """The plugin settings as the dock last loaded or saved them.

    ``fields`` gathers the dock's own fields (the offline switch and run parameters); ``save``
    writes only those over the stored settings, so the options page's fields are never
    overwritten."""

    def __init__(self, fields: Callable[[], dict[str, Any]]) -> None:
        self.current = PluginSettings.load()
        self._fields = fields

    def save(self) -> PluginSettings:
        """Save the dock's own fields over the current settings; returns all settings."""
        self.current = PluginSettings.save_fields(**self._fields())
        return self.current

    def params(self) -> Params:
        """The form's run parameters (saved as the new defaults)."""
        return self.save().params

    def worker(self) -> Path:
        """The overseec environment's worker; LookupError (with advice) when there is none."""
        worker = jobs.find_worker_for(self.save())
        if worker is None:
            report = jobs.check_worker_env(None)
            raise LookupError(report.problems[0] + "; " + "; ".join(report.advice))
        return worker

    def llm_config(self) -> LlmSettings:
        """The LLM the interpreter uses: none when the offline switch is on."""
        s = self.save()
        if s.offline:
            return LlmSettings()
        return LlmSettings(endpoint=s.llm_endpoint, model=s.llm_model, api_key=s.api_key())


class JobSlot(QObject):
    """The dock's one job slot (one overseec job at a time) and its status line.

    Sections start their tasks here and say what happened here; the Run box shows the status,
    progress and busy state through the signals."""

    #: a task finished: (stage, ok)
    task_done = pyqtSignal(str, bool)
    #: a job started (True) or ended (False): the run buttons follow it
    busy_changed = pyqtSignal(bool)
    #: the job's progress in percent
    progress = pyqtSignal(int)
    #: the status line's new text
    said = pyqtSignal(str)

    def __init__(self, iface, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.iface = iface
        self.task = None
        #: stage -> the red message-bar items its failures left (they stay until closed): a
        #: later success of that stage takes them down, so no error outlives its cause
        self._failures: dict[str, list[Any]] = {}

    def say(self, text: str) -> None:
        """Show ``text`` on the status line."""
        self.said.emit(text)

    def set_busy(self, busy: bool) -> None:
        """Tell the sections a job started or ended."""
        self.busy_changed.emit(busy)

    def fail(self, title: str, message: str, details: str = "") -> None:
        """An error: the status line, the log and a red message-bar item that stays until the
        user closes it or ``title`` next succeeds (:meth:`resolved`)."""
        self.say(f"{title}: {message}")
        log(f"{title}: {message}" + (f"\n{details}" if details else ""), Qgis.Critical)
        if self.iface is not None:
            bar = self.iface.messageBar()
            bar.pushMessage(f"overseec {title}", message, Qgis.Critical, 0)
            item = bar.currentItem()  # the item just pushed is the one shown
            if item is not None and item.title() == f"overseec {title}":
                self._failures.setdefault(title, []).append(item)

    def resolved(self, title: str) -> None:
        """``title`` went through: take down the red items its earlier failures left (those the
        user has not closed already)."""
        from qgis.PyQt import sip

        items = self._failures.pop(title, [])
        if self.iface is None:
            return
        bar = self.iface.messageBar()
        for item in items:
            if item is not None and not sip.isdeleted(item):
                bar.popWidget(item)

    def warn(self, title: str, message: str) -> None:
        """Something the user should change, though the job went through (a prompt entity that
        matches no layer): the log and a yellow message-bar item that goes away by itself."""
        log(f"{title}: {message}", Qgis.Warning)
        if self.iface is not None:
            self.iface.messageBar().pushMessage(f"overseec {title}", message, Qgis.Warning, WARN_S)

    def inform(self, title: str, message: str) -> None:
        """What the user asked for happened (a cancel, a folder chosen): information that
        goes away by itself, never a red error."""
        self.say(f"{title}: {message}")
        log(f"{title}: {message}", Qgis.Info)
        if self.iface is not None:
            self.iface.messageBar().pushMessage(f"overseec {title}", message, Qgis.Info, INFO_S)

    def start(
        self, stage: str, task, on_success: Callable[[Any], None], then: Callable[[], None] | None = None
    ) -> None:
        """Run ``task`` in the task manager; route its outcome to ``on_success`` (and then to the
        next stage, ``then``) or to the message bar."""
        if self.task is not None:
            self.fail(stage, "another overseec job is running; cancel it first")
            return
        self.task = task
        task.progressChanged.connect(lambda p: self.progress.emit(int(p)))
        task.status.connect(lambda s: self.say(f"{stage}: {s}…"))

        def done_ok(result) -> None:
            self.task = None
            self.set_busy(False)
            try:
                on_success(result)
            except Exception as exc:  # adding layers failed: report, keep what is there
                self.fail(stage, f"the run finished but its outputs could not be shown: {exc}", traceback.format_exc())
                self.task_done.emit(stage, False)
                return
            self.resolved(stage)
            self.task_done.emit(stage, True)
            if then is not None:
                try:
                    then()
                except Exception as exc:  # never let an exception escape a Qt slot
                    self.fail(stage, f"could not start the next stage: {exc}", traceback.format_exc())

        def done_fail(message: str, details: str) -> None:
            self.task = None
            self.set_busy(False)
            if task.was_cancelled:
                self.inform(stage, message)
            else:
                self.fail(stage, message, details)
            self.task_done.emit(stage, False)

        task.succeeded.connect(done_ok)
        task.failed.connect(done_fail)
        self.say(f"{stage}…")
        self.set_busy(True)
        QgsApplication.taskManager().addTask(task)

    def cancel(self) -> None:
        """Cancel the running job (its task reports back as cancelled)."""
        if self.task is not None:
            self.say("cancelling…")
            self.task.cancel()

    def shutdown(self) -> None:
        """Detach and cancel the running job (the dock is going away)."""
        detach(self.task)
        self.task = None


class CurrentRun:
    """The current run folder and the image it was made for, remembered in the project.

    Stages reuse it, so re-prompting re-uses the masks already segmented for that image."""

    def __init__(self, slot: JobSlot, ask: Callable[[], str], changed: Callable[[], None] = lambda: None) -> None:
        self.slot = slot
        #: called when where runs go changes (the folder asked for, or the temporary fallback)
        self.changed = changed
        self.run_dir: Path | None = None
        self.run_image: str | None = None
        #: runs folder of this project when no runs folder is set: the one chosen while it was
        #: unsaved (asked once; kept in the project), or the temporary one used when declined
        self.session_runs: Path | None = None
        #: whether ``session_runs`` is the temporary fallback (never saved with the project)
        self._temporary = False
        #: asks where runs go when the project is unsaved and no runs folder is set
        self.ask_runs_folder = ask

    def root(self) -> Path | None:
        """Where new run folders go, without asking: :func:`runs_root` (the runs folder setting,
        else ``overseec-runs`` beside the saved project), else the folder chosen for this project
        while it was unsaved (kept in it: a project stored in a database has no folder beside
        it); None while an unsaved project has none yet (the first run asks)."""
        root = runs_root(PluginSettings.load().runs_dir, QgsProject.instance().absolutePath())
        if root is None and self.session_runs is not None and not self._temporary:
            return self.session_runs
        return root

    def runs_folder(self) -> Path:
        """Where new run folders go (:meth:`root`); for an unsaved project without a runs
        folder setting the user is asked once, and a temporary folder (said so in the message
        bar) is used if they decline."""
        root = self.root()
        if root is not None:
            return root
        if self.session_runs is None:
            answer = self.ask_runs_folder()
            if answer:
                self.session_runs = Path(answer)
            else:
                self.session_runs, self._temporary = Path(tempfile.gettempdir()) / RUNS_FOLDER, True
                self.slot.inform(
                    "runs",
                    f"runs go to {self.session_runs}, which is temporary: save the project (runs then go "
                    f"beside it) or set a runs folder in Settings › Options › overseec to keep them",
                )
            self.changed()
        return self.session_runs

    def describe(self) -> str:
        """Where runs go, as the dock shows it: the folder, the temporary fallback said so, or
        that the first run will ask."""
        root = self.root()
        if root is not None:
            return str(root)
        if self.session_runs is not None and self._temporary:
            return f"{self.session_runs} (temporary: save the project or set a runs folder to keep runs)"
        return "asked on the first run (project not saved)"

    def ensure_run_dir(self, image: str, new: bool = False) -> Path:
        """The run directory for ``image``: the current one, or a new one under the runs folder."""
        if (
            not new
            and self.run_dir is not None
            and self.run_image is not None
            and Path(self.run_image).resolve() == Path(image).resolve()
        ):
            return self.run_dir
        run_dir = stamped_folder(self.runs_folder(), Path(image).stem)
        self.set_run_dir(run_dir, image)
        return run_dir

    def set_run_dir(self, run_dir: Path | None, image: str | None = None) -> None:
        """Make ``run_dir`` the current run and remember it in the project."""
        self.run_dir, self.run_image = run_dir, image
        project = QgsProject.instance()
        if run_dir is None:
            project.removeEntry(PROJECT_SCOPE, PROJECT_RUN_KEY)
            project.removeEntry(PROJECT_SCOPE, PROJECT_IMAGE_KEY)
        else:
            project.writeEntry(PROJECT_SCOPE, PROJECT_RUN_KEY, str(run_dir))
            project.writeEntry(PROJECT_SCOPE, PROJECT_IMAGE_KEY, image or "")

    def restore(self, project: QgsProject) -> str:
        """A project was opened: carry on with the run folder it was saved with (if it is still
        there). Returns the run's input image when that file still exists, else ""."""
        runs, _ = project.readEntry(PROJECT_SCOPE, PROJECT_RUNS_KEY, "")
        self.session_runs, self._temporary = (Path(runs) if runs else None), False
        run_dir, found = project.readEntry(PROJECT_SCOPE, PROJECT_RUN_KEY, "")
        image, _ = project.readEntry(PROJECT_SCOPE, PROJECT_IMAGE_KEY, "")
        if found and run_dir and Path(run_dir).is_dir():
            self.run_dir, self.run_image = Path(run_dir), image or None
            return image if image and Path(image).is_file() else ""
        self.run_dir, self.run_image = None, None
        return ""

    def save_to(self, project: QgsProject) -> None:
        """The project is being written: the runs folder chosen for it goes with it (never the
        temporary one)."""
        chosen = self.session_runs if self.session_runs is not None and not self._temporary else None
        project.writeEntry(PROJECT_SCOPE, PROJECT_RUNS_KEY, str(chosen) if chosen is not None else "")

    def forget(self) -> None:
        """The project was closed: no current run and no runs folder of its own (the project
        entries went with it); the next unsaved project asks again."""
        self.run_dir, self.run_image = None, None
        self.session_runs, self._temporary = None, False
