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
import json
from collections.abc import Mapping, Sequence
from functools import lru_cache
from pathlib import Path
from typing import Any, ClassVar

from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsProcessingAlgorithm,
    QgsProcessingException,
    QgsProcessingParameterDefinition,
    QgsProcessingParameterEnum,
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


def enum_parameter(name: str, description: str, options: Sequence[str], default: str) -> QgsProcessingParameterEnum:
    """An enum parameter whose default is named by its value (never by an index into a list).

    The options keep the order given: their indices are what saved models and ``qgis_process``
    calls hold, so reordering them would change what those mean."""
    return QgsProcessingParameterEnum(name, description, list(options), defaultValue=list(options).index(default))


def raster_path(name: str, layer) -> str:
    """The file behind the raster layer of parameter ``name``; an error for a non-file source (WMS ...)."""
    path = jobs.layer_file(layer)
    if not path:
        raise QgsProcessingException(f"{name}: {layer.source()} is not a raster file; save it as a GeoTIFF first")
    return path


class OverseecAlgorithm(QgsProcessingAlgorithm):
    """Names, groups, help, the CLI flags and the error contract shared by every overseec algorithm."""

    ID = ""
    DISPLAY = ""
    GROUP = "pipeline"
    #: What the algorithm does and which inputs it needs (paragraphs; per-parameter help follows).
    HELP = ""
    #: The ``overseec`` command the algorithm runs: ``"plan"``, or a sub-command such as
    #: ``"export costmap"`` (its words lead the argv).
    COMMAND: ClassVar[str] = ""
    #: Parameter -> the CLI flag its value feeds. The argv is built from it (:meth:`arg`) and
    #: ``tests/qgis/test_adapter_contract.py`` checks it against the CLI's parser: an enum's
    #: options are the flag's choices, a default is the CLI's (except :attr:`OWN_DEFAULTS`).
    #: Positional arguments (the image, the costmap) and LLM settings (the environment) feed none.
    FLAGS: ClassVar[Mapping[str, str]] = {}
    #: Boolean parameters whose switch is given when they are off (PLOTS feeds ``--no-plots``).
    INVERTED: ClassVar[frozenset[str]] = frozenset()
    #: Parameters whose default differs from the CLI's on purpose -> why.
    OWN_DEFAULTS: ClassVar[Mapping[str, str]] = {}

    #: Words the Processing toolbox's search finds the algorithm by (with "overseec"), besides
    #: its name: the task a user types, not the command's name.
    TAGS: ClassVar[tuple[str, ...]] = ()

    def name(self) -> str:
        return self.ID

    def tags(self) -> list[str]:
        return ["overseec", *self.TAGS]

    def displayName(self) -> str:
        return self.DISPLAY

    def group(self) -> str:
        return GROUPS[self.GROUP]

    def groupId(self) -> str:
        return self.GROUP

    def helpUrl(self) -> str:
        return help_url(self.ID)

    def shortHelpString(self) -> str:
        """The description, then one line per parameter with help (advanced ones marked)."""
        lines = [self.HELP.strip()]
        for p in self.parameterDefinitions():
            if p.help():
                advanced = " (advanced)" if p.flags() & QgsProcessingParameterDefinition.FlagAdvanced else ""
                lines.append(f"{p.description()}{advanced}: {p.help()}")
        return "\n".join(lines)

    def icon(self) -> QIcon:
        return QIcon(str(icon_path()))

    def createInstance(self):
        return type(self)()

    # -- parameters ------------------------------------------------------------------------

    def param(self, definition: QgsProcessingParameterDefinition, help: str = "", advanced: bool = False) -> None:
        """Add a parameter with its help text; ``advanced`` puts it under Advanced Parameters."""
        if help:
            definition.setHelp(help)
        if advanced:
            definition.setFlags(definition.flags() | QgsProcessingParameterDefinition.FlagAdvanced)
        self.addParameter(definition)

    def enum_value(self, parameters, name: str, context) -> str:
        """The option chosen for an enum parameter as its text (the value the CLI takes)."""
        options = self.parameterDefinition(name).options()
        return str(options[self.parameterAsEnum(parameters, name, context)])

    # -- the command line ------------------------------------------------------------------

    def arg(self, name: str, value: object, joined: bool = False) -> list[str]:
        """What parameter ``name`` holding ``value`` adds to the argv through its flag (:attr:`FLAGS`).

        ``[flag, value]``, or ``[flag=value]`` when ``joined`` (a value that may start with a dash,
        such as a prompt); for a switch (a bool) ``[flag]`` when on (when off for :attr:`INVERTED`);
        nothing for None or ''."""
        flag = self.FLAGS[name]
        if isinstance(value, bool):
            return [flag] if value != (name in self.INVERTED) else []
        if value is None or value == "":
            return []
        return [f"{flag}={value}"] if joined else [flag, str(value)]

    def point_arg(self, name: str, point: tuple[float, float]) -> list[str]:
        """``[flag, x, y]`` for a point parameter (``--start 1.0 2.0``)."""
        return point_args(self.FLAGS[name], point)

    # -- inputs as files -------------------------------------------------------------------

    def raster_file(self, parameters, name: str, context) -> str:
        """The GeoTIFF (or other GDAL file) behind a required raster parameter."""
        layer = self.parameterAsRasterLayer(parameters, name, context)
        if layer is None:
            raise QgsProcessingException(f"{name}: choose a raster layer or file")
        return raster_path(name, layer)

    def optional_raster_file(self, parameters, name: str, context) -> str | None:
        """The file behind an optional raster parameter, or None when it is not given."""
        if parameters.get(name) in (None, ""):
            return None
        layer = self.parameterAsRasterLayer(parameters, name, context)
        return None if layer is None else raster_path(name, layer)

    def vector_file(self, parameters, name: str, context, feedback) -> str | None:
        """A vector parameter as a file the CLI reads (memory layers exported to GeoJSON)."""
        if parameters.get(name) in (None, ""):
            return None
        path = self.parameterAsCompatibleSourceLayerPath(
            parameters, name, context, ["geojson", "gpkg", "shp", "json"], "geojson", feedback
        )
        return path.split("|")[0] or None

    def vector_file_and_layer(self, parameters, name: str, context, feedback) -> tuple[str, str | None]:
        """A feature-source parameter as (file, layer of that file or None) the CLI reads: a
        GeoPackage table keeps its name; a memory layer or a selection is exported first."""
        path, layer = self.parameterAsCompatibleSourceLayerPathAndLayerName(
            parameters, name, context, ["geojson", "gpkg", "shp", "json"], "gpkg", feedback
        )
        if not path:
            raise QgsProcessingException(f"{name}: choose a line layer or file")
        return path.split("|")[0], layer or None

    def optional_str(self, parameters, name: str, context) -> str | None:
        """A text parameter stripped, or None when empty."""
        value = self.parameterAsString(parameters, name, context).strip()
        return value or None

    def optional_file(self, parameters, name: str, context) -> Path | None:
        """A file or folder parameter as a path, or None when not given."""
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
        """The worker CLI of the configured environment; a missing one is an error saying how to set it up."""
        settings = PluginSettings.load()
        worker = jobs.find_worker_for(settings)
        if worker is None:
            report = jobs.check_worker_env(None)
            raise QgsProcessingException(report.problems[0] + ". To fix: " + "; ".join(report.advice))
        return worker

    def cli(
        self,
        args: Sequence[str],
        feedback,
        weights: Mapping[str, float] | None = None,
        env: Mapping[str, str] | None = None,
    ) -> dict[str, Any]:
        """Run ``overseec --json-progress <COMMAND> <args>`` and return its ``--json`` document
        (pass ``--json`` in ``args`` where the command takes it)."""
        command, *words = self.COMMAND.split()
        argv = cli_argv(self.find_worker(), command, [*words, *args])
        return self.run_argv(argv, env or jobs.worker_env(), weights, feedback)

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


def point_args(flag: str, point: tuple[float, float]) -> list[str]:
    """``[flag, x, y]`` with the coordinates as Python writes floats (exact round trip)."""
    return [flag, repr(float(point[0])), repr(float(point[1]))]


def temp_file(name: str) -> Path:
    """A new file name in Processing's temporary folder (its own sub-folder each call)."""
    return Path(QgsProcessingUtils.generateTempFilename(name))


def path_figures(geojson: Path) -> tuple[float, float]:
    """Cost and length (m) of the line a path GeoJSON holds (the smoothed one when smoothed)."""
    try:
        props = json.loads(geojson.read_text(encoding="utf-8"))["features"][0]["properties"]
        return float(props["total_cost"]), float(props["length_m"])
    except (OSError, ValueError, LookupError, TypeError) as exc:  # a worker that is not overseec's
        raise QgsProcessingException(f"the worker reported success but {geojson} holds no path ({exc})") from None
