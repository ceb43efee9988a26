"""Randomised scenes: quality measured on scenes no one looked at while tuning.

`random_scene(seed)` builds a room from the seed alone (numpy's default_rng
of (stream, seed): the same seed gives the same scene on every machine and in
every run, different seeds different scenes), with the sensor at a random pose
inside it. About a quarter of the scenes have no reflective surface at all
(`is_plain`); the others draw, each with its own chance:

* a glass partition across the room: panes between mullions on a sill, a band
  of wall above, one bay either a doorway (an opening with a frame, never
  glass) or a frameless glass door standing ajar by 0-60 deg; a second room
  behind it;
* windows in the outer walls (0-3), with frames, mullions and transoms, each
  pane its own object; outside a ground below the floor, boxes (parked cars,
  sheds, hedges) and a facade or the open sky;
* mirrors (0-2) of random size: hung on a wall and tilted by up to 15 deg,
  leaning on a wall from the floor by 5-20 deg, or free-standing at a random
  yaw on a stand;
* shiny metal panels (0-2) on the walls (lift doors, cabinet fronts);
* a doorway (an opening, never glass) into a corridor in an outer wall;
* furniture (tables with monitors, cabinets, chairs, boxes, plants) and people
  (8-sided prisms) on both sides of the glass.

The sensor stands 0.4-1.8 m high (a robot's mast or a tripod), anywhere on
the near side of the partition clear of furniture, at a random yaw and with
up to 3 deg of roll and pitch. Plain scenes (no mirror, glass or metal) are
the test of false objects; every other scene is a test of what the filter
makes of real-looking reflective surfaces.
"""
import math

import numpy as np

from . import scene as sc

_STREAM = 14   # keeps the generator's random numbers apart from the noise seeds of the sweeps

PLAIN_SHARE = 0.25
FRAME = 0.05   # frame and mullion width [m]


def is_plain(scene):
    """True when the scene has no mirror, glass or metal object."""
    return not scene.objects()


class _Walls:
    """The four outer walls of a room (0, 0)-(W, D): start, direction, inward normal, length; and
    what is already built into them (openings, intervals taken), so that nothing overlaps."""

    SIDES = ('south', 'east', 'north', 'west')

    def __init__(self, width, depth):
        w, d = width, depth
        self.geometry = {
            'south': (np.array([0.0, 0.0]), np.array([1.0, 0.0]), w),
            'east': (np.array([w, 0.0]), np.array([0.0, 1.0]), d),
            'north': (np.array([w, d]), np.array([-1.0, 0.0]), w),
            'west': (np.array([0.0, d]), np.array([0.0, -1.0]), d),
        }
        self.openings = {side: [] for side in self.SIDES}
        self.taken = {side: [] for side in self.SIDES}

    def length(self, side):
        return self.geometry[side][2]

    def point(self, side, s, inward=0.0):
        start, direction, _ = self.geometry[side]
        normal = np.array([-direction[1], direction[0]])
        return start + direction * s + normal * inward

    def facing_yaw(self, side):
        """Azimuth (deg) of the wall's inward normal."""
        _, direction, _ = self.geometry[side]
        return math.degrees(math.atan2(direction[0], -direction[1]))

    def reserve(self, rng, side, width, margin=0.3, tries=20):
        """A free interval [s0, s0 + width] on the wall, or None."""
        length = self.length(side)
        if width + 2 * margin > length:
            return None
        for _ in range(tries):
            s0 = rng.uniform(margin, length - margin - width)
            if all(s0 + width + 0.1 < a or s0 > b + 0.1 for a, b in self.taken[side]):
                self.taken[side].append((s0, s0 + width))
                return s0
        return None


class _Floor:
    """Footprints (centre, radius) of what stands on the floor, to keep things apart."""

    def __init__(self):
        self.items = []

    def free(self, xy, radius, margin=0.15):
        return all(np.hypot(*(np.asarray(xy) - c)) > radius + r + margin for c, r in self.items)

    def place(self, rng, region, radius, tries=30):
        (x0, x1), (y0, y1) = region
        if x1 - x0 < 2 * radius or y1 - y0 < 2 * radius:
            return None
        for _ in range(tries):
            xy = np.array([rng.uniform(x0 + radius, x1 - radius), rng.uniform(y0 + radius, y1 - radius)])
            if self.free(xy, radius):
                self.items.append((xy, radius))
                return xy
        return None


