"""Scene model of the sweep simulator: planar rectangles with materials.

A scene is a list of `Rectangle`s in a world frame whose z axis points up
(floor at z = 0), plus the default pose of the scanner. Boxes (furniture) are
six rectangles; walls with door openings are several. Mirrors, glass panes
and shiny metal panels are single rectangles and carry an object id (0, 1, ...
in the order they were added): ground truth labels refer to it and the
ground-truth object list is indexed by it.

Materials (see physics.py for what the simulator does with them; it has two
models, `realistic` (the default) and `ideal` (the simulator as it was before
glass reflected and beams had a footprint), and every material carries the
parameters of both):

* diffuse: returns an echo wherever it is hit; `albedo` scales the intensity
  (Lambertian).
* mirror: a front side (the rectangle's normal) that reflects the beam
  specularly; the back is diffuse (`albedo`). Realistic: a share `reflectance`
  is reflected at every incidence; the surface echo is a sharp specular peak
  near perpendicular incidence (`specular_lobe_deg`) plus a faint diffuse
  haze (`haze`: dust, the glass in front of the silver). Ideal: a surface echo
  only below `surface_echo_max_incidence_deg`.
* glass: both sides alike. Realistic: reflects and transmits by Fresnel's
  equations for a pane of `refractive_index` (8 % reflected at perpendicular
  incidence, rising to all of it at grazing incidence), so one pane gives
  surface echoes near perpendicular, transmitted points and reflected phantoms
  in the same sweep. Ideal: transmits (`transmission`), a surface echo below
  the incidence limit, a reflected share `reflectance` only when it is > 0.
* metal (shiny, brushed): partially specular. Realistic: a diffuse return
  (`haze`) wherever it is hit and a specular reflection of `reflectance`, with
  a broad lobe. Ideal: a mirror whose surface echo has no incidence limit.

The ideal model's incidence limits are chosen so the named scenes look like
the paper's experiments: 20 deg for mirrors (the leaning/tilted 60 x 40 cm
mirrors at about 2.3 m are seen at no more than ~15 deg, so the whole mirror
gives double echoes, surface + phantom, as in experiments 1, 3 and 4), 4 deg
for glass (a pane at 2.2 m then returns surface echoes on a disc of ~31 cm
diameter around the perpendicular foot point, the paper's 31 x 24 cm patch).
The realistic model's lobes and hazes are chosen for the same observations
(see physics.py).
"""
import math
from dataclasses import dataclass, field, replace
from typing import Callable, Dict, List, Tuple

import numpy as np

DIFFUSE, MIRROR, GLASS, METAL = 'diffuse', 'mirror', 'glass', 'metal'
SPECULAR_KINDS = (MIRROR, GLASS, METAL)

# ReflectiveObject.type values of the message.
OBJECT_TYPE_UNKNOWN, OBJECT_TYPE_MIRROR, OBJECT_TYPE_GLASS = 0, 1, 2


@dataclass(frozen=True)
class Material:
    name: str
    kind: str = DIFFUSE
    albedo: float = 0.6                          # diffuse reflectivity (also the back of a mirror or metal panel)
    # Ideal model.
    surface_echo_max_incidence_deg: float = 0.0  # mirror/glass: surface echo below this incidence angle
    surface_echo_strength: float = 1.0           # mirror/glass: peak of the surface echo relative to a white wall
    reflectance: float = 0.0                     # mirror/metal: reflected share (both models); glass: ideal only
    transmission: float = 0.0                    # glass: transmitted share (ideal only)
    # Realistic model.
    refractive_index: float = 1.52               # glass: Fresnel reflection and transmission of the pane
    specular_lobe_deg: float = 0.0               # mirror/glass/metal: spread of the specular reflection [deg]
    haze: float = 0.0                            # mirror/glass/metal: diffuse albedo of the front side


WALL = Material('wall', albedo=0.7)
FLOOR = Material('floor', albedo=0.4)
CEILING = Material('ceiling', albedo=0.8)
WOOD = Material('wood', albedo=0.5)
DOOR = Material('door', albedo=0.6)
METAL_FRAME = Material('frame', albedo=0.3)
FABRIC = Material('fabric', albedo=0.3)
SKIN = Material('skin', albedo=0.45)
MIRROR_GLASS = Material('mirror', kind=MIRROR, albedo=0.2, surface_echo_max_incidence_deg=20.0,
                        surface_echo_strength=1.5, reflectance=0.9, specular_lobe_deg=2.0, haze=0.01)
