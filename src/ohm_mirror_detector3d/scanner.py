"""Scanner models: beam directions of one sweep in the scanner (`laser`) frame, and ray origins in the world.

Both models return the beam grid row-major: `rows` x `cols`, beam index
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
"""
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

    name = 'hokuyo'

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

    name = 'dual_return'

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
    """Arbitrary beams (tests, hand-made geometry): unit directions (rows * cols, 3) in the laser frame."""

    name = 'beam_list'

    def __init__(self, directions, rows=1, min_range=0.1, max_range=30.0, range_noise=0.0):
        d = np.asarray(directions, float).reshape(-1, 3)
        self._directions = d / np.linalg.norm(d, axis=1, keepdims=True)
        if len(d) % rows:
            raise ValueError('%d beams do not fill %d rows' % (len(d), rows))
        self.rows, self.cols = rows, len(d) // rows
        self.min_range, self.max_range, self.range_noise = min_range, max_range, range_noise

    def directions(self):
        return self._directions


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
