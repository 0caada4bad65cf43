"""The plugin's page under Settings › Options: environment, runs folder, models, device, LLM.

These are set once per machine, so they live here rather than in the dock (which keeps what
changes per mission: the prompt, the offline switch and the run parameters). The page reads
:class:`PluginSettings` when it opens and, on OK, saves only its own fields
(``PluginSettings.save_fields``), then calls ``on_apply`` so the dock picks them up.

The plugin registers :class:`OverseecOptionsFactory` with ``iface.registerOptionsWidgetFactory``
in ``initGui`` and unregisters it in ``unload``; ``iface.showOptionsDialog(parent, PAGE_NAME)``
opens the dialog on this page (the dock's "Settings…" button does).
"""

from __future__ import annotations

from collections.abc import Callable

from qgis.gui import QgsAuthConfigSelect, QgsFileWidget, QgsOptionsPageWidget, QgsOptionsWidgetFactory
from qgis.PyQt.QtGui import QIcon
from qgis.PyQt.QtWidgets import QComboBox, QFormLayout, QGroupBox, QLabel, QLineEdit, QVBoxLayout

from overseec_core import defaults

from .layers import icon_path
from .settings import PluginSettings

#: objectName of the page: what ``showOptionsDialog`` looks the page up by.
PAGE_NAME = "overseecOptions"
TITLE = "overseec"
#: The fields this page owns (the dock owns the others).
FIELDS = ("worker_path", "venv", "install_source", "runs_dir", "llm_endpoint", "llm_model", "llm_authcfg")
PARAM_FIELDS = ("device", "clipseg_model", "model", "sam_model")