WINDOW_GLASS = Material('glass', kind=GLASS, albedo=0.0, surface_echo_max_incidence_deg=4.0,
                        surface_echo_strength=0.8, reflectance=0.0, transmission=0.85,
                        refractive_index=1.52, specular_lobe_deg=1.7, haze=0.0005)
SHINY_METAL = Material('metal', kind=METAL, albedo=0.3, surface_echo_max_incidence_deg=90.0,
                       surface_echo_strength=0.15, reflectance=0.5, specular_lobe_deg=8.0, haze=0.15)


@dataclass(frozen=True)
class Rectangle:
    """A planar rectangle: centre, unit side directions u (width) and v (height), side lengths.

    The front normal is u x v; for mirrors only the front reflects.
    """
    centre: Tuple[float, float, float]
    axis_u: Tuple[float, float, float]
    axis_v: Tuple[float, float, float]
    width: float
    height: float
    material: Material
    name: str = ''
    object_id: int = -1  # >= 0 for mirror/glass/metal objects

    @property
    def normal(self):
        return np.cross(self.axis_u, self.axis_v)

    def corners(self):
        """Corners in order around the rectangle, (4, 3)."""
        c, u, v = (np.asarray(a, float) for a in (self.centre, self.axis_u, self.axis_v))
        hu, hv = u * self.width / 2, v * self.height / 2
        return np.array([c - hu - hv, c + hu - hv, c + hu + hv, c - hu + hv])


@dataclass(frozen=True)
class Pose:
    """Scanner pose in the world: position and roll/pitch/yaw (rad, applied as Rz(yaw) Ry(pitch) Rx(roll))."""
    position: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy: Tuple[float, float, float] = (0.0, 0.0, 0.0)

    def rotation(self):
        r, p, y = self.rpy
        cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
        rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
        ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
        rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
        return rz @ ry @ rx


@dataclass
class Scene:
    name: str
    description: str = ''
    rectangles: List[Rectangle] = field(default_factory=list)
    scanner_pose: Pose = field(default_factory=Pose)
    layout: dict = field(default_factory=dict)   # what a generator knows of the scene (random_scenes)

    def add(self, rect):
        """Adds a rectangle; mirror, glass and metal rectangles get the next object id."""
        if rect.material.kind != DIFFUSE:
            rect = replace(rect, object_id=len(self.objects()))
        self.rectangles.append(rect)
        return rect

    def extend(self, rects):
        for r in rects:
            self.add(r)

    def objects(self):
        """The mirror, glass and metal rectangles, ordered by object id."""
        return [r for r in self.rectangles if r.material.kind != DIFFUSE]


# ---------------------------------------------------------------------------------------------
# Geometry helpers

def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def panel(centre, facing_yaw_deg, width, height, material, lean_deg=0.0, name=''):
    """A rectangle whose front normal points at azimuth `facing_yaw_deg`, tilted up by `lean_deg`.

    lean 0 = vertical; lean > 0 = the normal points upwards (a mirror leaning
    back against a wall); lean < 0 = it points downwards (a mirror hanging
    tilted above the viewer); lean 90 = lying flat, facing up. Width runs
    horizontally, height up the panel.
    """
    psi, lam = math.radians(facing_yaw_deg), math.radians(lean_deg)
    n = np.array([math.cos(psi) * math.cos(lam), math.sin(psi) * math.cos(lam), math.sin(lam)])
    u = np.array([-math.sin(psi), math.cos(psi), 0.0])
    v = np.cross(n, u)
    return Rectangle(tuple(np.asarray(centre, float)), tuple(u), tuple(v), width, height, material, name)


def leaning_panel(bottom_centre, facing_yaw_deg, width, height, material, lean_deg, name=''):
    """A panel standing on the point `bottom_centre` (middle of its lower edge), leaning back by lean_deg."""
    p = panel((0, 0, 0), facing_yaw_deg, width, height, material, lean_deg, name)
    centre = np.asarray(bottom_centre, float) + np.asarray(p.axis_v) * height / 2
    return replace(p, centre=tuple(centre))


