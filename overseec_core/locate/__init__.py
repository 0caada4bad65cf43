"""Locate: text-prompted segmentation (a registry of segmenters; CLIPSeg by default) and its SAM
refinement, over tiles; masks as polygons; fixing a mask by clicking.

Modules, lowest first (each imports only those above it; no cycles):

* :mod:`.entities`: entity validation, thresholds, prompt texts, output tags, stage checks;
* :mod:`.prompts`: connected components, SAM point/box/mask prompts, calibration (numpy/scipy);
* :mod:`.clipseg`: the CLIPSeg bundle and its shared-encoder batch predictor;
* :mod:`.sam`: the SAM bundle (attention, layouts) and the per-tile refiner;
* :mod:`.dask`: tiles as tasks on a dask.distributed cluster (task functions and client side);
* :mod:`.segmenters`: the segmenter registry and protocol, one module per backend (clipseg,
  boxes_sam, semantic); :mod:`.refiners`: the refiner table (SAM, SAM-HQ, SAM 2);
* :mod:`.segment` and :mod:`.refine`: the two stages, writing GeoTIFFs; :mod:`.stage` the front door;
* :mod:`.vectors` + :mod:`.polygonize`: masks -> GeoPackage polygons; :mod:`.interactive` +
  :mod:`.maskfiles`: click to fix a mask.

Importing this package imports none of them (and no torch): callers import the module they use.
"""
