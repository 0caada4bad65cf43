"""The dock's run parameters: the segmenter (its processing resolution, boxes+sam's box settings),
tiling, thresholds, refinement (and its refiner) and the planner mode, saved as the new defaults
whenever a stage runs; the models and runs folder the options page sets are shown beside them."""

from __future__ import annotations

from typing import Any

from qgis.PyQt.QtWidgets import (
    QCheckBox,
    QComboBox,
    QDoubleSpinBox,
    QFormLayout,
    QGroupBox,
    QLabel,
    QLineEdit,
    QSpinBox,
)

from overseec_core.locate.segmenters import describe_segmenters

from .. import params
from ..params import PLAN_MODES, PLAN_STEPS, REFINERS, SEGMENTERS
from ..settings import PluginSettings


class ParametersSection(QGroupBox):
    """The "Parameters" box."""

    def __init__(self) -> None:
        super().__init__("Parameters")
        form = QFormLayout(self)
        self.segmenter_combo = QComboBox()
        self.segmenter_combo.addItems(list(SEGMENTERS))
        self.segmenter_combo.setToolTip(describe_segmenters())
        form.addRow("Segmenter", self.segmenter_combo)
        self.gsd_edit = QLineEdit()
        self.gsd_edit.setPlaceholderText("native")
        self.gsd_edit.setToolTip(
            "ground metres per pixel the segmenter works at (e.g. 0.3): tiles are resampled to it and the "
            "masks written on the image's grid; auto: the model's trained resolution where it names one; "
            "empty: the image's own"
        )
        form.addRow("Resolution (m/px)", self.gsd_edit)
        self.box_threshold_spin = QDoubleSpinBox()
        self.box_threshold_spin.setRange(0.0, 0.99)
        self.box_threshold_spin.setSingleStep(0.05)
        self.box_threshold_spin.setDecimals(2)
        self.box_threshold_spin.setSpecialValueText("default")  # 0: the detector's own
        self.box_threshold_spin.setToolTip("boxes+sam: detector score a box needs (default: OWLv2 0.1, DINO 0.3)")
        form.addRow("Box threshold", self.box_threshold_spin)
        self.max_boxes_spin = QSpinBox()
        self.max_boxes_spin.setRange(0, 256)
        self.max_boxes_spin.setSpecialValueText("default")  # 0: 16
        self.max_boxes_spin.setToolTip("boxes+sam: boxes kept per entity and tile, best first (default 16)")
        form.addRow("Boxes per tile", self.max_boxes_spin)
        self.segmenter_combo.currentTextChanged.connect(self._segmenter_changed)
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
        self.refiner_combo = QComboBox()
        self.refiner_combo.addItems(list(REFINERS))
        self.refiner_combo.setToolTip(
            "sam: Segment Anything (the paper's); sam-hq: finer boundaries; sam2: SAM 2.1, fast on CPU"
        )
        self.refine_check.toggled.connect(self.refiner_combo.setEnabled)
        form.addRow("Refiner", self.refiner_combo)
        self.mode_combo = QComboBox()
        self.mode_combo.addItems(list(PLAN_MODES))
        form.addRow("Planner", self.mode_combo)
        self.steps_combo = QComboBox()
        for n in PLAN_STEPS:
            self.steps_combo.addItem(f"{n} neighbours" + (" (knight moves)" if n == 16 else ""), n)
        self.steps_combo.setToolTip(
            "16 adds knight moves priced by the exact cell integral: routes closer to straight lines, "
            "about 1.8x the planning time (map tool, Plan pairs and Run all)"
        )
        form.addRow("Steps", self.steps_combo)
        self.models_label = QLabel("")
        self.models_label.setWordWrap(True)
        self.models_label.setToolTip("Models, device and the runs folder are set in Settings › Options › overseec")
        form.addRow(self.models_label)

    def load(self, p: params.Params) -> None:
        """Show the saved run parameters (an unknown saved segmenter shows the default)."""
        self.segmenter_combo.setCurrentText(p.segmenter if p.segmenter in SEGMENTERS else SEGMENTERS[0])
        self.gsd_edit.setText(p.gsd)
        self.box_threshold_spin.setValue(p.box_threshold)
        self.max_boxes_spin.setValue(p.max_boxes)
        self._segmenter_changed(self.segmenter_combo.currentText())
        self.tile_spin.setValue(p.tile_size)
        self.overlap_spin.setValue(p.overlap)
        self.tau_linear_spin.setValue(p.tau_linear)
        self.tau_areal_spin.setValue(p.tau_areal)
        self.refine_check.setChecked(p.refine)
        self.refiner_combo.setCurrentText(p.refiner if p.refiner in REFINERS else REFINERS[0])
        self.refiner_combo.setEnabled(p.refine)
        self.mode_combo.setCurrentText(p.plan_mode)
        self.steps_combo.setCurrentIndex(max(0, self.steps_combo.findData(p.plan_neighbours)))

    def fields(self) -> dict[str, Any]:
        """The box's fields, as ``PluginSettings.save_fields`` takes them."""
        return {
            "segmenter": self.segmenter_combo.currentText(),
            "gsd": self.gsd_edit.text().strip().replace(",", "."),
            "box_threshold": self.box_threshold_spin.value(),
            "max_boxes": self.max_boxes_spin.value(),
            "tile_size": self.tile_spin.value(),
            "overlap": self.overlap_spin.value(),
            "tau_linear": self.tau_linear_spin.value(),
            "tau_areal": self.tau_areal_spin.value(),
            "refine": self.refine_check.isChecked(),
            "refiner": self.refiner_combo.currentText(),
            "plan_mode": self.mode_combo.currentText(),
            "plan_neighbours": int(self.steps_combo.currentData()),
        }

    def _segmenter_changed(self, name: str) -> None:
        """The box settings apply to boxes+sam only."""
        for widget in (self.box_threshold_spin, self.max_boxes_spin):
            widget.setEnabled(name == "boxes+sam")

    def show_settings(self, s: PluginSettings, runs: str) -> None:
        """The models and device the options page sets, and where runs go (``runs``, as
        :meth:`~.common.CurrentRun.describe` says it)."""
        p = s.params
        self.models_label.setText(
            f"CLIPSeg: {p.clipseg_model or 'default'}; other segmenters: {p.model or 'their default'}; "
            f"refiner model: {p.sam_model or 'default'}; device: {p.device}\n"
            f"Runs: {runs}"
        )