def horizontal(centre, size_x, size_y, material, facing_up=True, name=''):
    """An axis-aligned horizontal rectangle (floor, ceiling, table top)."""
    u = (1.0, 0.0, 0.0)
    v = (0.0, 1.0, 0.0) if facing_up else (0.0, -1.0, 0.0)
    return Rectangle(tuple(map(float, centre)), u, v, size_x, size_y, material, name)


def box(centre_xy, size, height, material, yaw_deg=0.0, z0=0.0, name='box'):
    """A closed box standing at z0: six rectangles, normals pointing out."""
    sx, sy = size
    cx, cy = centre_xy
    yaw = math.radians(yaw_deg)
    ex = np.array([math.cos(yaw), math.sin(yaw), 0.0])
    ey = np.array([-math.sin(yaw), math.cos(yaw), 0.0])
    ez = np.array([0.0, 0.0, 1.0])
    c = np.array([cx, cy, z0 + height / 2])
    faces = [
        (c + ex * sx / 2, ey, ez, sy, height), (c - ex * sx / 2, -ey, ez, sy, height),
        (c + ey * sy / 2, -ex, ez, sx, height), (c - ey * sy / 2, ex, ez, sx, height),
        (c + ez * height / 2, ex, ey, sx, sy), (c - ez * height / 2, ex, -ey, sx, sy),
    ]
    return [Rectangle(tuple(p), tuple(u), tuple(v), w, h, material, '%s_%d' % (name, i))
            for i, (p, u, v, w, h) in enumerate(faces)]


def cylinder(centre_xy, radius, height, material, sides=8, z0=0.0, name='cylinder'):
    """An upright prism of `sides` faces around a circle (a person, a column, a bin), with a top."""
    cx, cy = centre_xy
    half = radius * math.tan(math.pi / sides)   # half the width of a face
    apothem = radius
    rects = []
    for i in range(sides):
        a = 2 * math.pi * i / sides
        n = np.array([math.cos(a), math.sin(a), 0.0])
        u = np.array([-math.sin(a), math.cos(a), 0.0])
        c = np.array([cx, cy, z0 + height / 2]) + n * apothem
        rects.append(Rectangle(tuple(c), tuple(u), (0.0, 0.0, 1.0), 2 * half, height, material, '%s_%d' % (name, i)))
    rects.append(horizontal((cx, cy, z0 + height), 2 * radius, 2 * radius, material, True, name + '_top'))
    return rects


def table(centre_xy, size, height, material=WOOD, yaw_deg=0.0, name='table'):
    """A table as a thick top and four legs (boxes)."""
    sx, sy = size
    rects = box(centre_xy, size, 0.04, material, yaw_deg, z0=height - 0.04, name=name + '_top')
    yaw = math.radians(yaw_deg)
    for i, (fx, fy) in enumerate([(-1, -1), (1, -1), (1, 1), (-1, 1)]):
        lx, ly = fx * (sx / 2 - 0.05), fy * (sy / 2 - 0.05)
        p = (centre_xy[0] + lx * math.cos(yaw) - ly * math.sin(yaw), centre_xy[1] + lx * math.sin(yaw) + ly * math.cos(yaw))
        rects += box(p, (0.05, 0.05), height - 0.04, material, yaw_deg, name='%s_leg%d' % (name, i))
    return rects


def wall(start_xy, end_xy, height, material=WALL, openings=(), name='wall'):
    """A vertical wall from start to end (its front normal on the left of start->end), minus openings.

    openings: (s0, s1, z0, z1) in metres along the wall from start and height.
    The wall is split into rectangles around the openings (openings must not overlap).
    """
    a, b = np.asarray(start_xy, float), np.asarray(end_xy, float)
    length = float(np.linalg.norm(b - a))
    d = (b - a) / length
    u = np.array([d[0], d[1], 0.0])
    v = np.array([0.0, 0.0, 1.0])
    cuts = sorted({0.0, length} | {o[0] for o in openings} | {o[1] for o in openings})
    rects = []

    def add(s0, s1, z0, z1):
        if s1 - s0 > 1e-6 and z1 - z0 > 1e-6:
            centre = np.array([a[0], a[1], 0.0]) + u * (s0 + s1) / 2 + v * (z0 + z1) / 2
            rects.append(Rectangle(tuple(centre), tuple(u), tuple(v), s1 - s0, z1 - z0, material,
                                   '%s_%d' % (name, len(rects))))

    for s0, s1 in zip(cuts[:-1], cuts[1:]):
        mid = (s0 + s1) / 2
        holes = sorted((o[2], o[3]) for o in openings if o[0] <= mid <= o[1])
        z = 0.0
        for z0, z1 in holes:
            add(s0, s1, z, z0)
            z = z1
        add(s0, s1, z, height)
    return rects