def random_scene(seed):
    """The random scene of `seed` (a non-negative integer), named random_SEED."""
    seed = int(seed)
    if seed < 0:
        raise ValueError('a random scene needs a seed >= 0, not %d' % seed)
    rng = np.random.default_rng([_STREAM, seed])
    width, depth, height = rng.uniform(3.5, 10.0), rng.uniform(3.0, 9.0), rng.uniform(2.4, 3.4)
    plain = rng.random() < PLAIN_SHARE
    s = sc.Scene('%s%d' % (sc.RANDOM_PREFIX, seed))
    walls = _Walls(width, depth)
    floor = _Floor()
    parts = ['%.1f x %.1f x %.1f m room' % (width, depth, height)]

    partition_x = None
    if not plain and rng.random() < 0.5 and width > 5.0:
        partition_x = rng.uniform(0.45, 0.7) * width
        parts.append(_glass_partition(s, rng, partition_x, depth, height, floor))
        s.layout['partition_x'] = partition_x
    near = ((0.0, partition_x if partition_x is not None else width), (0.0, depth))
    s.layout['near'] = near   # where the sensor may stand (and drive: sensor_path.random_path)
    far = ((partition_x, width), (0.0, depth)) if partition_x is not None else None

    if rng.random() < 0.7:
        parts.append(_doorway(s, rng, walls, floor, height, partition_x))
    windows = 0 if plain else int(rng.choice([0, 1, 1, 2, 3]))
    if windows:
        parts.append(_windows(s, rng, walls, height, windows, partition_x))
    mirrors = 0 if plain else int(rng.choice([0, 1, 1, 2]))
    for k in range(mirrors):
        parts.append(_mirror(s, rng, walls, floor, near, height, k))
    metals = 0 if plain else int(rng.choice([0, 0, 1, 2]))
    for k in range(metals):
        parts.append(_metal_panel(s, rng, walls, height, partition_x, k))

    s.extend(sc.room(0.0, 0.0, width, depth, height, openings=walls.openings, name='room'))
    furniture = _furniture(s, rng, floor, near, int(rng.integers(3, 10)), 'near')
    people = _people(s, rng, floor, near, int(rng.integers(0, 4)), 'near')
    if far is not None:
        furniture += _furniture(s, rng, floor, far, int(rng.integers(2, 7)), 'far')
        people += _people(s, rng, floor, far, int(rng.integers(1, 4)), 'far')
    parts.append('%d pieces of furniture, %d %s' % (furniture, people, 'person' if people == 1 else 'people'))
    s.scanner_pose = _sensor_pose(rng, floor, near)
    if is_plain(s):
        parts.append('no mirror, glass or metal')
    s.description = 'Random scene %d: %s.' % (seed, '; '.join(p for p in parts if p))
    return s


