"""Results of more than one array are named tuples: they unpack as the plain tuples they were
and name their fields (hits.t, hits.ids). And the signatures the docstrings give, which
inspect.signature() reads and the stubtest check (python.stubtest) compares with sphray.pyi,
are the bindings' own."""

import inspect
import pickle

import numpy as np
import pytest

import sphray


def small_scene():
    centers = np.float32([[0, 0, -3], [0, 0, -6], [2, 0, -3]])
    return sphray.Scene(centers, np.float32([1, 1, 0.5]))


RAYS = (np.zeros((2, 3), np.float32), np.float32([[0, 0, -1], [0, 1, 0]]))


def results():
    """(the type, its fields, a result of it) for every query that returns several arrays."""
    scene = small_scene()
    o, d = RAYS
    t, ids = scene.intersect(o, d)
    return [
        (sphray.Hits, ("t", "ids"), scene.intersect(o, d)),
        (sphray.Surface, ("points", "normals", "front_face"), scene.surface(o, d, t, ids)),
        (sphray.Crossings, ("t", "ids", "exits", "counts"), scene.intersect_all(o, d, max_hits=4)),
        (sphray.NearestCrossings, ("t", "ids", "exits", "counts"),
         scene.intersect_nearest(o, d, k=1)),
        (sphray.Nearest, ("ids", "distances", "surface_points"),
         scene.nearest(np.float32([[0, 0, 0], [2, 0, -2]]))),
        (sphray.Overlaps, ("offsets", "ids"), scene.overlaps(np.float32([[0, 0, -3]]), 0.5)),
        (sphray.Rays, ("origins", "directions"),
         sphray.pinhole_rays([0, 0, 0], [0, 0, -1], [0, 1, 0], 40.0, 4, 3)),
    ]


@pytest.mark.parametrize("index", range(7), ids=lambda i: results()[i][0].__name__)
def test_each_result_names_its_fields_and_unpacks_as_before(index):
    cls, fields, result = results()[index]
    assert type(result) is cls and cls.__module__ == "sphray"
    assert cls._fields == fields
    assert isinstance(result, tuple) and len(result) == len(fields)
    unpacked = tuple(result)                      # positionally, as before
    for k, name in enumerate(fields):
        assert getattr(result, name) is unpacked[k] is result[k]
        assert isinstance(unpacked[k], np.ndarray)
        assert getattr(cls, name).__doc__         # each field says what it holds
    assert result._asdict().keys() == set(fields)
    # The class is found by name: a result pickles and comes back the same.
    back = pickle.loads(pickle.dumps(result))
    assert type(back) is cls
    for a, b in zip(back, result):
        np.testing.assert_array_equal(a, b)


def test_named_fields_hold_the_documented_answers():
    scene = small_scene()
    o, d = RAYS
    hits = scene.intersect(o, d)
    assert hits.t.dtype == np.float32 and hits.ids.dtype == np.uint32
    assert hits.t[0] == 2.0 and hits.ids[0] == 0 and hits.ids[1] == sphray.NO_HIT
    surface = scene.surface(o, d, hits.t, hits.ids)
    np.testing.assert_array_equal(surface.points[0], [0, 0, -2])
    np.testing.assert_array_equal(surface.normals[0], [0, 0, 1])
    assert surface.front_face.tolist() == [True, False]
    crossings = scene.intersect_all(o, d, max_hits=4)
    assert crossings.counts.tolist() == [4, 0]
    assert crossings.ids[0].tolist() == [0, 0, 1, 1] and crossings.exits[0].tolist() == [
        False, True, False, True]
    nearest = scene.nearest(np.float32([[0, 0, 0]]))
    assert nearest.ids[0] == 0 and nearest.distances[0] == 2.0
    np.testing.assert_array_equal(nearest.surface_points[0], [0, 0, -2])
    overlaps = scene.overlaps(np.float32([[0, 0, -3], [9, 9, 9]]), 0.5)
    assert overlaps.offsets.tolist() == [0, 1, 1] and overlaps.ids.tolist() == [0]
    rays = sphray.pinhole_rays([0, 0, 0], [0, 0, -1], [0, 1, 0], 40.0, 4, 3)
    assert rays.origins.shape == rays.directions.shape == (3, 4, 3)


# A value of the right kind for each parameter without a default, by name.
SAMPLES = {
    "origins": RAYS[0], "directions": RAYS[1], "t": np.float32([2, np.inf]),
    "ids": np.uint32([0, sphray.NO_HIT]), "new_directions": RAYS[1],
    "points": RAYS[0], "centre": np.zeros(3), "radius": 1.0, "centers": np.zeros((3, 3)),
    "radii": np.ones(3), "eye": [0, 0, 0], "target": [0, 0, -1], "up": [0, 1, 0],
    "vfov_deg": 40.0, "width": 4, "height": 3, "path": None,  # load(): set by the fixture below
}


@pytest.fixture(autouse=True)
def particle_file(tmp_path):
    """A particle file for load()'s path."""
    SAMPLES["path"] = tmp_path / "two.xyz"
    SAMPLES["path"].write_text("0 0 -1 0.5\n1 0 -2 0.25\n")


def callables():
    scene = small_scene()
    found = []
    for owner, prefix in ((scene, "Scene."), (sphray, "")):
        for name in dir(owner):
            member = getattr(owner, name)
            if callable(member) and not isinstance(member, type) and (
                    not name.startswith("_") or name == "__len__"):
                found.append((prefix + name, member))
    return found


@pytest.mark.parametrize("name, function", callables(), ids=[n for n, _ in callables()])
def test_the_documented_signature_is_the_bindings(name, function):
    """Each documented parameter, passed by keyword with its documented default (or a sample
    value), is accepted, and the documented defaults give what the binding's own give: a name in
    a docstring that the binding does not have raises TypeError here, a wrong default differs."""
    signature = inspect.signature(function)
    if name == "render":   # a whole image at the default size: the scene and size kept small
        kwargs = {p: v.default for p, v in signature.parameters.items()}
        kwargs.update(scene="single", width=8)
        required = dict(scene="single", width=8)
    else:
        kwargs = {p: SAMPLES[p] if v.default is inspect.Parameter.empty else v.default
                  for p, v in signature.parameters.items()}
        required = {p: SAMPLES[p] for p, v in signature.parameters.items()
                    if v.default is inspect.Parameter.empty}
    np.testing.assert_equal(function(**kwargs), function(**required))


def test_scene_init_documents_its_signature():
    signature = inspect.signature(sphray.Scene.__init__)
    assert list(signature.parameters) == ["self", "centers", "radii", "accel", "masks",
                                         "precision"]
    scene = sphray.Scene.__new__(sphray.Scene)
    kwargs = {p: SAMPLES.get(p, v.default) for p, v in signature.parameters.items() if p != "self"}
    sphray.Scene.__init__(scene, **kwargs)
    assert len(scene) == 3
