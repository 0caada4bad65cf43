"""Model resolution (local dir, hub cache, offline failure), devices, precision, OOM back-off."""

from __future__ import annotations

import json
import shutil
import time
from pathlib import Path

import pytest

torch = pytest.importorskip("torch")

from overseec_core.errors import ModelError  # noqa: E402
from overseec_core.locate.models import (  # noqa: E402
    BatchState,
    cached_model,
    download_model,
    resolve_device,
    resolve_model,
    resolve_precision,
    run_with_backoff,
)


def test_local_directory_resolves(tiny_clipseg: Path, tiny_sam: Path) -> None:
    ref = resolve_model(str(tiny_clipseg), "clipseg")
    assert (ref.source, ref.model_type, ref.revision) == ("local", "clipseg", None)
    assert Path(ref.path) == tiny_clipseg.resolve()
    assert resolve_model(tiny_sam, "sam").model_type == "sam"


def test_hub_id_resolves_from_the_local_cache_with_its_revision(tiny_clipseg: Path, empty_hub_cache: Path) -> None:
    commit = "0123456789abcdef0123456789abcdef01234567"
    repo = empty_hub_cache / "models--acme--tiny-clipseg"
    shutil.copytree(tiny_clipseg, repo / "snapshots" / commit)
    (repo / "refs").mkdir()
    (repo / "refs" / "main").write_text(commit)
    ref = resolve_model("acme/tiny-clipseg", "clipseg")
    assert ref.source == "hub-cache"
    assert ref.revision == commit
    assert Path(ref.path).name == commit


def test_missing_hub_model_fails_at_once_with_how_to_provide_it(empty_hub_cache: Path) -> None:
    t0 = time.monotonic()
    with pytest.raises(ModelError) as err:
        resolve_model("CIDAS/clipseg-rd64-refined", "clipseg")
    assert time.monotonic() - t0 < 5
    message = str(err.value)
    assert "\n" not in message
    assert "CIDAS/clipseg-rd64-refined" in message
    assert "overseec models download CIDAS/clipseg-rd64-refined" in message
    assert "--clipseg-model" in message


def test_model_directory_without_weights(tiny_clipseg: Path, tmp_path: Path) -> None:
    bare = tmp_path / "bare"
    bare.mkdir()
    shutil.copy(tiny_clipseg / "config.json", bare / "config.json")
    with pytest.raises(ModelError, match="has no weights"):
        resolve_model(bare, "clipseg")
    with pytest.raises(ModelError, match="no config.json"):
        resolve_model(tmp_path, "clipseg")


def test_unsupported_model_type(tmp_path: Path, tiny_sam: Path) -> None:
    from transformers import BertConfig

    bert = tmp_path / "bert"
    BertConfig(hidden_size=8, num_hidden_layers=1, num_attention_heads=1, intermediate_size=8).save_pretrained(bert)
    (bert / "model.safetensors").write_bytes(b"")
    with pytest.raises(ModelError, match="unsupported model type 'bert'"):
        resolve_model(bert, "clipseg")
    with pytest.raises(ModelError, match="unsupported model type 'sam'"):
        resolve_model(tiny_sam, "clipseg")


def test_not_a_directory_nor_a_hub_id(tmp_path: Path) -> None:
    with pytest.raises(ModelError, match="no such directory"):
        resolve_model(str(tmp_path / "nope" / "deeper"), "sam")
    file = tmp_path / "weights.bin"
    file.write_bytes(b"x")
    with pytest.raises(ModelError, match="is a file"):
        resolve_model(file, "sam")


def test_corrupt_weights_are_a_model_error(tiny_sam: Path, tmp_path: Path) -> None:
    from overseec_core.locate.sam_model import load_sam

    broken = tmp_path / "broken-sam"
    shutil.copytree(tiny_sam, broken)
    (broken / "model.safetensors").write_bytes(b"not a safetensors file")
    with pytest.raises(ModelError, match="could not be loaded"):
        load_sam(str(broken), "cpu")


def test_download_fails_fast_without_network(monkeypatch) -> None:
    from huggingface_hub import constants

    monkeypatch.setattr(constants, "ENDPOINT", "http://127.0.0.1:9")
    t0 = time.monotonic()
    with pytest.raises(ModelError, match="cannot download acme/model"):
        download_model("acme/model", "sam", timeout_s=2)
    assert time.monotonic() - t0 < 10
    with pytest.raises(ModelError, match="not a hub id"):
        download_model("./local/dir")


def test_devices() -> None:
    assert resolve_device("cpu").type == "cpu"
    assert resolve_device("auto").type in ("cpu", "cuda", "mps")
    with pytest.raises(ModelError, match="unknown device 'tpu'"):
        resolve_device("tpu")
    with pytest.raises(ModelError, match="unknown device"):
        resolve_device("cuda:x")
    if not torch.cuda.is_available():
        with pytest.raises(ModelError, match="CUDA is not available"):
            resolve_device("cuda:0")


def test_precision() -> None:
    cpu = torch.device("cpu")
    assert resolve_precision("auto", cpu) == "fp32"
    assert resolve_precision("bf16", cpu) == "bf16"
    with pytest.raises(ModelError, match="fp16 needs a GPU"):
        resolve_precision("fp16", cpu)
    with pytest.raises(ModelError, match="unknown precision"):
        resolve_precision("fp64", cpu)


