"""An independent float64 reference for the module's queries, written from the contract in
docs/kernel.md with numpy alone (it never calls sphray).

Inputs are the float32 values the kernel sees, widened exactly to float64 (for a scene of
precision "double", the float64 values themselves, and double's limits in place of float's).
The reference also says which rays float32 (or double) cannot decide (a near tie between two spheres, a ray grazing a
silhouette, a root within rounding of tmin or tmax): tests require exact agreement on every
other ray, and that the undecidable ones are rare, so a wrong kernel cannot hide among them.
"""

import numpy as np

NO_HIT = 2**32 - 1
FLT_MIN = float(np.finfo(np.float32).tiny)
FLT_MAX = float(np.finfo(np.float32).max)
# How close two float32 answers may come before the comparison calls a ray undecidable,
# relative to the scene's scale (the kernel's bound is 16 u (r + |c - o|), u = 2**-24).
DECIDE = 1e-4
# The same for a double scene: the kernel's bound is 16 u (r + |c - o|) with u = 2**-53, and
# the reference's own float64 roots are no better, so a margin far above both.
DECIDE_DOUBLE = 1e-9
DBL_MIN = float(np.finfo(np.float64).tiny)
DBL_MAX = float(np.finfo(np.float64).max)


def f64(a):
    return np.asarray(np.asarray(a, dtype=np.float32), dtype=np.float64)


def as_kernel(a, precision="float"):
    """a as the kernel of that precision reads it, in float64."""
    return f64(a) if precision == "float" else np.asarray(a, dtype=np.float64)


def valid_rays(o, d, tmin, tmax, precision="float"):
    a = np.einsum("ij,ij->i", d, d)
    lo, hi = (FLT_MIN, FLT_MAX) if precision == "float" else (DBL_MIN, DBL_MAX)
    return (np.isfinite(o).all(axis=1) & np.isfinite(d).all(axis=1)
            & (a >= lo) & (a <= hi)
            & ~np.isnan(tmin) & ~np.isnan(tmax) & (tmin < tmax))


def valid_spheres(c, r, precision="float"):
    # r * r a normal finite number of the precision: [2**-63, 2**64) in float, [2**-511,
    # 2**512) in double.
    lo, hi = (2.0**-63, 2.0**64) if precision == "float" else (2.0**-511, 2.0**512)
    return np.isfinite(c).all(axis=1) & (r >= lo) & (r < hi)


def roots(c, r, o, d):
    """Near and far roots (M, N) of every ray against every sphere, NaN where none, and how
    far each ray's closest approach is from the surface, relative to the scale."""
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        g = c[None, :, :] - o[:, None, :]                  # (M, N, 3)
        a = np.einsum("ij,ij->i", d, d)[:, None]           # (M, 1)
        b = np.einsum("mnk,mk->mn", g, d)                  # (M, N)
        closest = g - (b / a)[:, :, None] * d[:, None, :]  # centre to the ray's nearest point
        dist2 = np.einsum("mnk,mnk->mn", closest, closest)
        disc = r[None, :] ** 2 - dist2
        h = np.sqrt(np.where(disc >= 0, disc, np.nan) / a)
        k = b / a
        scale = r[None, :] + np.sqrt(np.einsum("mnk,mnk->mn", g, g))
        graze = np.abs(np.sqrt(dist2) - r[None, :]) / scale
        return k - h, k + h, graze, scale / np.sqrt(a)


