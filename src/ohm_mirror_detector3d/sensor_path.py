"""A scanner on a path: one pose per sweep in a fixed frame, as a robot driving through a scene.

The fixed frame is the scene's world frame, published as `odom` (FIXED_FRAME). Sweep k is taken
with the scanner at `path.poses[k]` (a scene.Pose) and held there for the whole sweep (the robot
moves between sweeps): the simulator's sweep, its ground truth and its objects are in the
scanner frame as for a standing scanner, and `path.fixed_from_sweep(k)` (4 x 4) takes them into
the fixed frame. ros_io writes the same pose as tf (odom <- the sweep's frame) at the sweep's
stamp, so a consumer with tf2 finds fixed_frame <- sweep frame at every sweep.

Paths:

* `straight(start, end, sweeps)`: evenly spaced poses on a segment, the scanner's yaw along it;
* `pass_by(scene, object_name, sweeps, distance, half_length)`: a straight pass parallel to a
  mirror or pane at `distance` in front of it, centred on it (a robot driving past a glass door,
  a mirror passed sideways); NAMED_PASSES holds one per named scene with an object;
* `random_path(scene, sweeps, seed)`: a seeded random walk through a random scene's near room
  (random_scenes: layout['near']), `step` metres per sweep, that keeps `clearance` from
  every wall, piece of furniture, mirror and pane (the robot's mast: a vertical segment from
  the floor to the scanner);
* `scene_path(scene, sweeps, seed)`: the named scene's pass, or a random scene's random walk.

Poses keep the scene's scanner height, roll and pitch; only position and yaw change.
"""
import math
from dataclasses import dataclass
from typing import Tuple

import numpy as np

from . import scene as scenes

FIXED_FRAME = 'odom'
_STREAM = 17   # keeps the paths' random numbers apart from the scenes' and the noise seeds
DEFAULT_STEP = 0.25        # m per sweep
DEFAULT_CLEARANCE = 0.35   # m from the mast to anything but the floor
_MAST_BOTTOM = 0.05        # m: the mast's lowest point that must clear things (the floor does not count)


@dataclass(frozen=True)
class SensorPath:
    """The scanner's pose per sweep in the fixed frame (the scene's world frame)."""
    scene_name: str
    poses: Tuple[scenes.Pose, ...]
    description: str = ''

    def __len__(self):
        return len(self.poses)

    def fixed_from_sweep(self, k):
        """4 x 4 transform taking points of sweep k (the scanner frame) into the fixed frame."""
        out = np.eye(4)
        out[:3, :3] = self.poses[k].rotation()
        out[:3, 3] = self.poses[k].position
        return out

    def matrices(self):
        """(sweeps, 4, 4): fixed_from_sweep of every sweep."""
        return np.stack([self.fixed_from_sweep(k) for k in range(len(self))]) if self.poses else np.zeros((0, 4, 4))

    def transform(self, k):
        """(translation (x, y, z), quaternion (x, y, z, w)) of fixed <- sweep k, as tf carries it."""
        return tuple(float(v) for v in self.poses[k].position), rotation_quaternion(self.poses[k].rotation())


