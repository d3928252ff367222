"""Input a careless or hostile caller gives (issue 30): failed conversions under a memory limit,
refit() and masks, numpy scalars where scalars are documented, and the odds (complex centres,
a second __init__, writes through scene.centers, the sphere count limit)."""

import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import sphray

# --- A conversion numpy cannot allocate raises MemoryError naming the argument -----------------
#
# Each case runs in a fresh interpreter whose address space (RLIMIT_AS) is limited to what it
# has mapped after building its arguments, plus HEADROOM: the arrays below are np.zeros (pages
# mapped, never touched), so the children stay small, and the copy the module would make of one
# argument (hundreds of MiB at least) cannot be mapped. Before the fix pybind11's ensure()
# swallowed numpy's MemoryError and the module dereferenced the null array: exit -11.

HEADROOM = 128 << 20
N = 60_000_000  # rows: a float32 copy of (N,) is 240 MB, of (N, 3) 720 MB

CHILD = """
import json, resource, sys, time
import numpy as np
import sphray

def mapped():
    for line in open("/proc/self/status"):
        if line.startswith("VmSize:"):
            return int(line.split()[1]) * 1024

N = {n}
rays = np.zeros((N, 3), np.float32)           # read in place: never copied
spheres = np.zeros((N, 3), np.float32, order="F")
small = sphray.Scene(np.zeros((4, 3), np.float32), np.ones(4, np.float32))
{setup}
limit = mapped() + {headroom}
resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
start = time.monotonic()
try:
    {call}
except MemoryError as e:
    print(json.dumps({{"message": str(e), "seconds": time.monotonic() - start,
                      "maxrss_kib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss}}))
    sys.exit(3)
sys.exit(0)
"""

MEMORY_CASES = {
    # The two reproductions.
    "count_hits float64 rays": ("o = np.zeros((N, 3))", "small.count_hits(o, o)", "origins"),
    "Scene of 2**32 - 2 broadcast spheres": (
        "",
        "sphray.Scene(np.broadcast_to(np.float32([0, 0, 0]), (2**32 - 2, 3)),"
        " np.broadcast_to(np.float32(1), (2**32 - 2,)))",
        "centers",
    ),
    # Every other conversion the module makes.
    "radii": ("r = np.zeros(N)", "sphray.Scene(spheres, r, precision='float')", "radii"),
    # float32 centres widened for a scene that is double (its radii are float64).
    "centers widened to float64": ("r = np.zeros(N)", "sphray.Scene(spheres, r)", "centers"),
    "sphere masks": ("m, r = np.zeros(N, np.uint8), np.zeros(N, np.float32)",
                     "sphray.Scene(spheres, r, masks=m)", "masks"),
    "tmax per ray": ("t = np.zeros(N)", "small.intersect(rays, rays, tmax=t)", "tmax"),
    "mask per ray": ("m = np.zeros(N, np.uint8)", "small.occluded(rays, rays, mask=m)", "mask"),
    "surface ids": ("i = np.zeros(N, np.uint8)", "small.surface(rays, rays, 1.0, i)", "ids"),
    "spawn new_directions": ("n, i = np.zeros((N, 3)), np.zeros(N, np.uint32)",
                             "small.spawn(rays, rays, 1.0, i, n)", "new_directions"),
    "points reshaped": ("p = np.broadcast_to(np.float64(0), (20000, 20000, 3))",
                        "small.inside(p)", "points"),
}


@pytest.mark.parametrize("case", MEMORY_CASES)
def test_a_conversion_out_of_memory_raises_memory_error(case):
    setup, call, what = MEMORY_CASES[case]
    code = CHILD.format(n=N, setup=setup, call=call, headroom=HEADROOM)
    child = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                           text=True, timeout=60)
    assert child.returncode == 3, (child.returncode, child.stderr[-2000:])
    report = json.loads(child.stdout)
    assert report["message"].startswith(what + ": Unable to allocate"), report["message"]
    # Refused as the copy is asked for: at once, and without touching the memory it needed.
    assert report["seconds"] < 1.0
    assert report["maxrss_kib"] < 200 * 1024


