"""The base the map tool's mixins derive from.

:class:`~overseec_qgis.maptool.PlanMapTool` is one object (one ``QgsMapTool`` the canvas talks
to) whose code is split by concern into mixins: the requests to the planner worker
(:mod:`~overseec_qgis.planrequests`), the paths layer (:mod:`~overseec_qgis.planpaths`), the
override polygons (:mod:`~overseec_qgis.planoverrides`) and the canvas items
(:mod:`~overseec_qgis.planmarkers`). Each mixin's methods use the tool's other state (the
points, the drag, the canvas), which collaborator objects would have to be handed back and forth;
as mixins they read as the tool's own methods, unchanged.

At run time :class:`ToolMixin` is ``object``; to mypy it is ``QgsMapTool`` (untyped, so the
mixins' ``self`` may use the attributes the other mixins and the tool define).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from qgis.gui import QgsMapTool as ToolMixin
else:
    ToolMixin = object

__all__ = ["ToolMixin"]
