"""Double precision scenes (issue 37): the scene's precision follows its arrays' dtype (float64
in: the double kernel, read in place), every query answers in double, and double holds where
float cannot (a millimetre sphere 100 km from the origin)."""

import json
import subprocess
import sys
import textwrap
from decimal import Decimal, getcontext

import numpy as np
import pytest

import reference as ref
import sphray

ACCELS = ["brute", "bvh"]
PRECISIONS = {"float": np.float32, "double": np.float64}


def reference_hits(centers, radii, origins, directions, chunk=250, **bounds):
    """reference.intersect a chunk of rays at a time: its (M, N, 3) temporaries at once would
    leave this process hundreds of MB larger, which the memory tests of test_hostile.py (run
    after this file, in children that inherit that size as their peak) would see."""
    parts = [ref.intersect(centers, radii, origins[i:i + chunk], directions[i:i + chunk],
                           **bounds) for i in range(0, len(origins), chunk)]
    return tuple(np.concatenate(p) for p in zip(*parts))


def unit(rng, n):
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1)[:, None]


# --- Which kernel: the dtype rule and precision= ----------------------------------------------

@pytest.mark.parametrize("centers, radii, expected", [
    (np.zeros((2, 3)), np.ones(2), "double"),                              # numpy's default
    (np.zeros((2, 3), np.float32), np.ones(2, np.float32), "float"),
    (np.zeros((2, 3), np.float32), np.ones(2), "double"),                  # either is enough
    (np.zeros((2, 3)), np.ones(2, np.float32), "double"),
    ([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], [0.5, 0.5], "double"),            # Python floats
    ([[0, 0, 0], [1, 0, 0]], [1, 1], "float"),                             # Python ints
    (np.zeros((2, 3), np.int64), np.ones(2, np.int32), "float"),
    (np.zeros((2, 3), np.float16), np.ones(2, np.float16), "float"),
])
def test_precision_follows_the_dtype(centers, radii, expected):
    scene = sphray.Scene(centers, radii)
    assert scene.precision == expected
    dtype = PRECISIONS[expected]
    assert scene.centers.dtype == dtype and scene.radii.dtype == dtype
    # The rays' dtype does not matter: the scene's precision decides what comes back.
    for rays in (np.float32, np.float64, np.int64):
        o, d = np.zeros((4, 3), rays), np.ones((4, 3), rays)
        assert scene.intersect(o, d).t.dtype == dtype
    assert expected in repr(scene)


@pytest.mark.parametrize("precision", ["float", "double"])
@pytest.mark.parametrize("dtype", [np.float32, np.float64, np.int32])
def test_precision_argument_forces_it(precision, dtype):
    centers = np.array([[0, 0, -3], [0, 0, -6]], dtype)
    scene = sphray.Scene(centers, np.ones(2, dtype), accel="brute", precision=precision)
    assert scene.precision == precision
    assert scene.centers.dtype == PRECISIONS[precision]
    np.testing.assert_array_equal(scene.centers, centers)
    hits = scene.intersect(np.zeros((1, 3)), np.array([[0, 0, -1.0]]))
    assert hits.t.dtype == PRECISIONS[precision] and (hits.t[0], hits.ids[0]) == (2.0, 0)


@pytest.mark.parametrize("bad", ["single", "Double", "float64", "", 64, np.float64, True])
def test_an_unknown_precision_is_a_value_error(bad):
    with pytest.raises(ValueError, match=r"precision: expected None, 'float' or 'double', got "):
        sphray.Scene(np.zeros((1, 3)), np.ones(1), precision=bad)


def test_precision_is_keyword_last_and_read_only():
    scene = sphray.Scene(np.zeros((1, 3)), np.ones(1), "brute", None, "float")  # positional too
    assert scene.precision == "float" and not scene.uses_bvh
    with pytest.raises(AttributeError):
        scene.precision = "double"


# --- float64 spheres are read in place -----------------------------------------------------------

