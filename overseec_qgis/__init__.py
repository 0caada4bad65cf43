"""overseec's QGIS adapter: dock panel, map tool, layers and styles, Processing provider.

Only the QGIS side lives here; every computation is a call into ``overseec_core.pipeline`` (in
process for the non-ML stages) or the ``overseec`` CLI in a worker process (segmentation), so
QGIS computes nothing differently from the command line and never imports torch.
"""


def classFactory(iface):
    """QGIS entry point: build the plugin (``iface`` is None under qgis_process)."""
    from .plugin import OverseecPlugin

    return OverseecPlugin(iface)
