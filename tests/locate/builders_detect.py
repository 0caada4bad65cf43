"""Random-weight text-to-box detectors (OWLv2, Grounding DINO) built from configs and saved with
``save_pretrained``, with their processors: the checkpoints the ``boxes+sam`` tests load by path.

Nothing is downloaded. OWLv2 reuses the handwritten CLIP tokenizer of :mod:`tests.locate.builders`;
its box and objectness heads are re-initialised with PyTorch's own init (the library's gives every
patch nearly the same box, so non-maximum suppression would leave one box per tile and the tests
would not see several). Grounding DINO gets a tiny Swin backbone and a BERT word-piece tokenizer
from a handwritten vocabulary.
"""

from __future__ import annotations

import json
from pathlib import Path

import torch

from .builders import write_tokenizer

#: OWLv2's pre-processing values (OpenAI CLIP's mean and std).
CLIP_MEAN, CLIP_STD = [0.48145466, 0.4578275, 0.40821073], [0.26862954, 0.26130258, 0.27577711]


def tiny_owlv2_config(vocab_size: int, image_size: int = 64):
    """A two-layer OWLv2 with 32-wide text and vision towers, 16 px patches."""
    from transformers import Owlv2Config

    return Owlv2Config(
        text_config=dict(
            vocab_size=vocab_size,
            hidden_size=32,
            intermediate_size=48,
            num_hidden_layers=2,
            num_attention_heads=2,
            max_position_embeddings=16,
            eos_token_id=vocab_size - 1,
            bos_token_id=vocab_size - 2,
            pad_token_id=0,
        ),
        vision_config=dict(
            hidden_size=32,
            intermediate_size=48,
            num_hidden_layers=2,
            num_attention_heads=2,
            image_size=image_size,
            patch_size=16,
        ),
        projection_dim=32,  # the class head compares image embeddings with text_config.hidden_size
    )


def save_owlv2(folder: Path, image_size: int = 64, seed: int = 2) -> Path:
    """Random OWLv2 with its tokenizer (16 tokens per query, as OWLv2's) and image processor."""
    from transformers import CLIPTokenizer, Owlv2ForObjectDetection

    folder.mkdir(parents=True, exist_ok=True)
    vocab = write_tokenizer(folder)
    tok = CLIPTokenizer.from_pretrained(folder)
    tok.model_max_length = 16
    tok.save_pretrained(folder)
    torch.manual_seed(seed)
    model = Owlv2ForObjectDetection(tiny_owlv2_config(vocab, image_size)).eval()
    with torch.no_grad():
        for head in (model.box_head, model.objectness_head, model.class_head):
            for module in head.modules():
                if hasattr(module, "reset_parameters"):
                    module.reset_parameters()
    model.save_pretrained(folder)
    (folder / "preprocessor_config.json").write_text(
        json.dumps(
            {
                "image_processor_type": "Owlv2ImageProcessor",
                "do_resize": True,
                "size": {"height": image_size, "width": image_size},
                "resample": 2,
                "do_pad": True,
                "do_rescale": True,
                "rescale_factor": 1 / 255,
                "do_normalize": True,
                "image_mean": CLIP_MEAN,
                "image_std": CLIP_STD,
            }
        ),
        encoding="utf-8",
    )
    (folder / "processor_config.json").write_text(json.dumps({"processor_class": "Owlv2Processor"}), encoding="utf-8")
    return folder


#: The word pieces of the tiny Grounding DINO tokenizer (BERT's specials, ".", the test prompts).
GDINO_WORDS = ["[PAD]", "[UNK]", "[CLS]", "[SEP]", "[MASK]", ".", "road", "tree", "water", "a", "baseball", "field"]


def tiny_grounding_dino_config(vocab_size: int, image_size: int = 128):
    """Grounding DINO with a one-block-per-stage 16-wide Swin, a one-layer BERT, 32-d transformer
    layers and 20 queries (two decoder layers: the box heads are tied across layers)."""
    from transformers import GroundingDinoConfig

    return GroundingDinoConfig(
        backbone_config=dict(
            model_type="swin",
            embed_dim=16,
            depths=[1, 1, 1, 1],
            num_heads=[1, 1, 1, 1],
            window_size=4,
            image_size=image_size,
            out_features=["stage2", "stage3", "stage4"],
        ),
        text_config=dict(
            model_type="bert",
            vocab_size=vocab_size,
            hidden_size=32,
            num_hidden_layers=1,
            num_attention_heads=2,
            intermediate_size=48,
            max_position_embeddings=64,
        ),
        num_queries=20,
        encoder_layers=1,
        decoder_layers=2,
        encoder_ffn_dim=32,
        decoder_ffn_dim=32,
        encoder_attention_heads=2,
        decoder_attention_heads=2,
        d_model=32,
        num_feature_levels=4,
        encoder_n_points=2,
        decoder_n_points=2,
        max_text_len=32,
        use_timm_backbone=False,
        backbone=None,
        use_pretrained_backbone=False,
    )


def save_grounding_dino(folder: Path, image_size: int = 128, seed: int = 3) -> Path:
    """Random Grounding DINO with a word-piece tokenizer and its image processor (shortest edge
    ``image_size``: the fourth feature level needs at least 2 x 2 cells)."""
    from transformers import BertTokenizer, GroundingDinoForObjectDetection

    folder.mkdir(parents=True, exist_ok=True)
    (folder / "vocab.txt").write_text("\n".join(GDINO_WORDS) + "\n", encoding="utf-8")
    tok = BertTokenizer(str(folder / "vocab.txt"))
    tok.model_max_length = 32
    tok.save_pretrained(folder)
    torch.manual_seed(seed)
    GroundingDinoForObjectDetection(tiny_grounding_dino_config(len(GDINO_WORDS), image_size)).eval().save_pretrained(
        folder
    )
    (folder / "preprocessor_config.json").write_text(
        json.dumps(
            {
                "image_processor_type": "GroundingDinoImageProcessor",
                "do_resize": True,
                "size": {"shortest_edge": image_size, "longest_edge": image_size * 3 // 2},
                "resample": 2,
                "do_rescale": True,
                "rescale_factor": 1 / 255,
                "do_normalize": True,
                "image_mean": [0.485, 0.456, 0.406],
                "image_std": [0.229, 0.224, 0.225],
                "do_pad": True,
            }
        ),
        encoding="utf-8",
    )
    (folder / "processor_config.json").write_text(
        json.dumps({"processor_class": "GroundingDinoProcessor"}), encoding="utf-8"
    )
    return folder