def test_float64_columns_and_radii_are_read_in_place():
    centers = np.asfortranarray([[0, 0, -3], [0, 0, -6]], np.float64)
    radii = np.array([1, 1], np.float64)
    scene = sphray.Scene(centers, radii, accel="brute")
    assert scene.precision == "double"
    assert np.shares_memory(scene.centers, centers) and np.shares_memory(scene.radii, radii)
    o, d = np.zeros((1, 3)), np.array([[0, 0, -1.0]])
    assert scene.intersect(o, d).ids[0] == 0
    radii[0] = 0.0                                   # seen by the next query: nothing was copied
    assert scene.intersect(o, d).ids[0] == 1
    centers[1, 2] = -2.5 + 1e-12                     # a change float32 could not even hold
    t, ids = scene.intersect(o, d)
    assert (t[0], ids[0]) == (1.5 - 1e-12, 1)


def test_transposed_float64_and_refit_are_read_in_place():
    xyz = np.zeros((3, 200))
    xyz[2] = -3.0 - np.arange(200)
    radii = np.full(200, 0.25)
    scene = sphray.Scene(xyz.T, radii, accel="bvh")
    assert scene.uses_bvh and np.shares_memory(scene.centers, xyz)
    o, d = np.zeros((1, 3)), np.array([[0, 0, -1.0]])
    radii[:5] = 0.0
    assert scene.intersect(o, d).ids[0] == 0         # the tree's own copy until refit
    scene.refit(xyz.T, radii)
    assert np.shares_memory(scene.radii, radii) and scene.intersect(o, d).ids[0] == 5


def test_other_float64_layouts_are_copied_once_into_float64_columns():
    c_order = np.array([[0, 0, -3], [0, 0, -6 - 1e-9]])
    scene = sphray.Scene(c_order, np.array([1, 1], np.int64), accel="brute")
    assert scene.precision == "double"
    assert not np.shares_memory(scene.centers, c_order)
    assert scene.centers.flags.f_contiguous and scene.centers.dtype == np.float64
    np.testing.assert_array_equal(scene.centers, c_order)    # not rounded through float32
    assert scene.radii.dtype == np.float64 and not scene.radii.flags.writeable


def test_float64_rays_are_read_in_place_and_float32_are_converted():
    # Under an address-space limit far below a copy of the rays: a double scene reads strided
    # float64 rays where they lie, while a float scene must convert them (and cannot).
    code = textwrap.dedent("""
        import json, resource, sys
        import numpy as np
        import sphray
        N = 20_000_000
        rays = np.zeros((N, 4))[:, :3]               # strided float64 views: 480 MB to copy
        double = sphray.Scene(np.zeros((1, 3)), np.ones(1))
        single = sphray.Scene(np.zeros((1, 3), np.float32), np.ones(1, np.float32))
        status = [l for l in open("/proc/self/status") if l.startswith("VmSize:")][0]
        limit = int(status.split()[1]) * 1024 + (128 << 20)
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        hit = double.occluded(rays, rays)            # bool results: 20 MB
        try:
            single.occluded(rays, rays)
            error = None
        except MemoryError as e:
            error = str(e)
        print(json.dumps({"precision": double.precision, "n": int(hit.size), "error": error}))
    """)
    child = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           timeout=120)
    assert child.returncode == 0, child.stderr[-2000:]
    report = json.loads(child.stdout)
    assert report["precision"] == "double" and report["n"] == 20_000_000
    assert report["error"] is not None and report["error"].startswith("origins: Unable")


def test_float32_rays_are_widened_exactly(rng):
    centers, radii = rng.uniform(-5, 5, (50, 3)), rng.uniform(0.3, 1.0, 50)
    scene = sphray.Scene(centers, radii)
    o32, d32 = ref.random_rays(rng, 2000, box=6)
    t32, i32 = scene.intersect(o32, d32, tmax=np.float32(20))
    t64, i64 = scene.intersect(o32.astype(np.float64), d32.astype(np.float64), tmax=20.0)
    np.testing.assert_array_equal(i32, i64)
    np.testing.assert_array_equal(t32, t64)
    assert t32.dtype == np.float64 and (i32 != sphray.NO_HIT).sum() > 100


