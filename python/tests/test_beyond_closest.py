"""intersect_all, intersect_nearest, count_hits, nearest, inside and overlapping
(docs/queries.md) against a float64 reference written here, brute force and BVH; and their bad
input."""

import numpy as np
import pytest

import reference as ref
import sphray

ACCELS = ["brute", "bvh"]


def crossings_ref(centers, radii, origins, directions):
    """Per ray, the sorted (t, id, exit) of every root in (0, inf), and whether float32 can be
    held to it (no grazing ray, no root near 0, no two spheres' roots within rounding)."""
    c, r, o, d = ref.f64(centers), ref.f64(radii), ref.f64(origins), ref.f64(directions)
    near, far, graze, scale = ref.roots(c, r, o, d)
    out, sure = [], []
    for m in range(len(o)):
        items = []
        ok = not np.any(graze[m] < 1e-4)
        for roots, exit_ in ((near[m], False), (far[m], True)):
            hit = np.isfinite(roots) & (roots > 0)
            ok &= not np.any(np.isfinite(roots) & (np.abs(roots) < 1e-4 * scale[m]))
            items += [(roots[i], i, exit_) for i in np.flatnonzero(hit)]
        items.sort()
        ts = np.array([x[0] for x in items])
        ids = np.array([x[1] for x in items])
        close = (np.diff(ts) < 1e-4 * (np.abs(ts[1:]) + 1)) & (ids[1:] != ids[:-1]) if len(ts) else []
        ok &= not np.any(close)
        out.append(items)
        sure.append(ok)
    return out, np.array(sure)


@pytest.mark.parametrize("accel", ACCELS)
def test_every_crossing_and_count(rng, accel):
    centers, radii = ref.random_scene(rng, 300, box=6.0, rmin=0.3, rmax=1.2)
    origins, directions = ref.random_rays(rng, 400, box=7.0)
    scene = sphray.Scene(centers, radii, accel=accel)
    t, ids, exits, counts = scene.intersect_all(origins, directions, max_hits=6)
    assert t.shape == ids.shape == exits.shape == (400, 6) and counts.shape == (400,)
    assert t.dtype == np.float32 and ids.dtype == np.uint32 and counts.dtype == np.uint64
    np.testing.assert_array_equal(scene.count_hits(origins, directions), counts)
    want, sure = crossings_ref(centers, radii, origins, directions)
    assert sure.mean() > 0.9
    for m in np.flatnonzero(sure):
        assert counts[m] == len(want[m])
        for k in range(min(6, len(want[m]))):
            wt, wid, wexit = want[m][k]
            assert ids[m, k] == wid and exits[m, k] == wexit
            assert abs(t[m, k] - wt) <= 1e-4 * (abs(wt) + 1)
        unused = np.arange(6) >= counts[m]
        assert np.all(np.isnan(t[m, unused])) and np.all(ids[m, unused] == sphray.NO_HIT)
    # The first crossing is the closest hit, bit for bit.
    t1, ids1 = scene.intersect(origins, directions)
    found = counts > 0
    np.testing.assert_array_equal(ids[found, 0], ids1[found])
    np.testing.assert_array_equal(t[found, 0], t1[found])
    # The nearest k alone: intersect_all's first k slots bit for bit, counted as written.
    assert counts.max() > 3
    for k in (1, 3, 6):
        near = scene.intersect_nearest(origins, directions, k=k)
        assert near.t.shape == (400, k) and near.counts.dtype == np.uint64
        np.testing.assert_array_equal(near.counts, np.minimum(counts, k))
        np.testing.assert_array_equal(near.t, t[:, :k])
        np.testing.assert_array_equal(near.ids, ids[:, :k])
        np.testing.assert_array_equal(near.exits, exits[:, :k])


def distances_ref(centers, radii, points):
    c, r, p = ref.f64(centers), ref.f64(radii), ref.f64(points)
    return np.linalg.norm(p[:, None, :] - c[None, :, :], axis=2) - r[None, :]


@pytest.mark.parametrize("accel", ACCELS)
def test_nearest_inside_overlapping(rng, accel):
    centers, radii = ref.random_scene(rng, 400, box=8.0, rmin=0.2, rmax=1.0)
    points = rng.uniform(-9, 9, size=(500, 3)).astype(np.float32)
    scene = sphray.Scene(centers, radii, accel=accel)
    ids, dist, surf = scene.nearest(points)
    d = distances_ref(centers, radii, points)
    order = np.sort(d, axis=1)
    sure = (order[:, 1] - order[:, 0]) > 1e-4
    np.testing.assert_array_equal(ids[sure], np.argmin(d, axis=1)[sure])
    np.testing.assert_allclose(dist, d.min(axis=1), atol=1e-4)
    on = np.linalg.norm(surf.astype(np.float64) - ref.f64(centers)[ids], axis=1)
    np.testing.assert_allclose(on, ref.f64(radii)[ids], rtol=1e-5, atol=1e-5)
    sure_in = np.all(np.abs(d) > 1e-4, axis=1)
    np.testing.assert_array_equal(scene.inside(points)[sure_in], (d < 0).any(axis=1)[sure_in])
    # Within a maximum distance: a miss keeps the point and reports the maximum.
    ids2, dist2, surf2 = scene.nearest(points, max_distance=0.1)
    far = d.min(axis=1) > 0.1 + 1e-4
    assert np.all(ids2[far] == sphray.NO_HIT) and np.all(dist2[far] == np.float32(0.1))
    np.testing.assert_array_equal(surf2[far], points[far])
    for p, row in zip(points[:50], d[:50]):
        got = scene.overlapping(p, 0.7)
        assert got.dtype == np.uint32 and np.all(np.diff(got.astype(np.int64)) > 0)
        if np.all(np.abs(row - 0.7) > 1e-4):
            np.testing.assert_array_equal(got, np.flatnonzero(row < 0.7))