def _glass_partition(s, rng, x, depth, height, floor):
    """Glass bays across the room at x (from y = 0 to depth), one of them maybe a doorway or a glass door."""
    bays = max(2, int(round(depth / rng.uniform(1.0, 1.6))))
    bay = depth / bays
    top = min(height, rng.uniform(2.1, 2.6))
    door_bay = int(rng.integers(0, bays)) if rng.random() < 0.7 else None
    door_kind = 'doorway' if door_bay is not None and rng.random() < 0.5 else 'glass door'
    panes = 0
    for i in range(bays):
        y0, y1 = i * bay, (i + 1) * bay
        if i == door_bay:
            door_width = min(bay - 2 * FRAME, rng.uniform(0.9, 1.2))
            yc = (y0 + y1) / 2
            for a, b in ((y0 + FRAME / 2, yc - door_width / 2), (yc + door_width / 2, y1 - FRAME / 2)):
                if b - a > 0.2:   # narrow fixed panes beside the door
                    s.add(sc.Rectangle((x, (a + b) / 2, (FRAME + top) / 2), (0, 1, 0), (0, 0, 1), b - a,
                                       top - FRAME, sc.WINDOW_GLASS, 'partition_pane_%d' % panes))
                    panes += 1
            for y in (yc - door_width / 2 - FRAME / 2, yc + door_width / 2 + FRAME / 2):
                s.extend(sc.box((x, y), (0.1, FRAME), top, sc.METAL_FRAME, name='door_post'))
            if door_kind == 'glass door':
                ajar = math.radians(rng.uniform(0.0, 60.0))
                hinge = np.array([x, yc - door_width / 2])
                along = np.array([-math.sin(ajar), math.cos(ajar)])   # opening towards the sensor (-x)
                centre = hinge + along * door_width / 2
                s.add(sc.Rectangle((centre[0], centre[1], 0.01 + 1.0), (along[0], along[1], 0.0), (0, 0, 1),
                                   door_width - 0.01, 2.0, sc.WINDOW_GLASS, 'glass_door'))
                panes += 1
            floor.items.append((np.array([x - 0.6, yc]), 0.6))   # keep the way through free
            floor.items.append((np.array([x + 0.6, yc]), 0.6))
        else:
            s.add(sc.Rectangle((x, (y0 + y1) / 2, (FRAME + top) / 2), (0, 1, 0), (0, 0, 1), bay - FRAME,
                               top - FRAME, sc.WINDOW_GLASS, 'partition_pane_%d' % panes))
            panes += 1
            s.extend(sc.box((x, (y0 + y1) / 2), (0.06, bay - FRAME), FRAME, sc.METAL_FRAME, name='sill'))
        if i > 0:
            s.extend(sc.box((x, y0), (0.08, FRAME), top, sc.METAL_FRAME, name='mullion'))
    if height - top > 0.01:
        s.extend(sc.box((x, depth / 2), (0.1, depth), height - top, sc.WALL, z0=top, name='partition_band'))
    what = '%d-pane glass partition at x = %.1f m' % (panes, x)
    if door_bay is not None:
        what += ' with a %s' % door_kind
    return what


def _doorway(s, rng, walls, floor, height, partition_x):
    """An opening (never glass) in an outer wall of the near side, with a corridor behind it."""
    sides = ['south', 'north', 'west'] + ([] if partition_x is not None else ['east'])
    side = str(rng.choice(sides))
    door_width, door_height = rng.uniform(0.8, 1.3), min(height - 0.1, rng.uniform(2.0, 2.3))
    length = walls.length(side)
    lo, hi = 0.3, length - 0.3 - door_width
    if partition_x is not None and side == 'south':      # only the near room's part of the wall
        hi = min(hi, partition_x - 0.3 - door_width)
    elif partition_x is not None and side == 'north':    # the north wall runs from x = W
        lo = max(lo, length - partition_x + 0.3)
    s0 = None
    for _ in range(20 if hi > lo else 0):
        candidate = rng.uniform(lo, hi)
        if all(candidate + door_width + 0.1 < a or candidate > b + 0.1 for a, b in walls.taken[side]):
            s0 = candidate
            break
    if s0 is None:
        return ''
    walls.taken[side].append((s0, s0 + door_width))
    walls.openings[side].append((s0, s0 + door_width, 0.0, door_height))
    middle = walls.point(side, s0 + door_width / 2)
    inward = walls.point(side, 0.0, 1.0) - walls.point(side, 0.0, 0.0)
    s.layout.setdefault('doorways', []).append({'centre': (float(middle[0]), float(middle[1]), door_height / 2),
                                                'inward': (float(inward[0]), float(inward[1]), 0.0),
                                                'width': door_width, 'height': door_height})
    floor.items.append((middle + inward[:2] * 0.6, 0.6))   # the way in stays free
    # The corridor: 1.5-3 m deep, 1 m wider than the door on both sides, three walls of its own.
    corridor_depth = rng.uniform(1.5, 3.0)
    a = walls.point(side, s0 - 1.0)
    b = walls.point(side, s0 + door_width + 1.0)
    outward = walls.point(side, 0.0, -1.0) - walls.point(side, 0.0, 0.0)
    a_out, b_out = a + outward * corridor_depth, b + outward * corridor_depth
    s.extend(sc.wall(tuple(b), tuple(b_out), height, name='corridor_side'))
    s.extend(sc.wall(tuple(b_out), tuple(a_out), height, name='corridor_end'))
    s.extend(sc.wall(tuple(a_out), tuple(a), height, name='corridor_side'))
    centre = (a + b_out) / 2
    size = np.abs(b_out - a)
    s.add(sc.horizontal((centre[0], centre[1], 0.0), max(size[0], 0.1), max(size[1], 0.1), sc.FLOOR, True,
                        'corridor_floor'))
    s.add(sc.horizontal((centre[0], centre[1], height), max(size[0], 0.1), max(size[1], 0.1), sc.CEILING, False,
                        'corridor_ceiling'))
    if rng.random() < 0.5:
        s.extend(sc.box(tuple(a_out + (b - a) * 0.7 - outward * 0.3), (0.4, 0.4), rng.uniform(0.8, 1.8), sc.WOOD,
                        name='corridor_cabinet'))
    return 'doorway in the %s wall' % side