def room(x0, y0, x1, y1, height, openings=None, name='room', floor=True, ceiling=True):
    """Four walls facing inwards plus floor and ceiling. openings: {'south'|'east'|'north'|'west': [...]}
    with (s0, s1, z0, z1) measured along the wall counter-clockwise (south: from x0, east: from y0,
    north: from x1, west: from y1)."""
    openings = openings or {}
    rects = []
    rects += wall((x0, y0), (x1, y0), height, openings=openings.get('south', ()), name=name + '_south')
    rects += wall((x1, y0), (x1, y1), height, openings=openings.get('east', ()), name=name + '_east')
    rects += wall((x1, y1), (x0, y1), height, openings=openings.get('north', ()), name=name + '_north')
    rects += wall((x0, y1), (x0, y0), height, openings=openings.get('west', ()), name=name + '_west')
    c = ((x0 + x1) / 2, (y0 + y1) / 2)
    if floor:
        rects.append(horizontal((c[0], c[1], 0.0), x1 - x0, y1 - y0, FLOOR, True, name + '_floor'))
    if ceiling:
        rects.append(horizontal((c[0], c[1], height), x1 - x0, y1 - y0, CEILING, False, name + '_ceiling'))
    return rects


def facing_yaw(from_xy, to_xy):
    """Azimuth (deg) of the direction from one point to another (to orient a panel towards the scanner)."""
    return math.degrees(math.atan2(to_xy[1] - from_xy[1], to_xy[0] - from_xy[0]))


def lean_towards(panel_centre, sensor):
    """Lean (deg) that makes a panel's normal point straight at the sensor's height."""
    d = np.asarray(sensor, float) - np.asarray(panel_centre, float)
    return math.degrees(math.atan2(d[2], math.hypot(d[0], d[1])))


# ---------------------------------------------------------------------------------------------
# Named scenes

SCANNER_HEIGHT = 1.0  # optical centre on a table: 0.75 m table + mount


def _scanner_on_table(scene, x, y, yaw_deg=0.0):
    scene.extend(table((x, y), (0.8, 0.6), 0.75, name='scanner_table'))
    scene.scanner_pose = Pose((x, y, SCANNER_HEIGHT), (0.0, 0.0, math.radians(yaw_deg)))


def experiment1():
    s = Scene('experiment1', 'Paper exp. 1: empty room, scanner on a table mid-room, an unframed 60x40 cm '
              'mirror leaning on a door (2.2 m away), seen at <= ~10 deg: double echoes over the whole mirror.')
    door = (1.55, 2.45, 0.0, 2.0)  # in the east wall x = 5, along y
    s.extend(room(0, 0, 5.0, 4.0, 2.6, openings={'east': [door]}))
    s.add(Rectangle((5.02, 2.0, 1.0), (0, 1, 0), (0, 0, 1), 0.96, 2.04, DOOR, 'door'))  # leaf, 2 cm recessed, overlaps the frame
    scanner = (2.6, 2.0, SCANNER_HEIGHT)
    _scanner_on_table(s, scanner[0], scanner[1])
    lean = 20.0  # top on the door, bottom ~14 cm out: the normal then points near the scanner
    s.add(leaning_panel((5.0 - 0.40 * math.sin(math.radians(lean)), 2.0, 0.0), 180.0, 0.60, 0.40,
                        MIRROR_GLASS, lean, 'mirror'))
    return s