def test_sphere_count_limit_is_the_c_apis():
    # 2**32 - 1 spheres are allowed (ids 0 to 2**32 - 2; NO_HIT is no sphere's id), as
    # kMaxSpheres in the C API: this one fails only at the copy, under the limit.
    code = CHILD.format(
        n=1, setup="", headroom=HEADROOM,
        call="sphray.Scene(np.broadcast_to(np.float32([0, 0, 0]), (2**32 - 1, 3)),"
             " np.broadcast_to(np.float32(1), (2**32 - 1,)), accel='brute')")
    child = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                           text=True, timeout=60)
    assert child.returncode == 3, (child.returncode, child.stderr[-2000:])
    assert "(4294967295, 3)" in json.loads(child.stdout)["message"]
    # One more is refused before any copy is tried, naming the limit.
    with pytest.raises(ValueError, match=r"at most 2\*\*32 - 1 spheres.*\(4294967296, 3\)"):
        sphray.Scene(np.broadcast_to(np.float32([0, 0, 0]), (2**32, 3)),
                     np.broadcast_to(np.float32(1), (2**32,)))


def test_numpys_other_conversion_errors_keep_their_type_and_name_the_argument():
    s = sphray.Scene(np.zeros((4, 3), np.float32), np.ones(4, np.float32))
    with pytest.raises(ValueError, match="^origins: .*inhomogeneous") as info:
        s.intersect([[0, 0, 0], [0, 0]], np.zeros((2, 3)))
    assert isinstance(info.value.__cause__, ValueError)      # numpy's own, chained


# --- refit() keeps the sphere masks when none are given -----------------------------------------


@pytest.mark.parametrize("accel", ["brute", "bvh"])
def test_refit_without_masks_keeps_them(rng, accel):
    n = 300
    centers = rng.uniform(-10, 10, (n, 3)).astype(np.float32)
    radii = rng.uniform(0.3, 1.0, n).astype(np.float32)
    masks = np.where(np.arange(n) % 2 == 0, 1, 2).astype(np.uint32)  # even ids: bit 0
    scene = sphray.Scene(centers, radii, accel=accel, masks=masks)
    origins = rng.uniform(-12, 12, (5000, 3)).astype(np.float32)
    directions = rng.normal(size=(5000, 3)).astype(np.float32)
    before = scene.intersect(origins, directions, mask=1)
    scene.refit(centers.copy(), radii.copy())                        # same spheres, no masks
    t, ids = scene.intersect(origins, directions, mask=1)
    hit = ids != sphray.NO_HIT
    assert hit.sum() > 100
    assert np.all(ids[hit] % 2 == 0), "rays hit spheres their mask hides"
    np.testing.assert_array_equal(ids, before[1])
    np.testing.assert_array_equal(t, before[0])
    # Masks given replace them: every bit for every sphere shows the odd ones again.
    scene.refit(centers, radii, masks=np.full(n, 0xFFFFFFFF, np.uint32))
    assert np.any(scene.intersect(origins, directions, mask=1)[1][hit] % 2 == 1)


# --- numpy scalars are scalars ------------------------------------------------------------------

SCALAR_SCENE = sphray.Scene(np.array([[0, 0, -3], [0, 0, -6]], np.float32),
                            np.ones(2, np.float32), masks=np.array([1, 2], np.uint32))
O = np.zeros((3, 3), np.float32)
D = np.tile(np.float32([0, 0, -1]), (3, 1))
MASKS = np.array([2, 1], np.uint32)


