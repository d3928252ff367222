"""Fast, exact ray/sphere intersection on numpy arrays (type stubs for the extension)."""

from os import PathLike
from typing import Any, Dict, Literal, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
NO_HIT: int
"""The id of a miss: 2**32 - 1."""

_ArrayLike = npt.ArrayLike
_Bound = Union[float, npt.ArrayLike]
# A Scene's real-valued results: float32 for a scene of precision "float", float64 for "double".
_Real = npt.NDArray[Union[np.float32, np.float64]]

class Hits(NamedTuple):
    """Scene.intersect()'s closest hit of each ray. Unpacks as t, ids = ..."""

    t: _Real
    ids: npt.NDArray[np.uint32]

class Surface(NamedTuple):
    """Scene.surface(), where each ray meets its hit."""

    points: _Real
    normals: _Real
    front_face: npt.NDArray[np.bool_]

class Crossings(NamedTuple):
    """Scene.intersect_all(), every crossing of each ray."""

    t: _Real
    ids: npt.NDArray[np.uint32]
    exits: npt.NDArray[np.bool_]
    counts: npt.NDArray[np.uint64]

class NearestCrossings(NamedTuple):
    """Scene.intersect_nearest(), the nearest k crossings of each ray alone."""

    t: _Real
    ids: npt.NDArray[np.uint32]
    exits: npt.NDArray[np.bool_]
    counts: npt.NDArray[np.uint64]

class Nearest(NamedTuple):
    """Scene.nearest(), the sphere nearest each point."""

    ids: npt.NDArray[np.uint32]
    distances: _Real
    surface_points: _Real

class Overlaps(NamedTuple):
    """Scene.overlaps(): ball i's spheres are ids[offsets[i]:offsets[i + 1]]."""

    offsets: npt.NDArray[np.int64]
    ids: npt.NDArray[np.uint32]

class Rays(NamedTuple):
    """pinhole_rays(), one camera ray through each pixel."""

    origins: npt.NDArray[np.float32]
    directions: npt.NDArray[np.float32]

class Particles(NamedTuple):
    """load(), the particles of a file."""

    centers: npt.NDArray[np.float32]
    radii: npt.NDArray[np.float32]
    colors: Optional[npt.NDArray[np.float32]]