def experiment2():
    s = Scene('experiment2', 'Paper exp. 2: stairway with a glass door of two 88x198 cm panes, scanner 2.2 m '
              'in front of the left pane at 1 m height; glass returns surface echoes only in a ~31 cm disc.')
    # Stairway x in [0, 4], y in [0, 2.2]; glass door in the east wall x = 4; corridor behind it.
    door_y0 = 0.2
    frame = (door_y0, door_y0 + 1.84, 0.0, 2.08)
    s.extend(room(0, 0, 4.0, 2.2, 3.0, openings={'east': [frame]}, name='stairway'))
    s.extend(room(4.0, -1.0, 9.0, 4.0, 3.0, openings={'west': [(5.0 - frame[1] - 1.0, 5.0 - frame[0] - 1.0, 0.0, 2.08)]},
                  name='corridor'))
    panes = []
    for i, y0 in enumerate((door_y0 + 0.02, door_y0 + 0.94)):
        panes.append(Rectangle((4.0, y0 + 0.44, 0.05 + 0.99), (0, 1, 0), (0, 0, 1), 0.88, 1.98, WINDOW_GLASS,
                               'glass_pane_%d' % i))
    # Frame: posts between and around the panes, lintel and sill (thin boxes).
    for y in (door_y0 + 0.01, door_y0 + 0.92, door_y0 + 1.83):
        s.extend(box((4.0, y), (0.05, 0.02), 2.08, METAL_FRAME, name='door_post'))
    s.extend(box((4.0, door_y0 + 0.92), (0.05, 1.84), 0.05, METAL_FRAME, name='door_sill'))
    s.extend(box((4.0, door_y0 + 0.92), (0.05, 1.84), 0.05, METAL_FRAME, z0=2.03, name='door_lintel'))
    for p in panes:
        s.add(p)
    # Stairs going up along the west part of the stairway, a landing, and furniture behind the door.
    for k in range(6):
        s.extend(box((0.3 + 0.28 * k, 1.7), (0.28, 1.0), 0.17 * (k + 1), WOOD, name='step%d' % k))
    s.extend(box((6.5, 0.2), (0.6, 0.8), 1.2, WOOD, name='cabinet'))
    s.extend(box((7.0, 2.8), (1.0, 0.5), 0.9, WOOD, name='bench'))
    s.scanner_pose = Pose((4.0 - 2.2, panes[0].centre[1], SCANNER_HEIGHT), (0.0, 0.0, 0.0))
    s.extend(box((1.8, panes[0].centre[1]), (0.5, 0.5), 0.75, WOOD, name='scanner_stand'))
    return s


def experiment3():
    s = Scene('experiment3', 'Paper exp. 3: two connected rooms; a 60x40 mirror standing on the floor in the '
              'open doorway below the scanner level, and one hanging tilted above the scanner.')
    opening = (1.5, 2.5, 0.0, 2.0)
    s.extend(room(0, 0, 5.0, 4.0, 2.6, openings={'east': [opening]}, name='room_a'))
    s.extend(room(5.0, 0, 9.0, 4.0, 2.6, openings={'west': [(4.0 - 2.5, 4.0 - 1.5, 0.0, 2.0)]}, name='room_b'))
    scanner = (2.6, 2.0, SCANNER_HEIGHT)
    _scanner_on_table(s, scanner[0], scanner[1])
    # Mirror 1: on the floor in the doorway, leaning back 12 deg on a stand.
    s.add(leaning_panel((4.9, 2.0, 0.0), 180.0, 0.60, 0.40, MIRROR_GLASS, 12.0, 'mirror_floor'))
    s.extend(box((5.05, 2.0), (0.05, 0.3), 0.35, METAL_FRAME, name='mirror_stand'))
    # Mirror 2: hangs from the ceiling near the north wall, facing down towards the scanner.
    centre = np.array([2.6, 3.8, 2.15])
    s.add(panel(centre, -90.0, 0.60, 0.40, MIRROR_GLASS, lean_towards(centre, scanner), 'mirror_hanging'))
    return s


