"""The plan server's cache of loaded costmaps drops the least recently *used* one, not the
oldest loaded nor the newest.

Driven through :func:`serve` (the JSON-lines protocol the QGIS plugin speaks); what was dropped
is read from the server's own report: ``ping`` lists the loaded costmaps (least recently used
first) and counts reads from disk (``loads``), so no timing is involved.
"""

from __future__ import annotations

import io
import json
from pathlib import Path

import pytest

from overseec_core.plan import server as srv

from .conftest import UTM_ORIGIN, smooth_costmap, write_costmap


def talk(server: srv.PlanServer, *requests: dict) -> list[dict]:
    """Answers of ``server`` to these requests, each checked to be a success."""
    text = "".join(json.dumps(r) + "\n" for r in requests)
    out = io.StringIO()
    assert srv.serve(io.StringIO(text), out, server) == 0
    answers = [json.loads(line) for line in out.getvalue().splitlines()]
    assert all(a["ok"] for a in answers), answers
    return answers


def costmaps(folder: Path, n: int) -> list[str]:
    """``n`` small distinct costmaps (no lethal pixels, so every plan finds a route)."""
    return [
        str(write_costmap(folder / f"c{i}.tif", smooth_costmap((12, 16), seed=i, lethal_fraction=0.0)))
        for i in range(n)
    ]


def load(path: str) -> dict:
    return {"op": "load", "costmap": path}


def plan(path: str) -> dict:
    """A plan request between two pixel centres of a :func:`costmaps` costmap (0.5 m pixels)."""
    x0, y0 = UTM_ORIGIN
    return {"op": "plan", "costmap": path, "points": [[x0 + 0.75, y0 - 0.75], [x0 + 7.25, y0 - 5.25]]}


def state(server: srv.PlanServer) -> tuple[list[str], int]:
    """The loaded costmaps (least recently used first) and the reads from disk, as ``ping`` says."""
    (ping,) = talk(server, {"op": "ping"})
    return ping["loaded"], ping["loads"]


@pytest.mark.parametrize("size", [srv.CACHE_SIZE, 3])
def test_a_costmap_used_again_outlives_one_loaded_after_it(tmp_path: Path, size: int) -> None:
    paths = costmaps(tmp_path, size + 1)
    first, second, newest = paths[0], paths[1], paths[size]
    server = srv.PlanServer(cache_size=size)
    talk(server, *(load(p) for p in paths[:size]))
    assert state(server) == (paths[:size], size)
    # planning on the first costmap uses it again (no read from disk): it is now the most recent
    talk(server, plan(first))
    assert state(server) == ([*paths[1:size], first], size)
    # one more costmap: the second (the least recently used) goes; the first stays loaded
    talk(server, load(newest))
    assert state(server) == ([*paths[2:size], first, newest], size + 1)
    talk(server, plan(first))
    in_use = [*paths[2:size], newest, first]
    assert state(server) == (in_use, size + 1)  # still loaded: not read again
    talk(server, load(second))
    assert state(server) == ([*in_use[1:], second], size + 2)  # it was dropped: read again
