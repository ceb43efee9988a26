"""Scanner models: beam directions of one sweep in the scanner (`laser`) frame, ray origins in the
world, and what the sensor makes of a beam's returns; named presets of the four sensor families
of SENSORS.md.

Both grid models return the beam grid row-major: `rows` x `cols`, beam index
= row * cols + col, which is the point index of the organised echo clouds.

RotatingHokuyo (the paper's sensor): a Hokuyo UTM-30LX-EW whose 270 deg scan
fan lies in a vertical plane through the rotation (z) axis and is centred on
the zenith. One sweep is half a rotation (180 deg about z) in `scans` steps;
each scan has `beams` (1080) beams 0.25 deg apart. Because the fan reaches
135 deg from the zenith on both sides of the axis, half a rotation covers the
whole sphere except a cone of 45 deg half-angle straight down (the mount and
the robot under the scanner), like the real unit. A 270 deg fan turning half
a turn cannot do better: each azimuth is seen by one side of the fan only.
Rows = scans (rotation angle 180 * k / scans), cols = beams (angle from the
zenith -135 .. +135 deg; negative angles look towards azimuth + 180 deg).
By default every scan is taken at one rotation angle (the unit stops for it).
With `continuous` the unit keeps turning while the scanner sweeps its fan: beam
i of scan k is taken `i * time_increment` after the scan starts and its plane
has turned on by that fraction of the step between scans (what a real unit
does; the input mode multi_echo_scan undoes it with tf). `rotation_offset`
turns the whole sweep about z (the second half rotation of a unit starts at
180 deg: the same planes, with each fan flipped).

BeamList: any given beam directions (tests and hand-made geometry).

DualReturnLidar: a spinning multi-beam lidar, `rings` beams spread evenly over
a vertical field of view, `azimuth_steps` firings per revolution. Rows = rings
(ring 0 lowest), cols = azimuth steps (0 deg = +x, counter-clockwise).

What the sensor makes of a beam (realistic physics only; PhysicsParams.ideal()
ignores all of it and keeps every distinct return, the nearest and farthest as
the two echoes, with a constant noise `range_noise`):

* `beam_divergence_deg`: the full angle of the beam's footprint. Where it may
  straddle a depth edge the simulator traces several rays across it; returns
  closer together than `echo_separation` merge into one echo at their
  intensity-weighted range (a mixed pixel between the two surfaces), returns
  farther apart are separate echoes (a double echo on ordinary geometry).
* `echo_separation` [m]: the smallest distance between two echoes the sensor
  resolves; a second return is stored only where it differs from the first by
  at least this much.
* `return_mode`: which two echoes are reported: 'first_last' (the rotating
  Hokuyo: the first and last of at most `max_echoes`), 'last_strongest' (the
  last and the strongest; if the last is the strongest, the second strongest,
  as Hesai and Velodyne drivers do), 'strongest_two' (the strongest and the
  second strongest, Ouster).
* detection: an echo is seen when its intensity reaches that of a Lambertian
  target of `detection_reflectivity` at `detection_range` (the data sheet's
  range figure); intensities saturate at `saturation` times a white wall at
  1 m.
* range noise: Gaussian, sigma `range_noise`, `range_noise_far` beyond
  `range_noise_far_from` (a data sheet's "+-3 cm" read as 3 sigma).

Values from the makers' public data sheets where SENSORS.md gives them; beam
divergences and echo separations other than the 64-ring lidar's 0.9 m are not
in SENSORS.md and are assumed (of the order such sensors have), see PRESETS.
"""
import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class RotatingHokuyo:
    scans: int = 400            # r, scans per half rotation
    beams: int = 1080           # N_beta, beams per scan
    fan_deg: float = 270.0
    min_range: float = 0.1
    max_range: float = 30.0
    range_noise: float = 0.01   # m, sigma of the Gaussian range noise
    scan_time: float = 0.025    # s per scan (40 Hz) and per turn of the scanner's mirror
    rotation_offset: float = 0.0  # rad, rotation angle of the first scan
    continuous: bool = False    # the unit turns while a scan is taken (see the module doc)
    beam_divergence_deg: float = 0.25
    echo_separation: float = 0.3
    return_mode: str = 'first_last'
    max_echoes: int = 3        # 0: no limit
    detection_reflectivity: float = 0.9
    detection_range: float = 40.0
    saturation: float = 3.0
    range_noise_far: float = 0.017
    range_noise_far_from: float = 10.0
    family: str = 'hokuyo_utm30lx_ew'

    name = 'hokuyo'
    wraps_columns = False

    @property
    def time_increment(self):
        """Seconds between two beams of a scan: the mirror turns 360 deg per scan_time (1440 steps of 0.25 deg)."""
        return self.scan_time * (self.fan_deg / self.beams) / 360.0

    @property
    def rotation_step(self):
        """Rotation of the unit between two scans (rad)."""
        return np.pi / self.scans

    @property
    def rows(self):
        return self.scans

    @property
    def cols(self):
        return self.beams

    def grid_steps(self):
        """Angles (rad) between neighbouring rows and between neighbouring columns of the grid (at most)."""
        return self.rotation_step, math.radians(self.fan_deg) / self.beams

    def scan_angles(self):
        """Rotation angle (rad) of the scan plane about z at the start of each row."""
        return self.rotation_offset + np.arange(self.scans) * self.rotation_step

    def beam_rotation(self):
        """How far the plane has turned (rad) when each beam of a scan is taken (0 unless continuous)."""
        if not self.continuous:
            return np.zeros(self.beams)
        return np.arange(self.beams) * self.time_increment / self.scan_time * self.rotation_step

    def beam_angles(self):
        """Angle (rad) of each beam from the zenith within the scan plane (0.25 deg steps, centred)."""
        step = np.radians(self.fan_deg) / self.beams
        return -np.radians(self.fan_deg) / 2 + step * (np.arange(self.beams) + 0.5)

    def directions(self):
        """Unit beam directions in the laser frame, (rows * cols, 3) row-major."""
        alpha = self.scan_angles()[:, None] + self.beam_rotation()[None, :]
        beta = self.beam_angles()[None, :]
        s = np.sin(beta)
        d = np.stack([s * np.cos(alpha), s * np.sin(alpha), np.cos(beta) * np.ones_like(alpha)], axis=-1)
        return d.reshape(-1, 3)


