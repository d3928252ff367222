"""The C++ contract's edge cases through the module (docs/kernel.md): ties, tmin and tmax,
rays from inside a sphere, invalid rays and spheres. Expected values are worked out by hand."""

import numpy as np
import pytest

import sphray

ACCELS = ["brute", "bvh"]
INF = np.inf
NAN = np.nan


def scene_of(spheres, accel, precision=None):
    spheres = np.asarray(spheres, dtype=np.float64)
    return sphray.Scene(spheres[:, :3], spheres[:, 3], accel=accel, precision=precision)


def one(scene, origin, direction, **bounds):
    t, ids = scene.intersect(np.array([origin], np.float64), np.array([direction], np.float64), **bounds)
    return float(t[0]), int(ids[0])


@pytest.mark.parametrize("accel", ACCELS)
def test_closest_hit_and_miss(accel):
    s = scene_of([[0, 0, -3, 1], [0, 0, -10, 1]], accel)
    assert one(s, [0, 0, 0], [0, 0, -1]) == (2.0, 0)
    assert one(s, [0, 0, 0], [0, 0, -2]) == (1.0, 0)        # t in units of the direction
    assert one(s, [0, 0, 0], [0, 0, 1]) == (INF, sphray.NO_HIT)
    assert one(s, [0, 0, 0], [0, 0, 1], tmax=5.0) == (5.0, sphray.NO_HIT)


@pytest.mark.parametrize("accel", ACCELS)
def test_equal_t_goes_to_the_lower_id(accel):
    # The same sphere three times, and two spheres touching the ray at the same t.
    s = scene_of([[5, 0, 0, 1], [0, 0, -3, 1], [0, 0, -3, 1], [0, 0, -3, 1]], accel)
    assert one(s, [0, 0, 0], [0, 0, -1]) == (2.0, 1)
    s = scene_of([[1, 0, -3, 1], [-1, 0, -3, 1], [0, 0, -9, 1]], accel)
    assert one(s, [0, 0, 0], [0, 0, -1]) == (3.0, 0)        # tangent to both at the same point


@pytest.mark.parametrize("accel", ACCELS)
def test_open_interval_bounds(accel):
    s = scene_of([[0, 0, -3, 1]], accel)                     # roots 2 and 4
    assert one(s, [0, 0, 0], [0, 0, -1], tmin=2.0) == (4.0, 0)   # t > tmin strictly: far root
    assert one(s, [0, 0, 0], [0, 0, -1], tmin=3.0) == (4.0, 0)
    assert one(s, [0, 0, 0], [0, 0, -1], tmin=4.0) == (INF, sphray.NO_HIT)
    assert one(s, [0, 0, 0], [0, 0, -1], tmax=2.0) == (2.0, sphray.NO_HIT)  # t < tmax strictly
    assert one(s, [0, 0, 0], [0, 0, -1], tmin=-INF, tmax=INF) == (2.0, 0)
    assert one(s, [0, 0, -6], [0, 0, 1], tmin=-INF) == (2.0, 0)  # behind the origin too


@pytest.mark.parametrize("accel", ACCELS)
def test_from_inside_hits_the_far_side(accel):
    s = scene_of([[0, 0, 0, 2]], accel)
    assert one(s, [0, 0, 0], [1, 0, 0]) == (2.0, 0)
    assert one(s, [1, 0, 0], [-1, 0, 0]) == (3.0, 0)
    o = np.array([[0.5, 0, 0]])
    d = np.array([[1.0, 0, 0]])
    points, normals, front = s.surface(o, d, *s.intersect(o, d))
    np.testing.assert_array_equal(points, [[2, 0, 0]])
    np.testing.assert_array_equal(normals, [[1, 0, 0]])       # outward, seen from inside
    assert not front[0]


# A direction whose squared length underflows each precision's normal range (float's 2**-126,
# double's 2**-1022): invalid there. In double, float's -1e-30 is a valid ray (test_double.py).
TINY = {"float": -1e-30, "double": -1e-160}


@pytest.mark.parametrize("precision", ["float", "double"])
@pytest.mark.parametrize("accel", ACCELS)
@pytest.mark.parametrize("origin, direction, bounds", [
    ([NAN, 0, 0], [0, 0, -1], {}),
    ([0, 0, INF], [0, 0, -1], {}),
    ([0, 0, 0], [0, NAN, -1], {}),
    ([0, 0, 0], [0, 0, -INF], {}),
    ([0, 0, 0], [0, 0, 0], {}),
    ([0, 0, 0], [0, 0, "tiny"], {}),                         # |d|^2 underflows: TINY
    ([0, 0, 0], [0, 0, -1], {"tmin": 3.0, "tmax": 3.0}),
    ([0, 0, 0], [0, 0, -1], {"tmin": 5.0, "tmax": 1.0}),
    ([0, 0, 0], [0, 0, -1], {"tmin": NAN}),
])
def test_invalid_rays_miss(accel, origin, direction, bounds, precision):
    direction = [TINY[precision] if x == "tiny" else x for x in direction]
    s = scene_of([[0, 0, -3, 1]], accel, precision)
    assert s.precision == precision
    t, i = one(s, origin, direction, **bounds)
    assert i == sphray.NO_HIT
    assert t == bounds.get("tmax", INF)
    o, d = np.array([origin], float), np.array([direction], float)
    assert not s.occluded(o, d, **bounds)[0]


def test_nan_tmax_misses_with_t_nan():
    s = scene_of([[0, 0, -3, 1]], "brute")
    t, i = one(s, [0, 0, 0], [0, 0, -1], tmax=NAN)
    assert i == sphray.NO_HIT and np.isnan(t)


@pytest.mark.parametrize("accel", ACCELS)
@pytest.mark.parametrize("bad", [[0, 0, -3, 0], [0, 0, -3, -1], [NAN, 0, -3, 1], [0, 0, -3, INF],
                                 [0, INF, -3, 1], [0, 0, -3, NAN]])
def test_invalid_spheres_are_never_hit(accel, bad):
    s = scene_of([bad, [0, 0, -10, 1]], accel)
    assert one(s, [0, 0, 0], [0, 0, -1]) == (9.0, 1)


def test_surface_of_a_miss_and_of_no_sphere():
    s = scene_of([[0, 0, -3, 1]], "brute")
    o = np.zeros((2, 3))
    d = np.array([[0, 0, 1.0], [0, 0, -1]])
    points, normals, front = s.surface(o, d, np.array([2.0, 2.0]), np.array([sphray.NO_HIT, 7]))
    np.testing.assert_array_equal(points, [[0, 0, 2], [0, 0, -2]])   # origin + t * direction
    np.testing.assert_array_equal(normals, 0)
    assert not front.any()
