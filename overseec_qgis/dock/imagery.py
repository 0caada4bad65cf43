"""The dock's imagery: extract any raster layer QGIS draws into a run folder, and the input image
(a layer or a file, its bands) with the worker's reading check of it."""

from __future__ import annotations

from pathlib import Path

from qgis.core import QgsApplication, QgsMapLayerProxyModel, QgsProject, QgsRasterLayer
from qgis.gui import QgsFileWidget, QgsMapLayerComboBox
from qgis.PyQt.QtCore import pyqtSignal
from qgis.PyQt.QtGui import QFontDatabase
from qgis.PyQt.QtWidgets import (
    QDoubleSpinBox,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QPlainTextEdit,
    QPushButton,
    QVBoxLayout,
    QWidget,
)

from overseec_core import runfiles

from .. import jobs
from ..extent_tool import ExtentMapTool
from ..extract import ExtractTask
from ..extract_plan import plan_extraction
from ..layers import Provenance, run_group, set_provenance
from ..task import WorkerTask
from .common import CurrentRun, DockSettings, JobSlot, stamped_folder
from .mission_state import InputImage, read_input, write_input

#: The image an extraction writes into its run folder.
EXTRACTED_IMAGE = runfiles.EXTRACTED_IMAGE
#: Ground resolution the Imagery box starts with (m per pixel).
DEFAULT_GSD_M = 0.5