@dataclass(frozen=True)
class DualReturnLidar:
    rings: int = 128
    azimuth_steps: int = 2048
    vertical_fov_deg: tuple = (-22.5, 22.5)
    min_range: float = 0.3
    max_range: float = 100.0
    range_noise: float = 0.01
    beam_divergence_deg: float = 0.18
    echo_separation: float = 0.9
    return_mode: str = 'strongest_two'
    max_echoes: int = 0        # 0: no limit
    detection_reflectivity: float = 0.8
    detection_range: float = 50.0
    saturation: float = 3.0
    range_noise_far: float = 0.017
    range_noise_far_from: float = 20.0
    family: str = ''

    name = 'dual_return'
    wraps_columns = True

    def grid_steps(self):
        lo, hi = np.radians(self.vertical_fov_deg)
        return (hi - lo) / max(self.rings - 1, 1), 2 * np.pi / self.azimuth_steps

    @property
    def rows(self):
        return self.rings

    @property
    def cols(self):
        return self.azimuth_steps

    def elevations(self):
        lo, hi = np.radians(self.vertical_fov_deg)
        return np.linspace(lo, hi, self.rings) if self.rings > 1 else np.array([(lo + hi) / 2])

    def azimuths(self):
        return np.arange(self.azimuth_steps) * (2 * np.pi / self.azimuth_steps)

    def directions(self):
        el = self.elevations()[:, None]
        az = self.azimuths()[None, :]
        d = np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el) * np.ones_like(az)], axis=-1)
        return d.reshape(-1, 3)


class BeamList:
    """Arbitrary beams (tests, hand-made geometry): unit directions (rows * cols, 3) in the laser frame.

    Thin beams (no footprint) unless `beam_divergence_deg` and the grid's angular `steps` (rad
    between rows, between columns) are given; the other sensor properties as the module doc says.
    """

    name = 'beam_list'
    wraps_columns = False

    def __init__(self, directions, rows=1, min_range=0.1, max_range=30.0, range_noise=0.0, beam_divergence_deg=0.0,
                 steps=None, echo_separation=0.0, return_mode='first_last', max_echoes=0,
                 detection_reflectivity=0.05, detection_range=100.0, saturation=float('inf')):
        d = np.asarray(directions, float).reshape(-1, 3)
        self._directions = d / np.linalg.norm(d, axis=1, keepdims=True)
        if len(d) % rows:
            raise ValueError('%d beams do not fill %d rows' % (len(d), rows))
        self.rows, self.cols = rows, len(d) // rows
        self.min_range, self.max_range, self.range_noise = min_range, max_range, range_noise
        self.range_noise_far, self.range_noise_far_from = range_noise, float('inf')
        self.beam_divergence_deg, self._steps = beam_divergence_deg, steps
        self.echo_separation, self.return_mode, self.max_echoes = echo_separation, return_mode, max_echoes
        self.detection_reflectivity, self.detection_range = detection_reflectivity, detection_range
        self.saturation = saturation
        self.family = ''

    def grid_steps(self):
        if self._steps is None:
            raise ValueError('a BeamList with a beam footprint needs the angular steps of its grid (steps=)')
        return self._steps

    def directions(self):
        return self._directions


RETURN_MODES = ('first_last', 'last_strongest', 'strongest_two')


