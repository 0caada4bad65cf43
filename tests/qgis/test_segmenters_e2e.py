"""boxes+sam and semantic end to end through Processing and the dock: the real `overseec` worker
with tiny random-weight models built from configs (in a subprocess: this process stands in for
QGIS and never imports torch), masks written on the image's grid and loaded as layers.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import rasterio
from qgis.core import QgsProject, QgsRasterLayer

from overseec_qgis.processing.parameters import DEVICES, SEGMENTERS

from .conftest import REPO
from .test_dock import run_and_wait
from .test_processing import Recording, run

pytestmark = [pytest.mark.qgis, pytest.mark.models]

BUILD = r"""
import json, sys
from pathlib import Path
from tests.locate.builders import save_sam
from tests.locate.builders_detect import save_owlv2
from tests.locate.builders_semantic import save_semantic, write_sidecar
root = Path(sys.argv[1])
semantic = save_semantic(root / "tiny-segformer")
write_sidecar(semantic, gsd_m=1.0)  # trained at 1 m/px: --gsd auto works at it
print(json.dumps({"semantic": str(semantic), "owlv2": str(save_owlv2(root / "tiny-owlv2")),
                  "sam": str(save_sam(root / "tiny-sam"))}))
"""


@pytest.fixture(scope="module")
def checkout_worker(tmp_path_factory) -> Path:
    """An ``overseec`` command that runs this checkout's core (an installed worker may be another
    copy: the plugin strips PYTHONPATH from the worker's environment), with its Python beside it
    as in a venv's bin/ (the environment check runs that one)."""
    bin_dir = tmp_path_factory.mktemp("venv") / "bin"
    bin_dir.mkdir()
    (bin_dir / "python3").symlink_to(sys.executable)
    worker = bin_dir / "overseec"
    worker.write_text(
        f"#!{sys.executable}\nimport sys\nsys.path.insert(0, {str(REPO)!r})\n"
        "from overseec_core.console import main\nsys.exit(main())\n"
    )
    worker.chmod(0o755)
    return worker


def use_worker(worker: Path) -> None:
    """Point the plugin's settings at ``worker`` (Settings › Options › overseec command)."""
    from overseec_qgis.settings import PluginSettings

    PluginSettings.save_fields(worker_path=str(worker))


@pytest.fixture
def dock(plugin, tmp_path):
    """The plugin's dock with its runs folder set on the options page."""
    page = plugin.options_factory.createWidget(None)
    page.runs_widget.setFilePath(str(tmp_path / "runs"))
    page.apply()
    page.deleteLater()
    return plugin.dock


