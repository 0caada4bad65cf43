"""Synthesize: an interpretation's preferences + entity layers -> a cost program -> a costmap.

Modules, lowest first:

* :mod:`.layers`: entity layers read a window at a time (segment masks, class rasters, vectors);
* :mod:`.overrides`: override polygons, an operator's corrections applied after the program;
* :mod:`.engine`: the block engine (program + layers -> costmap.tif and its lethal sidecar);
* :mod:`.options`: what the stage is asked for and what it answers;
* :mod:`.fit`: fitting an interpretation's program to the layers that exist;
* :mod:`.stage`: the front door, :func:`~.stage.run_synthesize`.

Synthesize receives an interpretation; it never interprets a prompt (the pipeline chains the two).
"""