def _windows(s, rng, walls, height, count, partition_x):
    """Windows with frames and mullions in the outer walls, and an outside to see through them."""
    made, panes = 0, 0
    sides = set()
    for _ in range(count):
        side = str(rng.choice(walls.SIDES))
        window_width = rng.uniform(0.8, 2.2)
        s0 = walls.reserve(rng, side, window_width)
        if s0 is None:
            continue
        if partition_x is not None and side in ('south', 'north'):
            x_mid = walls.point(side, s0 + window_width / 2)[0]
            if abs(x_mid - partition_x) < window_width / 2 + 0.2:   # not across the partition
                walls.taken[side].pop()
                continue
        sill = rng.uniform(0.5, 1.0)
        top = min(height - 0.15, sill + rng.uniform(1.0, 1.6))
        walls.openings[side].append((s0, s0 + window_width, sill, top))
        columns = 1 + int(rng.integers(0, 3)) if window_width > 1.2 else 1
        rows = 2 if rng.random() < 0.3 and top - sill > 1.2 else 1
        transom = sill + (top - sill) * rng.uniform(0.6, 0.75) if rows == 2 else None
        yaw = walls.facing_yaw(side)
        edges = np.linspace(s0, s0 + window_width, columns + 1)
        z_edges = [sill, transom, top] if transom is not None else [sill, top]
        for c0, c1 in zip(edges[:-1], edges[1:]):
            for z0, z1 in zip(z_edges[:-1], z_edges[1:]):
                centre = walls.point(side, (c0 + c1) / 2)
                s.add(sc.panel((centre[0], centre[1], (z0 + z1) / 2), yaw, c1 - c0, z1 - z0, sc.WINDOW_GLASS,
                               name='window_%d_pane' % made))
                panes += 1
        # Frame: sill, head, jambs, mullions, transom (boxes straddling the wall plane).
        along = walls.point(side, 1.0) - walls.point(side, 0.0)
        wall_yaw = math.degrees(math.atan2(along[1], along[0]))
        mid = walls.point(side, s0 + window_width / 2)
        for z in [sill - FRAME / 2, top - FRAME / 2] + ([transom - FRAME / 2] if transom is not None else []):
            s.extend(sc.box(tuple(mid), (window_width, 0.1), FRAME, sc.METAL_FRAME, yaw_deg=wall_yaw, z0=z,
                            name='window_frame'))
        for e in edges:
            p = walls.point(side, e)
            s.extend(sc.box(tuple(p), (FRAME, 0.1), top - sill, sc.METAL_FRAME, yaw_deg=wall_yaw, z0=sill,
                            name='window_frame'))
        made += 1
        sides.add(side)
    if not made:
        return ''
    _outside(s, rng, walls, sides)
    return '%d window%s (%d panes)' % (made, 's' if made > 1 else '', panes)