@pytest.mark.parametrize("kwargs, python_kwargs", [
    ({"tmax": np.float32(10)}, {"tmax": 10.0}),
    ({"tmax": np.float64(4)}, {"tmax": 4.0}),
    ({"tmax": np.int64(10)}, {"tmax": 10}),
    ({"tmax": np.array(4.5)}, {"tmax": 4.5}),
    ({"tmin": np.float32(2.5)}, {"tmin": 2.5}),
    ({"tmin": np.int32(3), "tmax": np.uint16(9)}, {"tmin": 3, "tmax": 9}),
    ({"mask": np.uint32(2)}, {"mask": 2}),
    ({"mask": MASKS[0]}, {"mask": 2}),
    ({"mask": np.int64(1)}, {"mask": 1}),
    ({"mask": np.array(2, np.uint8)}, {"mask": 2}),
    ({"tmax": 10**30}, {"tmax": float("inf")}),               # beyond float32: inf, as numpy
])
def test_numpy_scalars_are_scalars(kwargs, python_kwargs):
    for query in ("intersect", "occluded", "count_hits"):
        got = getattr(SCALAR_SCENE, query)(O, D, **kwargs)
        want = getattr(SCALAR_SCENE, query)(O, D, **python_kwargs)
        for g, w in zip(got if isinstance(got, tuple) else (got,),
                        want if isinstance(want, tuple) else (want,)):
            np.testing.assert_array_equal(g, w)


def test_numpy_scalar_t_in_surface_and_spawn():
    t, ids = SCALAR_SCENE.intersect(O, D)
    assert np.all(t == 2)
    np.testing.assert_array_equal(SCALAR_SCENE.surface(O, D, np.float32(2), ids)[0],
                                  SCALAR_SCENE.surface(O, D, 2.0, ids)[0])
    np.testing.assert_array_equal(SCALAR_SCENE.spawn(O, D, np.float32(2), ids, -D),
                                  SCALAR_SCENE.spawn(O, D, 2.0, ids, -D))


@pytest.mark.parametrize("mask", [2**32, 2**64, 2**70, -1, -(2**70), np.int64(-1),
                                  np.uint64(2**64 - 1), np.array(2**40)])
def test_out_of_range_masks_are_value_errors(mask):
    with pytest.raises(ValueError, match=r"^mask: masks must lie in \[0, 2\*\*32 - 1\], got -?\d+$"):
        SCALAR_SCENE.intersect(O, D, mask=mask)


def test_out_of_range_mask_arrays_name_the_value_and_index():
    with pytest.raises(ValueError, match=r"got 18446744073709551615 at flat index 1$"):
        SCALAR_SCENE.intersect(O, D, mask=np.array([1, 2**64 - 1, 1], np.uint64))


@pytest.mark.parametrize("value", [np.bool_(True), np.float32(1), np.complex64(1)])
def test_scalars_of_other_dtypes_are_type_errors(value):
    with pytest.raises(TypeError, match="^mask: "):
        SCALAR_SCENE.intersect(O, D, mask=value)


# --- The odds -----------------------------------------------------------------------------------


@pytest.mark.parametrize("centre, words", [
    (np.array([0, 0, 1j]), "complex128"),
    (np.array([0, 0, 1], np.complex64), "complex64"),
    (None, "object"),
    ("abc", "<U3"),
])
def test_overlapping_refuses_what_the_other_queries_refuse(centre, words):
    with pytest.raises(TypeError, match="^centre: .*" + words):
        SCALAR_SCENE.overlapping(centre, 1.0)
    with pytest.raises(TypeError, match="^points: .*" + words):
        SCALAR_SCENE.inside(np.array([centre] * 3) if centre is not None else None)


