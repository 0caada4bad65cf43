"""Save planned paths: the map tool's paths layers of a project, as GeoJSON, off the GUI thread.

A reopened project has its ``paths.gpkg`` layers but a map tool that knows none of them, so the
layers are found by their role and file (:func:`paths_layers`) and their costmap from the layer
alone (:func:`paths_costmap`), never from the planner worker. The routes are copied on the GUI
thread (:func:`paths_snapshot`, a handful of features); OGR's writer and the new layer's open run
in a task (:class:`SavePathsTask`), the layer joins the routes group when it is done.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from qgis.core import QgsApplication, QgsProject, QgsRasterLayer, QgsTask, QgsVectorLayer

from overseec_core import runfiles

from .layers import (
    PATH_INTERNAL_FIELDS,
    PROP_COSTMAP,
    PROP_ROLE,
    Provenance,
    ogr_parts,
    paths_table,
    set_provenance,
    style_route,
)
from .legend import add_to_routes


def paths_layers(project: QgsProject | None = None) -> list[QgsVectorLayer]:
    """The project's map-tool paths layers (role ``path`` on a ``paths.gpkg`` table), in the
    order they are drawn (top first): what a reopened project plans and saves with."""
    project = project or QgsProject.instance()
    ordered = project.layerTreeRoot().layerOrder()
    ordered += [lyr for lyr in project.mapLayers().values() if lyr not in ordered]
    return [
        lyr
        for lyr in ordered
        if isinstance(lyr, QgsVectorLayer)
        and lyr.customProperty(PROP_ROLE, "") == "path"
        and lyr.providerType() == "ogr"
        and Path(ogr_parts(lyr)[0]).name == runfiles.PATHS_LAYER
    ]


def paths_costmap(layer: QgsVectorLayer, project: QgsProject | None = None) -> Path | None:
    """The costmap file ``layer``'s routes were planned on, from the layer alone (no planner
    worker): its recorded costmap, else the costmap whose paths table it is -- a costmap layer of
    the project, or a GeoTIFF beside ``paths.gpkg``."""
    recorded = layer.customProperty(PROP_COSTMAP, "")
    if recorded and Path(recorded).is_file():
        return Path(recorded)
    file, table = ogr_parts(layer)
    project = project or QgsProject.instance()
    candidates = [
        Path(lyr.source().split("|")[0])
        for lyr in project.mapLayers().values()
        if isinstance(lyr, QgsRasterLayer) and lyr.customProperty(PROP_ROLE, "") == "costmap"
    ]
    candidates += sorted(Path(file).parent.glob("*.tif"))
    return next((c for c in candidates if paths_table(c) == table and c.is_file()), None)


@dataclass(frozen=True)
class PathsSnapshot:
    """A paths layer's routes copied on the GUI thread (unsaved edits included), in WGS 84, with
    the core's path properties only: what a background thread writes without touching the layer."""

    fields: Any  # QgsFields
    features: tuple[Any, ...]  # QgsFeature copies
    prompt: str = ""


def paths_snapshot(layer: QgsVectorLayer) -> PathsSnapshot:
    """Copy ``layer``'s routes (the edit buffer included) for :func:`write_paths_geojson`: the
    geometries in WGS 84 (RFC 7946), every field but the map tool's own (``PATH_INTERNAL_FIELDS``)."""
    from qgis.core import QgsCoordinateReferenceSystem, QgsCoordinateTransform, QgsFeature, QgsFields

    keep = [i for i, f in enumerate(layer.fields()) if f.name() not in PATH_INTERNAL_FIELDS]
    fields = QgsFields()
    for i in keep:
        fields.append(layer.fields().at(i))
    to_wgs84 = QgsCoordinateTransform(layer.crs(), QgsCoordinateReferenceSystem("EPSG:4326"), QgsProject.instance())
    features = []
    for source in layer.getFeatures():
        feature = QgsFeature(fields)
        geometry = source.geometry()
        geometry.transform(to_wgs84)
        feature.setGeometry(geometry)
        feature.setAttributes([source.attributes()[i] for i in keep])
        features.append(feature)
    return PathsSnapshot(fields, tuple(features), str(layer.customProperty("overseec/prompt", "") or ""))


def write_paths_geojson(snapshot: PathsSnapshot, path: str | os.PathLike) -> Path:
    """Write a :class:`PathsSnapshot` as RFC 7946 GeoJSON; the file appears whole or not at all.
    Touches no layer, so it runs on a task's thread."""
    from qgis.core import QgsCoordinateReferenceSystem, QgsCoordinateTransformContext, QgsVectorFileWriter, QgsWkbTypes

    options = QgsVectorFileWriter.SaveVectorOptions()
    options.driverName = "GeoJSON"
    options.layerOptions = ["RFC7946=YES"]
    path = Path(path)
    tmp = path.with_name(f".{path.stem}.partial.geojson")
    wgs84 = QgsCoordinateReferenceSystem("EPSG:4326")
    writer = QgsVectorFileWriter.create(
        str(tmp), snapshot.fields, QgsWkbTypes.LineString, wgs84, QgsCoordinateTransformContext(), options
    )
    ok = writer.hasError() == QgsVectorFileWriter.NoError and all(writer.addFeature(f) for f in snapshot.features)
    message = writer.errorMessage()
    del writer  # closes the file
    if not ok:
        tmp.unlink(missing_ok=True)
        raise OSError(f"cannot write {path}: {message or 'the GeoJSON writer failed'}")
    os.replace(tmp, path)
    return path


def save_paths_geojson(layer: QgsVectorLayer, path: str | os.PathLike) -> Path:
    """Write ``layer``'s routes (unsaved edits included) as RFC 7946 GeoJSON in WGS 84, with the
    core's path properties (not the map tool's ``path_id``); the file appears whole or not at all."""
    return write_paths_geojson(paths_snapshot(layer), path)


class SavePathsTask(QgsTask):
    """Write a :class:`PathsSnapshot` as GeoJSON and open the file as a layer, on the task's
    thread (OGR's writer and its open take tens of milliseconds, longer on a busy machine); then
    ``done(layer, error)`` on the GUI thread: the layer (moved to the GUI thread, not yet in a
    project), or None and a one-line reason."""

    def __init__(self, snapshot: PathsSnapshot, path: str | os.PathLike, done) -> None:
        super().__init__(f"overseec: save planned paths to {Path(path).name}", QgsTask.Flags())
        self.snapshot, self.path, self.done = snapshot, Path(path), done
        self.layer: QgsVectorLayer | None = None
        self.error = ""

    def run(self) -> bool:
        """On the task's thread: write, open, hand the layer to the GUI thread."""
        try:
            write_paths_geojson(self.snapshot, self.path)
            layer = QgsVectorLayer(str(self.path), self.path.stem, "ogr")
            if not layer.isValid():
                raise OSError(f"QGIS cannot open {self.path}")
            layer.moveToThread(QgsApplication.instance().thread())
            self.layer = layer
            return True
        except Exception as exc:  # reported in the message bar by done()
            self.error = str(exc) or type(exc).__name__
            return False

    def finished(self, result: bool) -> None:
        self.done(self.layer if result else None, self.error or "the paths were not saved")


def adopt_path_layer(
    layer: QgsVectorLayer, prov: Provenance, name: str, project: QgsProject | None = None
) -> QgsVectorLayer:
    """A path layer opened elsewhere (:class:`SavePathsTask`), styled, named, with provenance,
    first in the routes group."""
    layer.setName(name)
    style_route(layer, project)
    set_provenance(layer, prov, "path")
    return add_to_routes(layer, project)
