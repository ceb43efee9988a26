"""One simulated sweep: two echo clouds plus ground truth, in the scanner (`laser`) frame.

`simulate_sweep(scene, scanner, seed, physics=...)` traces every beam
(physics.py) and turns the returns into what the sensor reports:

* realistic physics (the default): where a beam's footprint may straddle a
  depth edge (a grid neighbour's centre ray met other surfaces), several rays
  across the footprint (`beam_divergence_deg`) are traced, each with its share
  of the power. A beam's contributions closer together than the scanner's
  `echo_separation` merge into one echo (intensity-weighted range: a mixed
  pixel between the surfaces; label, object and true position those of the
  strongest group of contributions); echoes below the detection threshold are
  not seen. Then Gaussian range noise (`scanner.range_sigma`), intensity noise
  by surface (speckle: 5 % on diffuse surfaces, more on mirrors, glass, metal),
  saturation, the range gate, and the two echoes the sensor reports
  (`return_mode`). A beam whose returns are all closer than `echo_separation`
  has one echo: the second return is stored only where it differs.
* ideal physics (PhysicsParams.ideal(), the simulator before issue 14): one ray
  per beam, Gaussian range noise of constant `range_noise`, every distinct
  return kept, the nearest and the farthest as the two echoes.

Echo 1 is the nearer of the two, echo 2 the farther (a beam with a single
return has echo 2 = echo 1, the same point; a beam without return has NaN in
both). A third return in between (e.g. mirror surface, glass surface and
phantom) is lost.

All arrays are numpy structured arrays whose field names are the PointCloud2
field names of the contract (see ros_io.py):

* echo1, echo2 (N = rows * cols, row-major): x y z intensity (float32).
* ground_truth (2 N: all echo-1 points in beam order, then all echo-2 points):
  x y z (measured), true_x true_y true_z (where the beam really hit; for a
  phantom the real surface point), label (uint8 Label), object_id (int32,
  index into `objects`, -1 none), echo (1/2), beam (uint32), double_echo (1
  when the beam has two distinct echoes in the output).
* objects: one dict per mirror/glass/metal rectangle, in the laser frame: id,
  type (1 mirror - also shiny metal, whose reflections are phantoms like a
  mirror's -, 2 glass), material, name, corners (4, 3), width, height (width
  along the more horizontal side; the longer side if the rectangle is
  horizontal), plane (a, b, c, d) with the unit normal pointing at the sensor,
  centre.

Noise is drawn from numpy's default_rng(seed) in a fixed order, so a sweep
is a deterministic function of (scene, scanner, pose, physics, seed).
"""
from dataclasses import dataclass, field
from typing import List

import numpy as np

from . import scene as scenes
from .labels import Label
from .physics import (SURFACE_DIFFUSE, SURFACE_GLASS, SURFACE_METAL, SURFACE_MIRROR, PhysicsParams, Returns,
                      SceneArrays, trace)
from .scanner import RotatingHokuyo, detection_threshold, range_sigma, world_rays

ECHO_DTYPE = np.dtype([('x', '<f4'), ('y', '<f4'), ('z', '<f4'), ('intensity', '<f4')])
GROUND_TRUTH_DTYPE = np.dtype([
    ('x', '<f4'), ('y', '<f4'), ('z', '<f4'),
    ('true_x', '<f4'), ('true_y', '<f4'), ('true_z', '<f4'),
    ('label', 'u1'), ('object_id', '<i4'), ('echo', 'u1'), ('beam', '<u4'), ('double_echo', 'u1'),
])

INTENSITY_NOISE = 0.05  # relative sigma of the intensity (ideal physics; realistic: diffuse surfaces)
# Realistic physics: relative sigma of the intensity by surface. Specular returns swing with the
# exact incidence and the state of the surface (dust, smears): glass most, being the faintest.
SURFACE_INTENSITY_NOISE = np.zeros(4)
SURFACE_INTENSITY_NOISE[[SURFACE_DIFFUSE, SURFACE_MIRROR, SURFACE_GLASS, SURFACE_METAL]] = 0.05, 0.2, 0.35, 0.15
# Realistic physics: contributions fainter than this share of the detection threshold are not
# worth merging (they cannot make or move an echo).
NEGLIGIBLE = 0.02


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
        'type': scenes.OBJECT_TYPE_GLASS if rect.material.kind == scenes.GLASS else scenes.OBJECT_TYPE_MIRROR,
        'material': rect.material.kind,
        'name': rect.name,
        'corners': corners,
        'width': float(width),
        'height': float(height),
        'plane': np.array([normal[0], normal[1], normal[2], d]),
        'centre': centre,
    }