# --- Hits against references: float64 with a tight tolerance, and exact on a few rays -----------

@pytest.mark.parametrize("accel", ACCELS)
def test_hits_match_the_double_reference(rng, accel):
    # Values float32 cannot hold (1e-7 apart): only a double kernel meets the 1e-12 tolerance.
    centers = rng.uniform(-8, 8, (400, 3)) + 1e-7 * rng.uniform(size=(400, 3))
    radii = rng.uniform(0.3, 0.8, 400) + 1e-9
    origins = rng.uniform(-10, 10, (3000, 3))
    directions = rng.normal(size=(3000, 3))
    scene = sphray.Scene(centers, radii, accel=accel)
    assert scene.precision == "double" and scene.uses_bvh == (accel == "bvh")
    t, ids = scene.intersect(origins, directions, tmax=50.0)
    t_ref, ids_ref, undecidable = reference_hits(centers, radii, origins, directions,
                                                 tmax=50.0, precision="double")
    assert t.dtype == np.float64 and t_ref.dtype == np.float64
    assert undecidable.mean() < 0.001, "the reference cannot judge enough rays"
    sure = ~undecidable
    np.testing.assert_array_equal(ids[sure], ids_ref[sure])
    hit = sure & (ids_ref != ref.NO_HIT)
    assert hit.sum() > 500
    np.testing.assert_allclose(t[hit], t_ref[hit], rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(t[sure & ~hit], 50.0)


def exact_t(c, r, o, d):
    """The near root of the ray o + t d on the sphere (c, r) to 60 digits, from the float64
    inputs as they are (Decimal holds each exactly); None for a miss."""
    getcontext().prec = 60
    c, o, d = ([Decimal(float(x)) for x in v] for v in (c, o, d))
    r = Decimal(float(r))
    g = [ci - oi for ci, oi in zip(c, o)]
    a = sum(x * x for x in d)
    b = sum(gi * di for gi, di in zip(g, d))
    disc = b * b - a * (sum(x * x for x in g) - r * r)
    if disc < 0:
        return None
    return (b - disc.sqrt()) / a


def test_hits_are_exact_to_a_few_ulps(rng):
    centers = rng.uniform(-3, 3, (5, 3)) * 10.0 ** rng.integers(-3, 4, (5, 1))
    radii = np.abs(centers).max(axis=1) * rng.uniform(0.05, 0.2, 5)
    scene = sphray.Scene(centers, radii, accel="brute")
    for i in range(5):
        # Rays from outside towards a point well inside sphere i's silhouette.
        o = centers[i] + 3 * radii[i] * unit(rng, 1)[0]
        d = centers[i] + 0.5 * radii[i] * unit(rng, 1)[0] - o
        t, ids = scene.intersect(o[None], d[None])
        expected = exact_t(centers[ids[0]], radii[ids[0]], o, d)
        assert expected is not None and ids[0] == i
        assert abs(Decimal(float(t[0])) - expected) <= Decimal(1e-14) * expected


# --- Where float fails and double holds ----------------------------------------------------------

FAR = (1e5 * np.array([1.0, 2.0, 3.0]) / np.sqrt(14)).astype(np.float32).astype(np.float64)


def far_scene(precision):
    """A 1 mm sphere 1e5 from the origin, at a centre float32 holds exactly (both scenes hold
    the same sphere)."""
    return sphray.Scene(FAR[None], np.array([1e-3]), accel="brute", precision=precision)


def rays_at_the_far_sphere(rng, n, away=1.0):
    origins = FAR + away * unit(rng, n)
    return origins, FAR + 0.9e-3 * unit(rng, n) - origins


def spawn_inward(scene, rng, origins, directions):
    """(hit, far_side): whether each ray hit the sphere, and whether a ray spawned from each hit
    in a random inward direction then meets the sphere's far side."""
    t, ids = scene.intersect(origins, directions)
    hit = ids == 0
    o, d, t, ids = origins[hit], directions[hit], t[hit], ids[hit]
    normals = scene.surface(o, d, t, ids).normals
    inward = unit(rng, len(o))
    inward[np.einsum("ij,ij->i", inward, normals) > 0] *= -1
    starts = scene.spawn(o, d, t, ids, inward)
    assert starts.dtype == PRECISIONS[scene.precision]
    return hit, scene.intersect(starts, inward).ids == 0


def test_rays_spawned_into_a_millimetre_sphere_100_km_away_meet_its_far_side(rng):
    origins, directions = rays_at_the_far_sphere(rng, 4000)
    hit, far_side = spawn_inward(far_scene("double"), rng, origins, directions)
    assert hit.all() and far_side.all()
    # Float holds the same sphere but rounds every point to 8 mm steps: most primary rays miss,
    # and the spawned rays of those that hit start beyond the far side.
    hit, far_side = spawn_inward(far_scene("float"), rng, origins, directions)
    assert hit.sum() >= 200, "too few float hits to measure its failure rate"
    assert (~far_side).mean() > 0.5
    assert hit.mean() < 0.5


def test_t_from_one_metre_to_a_millimetre_sphere_100_km_away(rng):
    origins, directions = rays_at_the_far_sphere(rng, 20)
    expected = np.array([float(exact_t(FAR, 1e-3, o, d)) for o, d in zip(origins, directions)])
    t, ids = far_scene("double").intersect(origins, directions)
    assert (ids == 0).all()
    np.testing.assert_allclose(t, expected, rtol=1e-9, atol=0)
    # Float's t (where it hits at all) is off by far more: a float32 ulp at 1e5 is 8 mm.
    t32, ids32 = far_scene("float").intersect(origins, directions)
    hit = ids32 == 0
    wrong = ~hit | (np.abs(t32 - expected) > 1e-6 * expected)
    assert wrong.mean() > 0.5


# --- Every other query: a double scene agrees with a float scene where both are exact ----------

def separated_scene(rng, radius=(0.5, 1.0)):
    """Spheres on a grid of spacing 3, float32 values (both precisions hold the same scene):
    radius (0.5, 1.0) keeps them well apart, (1.6, 1.9) makes each overlap its 6 neighbours."""
    g = np.arange(7) * 3.0 - 9.0
    centers = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)
    centers = (centers + rng.uniform(-0.05, 0.05, centers.shape)).astype(np.float32)
    radii = rng.uniform(*radius, len(centers)).astype(np.float32)
    return centers, radii


