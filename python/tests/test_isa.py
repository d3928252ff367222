"""Every instruction set this machine runs, forced through SPHRAY_ISA in a fresh interpreter
(the choice is made once per process): each agrees with the reference, brute force and BVH,
and all return the same bits."""

import hashlib
import os
import subprocess
import sys
from pathlib import Path

import pytest

import sphray

HERE = Path(__file__).resolve().parent

CHECK = r"""
import hashlib, sys
import numpy as np
import reference as ref
import sphray
rng = np.random.default_rng(7)
centers, radii = ref.random_scene(rng, 700, box=8)
origins, directions = ref.random_rays(rng, 4000, box=9)
tmax = rng.uniform(2, 30, size=4000).astype(np.float32)
t_ref, ids_ref, undecidable = ref.intersect(centers, radii, origins, directions, 0.0, tmax)
assert undecidable.mean() < 0.01
digest = hashlib.sha256()
for accel in ("brute", "bvh"):
    scene = sphray.Scene(centers, radii, accel=accel)
    t, ids = scene.intersect(origins, directions, tmax=tmax)
    assert (ids[~undecidable] == ids_ref[~undecidable]).all(), accel
    hit = ~undecidable & (ids_ref != ref.NO_HIT)
    assert (abs(t[hit] - t_ref[hit]) <= 1e-5 * np.maximum(t_ref[hit], 1)).all(), accel
    occ = scene.occluded(origins, directions, tmax=tmax)
    assert (occ[~undecidable] == (ids_ref != ref.NO_HIT)[~undecidable]).all(), accel
    digest.update(t.tobytes() + ids.tobytes() + occ.tobytes())
print(sphray.active_isa(), sphray.bvh_isa(700), digest.hexdigest())
"""


def run_with_isa(isa):
    env = dict(os.environ, SPHRAY_ISA=isa,
               PYTHONPATH=os.pathsep.join([str(HERE), os.environ.get("PYTHONPATH", "")]))
    out = subprocess.run([sys.executable, "-c", CHECK], env=env, capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout.split()


def test_every_instruction_set_agrees_with_the_reference_and_with_each_other():
    isas = sphray.supported_isas()
    assert "scalar" in isas
    digests = {}
    for isa in isas:
        active, tree, digests[isa] = run_with_isa(isa)
        assert active == isa and tree == isa
    assert len(set(digests.values())) == 1, digests


def test_the_tree_isa_is_one_this_machine_runs():
    for count in (None, 0, 512, 2048, 1 << 20):
        assert sphray.bvh_isa(count) in sphray.supported_isas()
    assert sphray.bvh_isa() == sphray.bvh_isa(None)