def detection_threshold(scanner, gain):
    """Intensity of the faintest echo the scanner sees (realistic physics)."""
    return gain * scanner.detection_reflectivity / scanner.detection_range ** 2


def range_sigma(scanner, ranges):
    """Range noise sigma [m] per range (realistic physics)."""
    ranges = np.asarray(ranges, float)
    return np.where(ranges > scanner.range_noise_far_from, scanner.range_noise_far, scanner.range_noise)


# The four sensor families of SENSORS.md. Divergences and echo separations except the 64-ring
# lidar's are assumptions (not in SENSORS.md); the rest is the data sheets'.
PRESETS = {
    # 1080 beams over 270 deg, 0.1-30 m, +-3 cm (+-5 cm beyond 10 m), up to 3 echoes all reported;
    # `scans` per half rotation (100-1000) given by the caller.
    'hokuyo_utm30lx_ew': (RotatingHokuyo, dict(
        scans=400, min_range=0.1, max_range=30.0, range_noise=0.01, range_noise_far=0.017,
        range_noise_far_from=10.0, beam_divergence_deg=0.25, echo_separation=0.3, return_mode='first_last',
        max_echoes=3, detection_reflectivity=0.9, detection_range=40.0)),
    # 64 rings over -52..+52 deg (spread evenly here; the real unit's spacing is not even, ~1.45 deg
    # in the middle), 600 columns (0.6 deg), 0.1-60 m, 20 m at 10 % reflectivity, +-3 cm; dual
    # return (last and strongest), the second stored only at least ~0.9 m from the first. The
    # divergence (0.5 deg) is assumed, chosen so that double echoes on ordinary geometry come nearer
    # the fifth of all second returns that SENSORS.md reports from real frames (9 % over the random
    # scenes, which are less cluttered than real rooms; 0.3 deg gave 6 %).
    'hesai_qt64': (DualReturnLidar, dict(
        rings=64, azimuth_steps=600, vertical_fov_deg=(-52.0, 52.0), min_range=0.1, max_range=60.0,
        range_noise=0.01, range_noise_far=0.01, range_noise_far_from=60.0, beam_divergence_deg=0.5,
        echo_separation=0.9, return_mode='last_strongest', detection_reflectivity=0.1, detection_range=20.0)),
    # 128 rings over +-45 deg, 2048 columns (0.176 deg), 0.3-50 m; dual return (strongest, second strongest).
    'ouster_os0_128': (DualReturnLidar, dict(
        rings=128, azimuth_steps=2048, vertical_fov_deg=(-45.0, 45.0), min_range=0.3, max_range=50.0,
        range_noise=0.01, range_noise_far=0.017, range_noise_far_from=20.0, beam_divergence_deg=0.18,
        echo_separation=0.9, return_mode='strongest_two', detection_reflectivity=0.8, detection_range=50.0)),
    # 32 rings from -30.67 to +10.67 deg (1.33 deg apart), ~0.16 deg at 10 Hz (2250 columns), up to
    # 100 m, +-2 cm; dual return (strongest and last).
    'velodyne_hdl32e': (DualReturnLidar, dict(
        rings=32, azimuth_steps=2250, vertical_fov_deg=(-30.67, 10.67), min_range=1.0, max_range=100.0,
        range_noise=0.007, range_noise_far=0.007, range_noise_far_from=100.0, beam_divergence_deg=0.17,
        echo_separation=0.9, return_mode='last_strongest', detection_reflectivity=0.8, detection_range=100.0)),
}
FAMILIES = tuple(PRESETS)


def preset(name, **overrides):
    """A sensor family of SENSORS.md by name (FAMILIES), e.g. preset('hesai_qt64') or
    preset('hokuyo_utm30lx_ew', scans=1000); keyword arguments override single properties."""
    try:
        cls, values = PRESETS[name]
    except KeyError:
        raise KeyError('unknown sensor preset %r; known: %s' % (name, ', '.join(FAMILIES))) from None
    values = dict(values, family=name)
    values.update(overrides)
    return cls(**values)


def make_scanner(model='hokuyo', scans=400, noise=0.01, **kwargs):
    """Scanner by name: 'hokuyo' (scans = r) or 'dual_return' (scans = rings unless rings is given)."""
    if model == 'hokuyo':
        return RotatingHokuyo(scans=scans, range_noise=noise, **kwargs)
    if model == 'dual_return':
        kwargs.setdefault('rings', scans)
        return DualReturnLidar(range_noise=noise, **kwargs)
    raise ValueError('unknown scanner model %r (hokuyo, dual_return)' % model)


def world_rays(scanner, pose):
    """Ray origins (3,) and unit directions (N, 3) in the world for a scanner at `pose` (scene.Pose)."""
    rotation = pose.rotation()
    return np.asarray(pose.position, float), scanner.directions() @ rotation.T
