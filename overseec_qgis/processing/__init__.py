"""Processing provider and algorithms (usable from the Toolbox, the Modeler and qgis_process)."""