def both(centers, radii, accel):
    return (sphray.Scene(centers, radii, accel=accel, precision="float"),
            sphray.Scene(centers, radii, accel=accel, precision="double"))


def decidable_rays(rng, centers, radii, m=2000):
    origins = rng.uniform(-11, 11, (m, 3)).astype(np.float32)
    directions = rng.normal(size=(m, 3)).astype(np.float32)
    _, _, undecidable = reference_hits(centers, radii, origins, directions)
    assert undecidable.mean() < 0.01
    return origins[~undecidable], directions[~undecidable]


def assert_close(a32, a64):
    assert a32.dtype == np.float32 and a64.dtype == np.float64
    np.testing.assert_allclose(a64, a32, rtol=2e-6, atol=2e-5)


@pytest.mark.parametrize("accel", ACCELS)
def test_ray_queries_agree_with_float(rng, accel):
    centers, radii = separated_scene(rng)
    single, double = both(centers, radii, accel)
    assert double.uses_bvh == single.uses_bvh == (accel == "bvh")
    o, d = decidable_rays(rng, centers, radii)
    h32, h64 = single.intersect(o, d), double.intersect(o, d)
    np.testing.assert_array_equal(h32.ids, h64.ids)
    assert_close(h32.t, h64.t)
    hit = h64.ids != sphray.NO_HIT
    assert hit.sum() > 300
    np.testing.assert_array_equal(single.occluded(o, d, tmax=5.0), double.occluded(o, d, tmax=5.0))
    s32 = single.surface(o[hit], d[hit], h32.t[hit], h32.ids[hit])
    s64 = double.surface(o[hit], d[hit], h64.t[hit], h64.ids[hit])
    assert_close(s32.points, s64.points)
    assert_close(s32.normals, s64.normals)
    np.testing.assert_array_equal(s32.front_face, s64.front_face)
    for query in ("intersect_all", "intersect_nearest"):
        c32, c64 = getattr(single, query)(o, d, 4), getattr(double, query)(o, d, 4)
        for name in ("ids", "exits", "counts"):
            np.testing.assert_array_equal(getattr(c32, name), getattr(c64, name))
        assert_close(c32.t, c64.t)                   # NaN in the same unused slots
    n32, n64 = single.count_hits(o, d), double.count_hits(o, d)
    np.testing.assert_array_equal(n32, n64)
    assert n64.dtype == np.uint64 and n64.max() >= 4