class Scene:
    """Spheres to trace rays against: Scene(centers (N, 3), radii (N,), accel="auto"), in float
    or double (precision: double when centers or radii are float64)."""

    def __init__(
        self,
        centers: _ArrayLike,
        radii: _ArrayLike,
        accel: Literal["auto", "bvh", "brute"] = "auto",
        masks: Optional[_ArrayLike] = None,
        precision: Optional[Literal["float", "double"]] = None,
    ) -> None: ...
    def intersect(
        self,
        origins: _ArrayLike,
        directions: _ArrayLike,
        tmin: _Bound = 0.0,
        tmax: _Bound = float("inf"),
        mask: Union[int, npt.ArrayLike] = 0xFFFFFFFF,
    ) -> Hits:
        """Closest hit of each ray: Hits(t, ids); a miss has ids == NO_HIT and t == tmax."""
    def occluded(
        self,
        origins: _ArrayLike,
        directions: _ArrayLike,
        tmin: _Bound = 0.0,
        tmax: _Bound = float("inf"),
        mask: Union[int, npt.ArrayLike] = 0xFFFFFFFF,
    ) -> npt.NDArray[np.bool_]:
        """Whether each ray hits any sphere in (tmin, tmax)."""
    def surface(
        self,
        origins: _ArrayLike,
        directions: _ArrayLike,
        t: _ArrayLike,
        ids: _ArrayLike,
    ) -> Surface:
        """Surface(points, outward unit normals, front_face) where each ray meets its hit."""
    def spawn(
        self,
        origins: _ArrayLike,
        directions: _ArrayLike,
        t: _ArrayLike,
        ids: _ArrayLike,
        new_directions: _ArrayLike,
    ) -> _Real:
        """Origins of rays leaving each hit towards new_directions (sphray::spawn)."""
    def intersect_all(
        self,
        origins: _ArrayLike,
        directions: _ArrayLike,
        max_hits: int = 16,
        tmin: _Bound = 0.0,
        tmax: _Bound = float("inf"),
        mask: Union[int, npt.ArrayLike] = 0xFFFFFFFF,
    ) -> Crossings:
        """Crossings(t, ids, exits, counts): every crossing of each ray; max_hits of them sorted."""
    def intersect_nearest(
        self,
        origins: _ArrayLike,
        directions: _ArrayLike,
        k: int = 16,
        tmin: _Bound = 0.0,
        tmax: _Bound = float("inf"),
        mask: Union[int, npt.ArrayLike] = 0xFFFFFFFF,
    ) -> NearestCrossings:
        """NearestCrossings(t, ids, exits, counts): intersect_all's first k; counts written."""
    def count_hits(
        self,
        origins: _ArrayLike,
        directions: _ArrayLike,
        tmin: _Bound = 0.0,
        tmax: _Bound = float("inf"),
        mask: Union[int, npt.ArrayLike] = 0xFFFFFFFF,
    ) -> npt.NDArray[np.uint64]:
        """The number of crossings of each ray in (tmin, tmax)."""
    def nearest(self, points: _ArrayLike, max_distance: float = float("inf")) -> Nearest:
        """Nearest(ids, distances, surface_points) of the sphere nearest each point."""
    def inside(self, points: _ArrayLike) -> npt.NDArray[np.bool_]:
        """Whether each point lies inside any sphere."""
    def overlapping(self, centre: _ArrayLike, radius: float) -> npt.NDArray[np.uint32]:
        """The ids of the spheres overlapping a ball, ascending."""
    def overlaps(self, centers: _ArrayLike, radii: _ArrayLike) -> Overlaps:
        """Overlaps(offsets, ids): ball i's spheres are ids[offsets[i]:offsets[i + 1]]."""
    def overlapping_pairs(self) -> npt.NDArray[np.uint32]:
        """(P, 2): the pairs (i, j), i < j, of the scene's spheres where j overlaps ball i."""
    def refit(
        self, centers: _ArrayLike, radii: _ArrayLike, masks: Optional[_ArrayLike] = None
    ) -> None:
        """New centres and radii for the same spheres (same N); masks=None keeps their masks."""
    def __len__(self) -> int: ...
    @property
    def uses_bvh(self) -> bool: ...
    @property
    def precision(self) -> Literal["float", "double"]:
        """The kernel the queries run: float32 arrays in and out, or float64."""
    @property
    def centers(self) -> _Real:
        """A read-only view of the (N, 3) array the scene reads: yours if it was not copied."""
    @property
    def radii(self) -> _Real:
        """A read-only view of the (N,) array the scene reads: yours if it was not copied."""

def load(path: Union[str, bytes, "PathLike[str]"], radius: Optional[float] = None) -> Particles:
    """Particles(centers (N, 3), radii (N,), colors (N, 3) or None) of a .sphp, .xyz, .csv, .ply
    or .pdb file; a .sphp file's arrays are views of a numpy.memmap of it."""

def pinhole_rays(
    eye: _ArrayLike,
    target: _ArrayLike,
    up: _ArrayLike,
    vfov_deg: float,
    width: int,
    height: int,
) -> Rays:
    """Rays(origins, unit directions), each (height, width, 3) float32, row 0 at the top."""

def render(
    scene: Union[str, "PathLike[str]", Scene, Tuple[_ArrayLike, _ArrayLike]] = "rtiow-final",
    mode: Literal["normals", "flat", "depth", "id", "shaded", "path"] = "normals",
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: int = 4,
    seed: int = 0,
    threads: int = 0,
    accel: Literal["auto", "bvh", "brute"] = "auto",
    max_depth: int = 50,
    time_limit: float = 0.0,
    camera: Optional[Dict[str, Any]] = None,
    colors: Optional[_ArrayLike] = None,
    materials: Union[None, Dict[str, Any], Sequence[Dict[str, Any]]] = None,
    linear: bool = False,
) -> npt.NDArray[Any]:
    """A preset, a JSON scene or your own spheres rendered: uint8 (height, width, 3), or
    float32 linear radiance with linear=True (path mode)."""

def active_isa() -> str:
    """The instruction set in use: 'scalar', 'sse4.2', 'avx2', 'avx512' or 'neon'."""

def bvh_isa(sphere_count: Optional[int] = None) -> str:
    """The instruction set the tree of a Scene of sphere_count spheres (None: many) is laid
    out for and walked with (SPHRAY_ISA, or the fastest for trees of that size on this CPU)."""

def supported_isas() -> list[str]:
    """The instruction sets this build has and this machine runs, best first."""
