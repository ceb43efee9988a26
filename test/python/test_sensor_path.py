"""The simulator drives: paths stay inside the room and clear of furniture, are reproducible from their
seed, carry the poses the sweeps are simulated at, and are written into bags as /tf that tf2 reads back
as the simulated pose at every sweep's stamp (one cloud per sweep, and the rotating Hokuyo's scans)."""
import math

import numpy as np
import pytest

import rospy
import tf2_py

from ohm_mirror_detector3d import ros_io
from ohm_mirror_detector3d import scan_sequence as ss
from ohm_mirror_detector3d import scene as scenes
from ohm_mirror_detector3d import sensor_path as sp
from ohm_mirror_detector3d.dual_return_cloud import dual_return_messages
from ohm_mirror_detector3d.scanner import DualReturnLidar, RotatingHokuyo
from ohm_mirror_detector3d.simulate import SweepSimulator, true_xyz

RANDOM_SEEDS = range(0, 12)


@pytest.mark.parametrize('seed', RANDOM_SEEDS)
def test_random_walk_stays_inside_the_near_room_and_clear_of_everything(seed):
    scene = scenes.get('random_%d' % seed)
    path = sp.random_path(scene, 12, seed=seed)
    (x0, x1), (y0, y1) = scene.layout['near']
    top = scene.scanner_pose.position[2]
    assert len(path) == 12
    for pose in path.poses:
        x, y, z = pose.position
        assert x0 + sp.DEFAULT_CLEARANCE <= x <= x1 - sp.DEFAULT_CLEARANCE
        assert y0 + sp.DEFAULT_CLEARANCE <= y <= y1 - sp.DEFAULT_CLEARANCE
        assert z == top
        assert sp.clearance(scene, (x, y), top) >= sp.DEFAULT_CLEARANCE
    steps = np.linalg.norm(np.diff([p.position[:2] for p in path.poses], axis=0), axis=1)
    assert np.all(steps <= sp.DEFAULT_STEP + 1e-9)
    assert steps.sum() > 0.5 * sp.DEFAULT_STEP * len(steps), 'the sensor hardly moved: %s' % steps
    assert sp.is_clear(scene, path)


def test_random_walk_is_reproducible_from_its_seed_and_differs_between_seeds():
    scene = scenes.get('random_3')
    a, b = sp.random_path(scene, 8, seed=5), sp.random_path(scenes.get('random_3'), 8, seed=5)
    assert a.poses == b.poses
    assert sp.random_path(scene, 8, seed=6).poses != a.poses


def test_clearance_sees_furniture_the_mast_would_hit():
    scene = scenes.get('experiment1')   # the scanner's table (0.8 x 0.6 m, 0.75 m high) at (2.6, 2.0)
    assert sp.clearance(scene, (2.6, 2.0), 1.0) < 0.01
    assert sp.clearance(scene, (2.6, 2.0 + 0.3 + 0.5), 1.0) == pytest.approx(0.5, abs=0.06)


@pytest.mark.parametrize('name', sorted(sp.NAMED_PASSES))
def test_named_pass_runs_parallel_to_its_object_clear_of_the_furniture(name):
    scene = scenes.get(name)
    path = sp.scene_path(scene, 7)
    obj, distance = sp.NAMED_PASSES[name][:2]
    rect = next(r for r in scene.objects() if r.name == obj)
    assert sp.is_clear(scene, path), [sp.clearance(scene, p.position[:2], 1.0) for p in path.poses]
    start, end = (np.asarray(path.poses[i].position[:2]) for i in (0, -1))
    assert np.linalg.norm(end - start) == pytest.approx(2 * sp.NAMED_PASSES[name][2])
    if abs(rect.normal[2]) < 0.5:   # upright: every pose at `distance` from its vertical plane
        normal = np.asarray(rect.normal[:2]) / np.linalg.norm(rect.normal[:2])
        for p in path.poses:
            assert abs(normal @ (np.asarray(p.position[:2]) - np.asarray(rect.centre[:2]))) == pytest.approx(
                distance, abs=0.25 * distance)


def test_experiment2_pass_goes_past_both_panes_of_the_glass_door():
    path = sp.scene_path('experiment2', 5)
    ys = [p.position[1] for p in path.poses]
    panes = [r for r in scenes.get('experiment2').objects()]
    assert min(ys) < panes[0].centre[1] and max(ys) > panes[1].centre[1]
    np.testing.assert_allclose([p.position[0] for p in path.poses], 4.0 - 1.5)


def test_fixed_from_sweep_takes_the_sweep_into_the_scene():
    """The Python API's pose: the sweep's true points and objects, taken into the fixed frame, are where
    the scene has them, wherever the sensor is on its path."""
    scene = scenes.get('experiment2')
    path = sp.scene_path(scene, 3)
    simulator = SweepSimulator(scene, DualReturnLidar(rings=16, azimuth_steps=360))
    panes = {r.object_id: r for r in scene.objects()}
    for k in range(len(path)):
        sweep = simulator.sweep(seed=k, pose=path.poses[k])
        m = path.fixed_from_sweep(k)
        for o in sweep.objects:
            corners = np.asarray(o['corners']) @ m[:3, :3].T + m[:3, 3]
            np.testing.assert_allclose(corners, panes[o['id']].corners(), atol=1e-9)
        gt = sweep.ground_truth
        hit = np.isfinite(gt['true_x'])
        world = true_xyz(gt[hit]) @ m[:3, :3].T + m[:3, 3]
        # Inside the stairway and the corridor behind the door (x 0-9, y -1-4, z 0-3) ...
        assert np.all((world >= [-1e-3, -1.001, -1e-3]) & (world <= [9.001, 4.001, 3.001]))
        # ... and what is seen through the door lies behind it, in the corridor.
        behind = (gt['label'][hit] == 7) & (gt['object_id'][hit] >= 0)
        assert behind.sum() > 20 and np.all(world[behind, 0] > 4.0)
    np.testing.assert_allclose(path.matrices()[1], path.fixed_from_sweep(1))


