"""The overseec dock panel (:mod:`.panel`) over its sections: imagery, mission, parameters, runs
and environment, one module each, sharing the settings, the current run and the job slot
(:mod:`.common`).

Widgets are built in code (no .ui file) so each section's layout is reviewable in one place. The
dock holds no pipeline logic: every stage (the image reading check, interpret, segment, build
costmap) runs the ``overseec`` CLI of the overseec environment as a worker process, built by
:mod:`overseec_qgis.jobs` and read back from its ``--json`` document, so QGIS's own Python needs
neither rasterio nor the planner kernel (Windows and macOS QGIS have neither). Results become
layers through :mod:`overseec_qgis.layers`.

The current run directory is kept between stages, so re-prompting (Interpret, edit, Build
costmap) re-uses the masks already segmented for that image: seconds, not minutes.

Runs persist: run folders go under the runs folder of Settings › Options › overseec, by default
``overseec-runs`` beside the saved project (an unsaved project asks once per session); every
layer the dock adds points at a file of its run folder, and the project remembers the current
run folder (``overseec/run_dir``), so a reopened project shows the same masks, costmaps and paths
and the dock carries on with that run.

Machine-wide settings (environment, models, device, runs folder, LLM) are on the options page
(``options.py``); the dock's Environment box checks the environment, offers "Set up environment"
(``setup_env.py``) and keeps one message-bar warning that goes away once the check passes.
"""
