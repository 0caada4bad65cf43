"""Locate: text-prompted segmentation (CLIPSeg) and its SAM refinement, over tiles.

Modules, lowest first (each imports only those above it; no cycles):

* :mod:`.entities`: entity validation, thresholds, prompt texts, output tags, stage checks;
* :mod:`.prompts`: connected components, SAM point/box/mask prompts, calibration (numpy/scipy);
* :mod:`.clipseg`: the CLIPSeg bundle and its shared-encoder batch predictor;
* :mod:`.sam`: the SAM bundle (attention, layouts) and the per-tile refiner;
* :mod:`.dask`: tiles as tasks on a dask.distributed cluster (task functions and client side);
* :mod:`.segment` and :mod:`.refine`: the two stages, writing GeoTIFFs.

Importing this package imports none of them (and no torch): callers import the module they use.
"""