class SweepSimulator:
    """Simulates sweeps of one scene with one scanner; caches the noise-free echoes per pose."""

    def __init__(self, scene, scanner=None, physics=None):
        self.scene = scenes.get(scene) if isinstance(scene, str) else scene
        self.scanner = scanner if scanner is not None else RotatingHokuyo()
        self.physics = physics if physics is not None else PhysicsParams()
        self._arrays = SceneArrays(self.scene)
        self._directions = self.scanner.directions()
        self._cache_key = None
        self._cache = None

    @property
    def realistic(self):
        return not self.physics.ideal_model

    def _returns(self, pose):
        """The noise-free echoes of every beam at `pose`, sorted by beam and range (Returns), and the
        number of beams traced with a footprint."""
        key = (tuple(pose.position), tuple(pose.rpy))
        if key != self._cache_key:
            origin, directions = world_rays(self.scanner, pose)
            max_path = self.scanner.max_range + 5 * max(self.scanner.range_noise,
                                                        getattr(self.scanner, 'range_noise_far', 0.0))
            if self.realistic:
                r, footprints = self._realistic_echoes(origin, directions, max_path)
            else:
                r, footprints = trace(self._arrays, origin, directions, max_path, self.physics), 0
            self._cache = r.select(np.lexsort((r.path_length, r.beam))), footprints   # fixed order for the noise
            self._cache_key = key
        return self._cache

    def _realistic_echoes(self, origin, directions, max_path):
        threshold = detection_threshold(self.scanner, self.physics.intensity_gain)
        r = trace(self._arrays, origin, directions, max_path, self.physics, min_intensity=threshold)
        divergence = np.radians(self.scanner.beam_divergence_deg)
        rays = self.physics.footprint_rays
        edge = np.zeros(0, np.int64)
        if divergence > 0 and rays > 0:
            edge = depth_edge_beams(r, self.scanner, threshold)
            share = 1.0 / (rays + 1)
            r.intensity[np.isin(r.beam, edge)] *= share
            sub_directions, sub_beams = footprint_rays(directions[edge], edge, divergence / 2, rays)
            r = Returns.concatenate([r, trace(self._arrays, origin, sub_directions, max_path, self.physics,
                                              beams=sub_beams, weights=share, min_intensity=threshold)])
        r = r.select(r.intensity >= NEGLIGIBLE * threshold)
        echoes = merge_returns(r, self.scanner.echo_separation)
        return echoes.select(echoes.intensity >= threshold), len(edge)

    def sweep(self, seed=0, pose=None, noise=None):
        """One Sweep; pose defaults to the scene's scanner pose, noise (a constant range sigma) to the
        scanner's range noise."""
        pose = pose if pose is not None else self.scene.scanner_pose
        r, footprints = self._returns(pose)
        rng = np.random.default_rng(seed)
        if self.realistic:
            sigma = range_sigma(self.scanner, r.path_length) if noise is None else np.full(len(r), float(noise))
            measured = r.path_length + sigma * rng.normal(size=len(r))
            spread = SURFACE_INTENSITY_NOISE[r.surface]
            intensity = r.intensity * np.exp(spread * rng.normal(size=len(r)) - spread ** 2 / 2)
            intensity = np.minimum(intensity, self.scanner.saturation * self.physics.intensity_gain)
        else:
            sigma = self.scanner.range_noise if noise is None else noise
            measured = r.path_length + (rng.normal(0.0, sigma, len(r)) if sigma > 0 else 0.0)
            intensity = r.intensity * np.clip(1 + INTENSITY_NOISE * rng.normal(size=len(r)), 0.0, None)
        gate = (measured >= self.scanner.min_range) & (measured <= self.scanner.max_range)
        beam, measured, intensity = r.beam[gate], measured[gate], intensity[gate]
        true_world, label, object_id = r.true_world[gate], r.label[gate], r.object_id[gate]

        if self.realistic:
            near, far = reported_echoes(beam, measured, intensity, self.scanner.return_mode,
                                        self.scanner.max_echoes)
        else:
            near, far = reported_echoes(beam, measured, intensity, 'first_last', 0)

        n = self.scanner.rows * self.scanner.cols
        rotation, position = pose.rotation(), np.asarray(pose.position, float)
        directions = self._directions
        double = np.zeros(n, np.uint8)
        double[beam[near]] = near != far
        gt = np.zeros(2 * n, GROUND_TRUTH_DTYPE)
        echoes = []
        for e, pick in ((1, near), (2, far)):
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
            g['double_echo'] = double

        objects = [rectangle_to_object(rect, rotation, position) for rect in self.scene.objects()]
        return Sweep(self.scene.name, self.scanner.name, self.scanner.rows, self.scanner.cols,
                     echoes[0], echoes[1], gt, objects, pose, seed,
                     info={'noise': noise if noise is not None else self.scanner.range_noise,
                           'physics': self.physics.model, 'returns_traced': int(len(r)),
                           'beams_with_footprint': int(footprints)})