def test_batch_halves_on_cuda_out_of_memory() -> None:
    calls = []

    def fn(start: int, stop: int):
        calls.append(stop - start)
        if stop - start > 2:
            raise torch.cuda.OutOfMemoryError("CUDA out of memory. Tried to allocate 2 GiB")
        return list(range(start, stop))

    halved = []
    state = BatchState(8, on_halve=halved.append)
    out = run_with_backoff(fn, 11, state)
    assert [x for chunk in out for x in chunk] == list(range(11))
    assert (state.size, state.halvings, halved) == (2, 2, [4, 2])
    assert calls[:3] == [8, 4, 2]

    def always(start: int, stop: int):
        raise torch.cuda.OutOfMemoryError("CUDA out of memory")

    with pytest.raises(ModelError, match="out of GPU memory even with batch size 1"):
        run_with_backoff(always, 3, BatchState(2))
    with pytest.raises(ValueError, match="not memory"):  # other errors are not swallowed
        run_with_backoff(lambda a, z: (_ for _ in ()).throw(ValueError("not memory")), 3, BatchState(2))


def test_models_are_loaded_once_per_process(tiny_clipseg: Path) -> None:
    from overseec_core.locate.clipseg import load_clipseg

    a = load_clipseg(str(tiny_clipseg), "cpu")
    b = load_clipseg(str(tiny_clipseg), "cpu")
    assert a is b
    built = []
    key = ("test", "x")
    assert cached_model(key, lambda: built.append(1) or "m") == "m"
    assert cached_model(key, lambda: built.append(1) or "n") == "m"
    assert built == [1]


def test_models_cli(tiny_clipseg: Path, empty_hub_cache: Path, capsys) -> None:
    from overseec_core.cli import main

    assert main(["models", "list", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert {"CIDAS/clipseg-rd64-refined", "facebook/sam-vit-base"} <= {r["name"] for r in rows}
    assert all(not r["available"] for r in rows)  # the cache is empty
    assert main(["models", "path", str(tiny_clipseg)]) == 0
    assert capsys.readouterr().out.strip() == str(tiny_clipseg.resolve())
    assert main(["models", "path", "facebook/sam-vit-base"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("overseec: error: sam model facebook/sam-vit-base is not available offline")
    assert len(err.splitlines()) == 1


# --------------------------------------------------------------------------------------------
# fast attention, layouts, compile switch
# --------------------------------------------------------------------------------------------


def test_auto_device_is_cuda_when_there_is_one_else_cpu() -> None:
    from overseec_core.locate.models import channels_last_on_gpu, describe_device

    dev = resolve_device("auto")
    if torch.cuda.is_available():
        assert dev.type == "cuda" and resolve_precision("auto", dev) in ("bf16", "fp16")
    elif not (getattr(torch.backends, "mps", None) and torch.backends.mps.is_available()):
        assert dev.type == "cpu" and describe_device(dev).startswith("cpu (")
        assert not channels_last_on_gpu(torch.nn.Conv2d(3, 4, 3), dev)  # CPU keeps its layout


def test_models_load_with_sdpa_attention_within_tolerance_of_eager(tiny_clipseg: Path, tiny_sam: Path) -> None:
    """The model classes support PyTorch's scaled-dot-product attention, it is what loading asks
    for, and it gives eager attention's outputs (fp32, to float rounding)."""
    from transformers import CLIPSegForImageSegmentation, SamModel

    from overseec_core.locate.models import attention_implementation, load_pretrained

    gen = torch.Generator().manual_seed(0)
    pixels = torch.randn(2, 3, 64, 64, generator=gen)
    ids = torch.tensor([[1, 5, 9, 2], [1, 7, 2, 0]])
    sam_pixels = torch.randn(1, 3, 128, 128, generator=gen)
    for cls, path in ((CLIPSegForImageSegmentation, tiny_clipseg), (SamModel, tiny_sam)):
        assert attention_implementation(cls) == "sdpa"
        ref = resolve_model(str(path), "clipseg" if cls is CLIPSegForImageSegmentation else "sam")
        fast = load_pretrained(cls, ref, torch.device("cpu"))
        eager = load_pretrained(cls, ref, torch.device("cpu"), attn_implementation="eager")
        assert fast.config._attn_implementation == "sdpa" and eager.config._attn_implementation == "eager"
        with torch.inference_mode():
            if cls is SamModel:
                a, b = fast.get_image_embeddings(sam_pixels), eager.get_image_embeddings(sam_pixels)
            else:
                mask = (ids > 0).long()
                a = fast(input_ids=ids, attention_mask=mask, pixel_values=pixels).logits
                b = eager(input_ids=ids, attention_mask=mask, pixel_values=pixels).logits
        torch.testing.assert_close(a, b, rtol=1e-4, atol=1e-4)
    assert attention_implementation(object) == "eager"


def test_compile_switch_is_its_own_cached_model(tiny_sam: Path) -> None:
    """--compile loads (and caches) a separate model whose encoder is compiled; the default one
    is left as it was. (Compiled speed is a benchmark matter, not tested here.)"""
    from overseec_core.locate.sam_model import load_sam

    plain = load_sam(str(tiny_sam), "cpu")
    compiled = load_sam(str(tiny_sam), "cpu", compile=True)
    assert plain is not compiled and plain is load_sam(str(tiny_sam), "cpu")
    assert getattr(compiled.model.vision_encoder, "_compiled_call_impl", None) is not None
    assert getattr(plain.model.vision_encoder, "_compiled_call_impl", None) is None
