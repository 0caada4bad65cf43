"""The override layer of a run: ``overrides.gpkg`` as an editable polygon layer with the fields
``overseec costmap|plan --override`` reads (:data:`OVERRIDE_FIELDS`), styled by kind, and a form
whose defaults and constraint make QGIS's own tools draw valid overrides
(:func:`guard_override_form`). Light to import: QGIS only, no rasterio (the override map tool reads
:data:`OVERRIDE_FIELDS` from here).
"""

from __future__ import annotations

import os
from pathlib import Path

from qgis.core import QgsLayerTreeGroup, QgsProject, QgsRasterLayer, QgsVectorLayer

from overseec_core import runfiles

from .layers import Provenance, _add, apply_style, set_provenance

#: The override layer's fields, as `overseec costmap|plan --override` reads them.
OVERRIDE_FIELDS = (("cost", "double"), ("prefer", "int"), ("lethal", "int"))


def open_overrides(
    folder: str | os.PathLike, group: QgsLayerTreeGroup | None = None, project: QgsProject | None = None
) -> QgsVectorLayer:
    """``overrides.gpkg`` in ``folder`` (created empty with the override fields when missing) as
    an editable polygon layer: the operator's corrections to the costmap, kept with the run.

    Styled by kind (the ``overrides`` QML, a rule per kind as the core classifies features), so
    every overrides layer the plugin opens -- the dock's, the override tool's -- looks the same."""
    from qgis.core import QgsField, QgsFields, QgsVectorFileWriter, QgsWkbTypes
    from qgis.PyQt.QtCore import QVariant

    path = Path(folder) / runfiles.OVERRIDES_LAYER
    if not path.exists():
        crs = _folder_crs(Path(folder))
        fields = QgsFields()
        for name, kind in OVERRIDE_FIELDS:
            fields.append(QgsField(name, QVariant.Double if kind == "double" else QVariant.Int))
        options = QgsVectorFileWriter.SaveVectorOptions()
        options.driverName = "GPKG"
        options.layerName = "overrides"
        writer = QgsVectorFileWriter.create(
            str(path), fields, QgsWkbTypes.Polygon, crs, (project or QgsProject.instance()).transformContext(), options
        )
        if writer.hasError():
            raise ValueError(f"cannot create {path}: {writer.errorMessage()}")
        del writer  # closes the file
    layer = QgsVectorLayer(f"{path}|layername=overrides", "overrides (cost 0-1 / prefer / lethal)", "ogr")
    if layer.isValid():
        # by kind, so the map says what each polygon does: lethal dark red hatched, prefer green,
        # cost in five classes of the costmap's own ramp, anything the core rejects grey
        apply_style(layer, "overrides")  # resources/styles/overrides.qml
        set_provenance(layer, Provenance(run_dir=str(folder), stage="overrides"), "overrides")
        guard_override_form(layer)
    return _add(layer, group, project)


#: The override form's rule, as the core applies it (override_rules.classify): exactly one kind.
OVERRIDE_FORM_RULE = (
    '(CASE WHEN "cost" IS NULL THEN 0 ELSE 1 END) + (CASE WHEN "lethal" = 1 THEN 1 ELSE 0 END)'
    ' + (CASE WHEN "prefer" = 1 THEN 1 ELSE 0 END) = 1 AND ("cost" IS NULL OR ("cost" >= 0 AND "cost" <= 1))'
)
OVERRIDE_FORM_HINT = "give exactly one of: lethal = 1, prefer = 1, or a cost in 0-1 (clear the others)"


def guard_override_form(layer: QgsVectorLayer) -> None:
    """Defaults and a constraint so that QGIS's own tools make valid overrides: a polygon drawn
    with Add Polygon starts as lethal (lethal = 1), and the form refuses a feature with none or
    several of cost/lethal/prefer (the core's rule), saying what to set. Stored with the layer in
    the project, so a reopened project keeps them."""
    from qgis.core import QgsDefaultValue, QgsFieldConstraints

    fields = layer.fields()
    lethal = fields.indexOf("lethal")
    if lethal < 0:
        return
    layer.setDefaultValueDefinition(lethal, QgsDefaultValue("1"))
    layer.setConstraintExpression(lethal, OVERRIDE_FORM_RULE, OVERRIDE_FORM_HINT)
    layer.setFieldConstraint(
        lethal, QgsFieldConstraints.ConstraintExpression, QgsFieldConstraints.ConstraintStrengthHard
    )


#: The costmaps of a run folder: costmap.tif, costmap-2.tif ... (see jobs.next_costmap_path).
_COSTMAPS_GLOB = f"{Path(runfiles.COSTMAP).stem}*{Path(runfiles.COSTMAP).suffix}"


def _folder_crs(folder: Path):
    """The CRS of the costmap in ``folder`` (overrides are drawn on it), else WGS 84."""
    from qgis.core import QgsCoordinateReferenceSystem

    for tif in sorted(folder.glob(_COSTMAPS_GLOB)):
        layer = QgsRasterLayer(str(tif), "probe")
        if layer.isValid():
            return layer.crs()
    return QgsCoordinateReferenceSystem("EPSG:4326")
