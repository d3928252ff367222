"""The worked example of docs/python.md runs as published (small, into a temporary folder)."""

import importlib.util
import os
from pathlib import Path

import numpy as np

EXAMPLES = Path(os.environ.get("SPHRAY_EXAMPLES",
                               Path(__file__).resolve().parents[2] / "docs" / "examples" / "python"))


def test_particle_snapshot_example(tmp_path):
    spec = importlib.util.spec_from_file_location("particles", EXAMPLES / "particles.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    out = tmp_path / "particles.png"
    image = example.main(["particles.py", str(out), "160", "20000"])
    assert out.stat().st_size > 1000
    assert image.shape == (90, 160, 3)
    lit = image.sum(axis=2) > 0.3
    assert 0.05 < lit.mean() < 0.95        # particles and background both in frame