@pytest.fixture(scope="module")
def tiny_models(tmp_path_factory) -> dict[str, str]:
    """A tiny SegFormer (classes background, road, tree, grass, water; metadata: 1 m/px), OWLv2
    and SAM, saved with save_pretrained."""
    import importlib.util

    if any(importlib.util.find_spec(m) is None for m in ("torch", "transformers")):
        pytest.skip("needs torch and transformers in the worker environment")
    root = tmp_path_factory.mktemp("models")
    done = subprocess.run(
        [sys.executable, "-c", BUILD, str(root)], cwd=REPO, capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def on_image_grid(path: Path, image: Path) -> np.ndarray:
    """The raster's bands, after checking it lies on the image's grid."""
    with rasterio.open(path) as out, rasterio.open(image) as img:
        assert (out.crs, out.transform, out.width, out.height) == (img.crs, img.transform, img.width, img.height)
        return out.read()


def backend_parameters(backend: str, models: dict[str, str]) -> dict:
    """The Processing parameters that pick ``backend`` with its tiny model (and its settings)."""
    if backend == "semantic":
        return {"SEGMENTER": SEGMENTERS.index("semantic"), "MODEL": models["semantic"], "GSD": "auto"}
    return {
        "SEGMENTER": SEGMENTERS.index("boxes+sam"),
        "MODEL": models["owlv2"],
        "SAM_MODEL": models["sam"],
        "BOX_THRESHOLD": 0.05,
        "MAX_BOXES": 3,
    }


@pytest.mark.parametrize("backend", ["semantic", "boxes+sam"])
def test_processing_segment_with_each_backend_writes_masks_on_the_image_grid(
    plugin, scene, tiny_models, checkout_worker, tmp_path, backend
) -> None:
    use_worker(checkout_worker)
    fb = Recording()
    out = tmp_path / "seg"
    res = run(
        "segment",
        {
            "INPUT": str(scene.image),
            "ENTITIES": "road:linear, grass",
            "REFINE": False,
            "TILE_SIZE": 64,
            "OVERLAP": 8,
            "DEVICE": DEVICES.index("cpu"),
            "OUTPUT_DIR": str(out),
            **backend_parameters(backend, tiny_models),
        },
        fb,
    )
    probs = on_image_grid(Path(res["PROBS"]), scene.image)
    masks = on_image_grid(Path(res["MASKS"]), scene.image)
    assert probs.shape[0] == masks.shape[0] == 2
    assert np.isfinite(probs).all() and (probs >= 0).all() and (probs <= 1).all()
    np.testing.assert_array_equal(masks[0], (probs[0] >= 0.4).astype(np.uint8))
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["segmenter"] == backend and manifest["stages"]["segment"]["status"] == "ok"
    (command,) = [c for c in fb.commands if "segment" in c]
    if backend == "semantic":  # the model's metadata says 1 m/px; the scene is finer
        assert "--gsd auto" in command
        assert manifest["segment"]["gsd"]["requested"] == "auto"
        assert manifest["segment"]["gsd"]["processing_m"] == 1.0
        assert manifest["models"]["semantic"]["path"] == tiny_models["semantic"]
    else:
        assert "--box-threshold 0.05 --max-boxes 3" in command and "--sam-model" in command
        assert manifest["models"]["boxes+sam"]["path"] == tiny_models["owlv2"]


def test_processing_refuses_a_bad_gsd_before_any_worker(plugin, scene, tmp_path) -> None:
    from qgis.core import QgsProcessingException

    fb = Recording()
    with pytest.raises(QgsProcessingException, match="GSD: --gsd '0.0.1': expected metres per pixel") as err:
        run(
            "segment",
            {"INPUT": str(scene.image), "ENTITIES": "road", "GSD": "0,0,1", "OUTPUT_DIR": str(tmp_path / "o")},
            fb,
        )
    assert "\n" not in str(err.value) and not fb.commands


@pytest.mark.parametrize("backend", ["semantic", "boxes+sam"])
def test_the_docks_segment_runs_each_backend(plugin, dock, scene, tiny_models, checkout_worker, backend) -> None:
    use_worker(checkout_worker)
    image = QgsRasterLayer(str(scene.image), "small image")
    QgsProject.instance().addMapLayer(image)
    dock.imagery.layer_combo.setLayer(image)
    dock.mission.entities_table.setRowCount(0)
    for name, geometry in (("road", "linear"), ("grass", "areal")):
        dock.mission.add_entity_row(name, geometry, None, ())
    page = plugin.options_factory.createWidget(None)
    page.segmenter_model_edit.setText(tiny_models["semantic" if backend == "semantic" else "owlv2"])
    page.sam_edit.setText(tiny_models["sam"])
    page.device_combo.setCurrentText("cpu")
    page.apply()
    page.deleteLater()
    p = dock.parameters
    p.segmenter_combo.setCurrentText(backend)
    assert p.box_threshold_spin.isEnabled() is (backend == "boxes+sam")
    p.refine_check.setChecked(False)
    p.tile_spin.setValue(64)
    p.overlap_spin.setValue(8)
    p.gsd_edit.setText("0,75" if backend == "semantic" else "")  # a decimal comma is read as a point
    p.box_threshold_spin.setValue(0.05)
    p.max_boxes_spin.setValue(3)
    assert run_and_wait(dock, dock.runs.segment_button.click) == ("segment", True)
    group = QgsProject.instance().layerTreeRoot().children()[0]
    names = [n.layer().name() for n in group.findLayers()]
    assert names == ["road mask", "grass mask", "road probability", "grass probability"]
    run_dir = dock.run.run_dir
    on_image_grid(run_dir / "masks.tif", scene.image)
    manifest = json.loads((run_dir / "manifest.json").read_text())
    assert manifest["segmenter"] == backend
    if backend == "semantic":
        assert manifest["segment"]["gsd"]["processing_m"] == 0.75
        assert manifest["segment"]["tile_size"] == round(64 * 0.75 / scene.grid.pixel_size_m()[0])
    else:
        assert manifest["parameters"]["segment"]["box_threshold"] == 0.05
        assert manifest["parameters"]["segment"]["max_boxes"] == 3
