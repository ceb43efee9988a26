"""The post-filter through the Python API (ohm_mirror_detector3d.core.Pipeline): a pose per sweep
(fixed_from_sweep, 4 x 4), the map objects in the fixed frame, the map file. No ROS, no master.

The window pane of pane_in_wall gives a surface echo only near the perpendicular: sweeps from
places 0.25 m apart along the wall each see another patch of it, and the map's one object grows
(with grow_objects 0, the paper's patches; by default each sweep grows the pane to its frame).
"""
import numpy as np
import pytest

core = pytest.importorskip('ohm_mirror_detector3d.core',
                           reason='the bindings are not built (build, then source .ws/devel/setup.bash)')

from ohm_mirror_detector3d import scene as scenes  # noqa: E402
from ohm_mirror_detector3d.scanner import RotatingHokuyo  # noqa: E402
from ohm_mirror_detector3d.scene import Pose  # noqa: E402
from ohm_mirror_detector3d.simulate import simulate_sweep  # noqa: E402


def fixed_from_sweep(pose):
    matrix = np.eye(4)
    matrix[:3, :3] = pose.rotation()
    matrix[:3, 3] = pose.position
    return matrix


@pytest.fixture(scope='module')
def pane_sweeps():
    scene = scenes.get('pane_in_wall')
    start = scene.scanner_pose
    poses = [Pose((start.position[0], start.position[1] + dy, start.position[2]), (0.0, 0.0, 0.1 * k))
             for k, dy in enumerate((0.0, 0.25, 0.5))]
    return [(simulate_sweep(scene, RotatingHokuyo(scans=200, range_noise=0.01), seed=k, pose=pose), pose)
            for k, pose in enumerate(poses)]


def test_a_map_object_keeps_its_id_and_grows_over_sweeps_in_the_fixed_frame(pane_sweeps):
    pipeline = core.Pipeline(post_filter=1, grow_objects=0)
    widths = []
    for k, (sweep, pose) in enumerate(pane_sweeps):
        pipeline.filter(sweep.echo1, sweep.echo2, pose=fixed_from_sweep(pose))
        objects = pipeline.map_objects(viewpoint=pose.position)
        assert [o['id'] for o in objects] == [0]
        assert objects[0]['type_name'] == 'glass'
        assert objects[0]['sweeps_seen'] == k + 1
        assert objects[0]['mirror_log_odds'] < 0
        np.testing.assert_allclose(objects[0]['corners'][:, 0], 5.0, atol=0.05)  # the pane's plane in the world
        widths.append(objects[0]['width'])
    assert widths[0] + 0.1 < widths[1] < widths[2] - 0.1 and widths[2] <= 2.4, widths


def test_with_the_defaults_the_first_sweep_already_maps_the_whole_pane(pane_sweeps):
    # The 2.4 m pane, grown to its frame in the sweep itself (grow_objects 2).
    pipeline = core.Pipeline(post_filter=1)
    sweep, pose = pane_sweeps[0]
    pipeline.filter(sweep.echo1, sweep.echo2, pose=fixed_from_sweep(pose))
    objects = pipeline.map_objects(viewpoint=pose.position)
    assert [o['type_name'] for o in objects] == ['glass']
    assert 2.3 <= objects[0]['width'] <= 2.45, objects[0]['width']


def test_without_a_pose_or_with_post_filter_off_nothing_is_kept(pane_sweeps):
    sweep, pose = pane_sweeps[0]
    pipeline = core.Pipeline(post_filter=1)
    single = core.Pipeline()
    with_no_pose = pipeline.filter(sweep.echo1, sweep.echo2)
    assert pipeline.map_objects() == []
    alone = single.filter(sweep.echo1, sweep.echo2, pose=fixed_from_sweep(pose))
    assert single.map_objects() == []
    np.testing.assert_array_equal(with_no_pose.labelled, alone.labelled)


@pytest.mark.parametrize('pose, problem', [
    (np.eye(3), '4 x 4'),
    (np.diag([2.0, 1.0, 1.0, 1.0]), 'rigid'),
    (np.diag([-1.0, 1.0, 1.0, 1.0]), 'rigid'),
    (np.full((4, 4), np.nan), 'rigid'),
])
def test_a_bad_pose_is_refused(pane_sweeps, pose, problem):
    sweep, _ = pane_sweeps[0]
    with pytest.raises(ValueError, match=problem):
        core.Pipeline(post_filter=1).filter(sweep.echo1, sweep.echo2, pose=pose)


def test_the_map_file_round_trips_and_a_corrupt_one_raises_and_empties_the_map(pane_sweeps, tmp_path):
    pipeline = core.Pipeline(post_filter=1)
    for sweep, pose in pane_sweeps[:2]:
        pipeline.filter(sweep.echo1, sweep.echo2, pose=fixed_from_sweep(pose))
    path = tmp_path / 'map.yaml'
    pipeline.save_map(path, 'odom')
    restarted = core.Pipeline(post_filter=1)
    restarted.load_map(path, 'odom')
    before, after = pipeline.map_objects(), restarted.map_objects()
    assert [(o['id'], o['type'], o['width'], o['height'], o['sweeps_seen'], o['mirror_log_odds']) for o in after] == \
        [(o['id'], o['type'], o['width'], o['height'], o['sweeps_seen'], o['mirror_log_odds']) for o in before]
    np.testing.assert_allclose(after[0]['corners'], before[0]['corners'], atol=1e-6)
    with pytest.raises(ValueError, match="frame 'odom'"):
        restarted.load_map(path, 'map')
    assert restarted.map_objects() == []
    path.write_text(path.read_text().replace('sweeps_seen: 2', 'sweeps_seen: two'))
    with pytest.raises(ValueError, match='sweeps_seen'):
        restarted.load_map(path, 'odom')
    assert restarted.map_objects() == []
