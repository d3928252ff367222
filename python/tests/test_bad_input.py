"""Every bad input raises ValueError (shapes, values) or TypeError (dtypes), naming the
argument and the offending shape or dtype, and never crashes."""

import numpy as np
import pytest

import sphray

GOOD_C = np.zeros((4, 3), np.float32)
GOOD_R = np.ones(4, np.float32)
RAYS = np.zeros((5, 3), np.float32)


def scene():
    return sphray.Scene(GOOD_C, GOOD_R)


CASES = [
    # (call, exception, words the message must hold)
    (lambda: sphray.Scene(np.zeros((4, 2)), GOOD_R), ValueError, ["centers", "(4, 2)"]),
    (lambda: sphray.Scene(np.zeros(12), GOOD_R), ValueError, ["centers", "(12,)"]),
    (lambda: sphray.Scene(np.zeros((2, 4, 3)), GOOD_R), ValueError, ["centers", "(2, 4, 3)"]),
    (lambda: sphray.Scene(GOOD_C, np.ones(3)), ValueError, ["radii", "(3,)", "(4,)"]),
    (lambda: sphray.Scene(GOOD_C, np.ones((4, 1))), ValueError, ["radii", "(4, 1)"]),
    (lambda: sphray.Scene(GOOD_C.astype(complex), GOOD_R), TypeError, ["centers", "complex128"]),
    (lambda: sphray.Scene(GOOD_C, GOOD_R.astype(bool)), TypeError, ["radii", "bool"]),
    (lambda: sphray.Scene(GOOD_C, np.array(["a"] * 4)), TypeError, ["radii", "<U1"]),
    (lambda: sphray.Scene(GOOD_C, GOOD_R.astype(object)), TypeError, ["radii", "object"]),
    (lambda: sphray.Scene(GOOD_C, GOOD_R, accel="kd"), ValueError, ["accel", "kd"]),
    (lambda: scene().intersect(np.zeros((5, 2)), RAYS), ValueError, ["origins", "(5, 2)"]),
    (lambda: scene().intersect(np.zeros(3), np.zeros(3)), ValueError, ["origins", "(3,)"]),
    (lambda: scene().intersect(RAYS, np.zeros((6, 3))), ValueError, ["directions", "(6, 3)", "(5, 3)"]),
    (lambda: scene().intersect(RAYS, RAYS.astype(complex)), TypeError, ["directions", "complex128"]),
    (lambda: scene().intersect(RAYS, RAYS, tmin=np.zeros(4)), ValueError, ["tmin", "(4,)", "(5,)"]),
    (lambda: scene().intersect(RAYS, RAYS, tmax=np.zeros((5, 1))), ValueError, ["tmax", "(5, 1)"]),
    (lambda: scene().intersect(RAYS, RAYS, tmax="far"), TypeError, ["tmax", "<U3"]),
    (lambda: scene().occluded(RAYS, np.zeros((5, 4))), ValueError, ["directions", "(5, 4)"]),
    (lambda: scene().surface(RAYS, RAYS, np.zeros(4), np.zeros(5, np.uint32)), ValueError, ["t", "(4,)"]),
    (lambda: scene().surface(RAYS, RAYS, np.zeros(5), np.zeros(4, np.uint32)), ValueError, ["ids", "(4,)"]),
    (lambda: scene().surface(RAYS, RAYS, np.zeros(5), np.zeros(5)), TypeError, ["ids", "float64"]),
    (lambda: scene().surface(RAYS, RAYS, np.zeros(5), -np.ones(5, int)), ValueError, ["ids", "-1"]),
    (lambda: scene().refit(np.zeros((3, 3)), np.ones(3)), ValueError, ["4 spheres", "(3, 3)"]),
    (lambda: scene().refit(GOOD_C, np.ones(5)), ValueError, ["radii", "(5,)"]),
    (lambda: sphray.pinhole_rays([0, 0], [0, 0, -1], [0, 1, 0], 90, 4, 4), ValueError, ["eye", "(2,)"]),
    (lambda: sphray.pinhole_rays([0, 0, 0], [0, 0, 0], [0, 1, 0], 90, 4, 4), ValueError, ["differ"]),
    (lambda: sphray.pinhole_rays([0, 0, 0], [0, 0, -1], [0, 0, 1], 90, 4, 4), ValueError, ["parallel"]),
    (lambda: sphray.pinhole_rays([0, 0, 0], [0, 0, -1], [0, 1, 0], 180, 4, 4), ValueError, ["vfov"]),
    (lambda: sphray.pinhole_rays([0, 0, 0], [0, 0, -1], [0, 1, 0], 90, 0, 4), ValueError, ["0x4"]),
    (lambda: sphray.pinhole_rays([0, 0, 0], [0, 0, -1], [0, 1, 0], 90, 10**6, 4), ValueError, ["1000000x4"]),
    (lambda: sphray.render("no-such-scene"), ValueError, ["no-such-scene"]),
    (lambda: sphray.render("single", mode="xray"), ValueError, ["xray"]),
    (lambda: sphray.render("single", width=-3), ValueError, ["-3"]),
]


@pytest.mark.parametrize("call, error, words", CASES, ids=[str(i) for i in range(len(CASES))])
def test_bad_input_raises(call, error, words):
    with pytest.raises(error) as info:
        call()
    for w in words:
        assert w in str(info.value), f"{w!r} not in {str(info.value)!r}"