class ImagerySection(QWidget):
    """The "Imagery from a layer" and "Input image" boxes."""

    #: the current run folder changed here (a new image dropped the old run, or an extraction
    #: made a new one): the masks shown are stale
    run_changed = pyqtSignal()

    def __init__(self, iface, settings: DockSettings, run: CurrentRun, slot: JobSlot) -> None:
        super().__init__()
        self.iface = iface
        self.settings = settings
        self.run = run
        self.slot = slot
        #: the rectangle tool of Draw area (made on first use)
        self.extent_tool: ExtentMapTool | None = None
        #: the area to extract, in ``extract_crs`` (the canvas CRS when it was chosen)
        self.extract_extent = None
        self.extract_crs = None
        self.extract_plan = None
        #: the image reading check in flight (the latest one wins; older results are dropped)
        self.info_task: WorkerTask | None = None
        col = QVBoxLayout(self)
        col.setContentsMargins(0, 0, 0, 0)
        col.addWidget(self._build_extract_box())
        col.addWidget(self._build_input_box())
        self.slot.busy_changed.connect(lambda busy: self.extract_button.setEnabled(not busy))
        self.layer_combo.layerChanged.connect(self._input_changed)
        self.file_widget.fileChanged.connect(self._input_changed)
        self.bands_edit.editingFinished.connect(self._input_changed)
        self.source_combo.layerChanged.connect(self.update_extract_plan)
        self.gsd_spin.valueChanged.connect(self.update_extract_plan)

    def _build_extract_box(self) -> QGroupBox:
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
            f"Write {EXTRACTED_IMAGE} into a new run folder (a background task; Cancel stops it) "
            "and use it as the image"
        )
        self.extract_button.clicked.connect(lambda _checked=False: self.extract())
        form.addRow(self.extract_button)
        return box

    def _build_input_box(self) -> QGroupBox:
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
        self.info_view.setFont(QFontDatabase.systemFont(QFontDatabase.FixedFont))
        form.addRow(self.info_view)
        return box

    # -- The area to extract -----------------------------------------------------------------

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

    def drop_extent_tool(self) -> None:
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
        """The area to extract is what the map shows now (shown by the rectangle tool's band)."""
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

    # -- Extraction --------------------------------------------------------------------------

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
            self.slot.fail("extract", self.extract_label.text().lstrip("✗ ") or "choose a source layer and an area")
            return
        name = "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in layer.name())[:40] or "imagery"
        run_dir = stamped_folder(self.run.runs_folder(), name)
        task = ExtractTask(layer, plan, run_dir / EXTRACTED_IMAGE)
        self.slot.start("extract", task, lambda path: self._use_extracted(run_dir, Path(path), layer.name()))

    def _use_extracted(self, run_dir: Path, image: Path, source_name: str) -> None:
        self.run.set_run_dir(run_dir, str(image))
        group = run_group(f"overseec imagery: {run_dir.name}")
        layer = QgsRasterLayer(str(image), f"{EXTRACTED_IMAGE} ({source_name})", "gdal")
        if not layer.isValid():
            raise ValueError(f"QGIS cannot open {image}")
        set_provenance(layer, Provenance(run_dir=str(run_dir), stage="extract"), "image")
        QgsProject.instance().addMapLayer(layer, False)
        group.addLayer(layer)
        self.show_image(str(image))
        self.run_changed.emit()
        self.slot.say(f"extract: done, {image} is the input image")

    # -- The input image ---------------------------------------------------------------------

    def show_image(self, path: str) -> None:
        """Make the file ``path`` the input image (instead of a layer)."""
        self.layer_combo.setLayer(None)
        self.file_widget.setFilePath(path)

    def image_path(self) -> str:
        """The chosen image file: the file box if set, else the layer's file."""
        path = self.file_widget.filePath().strip()
        if path:
            return path
        layer = self.layer_combo.currentLayer()
        if isinstance(layer, QgsRasterLayer):
            return jobs.layer_file(layer)
        return ""

    def input_image(self) -> InputImage:
        """The input image as the project keeps it (a layer id or a file, and the bands)."""
        layer = self.layer_combo.currentLayer()
        return InputImage(
            layer.id() if layer is not None else "", self.file_widget.filePath().strip(), self.bands_edit.text().strip()
        )

    def save_to(self, project: QgsProject) -> None:
        """The project is being written: the input image goes into its entries."""
        write_input(project, self.input_image())

    def restore(self, project: QgsProject, run_image: str = "") -> None:
        """A project was opened: its input image comes back (the layer it named, else its file);
        a project from an older plugin gets the image of its run (``run_image``), as before."""
        saved = read_input(project)
        layer = project.mapLayer(saved.layer_id) if saved.layer_id else None
        self.bands_edit.setText(saved.bands)
        if isinstance(layer, QgsRasterLayer) and not saved.file:
            self.file_widget.setFilePath("")
            self.layer_combo.setLayer(layer)
        elif saved.file or run_image:
            self.show_image(saved.file or run_image)
        else:
            self.show_image("")

    def clear(self) -> None:
        """The project was closed: no input image (the reading check in flight is dropped)."""
        self.bands_edit.setText("")
        self.show_image("")

    def bands(self) -> str | None:
        """The bands the user chose (None: automatic)."""
        return self.bands_edit.text().strip() or None

    def _input_changed(self, *_args) -> None:
        """Read the chosen image's description in the worker (``overseec info --json``), in a
        background task: picking an image never blocks QGIS while the worker starts."""
        self.drop_info_task()
        path = self.image_path()
        if not path:
            self.info_view.setPlainText("")
            return
        if self.run.run_image is not None and Path(self.run.run_image).resolve() != Path(path).resolve():
            self.run.set_run_dir(None)  # masks belong to the old image
            self.run_changed.emit()
        worker = jobs.find_worker_for(self.settings.current)
        if worker is None:
            self.info_view.setPlainText(f"cannot use this image: {jobs.no_worker_message()}")
            return
        argv, env = jobs.info_command(worker, path, self.bands())
        task = WorkerTask("overseec: read image", argv, env=env, capture=True)
        task.succeeded.connect(lambda _r: self._show_info(task))
        task.failed.connect(lambda message, _details: self._show_info(task, message))
        self.info_task = task
        self.info_view.setPlainText(f"reading {Path(path).name}…")
        QgsApplication.taskManager().addTask(task)

    def drop_info_task(self) -> None:
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
