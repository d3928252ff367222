"""sphray.load(): a particle file's spheres give the same hits as the same arrays given
directly; a .sphp file is a memory map of the file; a bad file raises ValueError with the
reader's FILE:LINE message."""

import struct

import numpy as np
import pytest

import sphray

CENTERS = np.float32([[-1.5, 0, 0], [0.1, 0.25, -0.5], [1.7, -0.3, 0.2]])
RADII = np.float32([0.5, 0.75, 0.6])


def write_sphp(path, centers, radii):
    header = b"SPHRAYP\0" + struct.pack("<IIQQ", 1, 0, len(radii), 0)
    records = np.column_stack([centers, radii]).astype("<f4")
    path.write_bytes(header + records.tobytes())


def fan_of_rays():
    ij = np.stack(np.meshgrid(np.arange(64), np.arange(16), indexing="ij"), -1).reshape(-1, 2)
    origins = np.column_stack([-3 + 0.1 * ij[:, 0], -0.8 + 0.1 * ij[:, 1],
                               np.full(len(ij), 5.0)]).astype(np.float32)
    directions = np.tile(np.float32([0, 0, -1]), (len(ij), 1))
    return origins, directions


def assert_same_hits(particles):
    o, d = fan_of_rays()
    loaded = sphray.Scene(particles.centers, particles.radii).intersect(o, d)
    given = sphray.Scene(CENTERS, RADII).intersect(o, d)
    np.testing.assert_array_equal(loaded.ids, given.ids)
    assert loaded.t.tobytes() == given.t.tobytes()
    assert (given.ids != sphray.NO_HIT).sum() > 10


def test_a_sphp_file_is_a_memory_map_and_gives_the_same_hits(tmp_path):
    write_sphp(tmp_path / "cloud.sphp", CENTERS, RADII)
    p = sphray.load(tmp_path / "cloud.sphp")
    assert type(p) is sphray.Particles and p._fields == ("centers", "radii", "colors")
    assert isinstance(p.centers, np.memmap) and isinstance(p.radii, np.memmap)
    assert p.centers.shape == (3, 3) and p.radii.shape == (3,)
    assert p.centers.dtype == np.float32 and p.radii.dtype == np.float32
    assert not p.centers.flags.writeable
    assert p.colors is None
    np.testing.assert_array_equal(p.centers, CENTERS)
    np.testing.assert_array_equal(p.radii, RADII)
    assert_same_hits(p)


def test_text_files_give_fresh_arrays_colours_and_the_same_hits(tmp_path):
    rows = "\n".join(",".join(f"{v!r}" for v in (*c.tolist(), r.item(), 0.0, 0.5, 1.0))
                     for c, r in zip(CENTERS, RADII))
    (tmp_path / "cloud.csv").write_text("x,y,z,radius,red,green,blue\n" + rows + "\n")
    p = sphray.load(str(tmp_path / "cloud.csv"))
    assert not isinstance(p.centers, np.memmap) and p.centers.flags.c_contiguous
    assert p.colors.shape == (3, 3) and p.colors.dtype == np.float32
    np.testing.assert_array_equal(p.colors[1], [0.0, 0.5, 1.0])
    assert_same_hits(p)
    (tmp_path / "cloud.xyz").write_text("-1.5 0 0\n0.1 0.25 -0.5\n")
    q = sphray.load(tmp_path / "cloud.xyz", radius=0.25)
    np.testing.assert_array_equal(q.radii, [0.25, 0.25])
    assert q.colors is None


def test_bad_files_raise_with_the_file_and_line(tmp_path):
    bad = tmp_path / "bad.xyz"
    bad.write_text("1 2 3 1\n1 2 x 1\n")
    with pytest.raises(ValueError) as e:
        sphray.load(bad)
    assert str(e.value) == f'{bad}:2: expected column 3 (z) to be a number, got "x"'
    (tmp_path / "r.xyz").write_text("1 2 3\n")
    with pytest.raises(ValueError, match=r"r\.xyz:1: expected a radius column"):
        sphray.load(tmp_path / "r.xyz")
    short = tmp_path / "short.sphp"
    write_sphp(short, CENTERS, RADII)
    short.write_bytes(short.read_bytes()[:-4])
    with pytest.raises(ValueError, match=r"short\.sphp: "):
        sphray.load(short)
    with pytest.raises(ValueError, match="No such file"):
        sphray.load(tmp_path / "none.sphp")
    with pytest.raises(ValueError, match=r"expected a particle file ending in"):
        sphray.load(tmp_path / "cloud.txt")


def test_an_empty_sphp_file_gives_empty_arrays(tmp_path):
    write_sphp(tmp_path / "empty.sphp", np.zeros((0, 3), np.float32), np.zeros(0, np.float32))
    p = sphray.load(tmp_path / "empty.sphp")
    assert p.centers.shape == (0, 3) and p.radii.shape == (0,)
