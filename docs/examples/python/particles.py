"""A particle snapshot rendered with sphray: 200,000 particles of a clumpy cloud, shaded by
their normals' facing to a light, with shadows, saved as a PNG with matplotlib.

    python3 particles.py [output.png] [width] [particles]

Every step is a numpy array going through the module: sphray.pinhole_rays makes the camera
rays, Scene.intersect finds the particles, Scene.surface their normals, Scene.occluded the
shadows.
"""

import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sphray  # noqa: E402


def snapshot(n, seed=1):
    """A stand-in for a simulation's output: particles in a few Gaussian clumps, with
    radii that shrink with the local crowding."""
    rng = np.random.default_rng(seed)
    clumps = rng.uniform(-4, 4, size=(12, 3))
    which = rng.integers(0, len(clumps), size=n)
    spread = rng.uniform(0.4, 1.5, size=len(clumps))[which]
    positions = clumps[which] + rng.normal(size=(n, 3)) * spread[:, None]
    radii = 0.02 + 0.03 * spread * rng.uniform(0.5, 1.0, size=n)
    return positions.astype(np.float32), radii.astype(np.float32)


def render(positions, radii, width, height):
    scene = sphray.Scene(positions, radii)
    origins, directions = sphray.pinhole_rays(
        eye=[14, 6, 14], target=[0, 0, 0], up=[0, 1, 0], vfov_deg=35, width=width, height=height)
    t, ids = scene.intersect(origins, directions)
    points, normals, _ = scene.surface(origins, directions, t, ids)
    hit = ids != sphray.NO_HIT

    light = np.array([0.5, 1.0, 0.3], np.float32)
    light /= np.linalg.norm(light)
    facing = np.clip(normals @ light, 0, None)
    # Shadow rays towards the light start where spawn() puts them: just past each hit point's
    # rounding error, so that they never meet the particle they leave (docs/kernel.md).
    towards_light = np.broadcast_to(light, points.shape)
    shadow_origins = scene.spawn(origins, directions, t, ids, towards_light)
    lit = ~scene.occluded(shadow_origins, towards_light)

    # Colour by the particle's distance from the centre of the cloud, like a density map.
    r = np.linalg.norm(positions, axis=1)
    tint = plt.get_cmap("magma")(0.25 + 0.7 * (1 - r / r.max()))[:, :3]
    colour = tint[np.where(hit, ids, 0)] * (0.15 + 0.85 * (facing * lit))[..., None]
    background = np.array([0.02, 0.02, 0.05])
    return np.where(hit[..., None], colour, background)


def main(argv):
    out = argv[1] if len(argv) > 1 else "particles.png"
    width = int(argv[2]) if len(argv) > 2 else 800
    n = int(argv[3]) if len(argv) > 3 else 200_000
    image = render(*snapshot(n), width, width * 9 // 16)
    plt.imsave(out, np.clip(image, 0, 1))
    print(f"{out}: {image.shape[1]}x{image.shape[0]}, {n} particles, {sphray.active_isa()}")
    return image


if __name__ == "__main__":
    main(sys.argv)