@pytest.mark.parametrize("accel", ACCELS)
def test_point_queries_agree_with_float(rng, accel):
    centers, radii = separated_scene(rng)
    single, double = both(centers, radii, accel)
    points = rng.uniform(-11, 11, (3000, 3)).astype(np.float32)
    near32, near64 = single.nearest(points, 1.5), double.nearest(points, 1.5)
    np.testing.assert_array_equal(near32.ids, near64.ids)
    assert_close(near32.distances, near64.distances)
    assert_close(near32.surface_points, near64.surface_points)
    assert (near64.ids == sphray.NO_HIT).any() and (near64.ids != sphray.NO_HIT).any()
    inside = double.inside(points)
    np.testing.assert_array_equal(single.inside(points), inside)
    assert inside.any() and not inside.all()
    for i in range(0, 300, 7):
        ball = points[i]
        np.testing.assert_array_equal(single.overlapping(ball, 2.0), double.overlapping(ball, 2.0))
    o32, o64 = single.overlaps(points, 1.0), double.overlaps(points, 1.0)
    np.testing.assert_array_equal(o32.offsets, o64.offsets)
    np.testing.assert_array_equal(o32.ids, o64.ids)
    assert len(o64.ids) > 500


@pytest.mark.parametrize("accel", ACCELS)
def test_overlapping_pairs_and_refit_agree_with_float(rng, accel):
    centers, radii = separated_scene(rng, radius=(1.6, 1.9))
    single, double = both(centers, radii, accel)
    pairs = double.overlapping_pairs()
    np.testing.assert_array_equal(single.overlapping_pairs(), pairs)
    assert len(pairs) == 3 * 6 * 7 * 7                  # each sphere's grid neighbours, once
    moved = (centers + rng.uniform(-0.2, 0.2, centers.shape)).astype(np.float32)
    smaller = (radii * 0.5).astype(np.float32)
    single.refit(moved, smaller)
    double.refit(moved, smaller)
    assert double.centers.dtype == np.float64 and double.precision == "double"
    np.testing.assert_array_equal(single.overlapping_pairs(), double.overlapping_pairs())
    o, d = decidable_rays(rng, moved, smaller)
    h32, h64 = single.intersect(o, d), double.intersect(o, d)
    np.testing.assert_array_equal(h32.ids, h64.ids)
    assert_close(h32.t, h64.t)


# --- Hostile input on a double scene ------------------------------------------------------------

@pytest.mark.parametrize("accel", ACCELS)
def test_invalid_rays_miss_in_double(accel):
    scene = sphray.Scene(np.array([[0, 0, -3.0]] * 130), np.ones(130), accel=accel)
    nan, inf = np.nan, np.inf
    o = np.array([[nan, 0, 0], [0, 0, inf], [0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]])
    d = np.array([[0, 0, -1], [0, 0, -1], [0, nan, -1], [0, 0, -inf], [0, 0, 0],
                  [0, 0, -1e-160]])                 # |d|^2 below double's normal range
    t, ids = scene.intersect(o, d, tmax=7.0)
    np.testing.assert_array_equal(ids, sphray.NO_HIT)
    np.testing.assert_array_equal(t, 7.0)
    assert not scene.occluded(o, d).any() and not scene.count_hits(o, d).any()
    # What float cannot hold is a valid ray in double: |d|^2 = 1e-60.
    t, ids = scene.intersect(np.zeros((1, 3)), np.array([[0, 0, -1e-30]]))
    assert ids[0] == 0 and t[0] == pytest.approx(2e30, rel=1e-12)


