"""What every overseec algorithm shares: names and groups, help, inputs as files, the worker.

Every algorithm that does the work of an ``overseec`` command runs that command through the
worker (:mod:`overseec_qgis.worker`: ``overseec --json-progress <command> ... --json`` of the
project's environment, argv lists, no shell). The QGIS process then needs no compiled planner
kernel, no torch and no plotting stack; progress comes from the CLI's JSON-lines events and
Cancel terminates the process, which discards partial outputs; the CLI's one-line error becomes
the ``QgsProcessingException``; and a result is the same bytes the CLI writes.
"""

from __future__ import annotations

import configparser
from collections.abc import Mapping, Sequence
from functools import lru_cache
from pathlib import Path
from typing import Any

from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsProcessingAlgorithm,
    QgsProcessingException,
    QgsProcessingParameterDefinition,
    QgsProcessingUtils,
)
from qgis.PyQt.QtGui import QIcon

from .. import jobs
from ..layers import icon_path, resources_dir
from ..settings import PluginSettings
from ..worker import WorkerEvent, cli_argv, event_reporter, run_worker

#: Toolbox groups under the provider (overseec > Pipeline > Plan path).
GROUPS = {"pipeline": "Pipeline", "evaluate": "Evaluate", "export": "Export"}
#: README section the help buttons open (each algorithm has its own anchor there).
README_SECTION = "processing-and-qgis_process"


@lru_cache(maxsize=1)
def repository_url() -> str:
    """The plugin's ``repository`` (else ``homepage``) from metadata.txt."""
    parser = configparser.ConfigParser(interpolation=None)
    parser.read(resources_dir().parent / "metadata.txt", encoding="utf-8")
    general = parser["general"] if parser.has_section("general") else {}
    return (general.get("repository") or general.get("homepage") or "").rstrip("/")


def help_url(alg_id: str) -> str:
    """The README's entry for ``overseec:<alg_id>``."""
    base = repository_url()
    return f"{base}/blob/main/README.md#processing-{alg_id}" if base else ""


