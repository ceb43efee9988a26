"""One simulated sweep: two echo clouds plus ground truth, in the scanner (`laser`) frame.

`simulate_sweep(scene, scanner, seed)` traces every beam (physics.py), adds
Gaussian range noise, applies the range gate, and keeps per beam the nearest
return as echo 1 and the farthest as echo 2 (a beam with a single return has
echo 2 = echo 1, the same point; a beam without return has NaN in both). A
real multi-echo scanner reports the first and the last echo, so a third
return in between (e.g. mirror surface, glass surface and phantom) is lost.

All arrays are numpy structured arrays whose field names are the PointCloud2
field names of the contract (see ros_io.py):

* echo1, echo2 (N = rows * cols, row-major): x y z intensity (float32).
* ground_truth (2 N: all echo-1 points in beam order, then all echo-2 points):
  x y z (measured), true_x true_y true_z (where the beam really hit; for a
  phantom the real surface point), label (uint8 Label), object_id (int32,
  index into `objects`, -1 none), echo (1/2), beam (uint32).
* objects: one dict per mirror/glass rectangle, in the laser frame: id, type
  (1 mirror, 2 glass), name, corners (4, 3), width, height (width along the
  more horizontal side; the longer side if the rectangle is horizontal),
  plane (a, b, c, d) with the unit normal pointing at the sensor, centre.

Noise is drawn from numpy's default_rng(seed) in a fixed order, so a sweep
is a deterministic function of (scene, scanner, pose, seed).
"""
from dataclasses import dataclass, field
from typing import List

import numpy as np

from . import scene as scenes
from .labels import Label
from .physics import PhysicsParams, SceneArrays, trace
from .scanner import RotatingHokuyo, world_rays

ECHO_DTYPE = np.dtype([('x', '<f4'), ('y', '<f4'), ('z', '<f4'), ('intensity', '<f4')])
GROUND_TRUTH_DTYPE = np.dtype([
    ('x', '<f4'), ('y', '<f4'), ('z', '<f4'),
    ('true_x', '<f4'), ('true_y', '<f4'), ('true_z', '<f4'),
    ('label', 'u1'), ('object_id', '<i4'), ('echo', 'u1'), ('beam', '<u4'),
])

INTENSITY_NOISE = 0.05  # relative sigma of the intensity


@dataclass
class Sweep:
    scene_name: str
    model: str
    rows: int
    cols: int
    echo1: np.ndarray
    echo2: np.ndarray
    ground_truth: np.ndarray
    objects: List[dict]
    pose: scenes.Pose
    seed: int
    frame_id: str = 'laser'
    info: dict = field(default_factory=dict)

    @property
    def num_beams(self):
        return self.rows * self.cols

    def counts(self):
        """Point counts for reports: physical returns per ground-truth label and per object."""
        return sweep_counts(self)


def xyz(array):
    """(n, 3) float array of the x y z fields of a structured array."""
    return np.stack([array['x'], array['y'], array['z']], axis=-1).astype(float)


def true_xyz(gt):
    return np.stack([gt['true_x'], gt['true_y'], gt['true_z']], axis=-1).astype(float)


def rectangle_to_object(rect, rotation, position):
    """Ground-truth object dict of a mirror/glass rectangle, in the laser frame."""
    to_laser = lambda p: (np.asarray(p, float) - position) @ rotation
    corners = to_laser(rect.corners())
    u = np.asarray(rect.axis_u, float) @ rotation
    v = np.asarray(rect.axis_v, float) @ rotation
    # Width along the more horizontal side; a horizontal rectangle: the longer side.
    if abs(abs(u[2]) - abs(v[2])) < 1e-6:
        width, height = max(rect.width, rect.height), min(rect.width, rect.height)
    elif abs(u[2]) < abs(v[2]):
        width, height = rect.width, rect.height
    else:
        width, height = rect.height, rect.width
    normal = np.cross(u, v)
    centre = corners.mean(axis=0)
    d = -float(normal @ centre)
    if d < 0:  # make the normal point at the sensor (origin): a*0 + d > 0
        normal, d = -normal, -d
    return {
        'id': int(rect.object_id),
        'type': scenes.OBJECT_TYPE_MIRROR if rect.material.kind == scenes.MIRROR else scenes.OBJECT_TYPE_GLASS,
        'name': rect.name,
        'corners': corners,
        'width': float(width),
        'height': float(height),
        'plane': np.array([normal[0], normal[1], normal[2], d]),
        'centre': centre,
    }


