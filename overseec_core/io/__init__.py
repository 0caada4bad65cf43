"""I/O: one concept per module, the lowest layer every stage stands on.

* :mod:`.grid`: the image grid and its ground scale (CRS, transform, pixel sizes in metres);
* :mod:`.read`: windowed, georeferenced reading (:class:`~.read.RasterSource`, class tables);
* :mod:`.write`: verified GeoTIFF writing (:class:`~.write.RasterWriter`);
* :mod:`.vectors`: the one vector reader (fiona + pyproj), features on a grid's CRS;
* :mod:`.atomic`, :mod:`.transaction`: files that appear whole or not at all, and stages whose
  outputs commit together;
* :mod:`.manifest`: the run folder's provenance record;
* :mod:`.inputs`: checks on user inputs (class rasters, image data) before a stage starts.
"""
