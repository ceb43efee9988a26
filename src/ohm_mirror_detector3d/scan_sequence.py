"""A simulated rotating Hokuyo as its driver and tf would publish it: single multi-echo scans and
the rotating transform, with ground truth for the sweep the pre-filter assembles (numpy only).

Frames:

* `laser` (the scan frame): the Hokuyo's own frame, a LaserScan frame. Beam i of a scan
  looks along (cos a_i, sin a_i, 0) with a_i = angle_min + i * angle_increment; the fan of
  270 deg lies in the laser's x-y plane, laser x (a = 0) pointing along the rotation axis.
* `base_link` (the sweep frame): fixed, z = the rotation axis, the laser's optical centre
  at `laser_offset`. The simulator's scanner frame (its ground truth, echo clouds and
  objects) is base_link shifted to the optical centre, axes parallel.

At rotation angle alpha the rotation base_link <- laser is Rz(alpha) * MOUNT, where MOUNT
takes laser x to base z (the zenith, beam angle 0), laser y to base x and laser z to base y,
so that beam i of scan k is the simulator's beam (k, i) (scanner.RotatingHokuyo: angle
beta_i from the zenith in the plane at azimuth alpha_k). A transform is stamped at the
start of every scan; tf interpolates linearly between them, which reproduces a unit turning
at constant speed (scanner.RotatingHokuyo with continuous=True) beam by beam.

Scan g of the stream (g = sweep * scans + k) starts at start_time + g * scan_time with
alpha = g * pi / scans. Sweep j (scans j * scans ... (j + 1) * scans - 1) is simulated with
rotation_offset j * pi; its ground truth is stamped with the stamp of its last scan, which
is the stamp the pre-filter gives the assembled sweep, and its beam index is
k * beams + i, as in the assembled sweep (rows = scans).
"""
import math
from dataclasses import dataclass, replace

import numpy as np

from .scanner import RotatingHokuyo
from .simulate import SweepSimulator, xyz

# base_link <- laser at alpha = 0, as a quaternion (x, y, z, w): -120 deg about (1, 1, 1).
MOUNT_QUATERNION = (-0.5, -0.5, -0.5, 0.5)


def laser_quaternion(alpha):
    """(x, y, z, w) of Rz(alpha) * MOUNT."""
    c, s = math.cos(alpha / 2), math.sin(alpha / 2)
    x1, y1, z1, w1 = 0.0, 0.0, s, c
    x2, y2, z2, w2 = MOUNT_QUATERNION
    return (w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2)


def quaternion_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


@dataclass(frozen=True)
class ScanGeometry:
    """The LaserScan fields of the simulated UTM-30LX-EW (1080 beams at the simulator's beam angles;
    the real one has 1081, from -135 to +135 deg)."""
    angle_min: float
    angle_max: float
    angle_increment: float
    time_increment: float
    scan_time: float
    range_min: float
    range_max: float

    @classmethod
    def of(cls, scanner):
        beta = scanner.beam_angles()
        return cls(float(beta[0]), float(beta[-1]), float(beta[1] - beta[0]), float(scanner.time_increment),
                   float(scanner.scan_time), float(scanner.min_range), float(scanner.max_range))


@dataclass
class Scan:
    """One scan: per beam a list of 0, 1 or 2 ranges and intensities (first = nearest)."""
    index: int         # g, in the whole stream
    stamp: float       # [s], start of the scan
    alpha: float       # rotation angle at its start [rad]
    ranges: list
    intensities: list


def beam_echoes(sweep):
    """Per beam of a simulated sweep (in the scanner frame): (ranges, intensities) as lists of lists.

    A beam with one return has one echo (the driver does not repeat it), a beam without
    return none.
    """
    p1, p2 = xyz(sweep.echo1), xyz(sweep.echo2)
    r1, r2 = np.linalg.norm(p1, axis=1), np.linalg.norm(p2, axis=1)
    i1, i2 = sweep.echo1['intensity'].astype(float), sweep.echo2['intensity'].astype(float)
    has1 = np.isfinite(r1)
    two = has1 & np.isfinite(r2) & ~np.all(p1 == p2, axis=1)
    ranges, intensities = [], []
    for b in range(len(r1)):
        if two[b]:
            ranges.append([float(r1[b]), float(r2[b])])
            intensities.append([float(i1[b]), float(i2[b])])
        elif has1[b]:
            ranges.append([float(r1[b])])
            intensities.append([float(i1[b])])
        else:
            ranges.append([])
            intensities.append([])
    return ranges, intensities


