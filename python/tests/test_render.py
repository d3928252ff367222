"""pinhole_rays and render against numpy references of the book's camera and shading."""

import numpy as np

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
    # flat mode: the sphere red (255, 0, 0) in the middle, sky at the corners
    assert tuple(from_path[9, 16]) == (255, 0, 0) and tuple(from_path[0, 0]) != (255, 0, 0)