def _outside(s, rng, walls, sides):
    """Ground below the floor level, boxes and, opposite most windowed walls, a facade (else sky)."""
    w, d = walls.length('south'), walls.length('east')
    s.add(sc.horizontal((w / 2, d / 2, -0.02), w + 60.0, d + 60.0, sc.FLOOR, True, 'ground'))
    for side in sorted(sides):
        distance = rng.uniform(6.0, 25.0)
        length = walls.length(side)
        if rng.random() < 0.6:
            a = walls.point(side, -15.0, -distance)
            b = walls.point(side, length + 15.0, -distance)
            s.extend(sc.wall(tuple(b), tuple(a), rng.uniform(3.0, 12.0), name='facade'))   # facing the room
        for k in range(int(rng.integers(1, 5))):
            p = walls.point(side, rng.uniform(-3.0, length + 3.0), -rng.uniform(1.5, distance - 1.0))
            s.extend(sc.box(tuple(p), (rng.uniform(0.8, 4.5), rng.uniform(0.8, 2.0)), rng.uniform(0.8, 2.5),
                            sc.WOOD, yaw_deg=rng.uniform(0, 180), name='outside_%d' % k))


def _mirror(s, rng, walls, floor, near, height, k):
    width, tall = rng.uniform(0.3, 1.2), rng.uniform(0.4, 1.8)
    how = str(rng.choice(['hung', 'leaning', 'free-standing']))
    name = 'mirror_%d' % k
    if how == 'free-standing':
        xy = floor.place(rng, near, max(width, 0.5) / 2 + 0.1)
        if xy is not None:
            yaw, lean, bottom = rng.uniform(0, 360), rng.uniform(0, 15), rng.uniform(0.05, 0.3)
            tall = min(tall, 1.6)
            mirror = sc.leaning_panel((xy[0], xy[1], bottom), yaw, width, tall, sc.MIRROR_GLASS, lean, name)
            s.add(mirror)
            # A stand behind it, clear of the mirror's back up to its top.
            gap = 0.05 + 0.3 * math.tan(math.radians(lean))
            behind = xy - gap * np.array([math.cos(math.radians(yaw)), math.sin(math.radians(yaw))])
            s.extend(sc.box(tuple(behind), (0.04, 0.3), bottom + 0.25, sc.METAL_FRAME, yaw_deg=yaw,
                            name='mirror_stand'))
            return '%.0f x %.0f cm free-standing mirror' % (100 * width, 100 * tall)
        how = 'hung'
    side = str(rng.choice(walls.SIDES))
    s0 = walls.reserve(rng, side, width)
    if s0 is None:
        return ''
    yaw = walls.facing_yaw(side)
    if how == 'hung':
        tall = min(tall, height - 0.5)
        lean = rng.uniform(-15.0, 15.0)
        zc = rng.uniform(0.3 + tall / 2, height - 0.1 - tall / 2)
        out = 0.02 + tall / 2 * abs(math.sin(math.radians(lean)))
        p = walls.point(side, s0 + width / 2, out)
        s.add(sc.panel((p[0], p[1], zc), yaw, width, tall, sc.MIRROR_GLASS, lean, name))
        return '%.0f x %.0f cm mirror hung at %.0f deg' % (100 * width, 100 * tall, lean)
    lean = rng.uniform(5.0, 20.0)
    tall = min(tall, height - 0.3)
    p = walls.point(side, s0 + width / 2, 0.01 + tall * math.sin(math.radians(lean)))
    s.add(sc.leaning_panel((p[0], p[1], 0.0), yaw, width, tall, sc.MIRROR_GLASS, lean, name))
    floor.items.append((p, width / 2))
    return '%.0f x %.0f cm mirror leaning at %.0f deg' % (100 * width, 100 * tall, lean)


