"""Loading and unloading the plugin the way QGIS does, and what it leaves behind."""

from __future__ import annotations

import pytest
from qgis.core import QgsApplication
from qgis.gui import QgsOptionsPageWidget, QgsOptionsWidgetFactory
from qgis.PyQt import sip
from qgis.PyQt.QtCore import QCoreApplication, QEvent
from qgis.PyQt.QtWidgets import QDockWidget

from overseec_qgis import classFactory
from overseec_qgis.options import PAGE_NAME

pytestmark = pytest.mark.qgis


class Recorder:
    """Wraps the iface calls a plugin must balance (add in initGui, remove in unload)."""

    def __init__(self, iface, monkeypatch) -> None:
        self.calls: list[tuple[str, object]] = []
        for name in (
            "addPluginToMenu",
            "removePluginMenu",
            "addToolBarIcon",
            "removeToolBarIcon",
            "addDockWidget",
            "removeDockWidget",
            "registerOptionsWidgetFactory",
            "unregisterOptionsWidgetFactory",
            "showOptionsDialog",
        ):
            monkeypatch.setattr(iface, name, self._recorder(name))

    def _recorder(self, name):
        def record(*args):
            self.calls.append((name, args[-1]))

        return record

    def objects(self, name: str) -> list:
        return [obj for n, obj in self.calls if n == name]


def _flush_deletes() -> None:
    QCoreApplication.sendPostedEvents(None, QEvent.DeferredDelete)
    QCoreApplication.processEvents()


def test_load_and_unload_leave_nothing_behind(qgis_iface, qgis_new_project, monkeypatch) -> None:
    rec = Recorder(qgis_iface, monkeypatch)
    canvas = qgis_iface.mapCanvas()
    registry = QgsApplication.processingRegistry()
    items_before = len(canvas.scene().items())

    assert registry.providerById("overseec") is None
    plugin = classFactory(qgis_iface)
    plugin.initGui()
    provider = registry.providerById("overseec")
    assert provider is not None and provider is plugin.provider
    for alg in provider.algorithms():  # found through the registry, named and documented
        assert registry.algorithmById(alg.id()) is alg and alg.provider() is provider
        assert alg.displayName() and alg.group() and len(alg.shortHelpString()) > 40
    assert len({alg.shortHelpString() for alg in provider.algorithms()}) == len(provider.algorithms())
    ids = {a.id() for a in provider.algorithms()}
    assert ids >= set(
        f"overseec:{n}"
        for n in (
            "interpret",
            "segment",
            "costmap",
            "plan",
            "run",
            "evaluate",
            "exportcostmap",
            "exportpath",
            "compare",
        )
    )
    menu_actions = rec.objects("addPluginToMenu")
    toolbar_actions = rec.objects("addToolBarIcon")
    docks = rec.objects("addDockWidget")
    assert len(menu_actions) == 6 and len(toolbar_actions) == 4 and len(docks) == 1
    dock = docks[0]
    assert isinstance(dock, QDockWidget) and dock.objectName() == "OverseecDock"
    # the settings page under Settings › Options, opened by the menu's and the dock's Settings…
    (factory,) = rec.objects("registerOptionsWidgetFactory")
    assert isinstance(factory, QgsOptionsWidgetFactory) and factory.title() == "overseec"
    page = factory.createWidget(None)
    assert isinstance(page, QgsOptionsPageWidget) and page.objectName() == PAGE_NAME
    page.deleteLater()
    plugin.options_action.trigger()
    dock.environment.options_button.click()
    assert rec.objects("showOptionsDialog") == [PAGE_NAME, PAGE_NAME]

    # the map tool is active while the plan action is on
    plugin.plan_action.trigger()
    assert canvas.mapTool() is plugin.map_tool
    tool = plugin.map_tool

    plugin.unload()
    _flush_deletes()
    assert registry.providerById("overseec") is None
    assert sorted(map(id, rec.objects("removePluginMenu"))) == sorted(map(id, menu_actions))
    assert sorted(map(id, rec.objects("removeToolBarIcon"))) == sorted(map(id, toolbar_actions))
    assert rec.objects("removeDockWidget") == [dock]
    assert rec.objects("unregisterOptionsWidgetFactory") == [factory] and plugin.options_factory is None
    assert sip.isdeleted(dock)
    assert all(sip.isdeleted(a) for a in menu_actions)
    assert sip.isdeleted(tool)
    assert canvas.mapTool() is not tool
    assert len(canvas.scene().items()) == items_before, "markers left on the canvas"
    assert plugin.dock is None and plugin.map_tool is None and plugin.provider is None


def test_reload_registers_the_provider_once(qgis_iface, qgis_new_project) -> None:
    registry = QgsApplication.processingRegistry()
    for _ in range(2):
        plugin = classFactory(qgis_iface)
        plugin.initGui()
        plugin.initProcessing()  # QGIS may call it again: no second provider
        assert [p.id() for p in registry.providers()].count("overseec") == 1
        plugin.unload()
        assert registry.providerById("overseec") is None


def test_processing_only_start_needs_no_iface() -> None:
    """qgis_process calls classFactory(None) and initProcessing() only."""
    registry = QgsApplication.processingRegistry()
    plugin = classFactory(None)
    plugin.initProcessing()
    try:
        assert registry.providerById("overseec") is not None
    finally:
        plugin.unload()
    assert registry.providerById("overseec") is None