BAD_CALLS = [
    lambda s: s.intersect(np.zeros((5, 3)), np.zeros((6, 3))),
    lambda s: s.intersect(np.zeros((5, 2)), np.zeros((5, 2))),
    lambda s: s.intersect(np.zeros((5, 3)), np.zeros((5, 3)), tmax=np.ones(4)),
    lambda s: s.intersect(np.zeros((5, 3), complex), np.zeros((5, 3))),
    lambda s: s.surface(np.zeros((2, 3)), np.zeros((2, 3)), 1.0, np.zeros(2)),
    lambda s: s.spawn(np.zeros((2, 3)), np.zeros((2, 3)), 1.0, np.zeros(2, int), np.zeros((3, 3))),
    lambda s: s.nearest(np.zeros(3)),
    lambda s: s.overlapping(np.zeros(4), 1.0),
    lambda s: s.overlaps(np.zeros((4, 3)), np.ones(3)),
    lambda s: s.refit(np.zeros((3, 3)), np.ones(3)),
    lambda s: s.refit(np.zeros((2, 3)), np.ones(3)),
    lambda s: s.intersect_all(np.zeros((1, 3)), np.ones((1, 3)), max_hits=2**21),
]


@pytest.mark.parametrize("call", range(len(BAD_CALLS)))
def test_bad_input_raises_as_in_float(call):
    errors = []
    for precision in PRECISIONS:
        scene = sphray.Scene(np.zeros((2, 3)), np.ones(2), precision=precision)
        with pytest.raises((ValueError, TypeError)) as e:
            BAD_CALLS[call](scene)
        errors.append((e.type, str(e.value)))
    assert errors[0] == errors[1]


def test_bad_spheres_raise_as_in_float():
    for centers, radii, kind in [(np.zeros((2, 2)), np.ones(2), ValueError),
                                 (np.zeros((2, 3)), np.ones(3), ValueError),
                                 (np.zeros((2, 3), complex), np.ones(2), TypeError)]:
        messages = set()
        for precision in PRECISIONS:
            with pytest.raises(kind) as e:
                sphray.Scene(centers, radii, precision=precision)
            messages.add(str(e.value))
        assert len(messages) == 1


# --- The renderer and the camera: float, fed from a double scene --------------------------------

def test_render_rounds_a_double_scene_to_float(rng):
    centers, radii = rng.uniform(-3, 3, (20, 3)), rng.uniform(0.3, 0.9, 20)
    image = sphray.render(sphray.Scene(centers, radii), mode="normals", width=48, height=32)
    rounded = sphray.Scene(centers.astype(np.float32), radii.astype(np.float32))
    assert rounded.precision == "float"
    np.testing.assert_array_equal(image, sphray.render(rounded, mode="normals", width=48,
                                                       height=32))
    assert image.std() > 0                          # something was drawn
    np.testing.assert_array_equal(image, sphray.render((centers, radii), mode="normals",
                                                       width=48, height=32))


def test_camera_rays_go_to_a_double_scene_widened():
    scene = sphray.Scene(np.array([[0.0, 0.0, 0.0]]), np.array([1.0]))
    origins, directions = sphray.pinhole_rays([0, 0, 5], [0, 0, 0], [0, 1, 0], 30.0, 16, 12)
    assert origins.dtype == directions.dtype == np.float32
    t, ids = scene.intersect(origins, directions)
    assert t.dtype == np.float64 and t.shape == (12, 16) and (ids == 0).sum() > 20
    t64, ids64 = scene.intersect(origins.astype(np.float64), directions.astype(np.float64))
    np.testing.assert_array_equal(ids, ids64)
    np.testing.assert_array_equal(t, t64)