@pytest.mark.parametrize("accel", ["brute", "bvh"])
def test_init_on_a_live_scene_raises(accel):
    scene = sphray.Scene(np.zeros((4, 3)), np.ones(4), accel=accel)
    with pytest.raises(RuntimeError, match="already initialised"):
        scene.__init__(np.zeros((2, 3)), np.ones(2))
    assert len(scene) == 4 and scene.uses_bvh == (accel == "bvh")

    class Sub(sphray.Scene):
        def __init__(self, n):
            super().__init__(np.zeros((n, 3)), np.ones(n))

    sub = Sub(3)
    assert len(sub) == 3
    with pytest.raises(RuntimeError, match="already initialised"):
        Sub.__init__(sub, 5)
    with pytest.raises(TypeError, match="must be a sphray.Scene"):
        sphray.Scene.__init__(object(), np.zeros((2, 3)), np.ones(2))


@pytest.mark.parametrize("c_order", [True, False])
def test_scene_arrays_are_read_only(c_order):
    centers = np.array([[0, 0, -3], [0, 0, -6]], np.float32)
    if not c_order:
        centers = np.asfortranarray(centers)                # read in place
    radii = np.ones(2, np.float64 if c_order else np.float32)
    # precision="float": the float64 radii are then the scene's own float32 copy.
    scene = sphray.Scene(centers, radii, accel="brute", precision="float")
    for array in (scene.centers, scene.radii):
        assert not array.flags.writeable
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 100
        if c_order:                                         # the scene's own copies
            with pytest.raises(ValueError):
                array.setflags(write=True)
    assert np.shares_memory(scene.centers, centers) == (not c_order)
    assert centers.flags.writeable                          # the caller's flags are untouched
    o, d = np.zeros((1, 3), np.float32), np.array([[0, 0, -1]], np.float32)
    assert scene.intersect(o, d)[1][0] == 0


def test_a_scene_whose_init_never_ran_raises():
    # Scene.__new__ alone: pybind11 handed the methods unconstructed memory (garbage, then a
    # segfault); every method now checks.
    scene = sphray.Scene.__new__(sphray.Scene)
    o = np.zeros((1, 3), np.float32)
    for call in (lambda: len(scene), lambda: scene.intersect(o, o), lambda: scene.centers,
                 lambda: repr(scene), lambda: scene.refit(o, np.ones(1))):
        with pytest.raises(RuntimeError, match="__init__ was never called"):
            call()
    with pytest.raises(TypeError, match="expected a sphray.Scene"):
        sphray.Scene.intersect(object(), o, o)
    scene.__init__(o, np.ones(1))                            # a late __init__ is still the first
    assert len(scene) == 1


def misaligned(a, order="C"):
    """a's values in an array one byte off its dtype's alignment (as np.frombuffer at an odd
    offset gives), with a's layout."""
    a = np.asarray(a)
    buf = np.zeros(a.nbytes + 1, np.uint8)
    out = np.ndarray(a.shape, a.dtype, buffer=buf, offset=1, order=order)
    out[...] = a
    assert not out.flags.aligned
    return out


@pytest.mark.parametrize("accel", ["brute", "bvh"])
def test_misaligned_arrays_are_copied_not_read_through_a_float_pointer(rng, accel):
    # numpy hands a misaligned contiguous array back unconverted unless alignment is asked
    # for: the rays' reader then had no strides and crashed.
    n = 200
    centers = rng.uniform(-5, 5, (n, 3)).astype(np.float32)
    radii = rng.uniform(0.2, 0.6, n).astype(np.float32)
    masks = rng.integers(1, 4, n).astype(np.uint32)
    o = rng.uniform(-6, 6, (500, 3)).astype(np.float32)
    d = rng.normal(size=(500, 3)).astype(np.float32)
    tmax = rng.uniform(1, 20, 500).astype(np.float32)
    ray_masks = rng.integers(1, 4, 500).astype(np.uint32)
    want_scene = sphray.Scene(centers, radii, accel=accel, masks=masks)
    got_scene = sphray.Scene(misaligned(centers, "F"), misaligned(radii), accel=accel,
                             masks=misaligned(masks))
    want = want_scene.intersect(o, d, tmax=tmax, mask=ray_masks)
    got = got_scene.intersect(misaligned(o), misaligned(d), tmax=misaligned(tmax),
                              mask=misaligned(ray_masks))
    np.testing.assert_array_equal(got[0], want[0])
    np.testing.assert_array_equal(got[1], want[1])
    np.testing.assert_array_equal(
        got_scene.surface(misaligned(o), misaligned(d), misaligned(want[0]), misaligned(want[1]))[0],
        want_scene.surface(o, d, *want)[0])
    assert got_scene.centers.flags.aligned and got_scene.radii.flags.aligned