def test_queries_follow_refit_and_invalid_input():
    centers = np.array([[0, 0, 5], [0, 0, 10]], dtype=np.float32)
    radii = np.array([1, 1], dtype=np.float32)
    scene = sphray.Scene(centers, radii, accel="bvh")
    o, d = np.zeros((1, 3), np.float32), np.array([[0, 0, 1]], np.float32)
    assert scene.count_hits(o, d)[0] == 4
    scene.refit(centers, np.array([1, 0], dtype=np.float32))  # the second one is now invalid
    assert scene.count_hits(o, d)[0] == 2
    nan_rays = np.full((1, 3), np.nan, np.float32)
    assert scene.count_hits(nan_rays, d)[0] == 0
    ids, dist, _ = scene.nearest(np.array([[np.nan, 0, 0]], np.float32))
    assert ids[0] == sphray.NO_HIT
    assert scene.overlapping([0, 0, 5], -1.0).size == 0
    assert not scene.inside(np.array([[np.inf, 0, 0]], np.float32))[0]


def test_bad_input_raises():
    scene = sphray.Scene(np.zeros((1, 3), np.float32), np.ones(1, np.float32))
    with pytest.raises(ValueError, match=r"\(2, 3\)"):
        scene.count_hits(np.zeros((2, 3)), np.zeros((3, 3)))
    with pytest.raises(ValueError, match="max_hits"):
        scene.intersect_all(np.zeros((1, 3)), np.ones((1, 3)), max_hits=1 << 30)
    with pytest.raises(ValueError, match=r"\(2,\)"):
        scene.overlapping([0, 0], 1.0)
    with pytest.raises(ValueError, match=r"\(4, 2\)"):
        scene.nearest(np.zeros((4, 2)))
    with pytest.raises(TypeError):
        scene.overlapping(["a", "b", "c"], 1.0)


@pytest.mark.parametrize("accel", ACCELS)
def test_masks_hide_spheres_as_if_they_were_gone(rng, accel):
    centers, radii = ref.random_scene(rng, 300, box=6.0, rmin=0.3, rmax=1.2)
    masks = rng.choice(np.array([0, 1, 2, 3, 0xFFFFFFFF], dtype=np.uint32), size=300)
    origins, directions = ref.random_rays(rng, 500, box=7.0)
    scene = sphray.Scene(centers, radii, accel=accel, masks=masks)
    ray_masks = rng.choice(np.array([0, 1, 2, 0xFFFFFFFF], dtype=np.uint32), size=500)
    t, ids = scene.intersect(origins, directions, mask=ray_masks)
    counts = scene.count_hits(origins, directions, mask=ray_masks)
    hit = scene.occluded(origins, directions, mask=ray_masks)
    # The oracle: for each ray mask, a scene of only the spheres it sees, without masks.
    for m in np.unique(ray_masks):
        seen = np.flatnonzero(masks & m)
        rows = ray_masks == m
        if seen.size == 0:
            assert np.all(ids[rows] == sphray.NO_HIT) and np.all(counts[rows] == 0)
            continue
        alone = sphray.Scene(centers[seen], radii[seen], accel=accel)
        t2, ids2 = alone.intersect(origins[rows], directions[rows])
        mapped = np.where(ids2 == sphray.NO_HIT, sphray.NO_HIT, seen[np.minimum(ids2, seen.size - 1)])
        np.testing.assert_array_equal(ids[rows], mapped)
        np.testing.assert_array_equal(t[rows], t2)
        np.testing.assert_array_equal(counts[rows], alone.count_hits(origins[rows], directions[rows]))
        np.testing.assert_array_equal(hit[rows], alone.occluded(origins[rows], directions[rows]))
    # A scalar mask is every ray's; refit replaces the masks.
    t1, _ = scene.intersect(origins, directions, mask=2)
    scene.refit(centers, radii)  # no masks: every sphere seen again
    t_all, _ = scene.intersect(origins, directions)
    t_none, ids_none = scene.intersect(origins, directions, mask=0)
    assert np.all(ids_none == sphray.NO_HIT)
    assert np.all(t_all <= t1)


def test_mask_bad_input():
    c, r = np.zeros((2, 3), np.float32), np.ones(2, np.float32)
    with pytest.raises(ValueError, match=r"\(3,\)"):
        sphray.Scene(c, r, masks=np.ones(3, np.uint32))
    with pytest.raises(TypeError, match="masks"):
        sphray.Scene(c, r, masks=np.ones(2, np.float32))
    scene = sphray.Scene(c, r)
    o, d = np.zeros((4, 3), np.float32), np.ones((4, 3), np.float32)
    with pytest.raises(ValueError, match=r"\(4,\)"):
        scene.intersect(o, d, mask=np.ones(3, np.uint32))
    with pytest.raises(ValueError, match="2\\*\\*32"):
        scene.intersect(o, d, mask=-1)
