"""The plugin object QGIS creates: actions, dock, map tools, Processing provider.

The map tools: plan (click start, vias, goal), fix a mask with SAM, and draw overrides (with
its preset toolbar -- Lethal, Prefer, Cost and a slider -- shown while it is active).

``initGui`` adds everything and ``unload`` removes exactly what ``initGui`` added (actions from
the menu and toolbar, the dock, the map tool from the canvas, the page under Settings › Options,
the Processing provider), so reloading or disabling the plugin leaves QGIS as it was.
``initProcessing`` alone runs under ``qgis_process`` (no GUI, ``iface`` is None).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from qgis.core import QgsApplication, QgsProject
from qgis.PyQt.QtCore import Qt, QTimer
from qgis.PyQt.QtGui import QIcon
from qgis.PyQt.QtWidgets import QAction, QMainWindow, QToolBar

from .envcheck import ensure_core_importable
from .layers import icon_path
from .planclient import close_shared_client
from .samclient import close_shared_client as close_shared_sam_client
from .settings import PluginSettings
from .worker import find_worker

if TYPE_CHECKING:
    from .dock.panel import OverseecDock
    from .fixtool import FixMaskTool
    from .legend import RoutesKeeper
    from .maptool import PlanMapTool
    from .options import OverseecOptionsFactory
    from .overridetool import OverrideTool, PresetWidget
    from .processing.provider import OverseecProvider
    from .task import PipelineTask

MENU = "&overseec"


def prepare_core() -> None:
    """Make ``overseec_core``'s dependencies importable (borrowing the venv's if needed)."""
    settings = PluginSettings.load()
    worker = find_worker(settings.worker_path, settings.venv, Path(__file__).parent)
    ensure_core_importable(settings.venv or None, worker)


class OverseecPlugin:
    """Owns the plugin's GUI pieces and its Processing provider."""

    def __init__(self, iface) -> None:
        self.iface = iface
        self.provider: OverseecProvider | None = None
        self.dock: OverseecDock | None = None
        self.map_tool: PlanMapTool | None = None
        self.fix_tool: FixMaskTool | None = None
        #: (worker, SAM setting) pairs whose SAM weights were found this session
        self._sam_ok: set[tuple[str, str]] = set()
        #: the SAM check in flight when the fix-mask tool was chosen
        self._sam_task: PipelineTask | None = None
        self.override_tool: OverrideTool | None = None
        self.preset_widget: PresetWidget | None = None
        self.override_toolbar: QToolBar | None = None
        self.options_factory: OverseecOptionsFactory | None = None
        self.routes_keeper: RoutesKeeper | None = None
        self.actions: list[QAction] = []
        self.toolbar_actions: list[QAction] = []

    # -- Processing (also under qgis_process) -----------------------------------------------

    def initProcessing(self) -> None:
        if self.provider is not None:
            return
        prepare_core()
        from .processing.provider import OverseecProvider

        self.provider = OverseecProvider()
        QgsApplication.processingRegistry().addProvider(self.provider)

    # -- GUI ---------------------------------------------------------------------------------

    def initGui(self) -> None:
        self.initProcessing()
        from .dock.panel import OverseecDock
        from .legend import RoutesKeeper
        from .maptool import PlanMapTool
        from .options import OverseecOptionsFactory

        icon = QIcon(str(icon_path()))
        window = self.iface.mainWindow()
        self.routes_keeper = RoutesKeeper(QgsProject.instance())  # routes above costmaps, also reopened
        self.dock = OverseecDock(self.iface, parent=window)
        self.dock.setObjectName("OverseecDock")
        self.dock.hide()
        self.iface.addDockWidget(Qt.RightDockWidgetArea, self.dock)

        self.panel_action = QAction(icon, "overseec panel", window)
        self.panel_action.setObjectName("overseecPanelAction")
        self.panel_action.setCheckable(True)
        self.panel_action.toggled.connect(self.dock.setVisible)
        self.dock.visibilityChanged.connect(self.panel_action.setChecked)

        self.map_tool = PlanMapTool(self.iface.mapCanvas(), self.iface)
        self.plan_action = QAction(
            icon,
            "Plan a path on the costmap (click start, Shift+click vias, click goal; right-click or Esc cancels)",
            window,
        )
        self.plan_action.setObjectName("overseecPlanAction")
        self.plan_action.setCheckable(True)
        self.plan_action.triggered.connect(self.activate_map_tool)
        self.map_tool.setAction(self.plan_action)
        self.dock.set_map_tool(self.map_tool, self.plan_action)

        from .fixtool import FixMaskTool

        self.fix_tool = FixMaskTool(self.iface.mapCanvas(), self.iface)
        self.fix_action = QAction(
            icon,
            "Fix a mask with SAM (select an entity's mask layer; click includes, right-click excludes, "
            "drag a box; Enter writes it)",
            window,
        )
        self.fix_action.setObjectName("overseecFixMaskAction")
        self.fix_action.setCheckable(True)
        self.fix_action.triggered.connect(self.activate_fix_tool)
        self.fix_tool.setAction(self.fix_action)

        self._init_override_tool(icon, window)

        self.env_action = QAction("Check the Python environment", window)
        self.env_action.setObjectName("overseecEnvAction")
        self.env_action.triggered.connect(self.dock.environment.check_environment)

        self.options_factory = OverseecOptionsFactory(on_apply=self.dock.reload_settings)
        self.options_factory.setObjectName("overseecOptionsFactory")
        self.iface.registerOptionsWidgetFactory(self.options_factory)
        self.options_action = QAction("Settings…", window)
        self.options_action.setObjectName("overseecOptionsAction")
        self.options_action.triggered.connect(self.dock.environment.show_options)

        menu_actions = (
            self.panel_action,
            self.plan_action,
            self.override_action,
            self.fix_action,
            self.env_action,
            self.options_action,
        )
        for action in menu_actions:
            self.iface.addPluginToMenu(MENU, action)
            self.actions.append(action)
        for action in (self.panel_action, self.plan_action, self.override_action, self.fix_action):
            self.iface.addToolBarIcon(action)
            self.toolbar_actions.append(action)

    def activate_map_tool(self, checked: bool = True) -> None:
        canvas = self.iface.mapCanvas()
        if checked:
            if canvas.mapTool() is not self.map_tool:
                canvas.setMapTool(self.map_tool)
        elif canvas.mapTool() is self.map_tool:
            canvas.unsetMapTool(self.map_tool)

    def _init_override_tool(self, icon: QIcon, window) -> None:
        """The override tool, its action and its preset toolbar (shown while the tool is active)."""
        from .overridetool import OverrideTool, PresetWidget

        assert self.dock is not None
        runs = self.dock.runs
        self.override_tool = OverrideTool(
            self.iface.mapCanvas(), self.iface, open_layer=lambda: runs.edit_overrides(start_editing=False)
        )
        self.override_action = QAction(
            icon,
            "Draw override polygons on the costmap (pick Lethal, Prefer or a Cost; click vertices, right-click, "
            "double-click or Enter finishes, Backspace removes a vertex, Esc cancels)",
            window,
        )
        self.override_action.setObjectName("overseecOverrideAction")
        self.override_action.setCheckable(True)
        self.override_action.triggered.connect(self.activate_override_tool)
        self.override_tool.setAction(self.override_action)
        self.preset_widget = PresetWidget()
        self.preset_widget.changed.connect(self.override_tool.set_preset)
        self.override_tool.set_preset(self.preset_widget.preset())
        toolbar = QToolBar("overseec overrides", window)
        toolbar.setObjectName("overseecOverridesToolbar")
        self.iface.addToolBar(toolbar)
        toolbar.addWidget(self.preset_widget)
        toolbar.hide()
        self.override_tool.activated.connect(toolbar.show)
        self.override_tool.deactivated.connect(toolbar.hide)
        self.override_toolbar = toolbar
        # the dock's Draw overrides opens the layer (its own slot runs first), then draws on it here
        runs.overrides_button.clicked.connect(self._draw_overrides)

    def activate_override_tool(self, checked: bool = True) -> None:
        """The override tool on the current costmap's ``overrides.gpkg`` (opened or created, in
        edit mode, through the dock's Draw overrides), or the dock's message saying why not.

        The tool goes on at once; a layer still to be opened is opened on the next turn of the
        event loop, so neither step holds the GUI for long."""
        canvas = self.iface.mapCanvas()
        tool = self.override_tool
        assert tool is not None
        if not checked:
            if canvas.mapTool() is tool:
                canvas.unsetMapTool(tool)
            return
        canvas.setMapTool(tool)
        if tool.layer is None or QgsProject.instance().mapLayer(tool.layer.id()) is None:
            QTimer.singleShot(0, self._open_override_layer)

    def _draw_overrides(self, _checked: bool = False) -> None:
        """After the dock's Draw overrides opened the layer: the override tool on it (nothing
        when it could not be opened: the dock said why)."""
        layer = self.map_tool.overrides_layer if self.map_tool is not None else None
        if layer is None or self.override_tool is None:
            return
        self.override_tool.set_layer(layer)
        if not self.override_action.isChecked():
            self.override_action.trigger()

    def _open_override_layer(self) -> None:
        """Give the active override tool its layer, or turn it off when there is none (no
        costmap yet: the dock said so)."""
        tool = self.override_tool
        if tool is None or self.iface.mapCanvas().mapTool() is not tool:
            return  # switched off (or to another tool) meanwhile
        layer = tool.target_layer(start_editing=False)
        if layer is None:
            self.iface.mapCanvas().unsetMapTool(tool)
            self.override_action.setChecked(False)
        elif not layer.isEditable():
            QTimer.singleShot(0, tool.start_editing)

    def _unload_override_tool(self) -> None:
        """Take the override tool off the canvas and remove its preset toolbar."""
        if self.override_tool is not None and self.iface is not None:
            if self.iface.mapCanvas().mapTool() is self.override_tool:
                self.iface.mapCanvas().unsetMapTool(self.override_tool)
            self.override_tool.clear()
            self.override_tool.deleteLater()
            self.override_tool = None
        if self.override_toolbar is not None:
            window = self.iface.mainWindow()
            if isinstance(window, QMainWindow):
                window.removeToolBar(self.override_toolbar)
            self.override_toolbar.deleteLater()
            self.override_toolbar = None
            self.preset_widget = None

    def activate_fix_tool(self, checked: bool = True) -> None:
        """The fix-mask tool on the active layer's entity (an overseec mask layer), or a message
        saying to select one.

        SAM's weights are checked when the tool is chosen, not at the first click: when the
        environment check's report already says they are missing it refuses at once; else the
        tool arms while a background check runs, and a failed check disarms it with the options
        page's remedy. A passed check is remembered for the session's worker and SAM setting."""
        from qgis.core import Qgis

        from .fixtool import target_from_layer

        canvas = self.iface.mapCanvas()
        if not checked:
            if canvas.mapTool() is self.fix_tool:
                canvas.unsetMapTool(self.fix_tool)
            return
        assert self.fix_tool is not None
        try:
            self.fix_tool.set_target(target_from_layer(self.iface.activeLayer()))
        except LookupError as exc:
            self.iface.messageBar().pushMessage("overseec", str(exc), Qgis.Warning, 6)
            self.fix_action.setChecked(False)
            return
        key, known = self._sam_known()
        if known:
            self._refuse_fix_tool(known)
            return
        canvas.setMapTool(self.fix_tool)
        if key is not None and key not in self._sam_ok:
            self._check_sam(key)

    def _sam_known(self) -> tuple[tuple[str, str] | None, str]:
        """(worker, SAM setting) of this session, and the reason SAM cannot run when that is
        already known ("" when it is not)."""
        from . import envcheck, jobs

        if self.dock is None:
            return None, ""
        settings = self.dock.settings.save()
        worker = jobs.find_worker_for(settings)
        if worker is None:
            return None, envcheck.fix_tool_problem(None)
        same_sam = settings.params.refiner == "sam"  # the options' SAM model is the chosen refiner's
        key = (str(worker), settings.params.sam_model if same_sam else "")
        report = self.dock.environment.report
        sam = report.weights.get("sam") if report is not None and report.worker == key[0] and same_sam else None
        if sam is not None and not sam.get("ok"):
            return key, envcheck.fix_tool_missing_sam(str(sam.get("name")))
        return key, ""

    def _check_sam(self, key: tuple[str, str]) -> None:
        """Check SAM's weights in a background task; a problem disarms the fix-mask tool."""
        from qgis.core import QgsApplication

        from . import envcheck
        from .task import PipelineTask

        def check(worker: str, sam_model: str, progress=None) -> str:
            return envcheck.fix_tool_problem(worker, sam_model)

        task = PipelineTask("overseec: SAM check", check, *key)

        def done(problem: str) -> None:
            self._sam_task = None
            if not problem:
                self._sam_ok.add(key)
            elif self.fix_tool is not None and self.iface.mapCanvas().mapTool() is self.fix_tool:
                self._refuse_fix_tool(problem)

        task.succeeded.connect(done)
        task.failed.connect(lambda message, _details: setattr(self, "_sam_task", None))
        self._sam_task = task
        QgsApplication.taskManager().addTask(task)

    def _refuse_fix_tool(self, problem: str) -> None:
        """Disarm the fix-mask tool with one warning and a button to the options page."""
        from qgis.core import Qgis
        from qgis.PyQt.QtWidgets import QPushButton

        canvas = self.iface.mapCanvas()
        if canvas.mapTool() is self.fix_tool:
            canvas.unsetMapTool(self.fix_tool)
        self.fix_action.setChecked(False)
        bar = self.iface.messageBar()
        item = bar.createMessage("overseec", problem)
        button = QPushButton("Options…", item)
        button.setObjectName("overseecFixToolOptions")
        button.clicked.connect(lambda _checked=False: self.dock.environment.show_options() if self.dock else None)
        item.layout().addWidget(button)
        bar.pushWidget(item, Qgis.Warning, 0)

    def _unload_fix_tool(self) -> None:
        """Take the fix-mask tool off the canvas and stop the session's SAM worker."""
        if self.fix_tool is not None and self.iface is not None:
            if self.iface.mapCanvas().mapTool() is self.fix_tool:
                self.iface.mapCanvas().unsetMapTool(self.fix_tool)
            self.fix_tool.clear()
            self.fix_tool.deleteLater()
            self.fix_tool = None
        close_shared_sam_client()

    def unload(self) -> None:
        if self.routes_keeper is not None:
            self.routes_keeper.close()
            self.routes_keeper = None
        if self.dock is not None:
            self.dock.shutdown()
        self._unload_fix_tool()
        self._unload_override_tool()
        if self.map_tool is not None and self.iface is not None:
            canvas = self.iface.mapCanvas()
            if canvas.mapTool() is self.map_tool:
                canvas.unsetMapTool(self.map_tool)
            self.map_tool.clear()
            self.map_tool.deleteLater()
            self.map_tool = None
        close_shared_client()  # the session's planner worker
        for action in self.toolbar_actions:
            self.iface.removeToolBarIcon(action)
        for action in self.actions:
            self.iface.removePluginMenu(MENU, action)
            action.deleteLater()
        self.actions.clear()
        self.toolbar_actions.clear()
        if self.options_factory is not None:
            self.iface.unregisterOptionsWidgetFactory(self.options_factory)
            self.options_factory = None
        if self.dock is not None:
            self.iface.removeDockWidget(self.dock)
            self.dock.deleteLater()
            self.dock = None
        if self.provider is not None:
            QgsApplication.processingRegistry().removeProvider(self.provider)
            self.provider = None
