"""A small built-in two-echo sweep for the demo and the smoke tests.

The scanner looks at a wall 3 m ahead; a 60 x 40 cm mirror stands 2.5 m ahead
in front of it. Beams that hit the mirror return a weak echo from its surface
and a phantom 4 m farther along the ray (the room behind the scanner seen in
the mirror); the top row of beams has no return at all (NaN, REP-117). A beam
with one return repeats it in echo 2, as the Hokuyo3D driver does.
"""
import numpy as np

WALL_DISTANCE = 3.0
MIRROR_DISTANCE = 2.5
MIRROR_HALF_WIDTH = 0.30
MIRROR_HALF_HEIGHT = 0.20
PHANTOM_EXTRA_RANGE = 4.0


def example_sweep(rows=60, cols=90, noise=0.003, seed=0):
    """Returns (echo1, echo2, is_mirror): two (rows, cols, 3) float32 arrays of points in
    the scanner frame (x ahead, z up) and a (rows, cols) bool array of beams that hit the mirror."""
    rng = np.random.default_rng(seed)
    azimuth = np.radians(np.linspace(-20.0, 20.0, cols))
    elevation = np.radians(np.linspace(-12.0, 12.0, rows))
    el, az = np.meshgrid(elevation, azimuth, indexing='ij')
    directions = np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], axis=-1)

    range_to_mirror_plane = MIRROR_DISTANCE / directions[..., 0]
    on_mirror_plane = directions * range_to_mirror_plane[..., None]
    is_mirror = ((np.abs(on_mirror_plane[..., 1]) <= MIRROR_HALF_WIDTH)
                 & (np.abs(on_mirror_plane[..., 2]) <= MIRROR_HALF_HEIGHT))

    range1 = np.where(is_mirror, range_to_mirror_plane, WALL_DISTANCE / directions[..., 0])
    range2 = np.where(is_mirror, range1 + PHANTOM_EXTRA_RANGE, range1)
    noise1 = rng.normal(0.0, noise, range1.shape)
    noise2 = np.where(is_mirror, rng.normal(0.0, noise, range1.shape), noise1)
    echo1 = directions * (range1 + noise1)[..., None]
    echo2 = directions * (range2 + noise2)[..., None]
    echo1[-1] = np.nan
    echo2[-1] = np.nan
    return echo1.astype(np.float32), echo2.astype(np.float32), is_mirror