class OverseecAlgorithm(QgsProcessingAlgorithm):
    """Names, groups, help and the error contract shared by every overseec algorithm."""

    ID = ""
    DISPLAY = ""
    GROUP = "pipeline"
    #: What the algorithm does and which inputs it needs (paragraphs; per-parameter help follows).
    HELP = ""

    def name(self) -> str:
        return self.ID

    def displayName(self) -> str:  # noqa: N802
        return self.DISPLAY

    def group(self) -> str:
        return GROUPS[self.GROUP]

    def groupId(self) -> str:  # noqa: N802
        return self.GROUP

    def helpUrl(self) -> str:  # noqa: N802
        return help_url(self.ID)

    def shortHelpString(self) -> str:  # noqa: N802
        """The description, then one line per parameter with help (advanced ones marked)."""
        lines = [self.HELP.strip()]
        for p in self.parameterDefinitions():
            if p.help():
                advanced = " (advanced)" if p.flags() & QgsProcessingParameterDefinition.FlagAdvanced else ""
                lines.append(f"{p.description()}{advanced}: {p.help()}")
        return "\n".join(lines)

    def icon(self) -> QIcon:
        return QIcon(str(icon_path()))

    def createInstance(self):  # noqa: N802
        return type(self)()

    # -- parameters ------------------------------------------------------------------------

    def param(self, definition: QgsProcessingParameterDefinition, help: str = "", advanced: bool = False) -> None:  # noqa: A002
        """Add a parameter with its help text; ``advanced`` puts it under Advanced Parameters."""
        if help:
            definition.setHelp(help)
        if advanced:
            definition.setFlags(definition.flags() | QgsProcessingParameterDefinition.FlagAdvanced)
        self.addParameter(definition)

    # -- inputs as files -------------------------------------------------------------------

    def raster_file(self, parameters, name: str, context, required: bool = True) -> str | None:
        """The GeoTIFF (or other GDAL file) behind a raster parameter."""
        if not required and parameters.get(name) in (None, ""):
            return None
        layer = self.parameterAsRasterLayer(parameters, name, context)
        if layer is None:
            if required:
                raise QgsProcessingException(f"{name}: choose a raster layer or file")
            return None
        path = jobs.layer_file(layer)
        if not path:
            raise QgsProcessingException(f"{name}: {layer.source()} is not a raster file; save it as a GeoTIFF first")
        return path

    def vector_file(self, parameters, name: str, context, feedback) -> str | None:
        """A vector parameter as a file the CLI reads (memory layers exported to GeoJSON)."""
        if parameters.get(name) in (None, ""):
            return None
        path = self.parameterAsCompatibleSourceLayerPath(
            parameters, name, context, ["geojson", "gpkg", "shp", "json"], "geojson", feedback
        )
        return path.split("|")[0] or None

    def optional_str(self, parameters, name: str, context) -> str | None:
        value = self.parameterAsString(parameters, name, context).strip()
        return value or None

    def optional_file(self, parameters, name: str, context) -> Path | None:
        value = self.parameterAsFile(parameters, name, context).strip()
        return Path(value) if value else None

    def polygon_files(self, parameters, name: str, context, feedback) -> tuple[Path, ...]:
        """The files behind a multiple-layer parameter, in layer order: a layer's own file when it
        is a plain OGR file layer, else (memory, unsaved edits, a filter) a temporary GeoPackage
        written in the layer's CRS (the CLI reprojects)."""
        from qgis.core import QgsVectorFileWriter

        files = []
        for i, layer in enumerate(self.parameterAsLayerList(parameters, name, context) or []):
            source = layer.source().split("|")[0]
            if (
                layer.providerType() == "ogr"
                and not layer.subsetString()
                and not layer.isModified()
                and Path(source).is_file()
            ):
                files.append(Path(source))
                continue
            out = Path(QgsProcessingUtils.generateTempFilename(f"overrides_{i}.gpkg"))
            options = QgsVectorFileWriter.SaveVectorOptions()
            options.driverName = "GPKG"
            error, message, *_ = QgsVectorFileWriter.writeAsVectorFormatV3(
                layer, str(out), context.transformContext(), options
            )
            if error != QgsVectorFileWriter.NoError:
                raise QgsProcessingException(f"{name}: cannot save layer {layer.name()} ({message})")
            feedback.pushInfo(f"{layer.name()}: saved to {out} for overseec")
            files.append(out)
        return tuple(files)

    def point_in(self, parameters, name: str, context, crs: QgsCoordinateReferenceSystem) -> tuple[float, float]:
        """A point parameter in ``crs`` (Processing reprojects from the point's own CRS)."""
        p = self.parameterAsPoint(parameters, name, context, crs)
        return (p.x(), p.y())

    def via_points(
        self, parameters, name: str, context, crs: QgsCoordinateReferenceSystem
    ) -> list[tuple[float, float]]:
        """The points of a point layer parameter, in feature order, in ``crs``."""
        source = self.parameterAsSource(parameters, name, context)
        if source is None:
            return []
        ct = QgsCoordinateTransform(source.sourceCrs(), crs, context.transformContext())
        points = []
        for f in source.getFeatures():
            if f.hasGeometry():
                p = ct.transform(f.geometry().asPoint())
                points.append((p.x(), p.y()))
        return points

    # -- the worker ------------------------------------------------------------------------

    def find_worker(self) -> Path:
        settings = PluginSettings.load()
        worker = jobs.find_worker_for(settings)
        if worker is None:
            report = jobs.check_worker_env(None)
            raise QgsProcessingException(report.problems[0] + ". To fix: " + "; ".join(report.advice))
        return worker

    def cli(
        self,
        command: str,
        args: Sequence[str],
        feedback,
        weights: Mapping[str, float] | None = None,
        env: Mapping[str, str] | None = None,
    ) -> dict[str, Any]:
        """Run ``overseec --json-progress <command> <args>`` and return its ``--json`` document
        (pass ``--json`` in ``args`` where the command takes it)."""
        return self.run_argv(cli_argv(self.find_worker(), command, args), env or jobs.worker_env(), weights, feedback)

    def run_argv(
        self, argv: list[str], env: Mapping[str, str], weights: Mapping[str, float] | None, feedback
    ) -> dict[str, Any]:
        """Run a worker argv: progress and messages to ``feedback``, Cancel terminates it, a
        failure becomes the CLI's one-line message; returns the ``--json`` document or {}."""
        report = event_reporter(weights, feedback.setProgress, feedback.setProgressText, feedback.pushInfo)
        printed: list[str] = []

        def on_event(event: WorkerEvent) -> None:
            if event.kind == "text":
                printed.append(event.text)  # the --json document, line by line
            else:
                report(event)

        feedback.pushCommandInfo(" ".join(argv))
        try:
            res = run_worker(argv, on_event=on_event, is_cancelled=feedback.isCanceled, env=env)
        except OSError as exc:
            raise QgsProcessingException(
                f"cannot start the overseec worker {argv[0]} ({exc.strerror or exc})"
            ) from None
        if res.cancelled:
            raise QgsProcessingException("cancelled; partial outputs were discarded")
        if not res.ok:
            detail = [ln for ln in res.stderr.strip().splitlines() if ln.strip()]
            if len(detail) > 1:
                feedback.pushDebugInfo("\n".join(detail))
            raise QgsProcessingException(res.summary())
        feedback.setProgress(100.0)
        return jobs.result_document(printed)


def parse_aliases(text: str) -> tuple[tuple[str, str], ...]:
    """'lake=water, woods=tree' -> (('lake', 'water'), ('woods', 'tree')); a mistake is one
    line naming ALIASES (checked here, before a worker starts)."""
    from overseec_core.interpret.matching import parse_aliases as parse

    try:
        return parse(text)
    except ValueError as exc:
        raise QgsProcessingException(f"ALIASES: {exc}") from None


def alias_args(aliases: Sequence[tuple[str, str]]) -> list[str]:
    return [f"--alias={entity}={layer}" for entity, layer in aliases]


def point_args(flag: str, point: tuple[float, float]) -> list[str]:
    return [flag, repr(float(point[0])), repr(float(point[1]))]


def route_args(points: Sequence[tuple[float, float]]) -> list[str]:
    """--start, --via ..., --goal for start, vias..., goal."""
    flags = ["--start"] + ["--via"] * (len(points) - 2) + ["--goal"]
    return [a for flag, p in zip(flags, points) for a in point_args(flag, p)]
