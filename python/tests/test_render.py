"""pinhole_rays and render against numpy references of the book's camera and shading."""

import json
import time

import numpy as np
import pytest

import reference as ref
import sphray


def test_pinhole_rays_match_the_book_camera():
    eye, target, up = [1.0, 2.0, 3.0], [0.0, 0.5, -1.0], [0.0, 1.0, 0.2]
    o, d = sphray.pinhole_rays(eye, target, up, 50.0, 32, 20)
    o_ref, d_ref = ref.pinhole_rays(eye, target, up, 50.0, 32, 20)
    assert o.shape == d.shape == (20, 32, 3) and o.dtype == d.dtype == np.float32
    np.testing.assert_array_equal(o, o_ref)
    np.testing.assert_allclose(d, d_ref, atol=2e-6)


def to_byte(c):
    return np.floor(255.999 * np.clip(c, 0, 1)).astype(np.uint8)


def test_render_normals_of_the_single_preset():
    """The 'single' preset (a sphere of radius 0.5 at (0, 0, -1), the camera at the origin,
    vfov 90): hits coloured (n + 1) / 2, misses the book's white-to-blue sky."""
    w, h = 64, 36
    image = sphray.render("single", mode="normals", width=w, height=h, spp=1)
    assert image.shape == (h, w, 3) and image.dtype == np.uint8
    o, d = ref.pinhole_rays([0, 0, 0], [0, 0, -1], [0, 1, 0], 90.0, w, h)
    o, d = o.reshape(-1, 3), d.reshape(-1, 3)
    t, ids, _ = ref.intersect(np.array([[0, 0, -1]]), np.array([0.5]), o, d)
    _, n, _ = ref.surface(np.array([[0, 0, -1]]), np.array([0.5]), o, d, t, ids)
    a = 0.5 * (d[:, 1] + 1)
    sky = (1 - a)[:, None] * np.ones(3) + a[:, None] * np.array([0.5, 0.7, 1.0])
    colour = np.where((ids != ref.NO_HIT)[:, None], 0.5 * (n + 1), sky)
    expected = to_byte(colour).reshape(h, w, 3)
    diff = np.abs(image.astype(int) - expected)
    assert (diff <= 1).mean() > 0.995      # silhouette pixels may round either way
    assert (ids != ref.NO_HIT).sum() > 100


def test_render_keeps_the_scene_aspect_for_one_side():
    assert sphray.render("single", width=80).shape == (45, 80, 3)   # the scene's 16:9
    assert sphray.render("single", height=9).shape == (9, 16, 3)


def test_render_takes_a_scene_file_as_path(tmp_path):
    scene = tmp_path / "one.json"
    scene.write_text('{"camera": {"lookfrom": [0, 0, 0], "lookat": [0, 0, -1], "vfov": 90},'
                     ' "spheres": [{"center": [0, 0, -1], "radius": 0.5, "color": [1, 0, 0]}]}')
    from_path = sphray.render(scene, mode="flat", width=32, height=18, spp=1)
    assert (from_path == sphray.render(str(scene), mode="flat", width=32, height=18, spp=1)).all()
    # flat mode: the sphere's colour, red (255, 0, 0), in the middle, sky at the corners
    assert tuple(from_path[9, 16]) == (255, 0, 0) and tuple(from_path[0, 0]) != (255, 0, 0)


def own_spheres(rng, n=40):
    centers = rng.uniform(-3, 3, size=(n, 3)).astype(np.float32)
    radii = rng.uniform(0.2, 0.8, size=n).astype(np.float32)
    colors = rng.uniform(0, 1, size=(n, 3)).astype(np.float32)
    return centers, radii, colors


CAMERA = {"lookfrom": [1.0, 2.0, 12.0], "lookat": [0.0, 0.0, 0.0], "vup": [0, 1, 0], "vfov": 45}


def as_scene_file(path, centers, radii, colors, camera, materials=None):
    """The same spheres and camera as a JSON scene file: what the command reads."""
    spheres = [{"center": [float(x) for x in c], "radius": float(r),
                "color": [float(x) for x in k]} for c, r, k in zip(centers, radii, colors)]
    for sphere, material in zip(spheres, materials or []):
        sphere["material"] = material
    path.write_text(json.dumps({"camera": camera, "spheres": spheres}))
    return path


MATERIALS = [{"type": "lambertian"}, {"type": "metal", "albedo": [0.8, 0.7, 0.6], "fuzz": 0.2},
             {"type": "dielectric", "ior": 1.5}, {"type": "metal", "fuzz": 0.0}]


