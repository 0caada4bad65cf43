"""The costmap chain: Interpret (offline, when the options carry a prompt), then Synthesize -- what
``overseec costmap`` runs, and what :mod:`.pipeline` and :mod:`.pipeline_compare` build on
(``pipeline.run_costmap`` is this module's).
"""

from __future__ import annotations

from overseec_core.errors import InputError
from overseec_core.interpret import interpret
from overseec_core.interpret.stage import require_all_read
from overseec_core.progress import Progress
from overseec_core.schema import Interpretation
from overseec_core.synthesize.fit import check_program_choice
from overseec_core.synthesize.options import CostmapOptions, CostmapResult
from overseec_core.synthesize.stage import run_synthesize


def interpret_for_costmap(options: CostmapOptions) -> Interpretation | None:
    """The offline interpretation of a costmap's prompt, or None when a program is given."""
    check_program_choice(options)
    if options.prompt is None:
        return None
    if not options.prompt.strip():
        raise InputError("--prompt is empty; say what to prefer and avoid")
    interp = interpret(options.prompt, offline=True, priors=options.prior_table())
    if options.strict:
        require_all_read(interp)
    return interp


def run_costmap(
    options: CostmapOptions,
    progress: Progress | None = None,
    command_args: dict | None = None,
    *,
    prompt: str | None = None,
) -> CostmapResult:
    """`overseec costmap`: Interpret (offline, when the options carry a prompt), then Synthesize
    (:func:`overseec_core.synthesize.stage.run_synthesize`)."""
    if options.dem is not None:
        from overseec_core.io.dem import check_dem_file

        check_dem_file(options.dem)  # a photo given as the DEM fails first, not after the reading
    interpretation = interpret_for_costmap(options)
    return run_synthesize(options, progress, command_args, prompt=prompt, interpretation=interpretation)