def shift_sweep(sweep, offset, frame_id):
    """The sweep's ground truth, echo clouds and objects moved from the scanner frame into a parallel frame
    in which the scanner sits at `offset` (the sweep frame)."""
    offset = np.asarray(offset, float)
    if not offset.any():
        return replace(sweep, frame_id=frame_id)
    gt = sweep.ground_truth.copy()
    echo1, echo2 = sweep.echo1.copy(), sweep.echo2.copy()
    for arr, prefixes in ((gt, ('', 'true_')), (echo1, ('',)), (echo2, ('',))):
        for prefix in prefixes:
            for axis, o in zip('xyz', offset):
                arr[prefix + axis] = (arr[prefix + axis].astype(float) + o).astype(np.float32)
    objects = []
    for o in sweep.objects:
        o = dict(o)
        o['corners'] = np.asarray(o['corners'], float) + offset
        o['centre'] = np.asarray(o['centre'], float) + offset
        plane = np.asarray(o['plane'], float).copy()
        plane[3] -= plane[:3] @ offset   # n . (p - offset) + d = 0
        o['plane'] = plane
        objects.append(o)
    return replace(sweep, echo1=echo1, echo2=echo2, ground_truth=gt, objects=objects, frame_id=frame_id,
                   info=dict(sweep.info, laser_offset=offset.tolist()))


class ScanStream:
    """Simulated sweeps of a scene cut into scans, with their stamps and rotation angles.

    `scanner` is a RotatingHokuyo (its rotation_offset is replaced per sweep; continuous by
    default, as a real unit turns). Sweeps use seeds seed, seed + 1, ...

    `path` (a sensor_path.SensorPath): the scanner moves, sweep j taken at path.poses[j] (held for
    the whole half rotation) instead of at `pose`; /tf then also carries fixed_frame <- sweep_frame
    with each scan's transform, the pose of the sweep the scan belongs to (exact at every sweep's
    stamp; the scan that completes the last sweep keeps the last pose).
    """

    def __init__(self, scene, scanner=None, pose=None, seed=0, start_time=1000.0, laser_offset=(0.0, 0.0, 0.0),
                 sweep_frame='base_link', physics=None, path=None, fixed_frame=None):
        scanner = scanner if scanner is not None else RotatingHokuyo(continuous=True)
        self.scanners = [replace(scanner, rotation_offset=0.0), replace(scanner, rotation_offset=math.pi)]
        self.simulators = [SweepSimulator(scene, s, physics) for s in self.scanners]
        self.scanner = self.scanners[0]
        self.geometry = ScanGeometry.of(self.scanner)
        self.pose, self.seed, self.start_time = pose, seed, float(start_time)
        self.laser_offset = tuple(float(v) for v in laser_offset)
        self.sweep_frame = sweep_frame
        self.path, self.fixed_frame = path, fixed_frame

    def path_index(self, g):
        """The pose of the path that scan g is taken at."""
        return min(g // self.scans_per_sweep, len(self.path) - 1)

    @property
    def scans_per_sweep(self):
        return self.scanner.scans

    def scan_stamp(self, g):
        return self.start_time + g * self.scanner.scan_time

    def scan_alpha(self, g):
        return g * self.scanner.rotation_step

    def sweep_stamp(self, j):
        """The stamp of sweep j's last scan: the stamp of the assembled sweep."""
        return self.scan_stamp((j + 1) * self.scans_per_sweep - 1)

    def sweep(self, j):
        """Sweep j in the scanner frame (simulate.Sweep), as its scans see it."""
        pose = self.pose if self.path is None else self.path.poses[self.path_index(j * self.scans_per_sweep)]
        return self.simulators[j % 2].sweep(seed=self.seed + j, pose=pose)

    def ground_truth(self, sweep):
        """The sweep with ground truth and objects in the sweep frame."""
        return shift_sweep(sweep, self.laser_offset, self.sweep_frame)

    def scans(self, j, sweep=None):
        """The scans of sweep j (from its simulated sweep, simulated when not given)."""
        sweep = sweep if sweep is not None else self.sweep(j)
        ranges, intensities = beam_echoes(sweep)
        n = self.scanner.beams
        out = []
        for k in range(self.scans_per_sweep):
            g = j * self.scans_per_sweep + k
            out.append(Scan(g, self.scan_stamp(g), self.scan_alpha(g), ranges[k * n:(k + 1) * n],
                            intensities[k * n:(k + 1) * n]))
        return out

    def laser_pose(self, g):
        """(translation, quaternion x y z w) of base_link <- laser at the start of scan g."""
        return self.laser_offset, laser_quaternion(self.scan_alpha(g))


def project_scan(scan, geometry, pose_at):
    """Points (n, 2, 3) of a scan's first and last echo in the sweep frame (NaN: none), every beam with the
    pose `pose_at(t)` -> (translation, rotation matrix) at its own time. For tests of the frames."""
    n = len(scan.ranges)
    out = np.full((n, 2, 3), np.nan)
    for i, echoes in enumerate(scan.ranges):
        if not echoes:
            continue
        t, rot = pose_at(scan.stamp + i * geometry.time_increment)
        a = geometry.angle_min + i * geometry.angle_increment
        d = np.array([math.cos(a), math.sin(a), 0.0])
        out[i, 0] = rot @ (d * echoes[0]) + t
        out[i, 1] = rot @ (d * echoes[-1]) + t
    return out