class SweepSimulator:
    """Simulates sweeps of one scene with one scanner; caches the noise-free trace per pose."""

    def __init__(self, scene, scanner=None, physics=None):
        self.scene = scenes.get(scene) if isinstance(scene, str) else scene
        self.scanner = scanner if scanner is not None else RotatingHokuyo()
        self.physics = physics if physics is not None else PhysicsParams()
        self._arrays = SceneArrays(self.scene)
        self._directions = self.scanner.directions()
        self._cache_key = None
        self._cache = None

    def _returns(self, pose):
        key = (tuple(pose.position), tuple(pose.rpy))
        if key != self._cache_key:
            origin, directions = world_rays(self.scanner, pose)
            r = trace(self._arrays, origin, directions, self.scanner.max_range + 5 * self.scanner.range_noise,
                      self.physics)
            order = np.lexsort((r.path_length, r.beam))   # fixed order for the noise draws
            self._cache = type(r)(*(getattr(r, f)[order] for f in
                                    ('beam', 'path_length', 'true_world', 'intensity', 'label', 'object_id')))
            self._cache_key = key
        return self._cache

    def sweep(self, seed=0, pose=None, noise=None):
        """One Sweep; pose defaults to the scene's scanner pose, noise to the scanner's range_noise."""
        pose = pose if pose is not None else self.scene.scanner_pose
        sigma = self.scanner.range_noise if noise is None else noise
        r = self._returns(pose)
        rng = np.random.default_rng(seed)
        measured = r.path_length + (rng.normal(0.0, sigma, len(r.beam)) if sigma > 0 else 0.0)
        intensity = r.intensity * np.clip(1 + INTENSITY_NOISE * rng.normal(size=len(r.beam)), 0.0, None)
        gate = (measured >= self.scanner.min_range) & (measured <= self.scanner.max_range)
        beam, measured, intensity = r.beam[gate], measured[gate], intensity[gate]
        true_world, label, object_id = r.true_world[gate], r.label[gate], r.object_id[gate]

        order = np.lexsort((measured, beam))
        beam_sorted = beam[order]
        starts = np.flatnonzero(np.r_[True, beam_sorted[1:] != beam_sorted[:-1]][:len(beam_sorted)])
        ends = np.r_[starts[1:], len(beam_sorted)].astype(np.int64)[:len(starts)] - 1
        nearest, farthest = order[starts], order[ends]

        n = self.scanner.rows * self.scanner.cols
        rotation, position = pose.rotation(), np.asarray(pose.position, float)
        directions = self._directions
        gt = np.zeros(2 * n, GROUND_TRUTH_DTYPE)
        echoes = []
        for e, pick in ((1, nearest), (2, farthest)):
            b = beam[pick]
            pts = np.full((n, 3), np.nan)
            pts[b] = directions[b] * measured[pick, None]
            tru = np.full((n, 3), np.nan)
            tru[b] = (true_world[pick] - position) @ rotation
            inten = np.full(n, np.nan)
            inten[b] = intensity[pick]
            lab = np.full(n, Label.NAN_POINT, np.uint8)
            lab[b] = label[pick]
            oid = np.full(n, -1, np.int32)
            oid[b] = object_id[pick]
            cloud = np.zeros(n, ECHO_DTYPE)
            cloud['x'], cloud['y'], cloud['z'], cloud['intensity'] = pts[:, 0], pts[:, 1], pts[:, 2], inten
            echoes.append(cloud)
            g = gt[(e - 1) * n:e * n]
            g['x'], g['y'], g['z'] = pts[:, 0], pts[:, 1], pts[:, 2]
            g['true_x'], g['true_y'], g['true_z'] = tru[:, 0], tru[:, 1], tru[:, 2]
            g['label'], g['object_id'], g['echo'], g['beam'] = lab, oid, e, np.arange(n)

        objects = [rectangle_to_object(rect, rotation, position) for rect in self.scene.objects()]
        return Sweep(self.scene.name, self.scanner.name, self.scanner.rows, self.scanner.cols,
                     echoes[0], echoes[1], gt, objects, pose, seed,
                     info={'noise': sigma, 'returns_traced': int(len(r.beam))})