# --- Every argument, every odd value: a result or an exception, never a crash -------------------


class ArrayRaises:
    """An object whose conversion to an array fails with an exception of its own."""

    def __array__(self, dtype=None):
        raise KeyError("from __array__")


ODD_VALUES = [
    None, 1, -1, 2**70, 1.5, float("nan"), True, "x", b"xy", [], [[]], [[1, 2, 3]],
    [[1, 2, 3], [1, 2]], np.zeros((0, 3)), np.zeros((2, 3))[::-1],
    np.zeros((2, 3), np.float32)[:, ::-1], np.zeros((2, 0)), np.zeros((2, 3), ">f4"),
    np.zeros((2, 3), np.float16), np.zeros((2, 3), np.longdouble), np.zeros((2, 3), np.uint64),
    np.zeros((2, 3), object), np.zeros((2, 3), complex), np.zeros(3), np.zeros(()),
    np.float32(1), np.uint32(7), np.zeros((2, 1, 3)), np.broadcast_to(np.float32(0), (2, 3)),
    np.ma.masked_array(np.zeros((2, 3))), np.zeros((2, 3), [("a", "f4")]), np.zeros(2, np.uint32),
    np.zeros(2, np.int8) - 1, memoryview(np.zeros((2, 3), np.float32)), ArrayRaises(),
    misaligned(np.zeros((2, 3), np.float32)),
]


def test_odd_values_in_every_argument_raise_python_exceptions():
    o, d, ids = np.zeros((2, 3)), np.ones((2, 3)), np.zeros(2, np.uint32)
    c, r = np.zeros((2, 3)), np.ones(2)
    for accel in ("brute", "bvh"):
        s = sphray.Scene(c, r, accel=accel)
        calls = {
            "Scene centers": lambda v: sphray.Scene(v, r, accel=accel),
            "Scene radii": lambda v: sphray.Scene(c, v, accel=accel),
            "Scene masks": lambda v: sphray.Scene(c, r, accel=accel, masks=v),
            "intersect origins": lambda v: s.intersect(v, d),
            "intersect directions": lambda v: s.intersect(o, v),
            "intersect tmin": lambda v: s.intersect(o, d, tmin=v),
            "occluded tmax": lambda v: s.occluded(o, d, tmax=v),
            "count_hits mask": lambda v: s.count_hits(o, d, mask=v),
            "intersect_all mask": lambda v: s.intersect_all(o, d, 4, mask=v),
            "surface t": lambda v: s.surface(o, d, v, ids),
            "surface ids": lambda v: s.surface(o, d, 1.0, v),
            "spawn new_directions": lambda v: s.spawn(o, d, 1.0, ids, v),
            "nearest points": lambda v: s.nearest(v),
            "inside points": lambda v: s.inside(v),
            "overlapping centre": lambda v: s.overlapping(v, 1.0),
            "refit centers": lambda v: s.refit(v, r),
            "refit radii": lambda v: s.refit(c, v),
            "refit masks": lambda v: s.refit(c, r, masks=v),
            "pinhole_rays eye": lambda v: sphray.pinhole_rays(v, [0, 0, -1], [0, 1, 0], 90, 4, 4),
        }
        for name, call in calls.items():
            for value in ODD_VALUES:
                try:
                    call(value)
                except (TypeError, ValueError, MemoryError):
                    pass
                except KeyError:
                    assert isinstance(value, ArrayRaises), (name, value)  # its own, unchanged
        assert len(s) == 2