def experiment4():
    s = Scene('experiment4', 'Paper exp. 4: office with desks, cabinets and chairs; a free-standing 60x40 '
              'mirror close to the floor, 2.3 m from the scanner.')
    s.extend(room(0, 0, 6.0, 5.0, 2.7))
    scanner = (3.0, 2.3, SCANNER_HEIGHT)
    _scanner_on_table(s, scanner[0], scanner[1])
    s.extend(table((1.0, 4.3), (1.6, 0.8), 0.74, name='desk1'))
    s.extend(table((5.0, 4.3), (1.6, 0.8), 0.74, name='desk2'))
    s.extend(box((0.25, 1.5), (0.45, 1.2), 1.9, WOOD, name='cabinet1'))
    s.extend(box((5.75, 1.0), (0.45, 0.9), 1.2, WOOD, name='cabinet2'))
    s.extend(box((1.2, 3.6), (0.5, 0.5), 0.45, FABRIC, name='chair1'))
    s.extend(box((4.8, 3.6), (0.5, 0.5), 0.45, FABRIC, name='chair2'))
    s.extend(box((0.5, 0.3), (0.9, 0.4), 0.9, WOOD, name='sideboard'))
    # Free-standing mirror 5 cm above the floor, leaning back 10 deg, facing the scanner.
    base = np.array([3.0, 0.0 + 0.25, 0.05])
    s.add(leaning_panel(base, 90.0, 0.60, 0.40, MIRROR_GLASS, 10.0, 'mirror'))
    s.extend(box((3.0, 0.12), (0.4, 0.15), 0.05, METAL_FRAME, name='mirror_foot'))
    return s


def empty_room():
    s = Scene('empty_room', 'A 5x4 m room, scanner on a table: no mirror or glass, no phantoms.')
    s.extend(room(0, 0, 5.0, 4.0, 2.6))
    _scanner_on_table(s, 2.6, 2.0)
    return s


def glass_wall():
    s = Scene('glass_wall', 'An office partitioned by a glass wall (three 1.0x2.4 m panes) 2 m in front of '
              'the scanner, with furniture behind it.')
    s.extend(room(0, 0, 8.0, 5.0, 2.6))
    _scanner_on_table(s, 2.0, 2.5)
    for i in range(3):
        s.add(Rectangle((4.0, 1.0 + 1.0 * i + 0.5, 1.2), (0, 1, 0), (0, 0, 1), 0.98, 2.4, WINDOW_GLASS,
                        'glass_wall_%d' % i))
    s.extend(wall((4.0, 0.0), (4.0, 1.0), 2.6, name='partition_s'))
    s.extend(wall((4.0, 4.0), (4.0, 5.0), 2.6, name='partition_n'))
    s.extend(box((4.0, 2.5), (0.1, 3.0), 0.2, WALL, z0=2.4, name='partition_top'))
    s.extend(table((6.0, 2.0), (1.6, 0.8), 0.74, name='desk'))
    s.extend(box((6.0, 3.2), (0.5, 0.5), 0.45, FABRIC, name='chair'))
    s.extend(box((7.6, 2.5), (0.45, 1.2), 1.9, WOOD, name='cabinet'))
    return s


def facing_mirrors():
    s = Scene('facing_mirrors', 'Two 60x40 mirrors on opposite walls of a 3.6 m wide room, facing each other '
              'at scanner height, the scanner between them (multiple reflections).')
    s.extend(room(0, 0, 5.0, 3.6, 2.6))
    _scanner_on_table(s, 2.3, 1.9)
    s.add(panel((2.5, 0.01, 1.1), 90.0, 0.60, 0.40, MIRROR_GLASS, 0.0, 'mirror_south'))
    s.add(panel((2.5, 3.59, 1.1), -90.0, 0.60, 0.40, MIRROR_GLASS, 0.0, 'mirror_north'))
    return s


def floor_mirror():
    s = Scene('floor_mirror', 'A 60x40 mirror lying flat on the floor 1.4 m from the scanner foot: seen at '
              '~55 deg incidence it gives no surface echo, only single-echo phantoms (mirrored ceiling).')
    s.extend(room(0, 0, 5.0, 4.0, 2.6))
    # A slim stand instead of a table, which would hide the floor in front of the scanner.
    s.extend(box((2.0, 2.0), (0.25, 0.25), 0.9, METAL_FRAME, name='scanner_stand'))
    s.scanner_pose = Pose((2.0, 2.0, SCANNER_HEIGHT), (0.0, 0.0, 0.0))
    s.add(Rectangle((3.4, 2.0, 0.005), (0, 1, 0), (-1, 0, 0), 0.60, 0.40, MIRROR_GLASS, 'mirror_floor'))
    return s


