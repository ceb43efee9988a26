"""The randomised scene generator: deterministic per seed, varied across seeds, and what it promises
(rooms of random size, glass, windows with frames, mirrors of random size and tilt, metal, doorways that
are openings, furniture and people on both sides of glass, plain scenes, the sensor inside and clear)."""
import numpy as np
import pytest

from ohm_mirror_detector3d import random_scenes, scanner, scene, simulate
from ohm_mirror_detector3d.labels import Label

SEEDS = range(40)


@pytest.fixture(scope='module')
def scenes():
    return [random_scenes.random_scene(s) for s in SEEDS]


def signature(s):
    return [(r.centre, r.axis_u, r.axis_v, r.width, r.height, r.material.name, r.object_id) for r in s.rectangles], \
        s.scanner_pose


def test_the_same_seed_gives_the_same_scene_and_other_seeds_other_scenes(scenes):
    assert signature(random_scenes.random_scene(7)) == signature(scenes[7])
    assert scene.get('random_7').description == scenes[7].description
    assert len({repr(signature(s)) for s in scenes}) == len(scenes)
    sizes = np.array([[r.width for r in s.rectangles if r.name == 'room_floor'][0] for s in scenes])
    assert sizes.min() < 5.0 and sizes.max() > 8.5  # rooms of random size
    with pytest.raises(ValueError):
        random_scenes.random_scene(-1)


def test_scenes_hold_every_kind_of_element_and_some_hold_no_reflective_surface(scenes):
    names = [r.name for s in scenes for r in s.rectangles]
    for part in ('partition_pane', 'glass_door', 'window_', 'window_frame', 'mullion', 'mirror_', 'metal_',
                 'corridor_end', 'table', 'person', 'facade'):
        assert any(n.startswith(part) or ('_' + part) in n for n in names), part
    plain = [s for s in scenes if random_scenes.is_plain(s)]
    assert 0.1 * len(scenes) <= len(plain) <= 0.45 * len(scenes)
    assert all('no mirror, glass or metal' in s.description for s in plain)
    kinds = {r.material.kind for s in scenes for r in s.objects()}
    assert kinds == {scene.MIRROR, scene.GLASS, scene.METAL}


def test_mirrors_come_in_random_sizes_and_tilts(scenes):
    mirrors = [r for s in scenes for r in s.objects() if r.material.kind == scene.MIRROR]
    assert len(mirrors) >= 15
    widths = np.array([m.width for m in mirrors])
    tilts = np.degrees(np.arcsin(np.abs([np.cross(m.axis_u, m.axis_v)[2] for m in mirrors])))
    assert widths.min() < 0.5 and widths.max() > 0.9
    assert tilts.min() < 2.0 and tilts.max() > 10.0


def test_the_sensor_stands_inside_the_room_clear_of_everything(scenes):
    for s in scenes:
        floor = [r for r in s.rectangles if r.name == 'room_floor'][0]
        x, y, z = s.scanner_pose.position
        assert 0.4 <= z <= 1.8
        assert abs(x - floor.centre[0]) < floor.width / 2 - 0.4 and abs(y - floor.centre[1]) < floor.height / 2 - 0.4
        # No rectangle within 0.2 m of the sensor (it is not inside furniture or a person).
        sa = simulate.SceneArrays(s)
        rel = np.asarray(s.scanner_pose.position) - sa.centre
        along_u, along_v, off = (np.abs(np.einsum('ij,ij->i', rel, a)) for a in (sa.u, sa.v, sa.normal))
        inside = (along_u <= sa.half_w + 0.2) & (along_v <= sa.half_h + 0.2) & (off < 0.2)
        assert not inside.any(), (s.name, [s.rectangles[i].name for i in np.flatnonzero(inside)])


def test_a_random_scene_simulates_with_every_kind_of_point():
    """Scene 3: a glass partition with a glass door, furniture and people on both sides, metal."""
    s = random_scenes.random_scene(3)
    sweep = simulate.simulate_sweep(s, scanner.preset('ouster_os0_128'), seed=3)
    labels = sweep.counts()['labels']
    for name in ('valid', 'reflective_surface', 'behind_reflective', 'transparent_surface', 'behind_transparent'):
        assert labels.get(name, 0) > 100, (name, labels)
    # People and furniture behind the glass are seen through it.
    gt = sweep.ground_truth
    behind = gt[gt['label'] == Label.BEHIND_TRANSPARENT]
    assert len(behind) > 1000


def test_doorways_are_openings_not_glass(scenes):
    """Beams from inside the room out through a doorway meet no glass and no wall in the opening."""
    checked = 0
    for s in scenes:
        sa = simulate.SceneArrays(s)
        for door in s.layout.get('doorways', []):
            centre, inward = np.asarray(door['centre']), np.asarray(door['inward'])
            along = np.cross(inward, [0.0, 0.0, 1.0])
            # A fan of rays from 0.5 m inside, through the middle half of the opening, out into the corridor.
            targets = [centre + along * a * door['width'] / 4 + np.array([0, 0, b * door['height'] / 4])
                       for a in (-1, 0, 1) for b in (-1, 0, 1)]
            origin = centre + 0.5 * inward
            d = np.array([t - origin for t in targets])
            d /= np.linalg.norm(d, axis=1, keepdims=True)
            t, k = sa.nearest_hit(np.broadcast_to(origin, d.shape).copy(), d, np.full(len(d), -1))
            hit = [s.rectangles[i] for i in k if i >= 0]
            assert all(r.material.kind != scene.GLASS for r in hit), s.name
            assert (t > 0.55).all(), (s.name, [r.name for r in hit])   # nothing in the opening itself
            checked += 1
    assert checked >= 10