def reported_echoes(beam, measured, intensity, return_mode, max_echoes):
    """Per beam with an echo, the indices (near, far) of the two echoes the sensor reports (the same
    index twice for a beam with one echo), ordered by beam. return_mode: scanner.RETURN_MODES."""
    order = np.lexsort((measured, beam))
    b = beam[order]
    starts = np.flatnonzero(np.r_[True, b[1:] != b[:-1]]) if len(b) else np.zeros(0, np.int64)
    counts = np.diff(np.r_[starts, len(b)])
    if max_echoes:
        counts = np.minimum(counts, max_echoes)
    first, last = order[starts], order[starts + counts - 1]
    rank = np.arange(len(b)) - np.repeat(starts, np.diff(np.r_[starts, len(b)]))
    usable = rank < np.repeat(counts, np.diff(np.r_[starts, len(b)]))   # within max_echoes
    if return_mode == 'first_last':
        a, z = first, last
    elif return_mode in ('last_strongest', 'strongest_two'):
        strength = np.where(usable, intensity[order], -np.inf)
        if return_mode == 'last_strongest':
            strength[starts + counts - 1] = -np.inf    # the last is reported anyway
        by_strength = np.lexsort((-strength, b))        # within each beam, strongest first
        strongest = order[by_strength[starts]]
        if return_mode == 'last_strongest':
            a, z = np.where(counts > 1, strongest, last), last
        else:
            second = order[by_strength[np.minimum(starts + 1, len(b) - 1)]]
            a, z = strongest, np.where(counts > 1, second, strongest)
    else:
        raise ValueError('unknown return mode %r' % (return_mode,))
    swap = measured[a] > measured[z]
    return np.where(swap, z, a), np.where(swap, a, z)


def depth_edge_beams(returns, scanner, threshold):
    """Beams whose footprint may straddle a depth edge: a grid neighbour (within the footprint's
    reach) saw another set of surfaces along its centre ray. Only contributions that could be
    seen (a tenth of the detection threshold) count."""
    rows, cols = scanner.rows, scanner.cols
    seen = returns.intensity >= 0.1 * threshold
    signature = np.zeros(rows * cols, np.int64)
    # A sum of per-surface hashes: equal for beams that met the same surfaces.
    np.add.at(signature, returns.beam[seen], (returns.rect[seen].astype(np.int64) + 1) * 2654435761 % (1 << 40))
    grid = signature.reshape(rows, cols)
    row_step, col_step = scanner.grid_steps()
    reach = np.radians(scanner.beam_divergence_deg) / 2
    k_rows = min(rows - 1, max(1, int(np.ceil(reach / max(row_step, 1e-9)))))
    k_cols = min(cols - 1, max(1, int(np.ceil(reach / max(col_step, 1e-9)))))
    edge = np.zeros((rows, cols), bool)
    for dr in range(-k_rows, k_rows + 1):
        for dc in range(-k_cols, k_cols + 1):
            if (dr, dc) == (0, 0):
                continue
            shifted = np.roll(grid, (dr, dc), axis=(0, 1))
            differs = shifted != grid
            # Rows never wrap; columns wrap only round a full revolution.
            if dr > 0:
                differs[:dr] = False
            elif dr < 0:
                differs[dr:] = False
            if not scanner.wraps_columns:
                if dc > 0:
                    differs[:, :dc] = False
                elif dc < 0:
                    differs[:, dc:] = False
            edge |= differs
    return np.flatnonzero(edge)