def test_render_own_spheres_with_materials_as_a_scene_file(rng, tmp_path):
    centers, radii, colors = own_spheres(rng, 12)
    materials = [MATERIALS[i % len(MATERIALS)] for i in range(12)]
    file = as_scene_file(tmp_path / "m.json", centers, radii, colors, CAMERA, materials)
    options = dict(mode="path", width=48, height=27, spp=4, max_depth=6)
    expected = sphray.render(file, **options)
    got = sphray.render((centers, radii), camera=CAMERA, colors=colors, materials=materials,
                        **options)
    np.testing.assert_array_equal(got, expected)
    # Glass is not what Lambertian spheres give: the materials were used.
    assert not np.array_equal(
        got, sphray.render((centers, radii), camera=CAMERA, colors=colors, **options))
    # One material for every sphere.
    one = sphray.render((centers, radii), camera=CAMERA, colors=colors, materials=MATERIALS[1],
                        **options)
    every = sphray.render((centers, radii), camera=CAMERA, colors=colors,
                          materials=[MATERIALS[1]] * 12, **options)
    np.testing.assert_array_equal(one, every)
    with pytest.raises(ValueError, match="materials: expected one, or one per sphere"):
        sphray.render((centers, radii), materials=MATERIALS[:2])
    with pytest.raises(ValueError, match="fuzz"):
        sphray.render((centers, radii), materials={"type": "metal", "fuzz": 2})
    # A bad material in a list is named by the first sphere that has it.
    bad = materials[:5] + [{"type": "glass"}] * 7
    with pytest.raises(ValueError, match=r"materials\[5\]:1:10: expected \"type\" to be"):
        sphray.render((centers, radii), materials=bad)


@pytest.mark.parametrize("mode", ["normals", "shaded", "path"])
def test_render_own_spheres_as_the_command_renders_them(rng, tmp_path, mode):
    centers, radii, colors = own_spheres(rng)
    file = as_scene_file(tmp_path / "own.json", centers, radii, colors, CAMERA)
    options = dict(mode=mode, width=64, height=36, spp=2, max_depth=4)
    expected = sphray.render(file, **options)
    scene = sphray.Scene(centers, radii)
    got = sphray.render(scene, camera=CAMERA, colors=colors, **options)
    np.testing.assert_array_equal(got, expected)
    # The arrays themselves, and a camera of numpy values, give the same image.
    camera = {k: np.asarray(v) for k, v in CAMERA.items()}
    np.testing.assert_array_equal(
        sphray.render((centers, radii), camera=camera, colors=colors, **options), expected)


def test_render_frames_own_spheres_without_a_camera(rng):
    centers, radii, _ = own_spheres(rng)
    centers += np.float32([100, -50, 20])   # far from the default camera's view
    image = sphray.render((centers, radii), mode="flat", width=96, height=54, spp=1)
    # Without colours every sphere is grey 0.5, int(255.999 * 0.5) = 127; the sky's blue is 255.
    grey = np.all(image == [127, 127, 127], axis=2)
    assert grey.sum() > 0.05 * grey.size     # the spheres fill a good part of the image
    assert not grey[0].any() and not grey[-1].any()   # and all of them fit: sky above and below
    assert not grey[:, 0].any() and not grey[:, -1].any()


def test_render_linear_is_the_radiance_the_bytes_encode(rng):
    linear = sphray.render("three", mode="path", width=48, height=27, spp=3, linear=True)
    assert linear.dtype == np.float32 and linear.shape == (27, 48, 3)
    image = sphray.render("three", mode="path", width=48, height=27, spp=3)
    # Gamma 2, then the book's bytes.
    np.testing.assert_array_equal(to_byte(np.sqrt(np.maximum(linear, 0))), image)
    with pytest.raises(ValueError, match="linear"):
        sphray.render("three", mode="normals", linear=True)


def test_render_refuses_bad_colors_and_cameras(rng):
    centers, radii, colors = own_spheres(rng, 5)
    with pytest.raises(ValueError, match=r"colors.*\(5, 3\)"):
        sphray.render((centers, radii), colors=colors[:4])
    with pytest.raises(ValueError, match=r"colors\[2\]"):
        bad = colors.copy()
        bad[2, 1] = 1.5
        sphray.render((centers, radii), colors=bad)
    with pytest.raises(ValueError, match="colors"):
        sphray.render("three", colors=colors)
    with pytest.raises(ValueError, match="camera"):
        sphray.render("three", camera={"lookfrom": [0, 0, 0], "lookat": [0, 0, 0]})


def test_render_time_limit_reaches_the_path_tracer():
    with pytest.raises(ValueError, match="time limit"):
        sphray.render("three", mode="path", time_limit=-1.0)
    # 60,000 samples a pixel would take minutes; the limit stops starting samples after 0.3 s.
    start = time.monotonic()
    image = sphray.render("three", mode="path", width=64, height=36, spp=60000, time_limit=0.3)
    assert image.shape == (36, 64, 3)
    assert time.monotonic() - start < 30.0
