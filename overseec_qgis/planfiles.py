"""Files the map tool writes, written off the GUI thread.

* :class:`OverridesSnapshot`: the override polygons as they are at one moment (unsaved edits
  included), copied from the layer on the GUI thread (a few features: fast) and written to a
  GeoPackage by the first request thread that needs the file (the worker applies it to its copy
  of the costmap). Writing a GeoPackage takes 10-70 ms, too long for every edit on the GUI thread.
* :func:`prepare_paths_table`: ``paths.gpkg``'s table for a costmap, created in the background
  while the costmap loads (the same file, table and fields as
  :func:`overseec_qgis.layers.open_paths_layer` makes, which then only opens it), so storing the
  first route does not create a GeoPackage on the GUI thread.

``QgsVectorFileWriter`` with no layer behind it is safe in any thread (QGIS's Processing writes
with it from tasks); one lock serialises the writers of paths tables, which share a file.
"""

from __future__ import annotations

import sqlite3
import threading
from pathlib import Path

from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransformContext,
    QgsFeature,
    QgsFields,
    QgsVectorFileWriter,
    QgsVectorLayer,
)

from overseec_core import runfiles

from .layers import create_paths_table
from .overridecheck import usable_features

_PATHS_LOCK = threading.Lock()


class OverridesSnapshot:
    """The override polygons of a layer at one moment, to be written to ``path`` once: only the
    features the core accepts (:mod:`.overridecheck`); :attr:`skipped` names the others, so one
    attribute-less polygon never stops planning."""

    def __init__(self, layer: QgsVectorLayer, path: Path, context: QgsCoordinateTransformContext) -> None:
        # a GeoPackage source's own fid column would clash with the new file's (new features in
        # the edit buffer carry temporary ids): the core reads only cost/prefer/lethal
        keep = [i for i, f in enumerate(layer.fields()) if f.name().lower() != "fid"]
        self.fields = QgsFields()
        for i in keep:
            self.fields.append(layer.fields().at(i))
        self.features = []
        usable, self.skipped = usable_features(layer)
        for feature in usable:
            copy = QgsFeature(self.fields)
            copy.setGeometry(feature.geometry())
            copy.setAttributes([feature.attributes()[i] for i in keep])
            self.features.append(copy)
        self.crs = QgsCoordinateReferenceSystem(layer.crs())
        self.wkb_type = layer.wkbType()
        self.path = path
        self._context = context
        self._lock = threading.Lock()
        self._written = False
        self._error: str | None = None

    def ensure_written(self) -> str:
        """Write the file if no thread has yet; its path. Raises OSError if it cannot be written."""
        with self._lock:
            if not self._written:
                self._error = self._write()
                self._written = True
        if self._error is not None:
            raise OSError(f"cannot write the override polygons: {self._error}")
        return str(self.path)

    def _write(self) -> str | None:
        options = QgsVectorFileWriter.SaveVectorOptions()
        options.driverName = "GPKG"
        options.layerName = "overrides"
        writer = QgsVectorFileWriter.create(
            str(self.path), self.fields, self.wkb_type, self.crs, self._context, options
        )
        if writer.hasError():
            return writer.errorMessage()
        ok = writer.addFeatures(self.features)
        error = None if ok else writer.errorMessage() or "a feature could not be written"
        del writer  # closes the file
        return error


def gpkg_tables(path: Path) -> set[str]:
    """The feature tables of a GeoPackage (empty if it is missing or not one)."""
    if not path.is_file():
        return set()
    try:
        with sqlite3.connect(f"file:{path}?mode=ro", uri=True) as db:
            return {row[0] for row in db.execute("SELECT table_name FROM gpkg_contents")}
    except sqlite3.Error:
        return set()


def prepare_paths_table(
    folder: Path, table: str, crs: QgsCoordinateReferenceSystem, context: QgsCoordinateTransformContext
) -> None:
    """Create ``folder/paths.gpkg``'s ``table`` (LineString, :data:`~overseec_qgis.layers.PATH_FIELDS`)
    if it is missing; silent on failure (storing the first route creates it then and says why)."""
    path = Path(folder) / runfiles.PATHS_LAYER
    with _PATHS_LOCK:
        if table in gpkg_tables(path) or not Path(folder).is_dir():
            return
        create_paths_table(path, table, crs, context)