def simulate_sweep(scene, scanner=None, seed=0, pose=None, noise=None, physics=None):
    """One sweep of `scene` (a Scene or a registered name) seen by `scanner` (default RotatingHokuyo())."""
    return SweepSimulator(scene, scanner, physics).sweep(seed=seed, pose=pose, noise=noise)


def physical_return_mask(gt):
    """Mask over the 2N ground-truth entries: one entry per physical return (and one per empty beam).

    Echo-1 entries always count; an echo-2 entry counts only when the beam has
    two distinct returns (a single return is duplicated as echo 2).
    """
    n = len(gt) // 2
    p1, p2 = xyz(gt[:n]), xyz(gt[n:])
    distinct = np.isfinite(p2).all(axis=1) & ~np.all(p1 == p2, axis=1)
    return np.r_[np.ones(n, bool), distinct]


def ground_truth_objects(sweep):
    """The sweep's objects with the ground-truth point counts filled in (surface_points,
    behind_points, mean_surface_intensity), as the evaluator compares them (also ros_io's)."""
    gt = sweep.ground_truth
    real = physical_return_mask(gt)
    intensity = np.r_[sweep.echo1['intensity'], sweep.echo2['intensity']]
    out = []
    for o in sweep.objects:
        mine = (gt['object_id'] == o['id']) & real
        surface = mine & np.isin(gt['label'], [Label.REFLECTIVE_SURFACE, Label.TRANSPARENT_SURFACE])
        behind = mine & np.isin(gt['label'], [Label.BEHIND_REFLECTIVE, Label.BEHIND_TRANSPARENT])
        d = dict(o)
        d['surface_points'] = int(surface.sum())
        d['behind_points'] = int(behind.sum())
        d['mean_surface_intensity'] = float(intensity[surface].mean()) if surface.any() else float('nan')
        out.append(d)
    return out


def sweep_counts(sweep):
    """Counts per label and per object (physical returns), for reports and tests."""
    gt = sweep.ground_truth
    real = physical_return_mask(gt)
    n = sweep.num_beams
    two = real[n:]
    counts = {
        'beams': int(n),
        'beams_with_return': int(np.isfinite(sweep.echo1['x']).sum()),
        'beams_with_two_returns': int(two.sum()),
        'labels': {Label(l).name.lower(): int(((gt['label'] == l) & real).sum())
                   for l in np.unique(gt['label'][real])},
        'objects': [],
    }
    for obj in sweep.objects:
        of = (gt['object_id'] == obj['id']) & real
        lab = gt['label']
        counts['objects'].append({
            'id': obj['id'], 'name': obj['name'], 'type': obj['type'],
            'surface': int((of & np.isin(lab, [Label.REFLECTIVE_SURFACE, Label.TRANSPARENT_SURFACE])).sum()),
            'surface_double_echo': int((of[:n] & two & np.isin(lab[:n], [Label.REFLECTIVE_SURFACE,
                                                                        Label.TRANSPARENT_SURFACE])).sum()),
            'phantoms': int((of & (lab == Label.BEHIND_REFLECTIVE)).sum()),
            'behind_glass': int((of & (lab == Label.BEHIND_TRANSPARENT)).sum()),
        })
    return counts