def rotation_quaternion(rotation):
    """(x, y, z, w), w >= 0, of a 3 x 3 rotation matrix."""
    m = np.asarray(rotation, float)
    trace = np.trace(m)
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = ((m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, s / 4)
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(max(1.0 + m[i, i] - m[j, j] - m[k, k], 1e-12))
        v = [0.0, 0.0, 0.0]
        v[i] = s / 4
        v[j] = (m[j, i] + m[i, j]) / s
        v[k] = (m[k, i] + m[i, k]) / s
        q = (v[0], v[1], v[2], (m[k, j] - m[j, k]) / s)
    q = np.asarray(q, float)
    q /= np.linalg.norm(q)
    return tuple(float(v) for v in (q if q[3] >= 0 else -q))


def _pose(xy, yaw, like):
    return scenes.Pose((float(xy[0]), float(xy[1]), float(like.position[2])),
                       (float(like.rpy[0]), float(like.rpy[1]), float(yaw)))


def straight(start, end, sweeps, like=None, scene_name='', description=''):
    """`sweeps` poses evenly spaced from `start` to `end` (x, y), yaw along the segment; height, roll
    and pitch those of the pose `like` (default: 1 m high, level)."""
    if sweeps < 1:
        raise ValueError('a path needs at least one sweep, not %d' % sweeps)
    like = like if like is not None else scenes.Pose((0.0, 0.0, scenes.SCANNER_HEIGHT))
    a, b = np.asarray(start, float)[:2], np.asarray(end, float)[:2]
    yaw = math.atan2(*(b - a)[::-1]) if np.any(b != a) else like.rpy[2]
    steps = np.linspace(0.0, 1.0, sweeps) if sweeps > 1 else np.zeros(1)
    return SensorPath(scene_name, tuple(_pose(a + t * (b - a), yaw, like) for t in steps), description)


def _object(scene, name):
    for rect in scene.objects():
        if rect.name == name:
            return rect
    raise KeyError('scene %s has no mirror, glass or metal object %r; it has: %s'
                   % (scene.name, name, ', '.join(r.name for r in scene.objects())))


def pass_by(scene, object_name, sweeps, distance, half_length, shift=0.0):
    """A straight pass in front of the object `object_name` of `scene`: parallel to its more horizontal
    side, `distance` from its centre on the side the scene's scanner is on (beside it, for an object
    lying flat), from `half_length` before its centre (moved `shift` along the side) to `half_length`
    after it."""
    rect = _object(scene, object_name)
    along = np.asarray(rect.axis_u if abs(rect.axis_u[2]) <= abs(rect.axis_v[2]) else rect.axis_v, float)[:2]
    along /= np.linalg.norm(along)
    away = np.array([-along[1], along[0]])   # horizontal, across the side: the plane's normal unless it lies flat
    centre = np.asarray(rect.centre, float)[:2] + shift * along
    if away @ (np.asarray(scene.scanner_pose.position, float)[:2] - centre) < 0:
        away = -away
    foot = centre + distance * away
    return straight(foot - half_length * along, foot + half_length * along, sweeps, scene.scanner_pose, scene.name,
                    'pass %.1f m in front of %s, %.1f m long' % (distance, object_name, 2 * half_length))


# Named scene -> (object, distance [m], half length [m], shift [m]) of its pass, clear of the furniture.
NAMED_PASSES = {
    'experiment1': ('mirror', 1.3, 1.4),
    'experiment2': ('glass_pane_0', 1.5, 0.7, 0.46),   # past both panes of the glass door
    'experiment3': ('mirror_floor', 1.5, 1.3),
    'experiment4': ('mirror', 1.2, 1.6),
    'glass_wall': ('glass_wall_1', 1.2, 1.6),
    'facing_mirrors': ('mirror_south', 1.0, 1.8),
    'floor_mirror': ('mirror_floor', 2.3, 1.3),
    'mirror_and_glass': ('mirror', 1.3, 1.4),
    'mirror_open_space': ('mirror', 1.2, 2.0),
    'two_mirrors_and_glass': ('window', 1.4, 1.5),
    'facing_tall_mirrors': ('mirror_south', 1.2, 0.6, -1.35),   # beside the scanner's table, 1.2 m between the mirrors
    'wall_mirror': ('mirror', 2.5, 1.5),
    'pane_in_wall': ('pane', 1.0, 1.5),
}


def clearance(scene, xy, top):
    """Distance [m] from the robot's mast at `xy` (a vertical segment from just above the floor to
    height `top`) to the nearest rectangle of the scene, floors not counted (sampled every 0.1 m)."""
    rects = _obstacles(scene)
    if not len(rects[0]):
        return float('inf')
    centre, u, v, half_u, half_v = rects
    heights = np.arange(_MAST_BOTTOM, top + 1e-9, 0.1)
    points = np.stack([np.full_like(heights, xy[0]), np.full_like(heights, xy[1]), heights], axis=1)
    d = points[:, None, :] - centre[None]
    s = np.clip(np.einsum('pri,ri->pr', d, u), -half_u, half_u)
    t = np.clip(np.einsum('pri,ri->pr', d, v), -half_v, half_v)
    nearest = centre[None] + s[..., None] * u[None] + t[..., None] * v[None]
    return float(np.linalg.norm(points[:, None, :] - nearest, axis=2).min())


def _obstacles(scene):
    """(centres, u, v, half widths, half heights) of every rectangle that is not a floor."""
    keep = [r for r in scene.rectangles if max(c[2] for c in r.corners()) > _MAST_BOTTOM / 2]
    if not keep:
        return (np.zeros((0, 3)),) * 3 + (np.zeros(0),) * 2
    return (np.array([r.centre for r in keep], float), np.array([r.axis_u for r in keep], float),
            np.array([r.axis_v for r in keep], float), np.array([r.width / 2 for r in keep]),
            np.array([r.height / 2 for r in keep]))


def is_clear(scene, path, clearance_m=DEFAULT_CLEARANCE, between=3):
    """True when the mast keeps `clearance_m` from everything at every pose and at `between` points
    between two poses."""
    xy = [np.asarray(p.position[:2], float) for p in path.poses]
    top = max((p.position[2] for p in path.poses), default=0.0)
    points = list(xy)
    for a, b in zip(xy[:-1], xy[1:]):
        points += [a + (b - a) * (i + 1) / (between + 1) for i in range(between)]
    return all(clearance(scene, p, top) >= clearance_m for p in points)


def random_path(scene, sweeps, seed, step=DEFAULT_STEP, clearance_m=DEFAULT_CLEARANCE, region=None):
    """A seeded random walk of `sweeps` poses, `step` apart, inside `region` ((x0, x1), (y0, y1); default
    the random scene's layout['near']) shrunk by `clearance_m`, keeping `clearance_m` from everything.
    It starts at the scene's scanner pose when that is clear, else at the first clear point drawn;
    where no step is free it turns round on the spot. ValueError when no clear start exists."""
    if sweeps < 1:
        raise ValueError('a path needs at least one sweep, not %d' % sweeps)
    if region is None:
        if 'near' not in scene.layout:
            raise ValueError('scene %s has no layout["near"] (not a random scene): give region=' % scene.name)
        region = scene.layout['near']
    (x0, x1), (y0, y1) = region
    x0, x1, y0, y1 = x0 + clearance_m, x1 - clearance_m, y0 + clearance_m, y1 - clearance_m
    like = scene.scanner_pose
    top = like.position[2]
    rng = np.random.default_rng([_STREAM, int(seed)])

    def free(p):
        return x0 <= p[0] <= x1 and y0 <= p[1] <= y1 and clearance(scene, p, top) >= clearance_m

    here = np.asarray(like.position[:2], float)
    if not free(here):
        for _ in range(500):
            here = np.array([rng.uniform(x0, x1), rng.uniform(y0, y1)]) if x1 > x0 and y1 > y0 else here
            if free(here):
                break
        else:
            raise ValueError('no clear place for the sensor in %s (clearance %.2f m)' % (scene.name, clearance_m))
    heading = rng.uniform(0.0, 2 * math.pi)
    poses = [_pose(here, heading, like)]
    while len(poses) < sweeps:
        for attempt in range(40):
            # Mostly straight on, turning more the more tries fail.
            turn = rng.normal(0.0, 0.3) if attempt < 10 else rng.uniform(-math.pi, math.pi)
            candidate = here + step * np.array([math.cos(heading + turn), math.sin(heading + turn)])
            middle = (here + candidate) / 2
            if free(candidate) and free(middle):
                heading, here = heading + turn, candidate
                break
        else:
            heading += math.pi
        poses.append(_pose(here, heading, like))
    return SensorPath(scene.name, tuple(poses), 'random walk of %d sweeps, %.2f m a sweep (seed %d)'
                      % (sweeps, step, seed))


def scene_path(scene, sweeps, seed=0, step=DEFAULT_STEP):
    """The path a moving sensor takes through `scene` (a Scene or a name): the NAMED_PASSES pass of a named
    scene, a random walk (random_path, `seed`) through a random scene. KeyError for a named scene without one."""
    scene = scenes.get(scene) if isinstance(scene, str) else scene
    if 'near' in scene.layout:
        return random_path(scene, sweeps, seed, step)
    if scene.name not in NAMED_PASSES:
        raise KeyError('scene %s has no pass (NAMED_PASSES: %s)' % (scene.name, ', '.join(NAMED_PASSES)))
    object_name, *geometry = NAMED_PASSES[scene.name]
    return pass_by(scene, object_name, sweeps, *geometry)
