"""The scenes, rays and timing the Python benchmarks share (bench/python_vs_*.py,
bench/nearest_vs_open3d.py): the renderer's random:N recipe drawn with numpy, rays with origins
uniform in its 100-unit box and directions uniform on the unit sphere, and a best-of timer."""

import time

import numpy as np


def random_scene(n, seed):
    """n spheres: centres uniform in [-50, 50]^3, radii uniform in [0.5, 1.5) x 50 / cbrt(n)."""
    rng = np.random.default_rng(seed)
    scale = 50.0 / np.cbrt(n)
    centers = rng.uniform(-50, 50, size=(n, 3)).astype(np.float32)
    radii = (rng.uniform(0.5, 1.5, size=n) * scale).astype(np.float32)
    return centers, radii


def random_rays(m, seed):
    """m rays: origins uniform in the scene's box, unit directions uniform on the sphere."""
    rng = np.random.default_rng(seed)
    origins = rng.uniform(-50, 50, size=(m, 3)).astype(np.float32)
    d = rng.normal(size=(m, 3))
    directions = (d / np.linalg.norm(d, axis=1)[:, None]).astype(np.float32)
    return origins, directions


def best_of(repeats, fn):
    """(the shortest time of repeats calls of fn, the last call's result)."""
    best, result = np.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - start)
    return best, result