class OverseecOptionsPage(QgsOptionsPageWidget):
    """The form; ``apply()`` (QGIS calls it on OK) saves it."""

    def __init__(self, parent=None, on_apply: Callable[[PluginSettings], None] | None = None) -> None:
        super().__init__(parent)
        self.setObjectName(PAGE_NAME)
        self.on_apply = on_apply
        col = QVBoxLayout(self)

        box = QGroupBox("Python environment (the worker that runs CLIPSeg and SAM)")
        form = QFormLayout(box)
        self.worker_widget = QgsFileWidget()
        self.worker_widget.setToolTip(
            "The `overseec` command: <venv>/bin/overseec, or <venv>\\Scripts\\overseec.exe on Windows "
            "(empty: found from the venv below, $OVERSEEC_VENV, or beside the plugin)"
        )
        form.addRow("overseec command", self.worker_widget)
        self.venv_widget = QgsFileWidget()
        self.venv_widget.setStorageMode(QgsFileWidget.GetDirectory)
        self.venv_widget.setToolTip(
            "The environment 'Set up environment' makes and installs into; it also lends QGIS "
            "the packages its own Python lacks (empty: the default place)"
        )
        form.addRow("Environment (venv)", self.venv_widget)
        self.source_widget = QgsFileWidget()
        self.source_widget.setFilter("Python packages (*.tar.gz *.zip *.whl);;All files (*)")
        self.source_widget.setToolTip(
            "What 'Set up environment' installs with pip: an overseec sdist, wheel or checkout "
            "(empty: the checkout the plugin runs from, else overseec[models] from the package index)"
        )
        form.addRow("Install from", self.source_widget)
        col.addWidget(box)

        box = QGroupBox("Runs")
        form = QFormLayout(box)
        self.runs_widget = QgsFileWidget()
        self.runs_widget.setStorageMode(QgsFileWidget.GetDirectory)
        self.runs_widget.lineEdit().setPlaceholderText("empty: overseec-runs beside the saved project")
        self.runs_widget.setToolTip(
            "Each run gets its own folder here; layers point at its files, so a saved project "
            "reopens with the same masks, costmaps and paths"
        )
        form.addRow("Runs folder", self.runs_widget)
        col.addWidget(box)

        box = QGroupBox("Models (never downloaded by a run)")
        form = QFormLayout(box)
        self.clipseg_edit = QLineEdit()
        self.clipseg_edit.setPlaceholderText("default: CIDAS/clipseg-rd64-refined (hub id in the cache, or a folder)")
        form.addRow("CLIPSeg model", self.clipseg_edit)
        self.segmenter_model_edit = QLineEdit()
        self.segmenter_model_edit.setPlaceholderText(
            "the boxes+sam or semantic segmenter's model; default: that segmenter's (`overseec models list`)"
        )
        form.addRow("Segmenter model", self.segmenter_model_edit)
        self.sam_edit = QLineEdit()
        self.sam_edit.setPlaceholderText("default: facebook/sam-vit-base (hub id in the cache, or a folder)")
        form.addRow("SAM model", self.sam_edit)
        hint = QLabel(
            "Offline: copy a model folder (`overseec models path NAME` prints it on a machine that has "
            "the model) and enter its path here."
        )
        hint.setWordWrap(True)
        form.addRow(hint)
        self.device_combo = QComboBox()
        self.device_combo.addItems(list(defaults.DEVICES))
        self.device_combo.setEditable(True)
        form.addRow("Device", self.device_combo)
        col.addWidget(box)

        box = QGroupBox("LLM interpreter (used when the dock's 'Offline interpreter' is off)")
        form = QFormLayout(box)
        self.endpoint_edit = QLineEdit()
        self.endpoint_edit.setPlaceholderText("OpenAI-compatible URL, e.g. http://localhost:11434/v1")
        form.addRow("Endpoint", self.endpoint_edit)
        self.model_edit = QLineEdit()
        form.addRow("Model", self.model_edit)
        self.auth_select = QgsAuthConfigSelect(self)
        self.auth_select.setToolTip("The API key, kept encrypted in QGIS's authentication database")
        form.addRow("API key", self.auth_select)
        col.addWidget(box)
        col.addStretch(1)
        self.load()

    def load(self) -> None:
        s = PluginSettings.load()
        self.worker_widget.setFilePath(s.worker_path)
        self.venv_widget.setFilePath(s.venv)
        self.source_widget.setFilePath(s.install_source)
        self.runs_widget.setFilePath(s.runs_dir)
        self.clipseg_edit.setText(s.params.clipseg_model)
        self.segmenter_model_edit.setText(s.params.model)
        self.sam_edit.setText(s.params.sam_model)
        self.device_combo.setCurrentText(s.params.device)
        self.endpoint_edit.setText(s.llm_endpoint)
        self.model_edit.setText(s.llm_model)
        self.auth_select.setConfigId(s.llm_authcfg)

    def values(self) -> dict:
        """The form as setting names and values (what ``apply`` saves)."""
        return {
            "worker_path": self.worker_widget.filePath().strip(),
            "venv": self.venv_widget.filePath().strip(),
            "install_source": self.source_widget.filePath().strip(),
            "runs_dir": self.runs_widget.filePath().strip(),
            "llm_endpoint": self.endpoint_edit.text().strip(),
            "llm_model": self.model_edit.text().strip(),
            "llm_authcfg": self.auth_select.configId(),
            "device": self.device_combo.currentText().strip() or "auto",
            "clipseg_model": self.clipseg_edit.text().strip(),
            "model": self.segmenter_model_edit.text().strip(),
            "sam_model": self.sam_edit.text().strip(),
        }

    def apply(self) -> None:
        saved = PluginSettings.save_fields(**self.values())
        if self.on_apply is not None:
            self.on_apply(saved)


class OverseecOptionsFactory(QgsOptionsWidgetFactory):
    """Makes the page each time the Options dialog opens."""

    def __init__(self, on_apply: Callable[[PluginSettings], None] | None = None) -> None:
        super().__init__(TITLE, QIcon(str(icon_path())))
        self.on_apply = on_apply

    def icon(self) -> QIcon:
        return QIcon(str(icon_path()))

    def createWidget(self, parent=None) -> OverseecOptionsPage:
        return OverseecOptionsPage(parent, self.on_apply)