def mirror_and_glass():
    s = Scene('mirror_and_glass', 'A room with a 60x40 mirror leaning on the east wall and a 1.2x1.5 m '
              'window pane in the north wall, both about 2.2 m from the scanner, a yard behind the window.')
    window = (2.0, 3.2, 0.6, 2.1)  # north wall runs from x1 to x0
    s.extend(room(0, 0, 5.0, 4.2, 2.6, openings={'north': [window]}))
    _scanner_on_table(s, 2.6, 2.0)
    lean = 20.0
    s.add(leaning_panel((5.0 - 0.40 * math.sin(math.radians(lean)), 1.8, 0.0), 180.0, 0.60, 0.40,
                        MIRROR_GLASS, lean, 'mirror'))
    s.add(Rectangle((2.4, 4.2, 1.35), (-1, 0, 0), (0, 0, 1), 1.2, 1.5, WINDOW_GLASS, 'window'))
    # Outside: ground, a fence and a shed.
    s.add(horizontal((2.5, 9.2, -0.1), 12.0, 10.0, FLOOR, True, 'yard'))
    s.extend(wall((8.0, 11.0), (-3.0, 11.0), 1.8, name='fence'))
    s.extend(box((1.0, 7.0), (2.0, 1.5), 2.0, WOOD, name='shed'))
    return s


def two_mirrors_and_glass():
    s = Scene('two_mirrors_and_glass', 'mirror_and_glass with a second 60x40 mirror leaning on the west wall '
              '(about 2.6 m from the scanner): two mirrors and a window pane, a yard behind the window.')
    base = mirror_and_glass()
    s.extend(base.rectangles)
    s.scanner_pose = base.scanner_pose
    lean = 20.0
    s.add(leaning_panel((0.40 * math.sin(math.radians(lean)), 2.3, 0.0), 0.0, 0.60, 0.40,
                        MIRROR_GLASS, lean, 'mirror_west'))
    return s


def mirror_open_space():
    s = Scene('mirror_open_space', 'A 60x40 mirror leaning 15 deg back on a short wall in open space: its '
              'reflections go to the sky, so its surface echoes are single and there are no phantoms.')
    s.add(horizontal((0.0, 0.0, 0.0), 12.0, 12.0, FLOOR, True, 'ground'))
    s.extend(box((2.3, 0.0), (0.2, 3.0), 1.2, WALL, name='low_wall'))
    lean = 15.0
    s.add(leaning_panel((2.2 - 0.40 * math.sin(math.radians(lean)), 0.0, 0.0), 180.0, 0.60, 0.40,
                        MIRROR_GLASS, lean, 'mirror'))
    s.extend(table((0.0, 0.0), (0.8, 0.6), 0.75, name='scanner_table'))
    s.scanner_pose = Pose((0.0, 0.0, SCANNER_HEIGHT), (0.0, 0.0, 0.0))
    return s


def facing_tall_mirrors():
    s = Scene('facing_tall_mirrors', 'Two 0.9x1.9 m mirrors on opposite walls 2.4 m apart, facing each other, '
              'the scanner between them: surface echoes only near the perpendicular, beams reflected twice.')
    s.extend(room(0, 0, 5.0, 2.4, 2.6))
    _scanner_on_table(s, 2.3, 1.2)
    s.add(panel((2.5, 0.01, 1.05), 90.0, 0.90, 1.90, MIRROR_GLASS, 0.0, 'mirror_south'))
    s.add(panel((2.5, 2.39, 1.05), -90.0, 0.90, 1.90, MIRROR_GLASS, 0.0, 'mirror_north'))
    return s


def wall_mirror():
    s = Scene('wall_mirror', 'A 2x1.5 m mirror on the wall 1.5 m in front of the scanner: a surface echo only '
              'near the perpendicular, single-echo phantoms over the rest of it.')
    s.extend(room(0, 0, 5.0, 4.0, 2.6))
    _scanner_on_table(s, 3.5, 2.0)
    s.add(panel((4.99, 2.0, 1.25), 180.0, 2.0, 1.5, MIRROR_GLASS, 0.0, 'mirror'))
    return s


