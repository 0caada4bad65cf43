"""Start/goal pairs from QGIS layers, written as the CSV `overseec plan --pairs` reads.

The dock's Plan pairs and Processing's Plan path take pairs as a layer of lines (first vertex =
start, last = goal) or as two point layers (starts and goals, paired by a shared ``id`` field
when both have one, else by feature order). Both end here: the pairs are read in the costmap's
CRS and written as ``start_x,start_y,goal_x,goal_y,id``, the CLI's CSV columns, so the worker
needs no ``--crs``.

Each geometry is transformed explicitly by a transform the caller builds with
:func:`transform_to`, and a point that cannot be transformed is an error that names it. Read them
on the GUI thread (the dock does; pairs layers are small, planning them is what takes time). On a
task thread of QGIS 3.22's pool, in a long test session, transforms were seen to pass lon/lat
through unchanged (no error), whether from the request's destination CRS or from a transform
built on the GUI thread: the planner then refused them as outside the costmap. Processing reads
its sources on the algorithm's thread, as Processing itself does.
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Sequence
from pathlib import Path

from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsCoordinateTransformContext,
    QgsCsException,
    QgsPointXY,
)

from overseec_core.errors import InputError

#: The field whose value names a pair (or a point): the CLI's optional ``id`` column.
ID_FIELD = "id"
#: The CLI's pairs CSV columns (``overseec plan --pairs``).
COLUMNS = ("start_x", "start_y", "goal_x", "goal_y", "id")

Pair = tuple[str, QgsPointXY, QgsPointXY]


def _source_crs(source) -> QgsCoordinateReferenceSystem:
    """The CRS of a layer, a layer's feature-source snapshot or a Processing source."""
    for name in ("sourceCrs", "crs"):
        if hasattr(source, name):
            return getattr(source, name)()
    return QgsCoordinateReferenceSystem()


def transform_to(
    source, crs: QgsCoordinateReferenceSystem, context: QgsCoordinateTransformContext
) -> QgsCoordinateTransform | None:
    """The transform from ``source``'s CRS to ``crs``; None where none is needed: the same
    authority id, or a source without a CRS (taken to be in ``crs``, QGIS's own rule for layers
    with an unknown CRS). Build and use it on the thread that owns the layer."""
    source_crs = _source_crs(source)
    if not source_crs.isValid() or not crs.isValid() or source_crs.authid() == crs.authid() != "":
        return None
    return QgsCoordinateTransform(source_crs, crs, context)


def _features(source, transform: QgsCoordinateTransform | None):
    """The features of ``source`` with their geometry transformed by ``transform``."""
    for n, feature in enumerate(source.getFeatures(), start=1):
        if transform is not None and feature.hasGeometry():
            geom = feature.geometry()
            try:
                geom.transform(transform)
            except QgsCsException as exc:
                raise InputError(
                    f"feature {n} cannot be transformed from {transform.sourceCrs().authid()} "
                    f"to {transform.destinationCrs().authid()}: {exc}"
                ) from None
            feature.setGeometry(geom)
        yield feature


def _ident(feature, has_id: bool, n: int) -> str:
    """The feature's ``id`` value, else its 1-based position."""
    if has_id:
        value = feature[ID_FIELD]
        if value is not None and str(value) not in ("", "NULL"):
            return str(value)
    return str(n)


def _has_id(source) -> bool:
    return source.fields().indexFromName(ID_FIELD) >= 0


def _vertices(feature) -> list[QgsPointXY]:
    geom = feature.geometry()
    if geom is None or geom.isEmpty():
        return []
    return [QgsPointXY(v.x(), v.y()) for v in geom.vertices()]


def line_pairs(source, transform: QgsCoordinateTransform | None) -> list[Pair]:
    """(id, start, goal) per line of ``source``, by ``transform`` (:func:`transform_to`) in the
    costmap's CRS: its first and last vertex; InputError for a feature without two vertices (it
    says which)."""
    has_id = _has_id(source)
    pairs: list[Pair] = []
    for n, feature in enumerate(_features(source, transform), start=1):
        vertices = _vertices(feature)
        ident = _ident(feature, has_id, n)
        if len(vertices) < 2:
            raise InputError(f"pair {ident}: a line from start to goal needs two vertices")
        pairs.append((ident, vertices[0], vertices[-1]))
    return pairs


def _points(source, transform: QgsCoordinateTransform | None, label: str) -> list[tuple[str, QgsPointXY]]:
    has_id = _has_id(source)
    points = []
    for n, feature in enumerate(_features(source, transform), start=1):
        vertices = _vertices(feature)
        ident = _ident(feature, has_id, n)
        if not vertices:
            raise InputError(f"{label} point {ident} has no geometry")
        points.append((ident, vertices[0]))
    return points


def point_pairs(
    starts,
    goals,
    start_transform: QgsCoordinateTransform | None,
    goal_transform: QgsCoordinateTransform | None,
) -> list[Pair]:
    """(id, start, goal) from two point sources, each by its transform (:func:`transform_to`) in
    the costmap's CRS: matched by ``id`` when both have the field, else by feature order;
    InputError when they do not pair up (unequal counts, an id on one side only, an id twice)."""
    a = _points(starts, start_transform, "start")
    b = _points(goals, goal_transform, "goal")
    if not a:
        raise InputError("the start layer has no points")
    if _has_id(starts) and _has_id(goals):
        by_id = dict(b)
        if len(by_id) != len(b) or len(dict(a)) != len(a):
            raise InputError("an id is used twice among the start or goal points; give each point its own id")
        missing = [i for i, _ in a if i not in by_id] + [i for i, _ in b if i not in dict(a)]
        if missing:
            raise InputError(f"start and goal points pair by id; no partner for id {', '.join(missing[:5])}")
        return [(i, p, by_id[i]) for i, p in a]
    if len(a) != len(b):
        raise InputError(f"{len(a)} start points but {len(b)} goal points: pairs need as many of each (in order)")
    return [(i, p, q) for (i, p), (_j, q) in zip(a, b)]


def pairs_csv(pairs: Sequence[Pair]) -> str:
    """The pairs as the CLI's CSV (``start_x,start_y,goal_x,goal_y,id``, full precision)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(COLUMNS)
    for ident, s, g in pairs:
        w.writerow([repr(s.x()), repr(s.y()), repr(g.x()), repr(g.y()), ident])
    return buf.getvalue()


def write_pairs(pairs: Sequence[Pair], path: str | os.PathLike) -> Path:
    """Write :func:`pairs_csv` to ``path`` atomically; InputError when there are no pairs."""
    from overseec_core.io.atomic import write_text_atomic

    if not pairs:
        raise InputError("no start/goal pairs to plan")
    return write_text_atomic(Path(path), pairs_csv(pairs))