def footprint_rays(directions, beams, half_angle, count):
    """`count` rays on a ring at 0.7 half_angle around each direction (a beam's footprint; with the
    centre ray they share its power evenly): (directions (n * count, 3), beams (n * count,))."""
    d = np.asarray(directions, float)
    helper = np.where(np.abs(d[:, 2:3]) < 0.9, np.array([[0.0, 0.0, 1.0]]), np.array([[1.0, 0.0, 0.0]]))
    e1 = np.cross(helper, d)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(d, e1)
    phi = 2 * np.pi * (np.arange(count) + 0.5) / count
    offset = np.tan(0.7 * half_angle) * (np.cos(phi)[None, :, None] * e1[:, None, :]
                                         + np.sin(phi)[None, :, None] * e2[:, None, :])
    rays = d[:, None, :] + offset
    rays /= np.linalg.norm(rays, axis=2, keepdims=True)
    return rays.reshape(-1, 3), np.repeat(np.asarray(beams, np.int64), count)


def merge_returns(returns, separation):
    """The echoes a sensor makes of a beam's contributions: contributions within `separation` of the
    previous one merge (intensities add, range is the intensity-weighted mean); label, object,
    surface and true position are those of the strongest group of equal (label, object) in the
    echo (its intensity-weighted true position)."""
    r = returns.select(np.lexsort((returns.path_length, returns.beam)))
    if len(r) == 0:
        return r
    new = np.r_[True, (r.beam[1:] != r.beam[:-1]) | (np.diff(r.path_length) > separation)]
    echo = np.cumsum(new) - 1
    n_echo = int(echo[-1]) + 1
    total = np.bincount(echo, r.intensity, n_echo)
    weight = np.where(total[echo] > 0, r.intensity / np.where(total[echo] > 0, total[echo], 1), 1.0)
    path = np.bincount(echo, weight * r.path_length, n_echo)
    # The strongest (label, object) group of each echo.
    group = r.label.astype(np.int64) * (1 << 32) + (r.object_id.astype(np.int64) + 1)
    order = np.lexsort((group, echo))
    run = np.r_[True, (echo[order][1:] != echo[order][:-1]) | (group[order][1:] != group[order][:-1])]
    run_id = np.cumsum(run) - 1
    run_start = np.flatnonzero(run)
    run_sum = np.bincount(run_id, r.intensity[order])
    run_echo = echo[order][run_start]
    best_run = np.lexsort((-run_sum, run_echo))
    best_run = best_run[np.r_[True, run_echo[best_run][1:] != run_echo[best_run][:-1]]]   # one per echo
    in_best = np.zeros(len(run_sum), bool)
    in_best[best_run] = True
    member = order[in_best[run_id]]
    w = r.intensity[member]
    true = np.stack([np.bincount(echo[member], w * r.true_world[member, i], n_echo) for i in range(3)], axis=1)
    w_sum = np.bincount(echo[member], w, n_echo)
    true /= np.where(w_sum > 0, w_sum, 1.0)[:, None]
    # Where all weights are zero (cannot happen above the threshold) keep the first member's point.
    representative = member[np.r_[True, echo[member][1:] != echo[member][:-1]]]
    true = np.where((w_sum > 0)[:, None], true, r.true_world[representative])
    strongest = np.lexsort((-r.intensity, echo))
    strongest = strongest[np.r_[True, echo[strongest][1:] != echo[strongest][:-1]]]
    return Returns(r.beam[new], path, true, total, r.label[representative], r.object_id[representative],
                   r.rect[strongest], r.surface[strongest])


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
    double_echo_surface_points: those of a beam that returned a second echo too, behind_points,
    mean_surface_intensity), as the evaluator compares them (also ros_io's)."""
    gt = sweep.ground_truth
    real = physical_return_mask(gt)
    intensity = np.r_[sweep.echo1['intensity'], sweep.echo2['intensity']]
    # Per ground-truth entry: its beam returned two echoes that differ (the evaluator's double-echo points).
    two = real[len(gt) // 2:]
    beam_has_two = np.r_[two, two]
    out = []
    for o in sweep.objects:
        mine = (gt['object_id'] == o['id']) & real
        surface = mine & np.isin(gt['label'], [Label.REFLECTIVE_SURFACE, Label.TRANSPARENT_SURFACE])
        behind = mine & np.isin(gt['label'], [Label.BEHIND_REFLECTIVE, Label.BEHIND_TRANSPARENT])
        d = dict(o)
        d['surface_points'] = int(surface.sum())
        d['double_echo_surface_points'] = int((surface & beam_has_two).sum())
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