def _metal_panel(s, rng, walls, height, partition_x, k):
    width, tall = rng.uniform(0.5, 1.2), rng.uniform(0.8, min(2.1, height - 0.2))
    side = str(rng.choice(walls.SIDES))
    s0 = walls.reserve(rng, side, width)
    if s0 is None:
        return ''
    bottom = rng.uniform(0.0, min(0.5, height - tall - 0.05))
    p = walls.point(side, s0 + width / 2, 0.01)
    if partition_x is not None and abs(p[0] - partition_x) < width / 2 + 0.1:
        return ''
    s.add(sc.panel((p[0], p[1], bottom + tall / 2), walls.facing_yaw(side), width, tall, sc.SHINY_METAL,
                   0.0, 'metal_%d' % k))
    return '%.0f x %.0f cm metal panel' % (100 * width, 100 * tall)


def _furniture(s, rng, floor, region, count, where):
    made = 0
    for k in range(count):
        kind = str(rng.choice(['table', 'table', 'cabinet', 'chair', 'box', 'plant']))
        yaw = float(rng.choice([0.0, 90.0, rng.uniform(0, 180)]))
        if kind == 'table':
            size = (rng.uniform(0.8, 1.8), rng.uniform(0.6, 0.9))
            xy = floor.place(rng, region, math.hypot(*size) / 2)
            if xy is not None:
                top = rng.uniform(0.7, 0.78)
                s.extend(sc.table(tuple(xy), size, top, sc.WOOD, yaw, name='%s_table%d' % (where, k)))
                if rng.random() < 0.6:   # a monitor on it
                    s.extend(sc.box(tuple(xy), (rng.uniform(0.45, 0.7), 0.04), rng.uniform(0.3, 0.45), sc.FABRIC,
                                    yaw + rng.uniform(-20, 20), z0=top, name='%s_monitor%d' % (where, k)))
        elif kind == 'plant':
            radius = rng.uniform(0.15, 0.3)
            xy = floor.place(rng, region, radius)
            if xy is not None:
                s.extend(sc.cylinder(tuple(xy), radius, rng.uniform(0.6, 1.6), sc.FABRIC, sides=6,
                                     name='%s_plant%d' % (where, k)))
        else:
            size, tall, material = {
                'cabinet': ((rng.uniform(0.4, 1.2), rng.uniform(0.35, 0.6)), rng.uniform(0.8, 2.0), sc.WOOD),
                'chair': ((rng.uniform(0.4, 0.55), rng.uniform(0.4, 0.55)), rng.uniform(0.45, 0.95), sc.FABRIC),
                'box': ((rng.uniform(0.3, 0.8), rng.uniform(0.3, 0.8)), rng.uniform(0.3, 1.0), sc.WOOD),
            }[kind]
            xy = floor.place(rng, region, math.hypot(*size) / 2)
            if xy is not None:
                s.extend(sc.box(tuple(xy), size, tall, material, yaw, name='%s_%s%d' % (where, kind, k)))
        made += xy is not None
    return made


def _people(s, rng, floor, region, count, where):
    made = 0
    for k in range(count):
        radius = rng.uniform(0.17, 0.25)
        xy = floor.place(rng, region, radius)
        if xy is not None:
            s.extend(sc.cylinder(tuple(xy), radius, rng.uniform(1.55, 1.9),
                                 sc.FABRIC if rng.random() < 0.5 else sc.SKIN, name='%s_person%d' % (where, k)))
            made += 1
    return made


def _sensor_pose(rng, floor, region):
    """Anywhere on the near side, 0.5 m from the walls and clear of what stands on the floor."""
    (x0, x1), (y0, y1) = region
    for _ in range(200):
        xy = np.array([rng.uniform(x0 + 0.5, x1 - 0.5), rng.uniform(y0 + 0.5, y1 - 0.5)])
        if floor.free(xy, 0.25):
            break
    z = rng.uniform(0.4, 1.8)
    roll, pitch = np.radians(rng.uniform(-3.0, 3.0, 2))
    return sc.Pose((float(xy[0]), float(xy[1]), float(z)), (float(roll), float(pitch), float(rng.uniform(0, 2 * np.pi))))
