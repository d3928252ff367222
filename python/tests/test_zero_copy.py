"""Float32 spheres in the kernel's layout are read in place, not copied: the scene's arrays
are the caller's, and a write into them is what the next query sees."""

import numpy as np

import sphray


def columns(centers):
    """An (N, 3) float32 array with contiguous columns: the transpose of a C-ordered (3, N)."""
    return np.ascontiguousarray(np.asarray(centers, np.float32).T).T


def test_float32_columns_and_radii_are_read_in_place():
    centers = columns([[0, 0, -3], [0, 0, -6]])
    radii = np.array([1, 1], np.float32)
    scene = sphray.Scene(centers, radii, accel="brute")
    assert scene.centers.ctypes.data == centers.ctypes.data
    assert scene.radii.ctypes.data == radii.ctypes.data
    o, d = np.zeros((1, 3), np.float32), np.array([[0, 0, -1]], np.float32)
    assert scene.intersect(o, d)[1][0] == 0
    # Writes into the caller's arrays reach the kernel without any call: nothing was copied.
    radii[0] = 0.0
    assert scene.intersect(o, d)[1][0] == 1
    centers[1, 2] = -2.5
    t, ids = scene.intersect(o, d)
    assert (t[0], ids[0]) == (1.5, 1)


def test_a_bvh_sees_writes_at_refit():
    centers = columns(np.c_[np.zeros(200), np.zeros(200), -3.0 - np.arange(200)])
    radii = np.full(200, 0.25, np.float32)
    scene = sphray.Scene(centers, radii, accel="bvh")
    o, d = np.zeros((1, 3), np.float32), np.array([[0, 0, -1]], np.float32)
    assert scene.intersect(o, d)[1][0] == 0
    radii[:5] = 0.0
    assert scene.intersect(o, d)[1][0] == 0         # the tree's own copy: unchanged
    scene.refit(centers, radii)                     # the same arrays, still not copied
    assert scene.radii.ctypes.data == radii.ctypes.data
    assert scene.intersect(o, d)[1][0] == 5


def test_other_layouts_are_copied_once_into_columns():
    c_order = np.array([[0, 0, -3], [0, 0, -6]], np.float32)
    # precision="float": float64 radii alone would make the scene double (test_double.py).
    scene = sphray.Scene(c_order, np.array([1, 1], np.float64), accel="brute", precision="float")
    assert not np.shares_memory(scene.centers, c_order)
    assert scene.centers.flags.f_contiguous and scene.centers.dtype == np.float32
    np.testing.assert_array_equal(scene.centers, c_order)
    assert scene.radii.dtype == np.float32
    c_order[0, 2] = -100                            # the copy is the scene's own
    o, d = np.zeros((1, 3)), np.array([[0, 0, -1.0]])
    assert scene.intersect(o, d)[1][0] == 0