def intersect(centers, radii, origins, directions, tmin=0.0, tmax=np.inf, precision="float"):
    """(t, ids, undecidable): the closest hits by the contract, and the rays the precision
    ("float" or "double") cannot be held to; t float32 or float64 as the scene returns it."""
    c, r, o, d = (as_kernel(a, precision) for a in (centers, radii, origins, directions))
    m = len(o)
    tmin = np.broadcast_to(as_kernel(tmin, precision), (m,))
    tmax = np.broadcast_to(as_kernel(tmax, precision), (m,))
    decide = DECIDE if precision == "float" else DECIDE_DOUBLE
    out = np.float32 if precision == "float" else np.float64
    t = tmax.copy()
    ids = np.full(m, NO_HIT, dtype=np.uint32)
    undecidable = np.zeros(m, dtype=bool)
    if len(c) == 0 or m == 0:
        return t.astype(out), ids, undecidable
    near, far, graze, t_scale = roots(c, r, o, d)
    lo, hi = tmin[:, None], tmax[:, None]
    with np.errstate(invalid="ignore"):
        root = np.where((lo < near) & (near < hi), near, np.where((lo < far) & (far < hi), far, np.nan))
        pairs = (valid_rays(o, d, tmin, tmax, precision)[:, None]
                 & valid_spheres(c, r, precision)[None, :])
        ok = pairs & ~np.isnan(root)
        root = np.where(ok, root, np.inf)
        best = np.argmin(root, axis=1)       # argmin takes the lower id on equal t
        t_best = root[np.arange(m), best]
        hit = np.isfinite(t_best)
        t[hit] = t_best[hit]
        ids[hit] = best[hit]
        # Undecidable: a second sphere within DECIDE of the best t (a near tie; identical
        # spheres give identical float32 roots, so their tie goes to the lower id exactly), a
        # ray grazing some sphere, or a root near a bound.
        rows = np.arange(m)
        tol = decide * t_scale[rows, best]
        order = np.argsort(root, axis=1, kind="stable")
        runner = order[:, 1] if root.shape[1] > 1 else best
        same = (c[runner] == c[best]).all(axis=1) & (r[runner] == r[best])
        tie = hit & (root[rows, runner] - t_best <= tol) & ~same
        tols = decide * t_scale
        near_bound = ((np.abs(near - lo) <= tols) | (np.abs(far - lo) <= tols)
                      | (np.abs(near - hi) <= tols) | (np.abs(far - hi) <= tols))
        undecidable = tie | (((graze <= decide) | near_bound) & pairs).any(axis=1)
    return t.astype(out), ids, undecidable


def occluded(centers, radii, origins, directions, tmin=0.0, tmax=np.inf):
    _, ids, undecidable = intersect(centers, radii, origins, directions, tmin, tmax)
    return ids != NO_HIT, undecidable


def surface(centers, radii, origins, directions, t, ids):
    """Points on the spheres and outward unit normals, float64."""
    c, r, o, d = f64(centers), f64(radii), f64(origins), f64(directions)
    t = f64(t)
    hit = ids != NO_HIT
    p = o + t[:, None] * d
    n = np.zeros_like(p)
    front = np.zeros(len(o), dtype=bool)
    cc = c[ids[hit]]
    n[hit] = (p[hit] - cc) / np.linalg.norm(p[hit] - cc, axis=1)[:, None]
    p[hit] = cc + r[ids[hit]][:, None] * n[hit]
    front[hit] = np.einsum("ij,ij->i", d[hit], n[hit]) < 0
    return p, n, front


def pinhole_rays(eye, target, up, vfov_deg, width, height):
    """Ray Tracing in One Weekend's camera in float64: unit directions through pixel centres."""
    eye, target, up = (np.asarray(v, dtype=np.float64) for v in (eye, target, up))
    h = 2 * np.tan(np.radians(vfov_deg) / 2)
    w_ = h * width / height
    w = (eye - target) / np.linalg.norm(eye - target)
    u = np.cross(up, w)
    u /= np.linalg.norm(u)
    v = np.cross(w, u)
    px = (np.arange(width) + 0.5) / width - 0.5
    py = (np.arange(height) + 0.5) / height - 0.5
    d = (-w[None, None, :] + px[None, :, None] * w_ * u[None, None, :]
         - py[:, None, None] * h * v[None, None, :])
    d /= np.linalg.norm(d, axis=2)[:, :, None]
    return np.broadcast_to(eye, d.shape), d


def random_scene(rng, n, box=10.0, rmin=0.05, rmax=0.6):
    centers = rng.uniform(-box, box, size=(n, 3)).astype(np.float32)
    radii = rng.uniform(rmin, rmax, size=n).astype(np.float32)
    return centers, radii


def random_rays(rng, m, box=12.0):
    origins = rng.uniform(-box, box, size=(m, 3)).astype(np.float32)
    directions = rng.normal(size=(m, 3)).astype(np.float32)
    return origins, directions