def pane_in_wall():
    s = Scene('pane_in_wall', 'A 2.4x1.5 m window pane in a wall 3 m in front of the scanner, a furnished room '
              'behind it: a surface echo only near the perpendicular.')
    window = (0.8, 3.2, 0.5, 2.0)   # east wall x = 5, along y
    s.extend(room(0, 0, 5.0, 4.0, 2.6, openings={'east': [window]}))
    s.extend(room(5.0, -1.0, 10.0, 5.0, 2.6, openings={'west': [(6.0 - 3.2 - 1.0, 6.0 - 0.8 - 1.0, 0.5, 2.0)]},
                  name='room_behind'))
    _scanner_on_table(s, 2.0, 2.0)
    s.add(Rectangle((5.0, 2.0, 1.25), (0, 1, 0), (0, 0, 1), 2.4, 1.5, WINDOW_GLASS, 'pane'))
    s.extend(table((7.5, 1.0), (1.6, 0.8), 0.74, name='desk'))
    s.extend(box((8.0, 3.2), (0.5, 0.5), 0.45, FABRIC, name='chair'))
    s.extend(box((9.6, 2.0), (0.45, 1.2), 1.9, WOOD, name='cabinet'))
    return s


def office():
    s = Scene('office', 'An office without mirrors or glass: desks, cabinets, chairs, a sideboard.')
    s.extend(room(0, 0, 6.0, 5.0, 2.7))
    _scanner_on_table(s, 3.0, 2.3)
    s.extend(table((1.0, 4.3), (1.6, 0.8), 0.74, name='desk1'))
    s.extend(table((5.0, 4.3), (1.6, 0.8), 0.74, name='desk2'))
    s.extend(table((3.0, 0.6), (1.6, 0.8), 0.74, name='desk3'))
    s.extend(box((0.25, 1.5), (0.45, 1.2), 1.9, WOOD, name='cabinet1'))
    s.extend(box((5.75, 1.0), (0.45, 0.9), 1.2, WOOD, name='cabinet2'))
    s.extend(box((1.2, 3.6), (0.5, 0.5), 0.45, FABRIC, name='chair1'))
    s.extend(box((4.8, 3.6), (0.5, 0.5), 0.45, FABRIC, name='chair2'))
    s.extend(box((0.5, 0.3), (0.9, 0.4), 0.9, WOOD, name='sideboard'))
    return s


def doorway_room():
    s = Scene('doorway_room', 'A room with a large doorway (1.6x2.1 m, no door) in the wall 2.4 m in front of '
              'the scanner, a corridor behind it: an opening is never glass.')
    doorway = (1.2, 2.8, 0.0, 2.1)   # east wall x = 5, along y
    s.extend(room(0, 0, 5.0, 4.0, 2.6, openings={'east': [doorway]}))
    s.extend(room(5.0, -2.0, 7.0, 6.0, 2.6, openings={'west': [(8.0 - 2.8 - 2.0, 8.0 - 1.2 - 2.0, 0.0, 2.1)]},
                  name='corridor'))
    _scanner_on_table(s, 2.6, 2.0)
    s.extend(box((6.5, 3.0), (0.45, 1.2), 1.9, WOOD, name='cabinet'))
    return s


_REGISTRY: Dict[str, Callable[[], Scene]] = {
    f.__name__: f for f in (experiment1, experiment2, experiment3, experiment4, empty_room, glass_wall,
                            facing_mirrors, floor_mirror, mirror_and_glass, mirror_open_space,
                            two_mirrors_and_glass, facing_tall_mirrors, wall_mirror, pane_in_wall, office,
                            doorway_room)
}


def names():
    """Names of the registered scenes."""
    return list(_REGISTRY)


RANDOM_PREFIX = 'random_'


def get(name):
    """A fresh instance of the named scene, or `random_SEED` for random_scenes.random_scene(SEED)
    (KeyError with the known names otherwise)."""
    if name.startswith(RANDOM_PREFIX) and name[len(RANDOM_PREFIX):].isdigit():
        from .random_scenes import random_scene
        return random_scene(int(name[len(RANDOM_PREFIX):]))
    try:
        return _REGISTRY[name]()
    except KeyError:
        raise KeyError('unknown scene %r; known: %s, or %sSEED (a random scene)'
                       % (name, ', '.join(_REGISTRY), RANDOM_PREFIX)) from None


def register(name, builder):
    """Adds a scene builder (a callable returning a Scene) to the registry."""
    _REGISTRY[name] = builder


def describe():
    """(name, description) of every registered scene."""
    return [(n, _REGISTRY[n]().description) for n in _REGISTRY]
