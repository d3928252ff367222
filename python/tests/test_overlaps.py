"""The batch overlap queries, overlaps() and overlapping_pairs(), against single overlapping()
calls and against a float64 brute-force reference with unequal radii."""

import numpy as np
import pytest

import reference as ref
import sphray

ACCELS = ["bvh", "brute"]
BAND = 1e-4  # a pair this close to touching may go either way in float


def gaps(centers, radii, balls, ball_radii):
    """|c_j - centre_i| - (r_j + radius_i), float64, (balls, spheres)."""
    c, r = ref.f64(centers), ref.f64(radii)
    p, pr = ref.f64(balls), ref.f64(ball_radii)
    return np.linalg.norm(p[:, None, :] - c[None, :, :], axis=2) - (r[None, :] + pr[:, None])


@pytest.mark.parametrize("accel", ACCELS)
def test_overlaps_equals_single_calls_and_the_reference(rng, accel):
    centers, radii = ref.random_scene(rng, 600, box=8.0, rmin=0.1, rmax=1.2)
    scene = sphray.Scene(centers, radii, accel=accel)
    # More balls than one chunk of work, so that several threads answer.
    balls = rng.uniform(-9, 9, size=(5000, 3)).astype(np.float32)
    ball_radii = rng.uniform(0, 0.8, size=5000).astype(np.float32)
    offsets, ids = scene.overlaps(balls, ball_radii)
    assert offsets.dtype == np.int64 and ids.dtype == np.uint32
    assert offsets.shape == (5001,) and offsets[0] == 0 and offsets[-1] == ids.size
    assert np.all(np.diff(offsets) >= 0)
    assert ids.size > 2000  # the balls overlap spheres: the comparison below means something
    g = gaps(centers, radii, balls, ball_radii)
    for i in range(len(balls)):
        got = ids[offsets[i]:offsets[i + 1]]
        np.testing.assert_array_equal(got, scene.overlapping(balls[i], ball_radii[i]))
        sure = np.abs(g[i]) > BAND
        np.testing.assert_array_equal(np.isin(np.flatnonzero(sure), got),
                                      g[i][sure] < 0)


def test_overlaps_takes_one_radius_any_leading_shape_and_no_balls(rng):
    centers, radii = ref.random_scene(rng, 100, box=4.0)
    scene = sphray.Scene(centers, radii)
    balls = rng.uniform(-5, 5, size=(2, 7, 3)).astype(np.float32)
    offsets, ids = scene.overlaps(balls, 0.5)
    flat = balls.reshape(-1, 3)
    for i in range(14):
        np.testing.assert_array_equal(ids[offsets[i]:offsets[i + 1]],
                                      scene.overlapping(flat[i], 0.5))
    offsets, ids = scene.overlaps(np.zeros((0, 3), np.float32), 1.0)
    assert offsets.tolist() == [0] and ids.size == 0
    # A NaN or negative radius overlaps nothing, as for overlapping().
    offsets, ids = scene.overlaps(flat[:2], np.float32([np.nan, -1]))
    assert offsets.tolist() == [0, 0, 0]


def test_overlaps_refuses_bad_shapes():
    scene = sphray.Scene(np.zeros((1, 3), np.float32), np.ones(1, np.float32))
    with pytest.raises(ValueError, match="centers"):
        scene.overlaps(np.zeros((4, 2)), 1.0)
    with pytest.raises(ValueError, match="radii"):
        scene.overlaps(np.zeros((4, 3)), np.ones(3))


@pytest.mark.parametrize("accel", ACCELS)
def test_overlapping_pairs_against_the_reference(rng, accel):
    centers, radii = ref.random_scene(rng, 3000, box=12.0, rmin=0.05, rmax=0.8)
    scene = sphray.Scene(centers, radii, accel=accel)
    pairs = scene.overlapping_pairs()
    assert pairs.dtype == np.uint32 and pairs.ndim == 2 and pairs.shape[1] == 2
    assert len(pairs) > 1000
    i, j = pairs[:, 0].astype(np.int64), pairs[:, 1].astype(np.int64)
    assert np.all(i < j)
    key = i * len(centers) + j
    assert np.all(np.diff(key) > 0)  # sorted by i then j, each pair once
    g = gaps(centers, radii, centers, radii)
    expected = np.triu(g < 0, k=1)
    sure = np.abs(g) > BAND
    got = np.zeros_like(expected)
    got[i, j] = True
    np.testing.assert_array_equal(got[sure], expected[sure])
    # The same pairs as the batch query of the scene's own spheres.
    offsets, ids = scene.overlaps(centers, radii)
    rows = np.repeat(np.arange(len(centers)), np.diff(offsets))
    keep = ids > rows
    np.testing.assert_array_equal(np.column_stack([rows[keep], ids[keep]]), pairs)


@pytest.mark.parametrize("accel", ACCELS)
def test_overlapping_pairs_leave_out_invalid_spheres(accel):
    # Sphere 0 holds the centres of all the others; only 1 and 2 are valid spheres (a radius
    # of 0 or below, or a NaN centre, makes a sphere no ray or query ever finds).
    centers = np.float32([[0, 0, 0], [0.5, 0, 0], [0.3, 0.2, 0], [0, 0, 0.5], [np.nan, 0, 0],
                          [0.1, 0.1, 0]])
    radii = np.float32([2, 0.25, 0.25, 0, 1, -1])
    pairs = sphray.Scene(centers, radii, accel=accel).overlapping_pairs()
    assert pairs.tolist() == [[0, 1], [0, 2], [1, 2]]


def test_overlaps_refuses_more_balls_than_32_bits_number():
    scene = sphray.Scene(np.zeros((1, 3), np.float32), np.ones(1, np.float32))
    # A broadcast view: 2**32 rows, no memory.
    balls = np.broadcast_to(np.zeros(3, np.float32), (2**32, 3))
    with pytest.raises(ValueError, match="2\\*\\*32 - 1"):
        scene.overlaps(balls, 0.5)
