"""The map tool's override polygons: applied while planning, and watched for edits.

With an override polygon layer set (:meth:`OverridesMixin.set_overrides_layer`; fields
``cost``/``prefer``/``lethal``, as `overseec plan --override` reads them), its polygons --
including unsaved edits -- are applied to the costmap while planning: a snapshot per change
(:class:`~overseec_qgis.planfiles.OverridesSnapshot`), copied on the GUI thread and written for
the worker off it, into a temporary folder; a superseded snapshot's file is removed once no
request reads it any more. Any edit of that layer, whatever tool made it (QGIS's Add Polygon, the
attribute table, undo, commit, roll back), re-plans the current route once,
:data:`OVERRIDES_SETTLE_MS` after the last edit. A project that opens with an overrides layer
beside its costmap has it applied again (:func:`find_overrides_layer`).

A mixin of :class:`~overseec_qgis.maptool.PlanMapTool` (see :mod:`overseec_qgis.planmixin` for
why): a settled edit re-plans the tool's current route.
"""

from __future__ import annotations

import collections
import tempfile
from pathlib import Path

from qgis.core import QgsProject, QgsVectorLayer
from qgis.PyQt.QtCore import QTimer

from overseec_core import runfiles

from .overridecheck import project_overrides_layers, push_skipped
from .planfiles import OverridesSnapshot
from .planmixin import ToolMixin

#: Edits of the override layer re-plan once, this long after the last one (ms).
OVERRIDES_SETTLE_MS = 300


def find_overrides_layer(folder: Path, project: QgsProject | None = None) -> QgsVectorLayer | None:
    """The project's overrides layer: the one drawn from ``folder``'s overrides GeoPackage, else
    the project's first (overrides belong to the project, not to a run folder), else None."""
    source = str(folder / runfiles.OVERRIDES_LAYER)
    layers = project_overrides_layers(project)
    return next((lyr for lyr in layers if lyr.source().split("|")[0] == source), layers[0] if layers else None)


class OverridesMixin(ToolMixin):
    """The override layer, its edit signals (debounced) and its snapshot files."""

    def _init_overrides(self) -> None:
        self.overrides_layer: QgsVectorLayer | None = None
        self._overrides_version = 0
        self._overrides_files: tuple[OverridesSnapshot, ...] = ()
        self._overrides_dirty = False
        self._overrides_dir = tempfile.TemporaryDirectory(prefix="overseec-overrides-")
        self._file_refs: collections.Counter[Path] = collections.Counter()  # files jobs still read
        self._retired: set[Path] = set()
        self._skipped_warned: tuple = ()  # the skipped features last warned about
        self._settle = QTimer(self)
        self._settle.setSingleShot(True)
        self._settle.setInterval(OVERRIDES_SETTLE_MS)
        self._settle.timeout.connect(self._overrides_settled)

    def set_overrides_layer(self, layer: QgsVectorLayer | None) -> None:
        """Apply this polygon layer's overrides while planning; any edit to it, by any tool,
        re-plans the current route (once, :data:`OVERRIDES_SETTLE_MS` after the last edit)."""
        old = self.overrides_layer
        if old is not None:
            for signal in self._override_signals(old):
                try:
                    signal.disconnect(self._overrides_edited)
                except (TypeError, RuntimeError):  # not connected, or the layer is gone
                    pass
        self.overrides_layer = layer
        if layer is not None:
            for signal in self._override_signals(layer):
                signal.connect(self._overrides_edited)
        self._overrides_dirty = True
        self._flush_overrides()  # a plan asked for from now on applies them
        if self.complete:
            self._settle.start()

    @staticmethod
    def _override_signals(layer: QgsVectorLayer) -> tuple:
        return (
            layer.featureAdded,
            layer.featuresDeleted,
            layer.geometryChanged,
            layer.attributeValueChanged,
            layer.afterCommitChanges,
            layer.afterRollBack,
            layer.undoStack().indexChanged,  # undo and redo of any of the above
            layer.willBeDeleted,
        )

    def _overrides_edited(self, *_args) -> None:
        """The override polygons changed: re-plan once the edits settle (one re-plan for a burst)."""
        self._overrides_dirty = True
        self._settle.start()  # restarts: the re-plan follows the last edit

    def _overrides_settled(self) -> None:
        self._flush_overrides()
        if self.complete and len(self.points) > 1:
            self.replan()

    def _flush_overrides(self) -> None:
        """Write the override polygons (with unsaved edits) for the worker if they changed."""
        if not self._overrides_dirty:
            return
        self._overrides_dirty = False
        self._overrides_version += 1
        old, self._overrides_files = self._overrides_files, self._snapshot_overrides()
        self._retired.update(f.path for f in old)
        self._unlink_retired()

    def _unlink_retired(self) -> None:
        """Remove old override files no request still reads (the worker reads them per request)."""
        for f in [f for f in self._retired if not self._file_refs[f]]:
            f.unlink(missing_ok=True)
            self._retired.discard(f)

    def _snapshot_overrides(self) -> tuple[OverridesSnapshot, ...]:
        """The override polygons now (unsaved edits included); the file is written off this thread."""
        layer = self.overrides_layer
        try:
            if layer is None or QgsProject.instance().mapLayer(layer.id()) is None or layer.featureCount() == 0:
                return ()
        except RuntimeError:  # the layer was deleted
            self.overrides_layer = None
            return ()
        out = Path(self._overrides_dir.name) / f"overrides-{self._overrides_version}.gpkg"
        snapshot = OverridesSnapshot(layer, out, QgsProject.instance().transformContext())
        self._warn_skipped(snapshot.skipped)
        return (snapshot,) if snapshot.features else ()

    def _warn_skipped(self, skipped: list) -> None:
        """One warning per new set of skipped features (an edit that changes nothing about them
        says nothing again)."""
        key = tuple((s.layer_id, s.fid, s.why) for s in skipped)
        if key and key != self._skipped_warned:
            push_skipped(getattr(self, "iface", None), skipped)
        self._skipped_warned = key