def test_rotation_quaternion_round_trips_through_the_matrix():
    rng = np.random.default_rng(1)
    for _ in range(50):
        pose = scenes.Pose((0, 0, 0), tuple(rng.uniform(-math.pi, math.pi, 3)))
        q = sp.rotation_quaternion(pose.rotation())
        np.testing.assert_allclose(ss.quaternion_matrix(q), pose.rotation(), atol=1e-9)
        assert q[3] >= 0


def tf_buffer(bag_path):
    import rosbag
    buffer = tf2_py.BufferCore(rospy.Duration(1000.0))
    with rosbag.Bag(bag_path) as bag:
        for _, msg, _ in bag.read_messages(topics=['/tf']):
            for t in msg.transforms:
                buffer.set_transform(_plain_transform(t), 'bag')
    return buffer


def _plain_transform(t):
    """A bag's TransformStamped as the generated class tf2_py expects (a bag holds its own message classes)."""
    from geometry_msgs.msg import TransformStamped
    out = TransformStamped()
    out.deserialize(_serialized(t))
    return out


def _serialized(msg):
    from io import BytesIO
    buffer = BytesIO()
    msg.serialize(buffer)
    return buffer.getvalue()


def assert_pose(transform, translation, rotation):
    t, r = transform.transform.translation, transform.transform.rotation
    np.testing.assert_allclose([t.x, t.y, t.z], translation, atol=1e-6)
    np.testing.assert_allclose(ss.quaternion_matrix((r.x, r.y, r.z, r.w)), rotation, atol=1e-6)


def test_bag_of_a_driving_lidar_has_tf_giving_each_sweeps_pose_at_its_stamp(tmp_path):
    scene = scenes.get('random_5')
    path = sp.random_path(scene, 4, seed=2)
    simulator = SweepSimulator(scene, DualReturnLidar(rings=8, azimuth_steps=90))
    sweeps = [simulator.sweep(seed=k, pose=path.poses[k]) for k in range(len(path))]
    bag = str(tmp_path / 'drive.bag')
    stamps = ros_io.write_sweeps_bag(bag, sweeps, start_time=20.0, period=0.1, frame_id='lidar',
                                     to_messages=lambda s, stamp, frame: dual_return_messages(s, stamp, frame),
                                     sensor_path=path)
    clouds = ros_io.read_bag_by_stamp(bag, ['/points'])['/points']
    buffer = tf_buffer(bag)
    assert sorted(clouds) == stamps
    for k, stamp in enumerate(stamps):
        frame = clouds[stamp].header.frame_id
        assert frame == 'lidar'
        assert_pose(buffer.lookup_transform_core(sp.FIXED_FRAME, frame, stamp), path.poses[k].position,
                    path.poses[k].rotation())


def test_scan_stream_on_a_path_has_the_sweep_frames_pose_at_every_sweep_stamp(tmp_path):
    """The rotating Hokuyo on a path: odom <- base_link beside the rotating base_link <- laser; at the stamp
    of each assembled sweep (its ground truth's) tf gives the sweep's pose, the optical centre at the
    simulated position."""
    offset = (0.05, 0.0, 0.3)
    path = sp.scene_path('experiment1', 3)
    stream = ss.ScanStream('experiment1', RotatingHokuyo(scans=6, continuous=True), seed=1, start_time=30.0,
                           laser_offset=offset, path=path)
    bag = str(tmp_path / 'scans.bag')
    stamps = ros_io.write_scan_stream_bag(bag, stream, len(path))
    buffer = tf_buffer(bag)
    assert len(stamps) == len(path)
    for k, stamp in enumerate(stamps):
        rotation = path.poses[k].rotation()
        base = np.asarray(path.poses[k].position) - rotation @ offset
        assert_pose(buffer.lookup_transform_core(sp.FIXED_FRAME, 'base_link', stamp), base, rotation)
        laser = buffer.lookup_transform_core(sp.FIXED_FRAME, 'laser', stamp).transform.translation
        np.testing.assert_allclose([laser.x, laser.y, laser.z], path.poses[k].position, atol=1e-6)
    truth = ros_io.read_bag_by_stamp(bag, ['/ground_truth_objects'])['/ground_truth_objects']
    for k, stamp in enumerate(stamps):   # the ground truth of sweep k is that of its own pose
        corners = ros_io.objects_from_msg(truth[stamp])[0]['corners']
        m = path.fixed_from_sweep(k)
        world = (corners - offset) @ m[:3, :3].T + m[:3, 3]
        np.testing.assert_allclose(world, scenes.get('experiment1').objects()[0].corners(), atol=1e-5)
