"""The rotating Hokuyo as scans + tf: projecting every beam with the interpolated transform at its own time
reproduces the simulated points, in both half rotations, with the ground truth in the sweep frame."""
import math

import numpy as np
import pytest

from ohm_mirror_detector3d import scan_sequence as ss
from ohm_mirror_detector3d.scanner import RotatingHokuyo
from ohm_mirror_detector3d.simulate import xyz

OFFSET = (0.1, -0.2, 0.3)


@pytest.fixture(scope='module')
def stream():
    return ss.ScanStream('experiment1', RotatingHokuyo(scans=20, continuous=True, range_noise=0.01), seed=3,
                         start_time=50.0, laser_offset=OFFSET)


def interpolated_pose(stream):
    """What tf does with one transform per scan start: linear interpolation (slerp about z) in between."""
    def pose_at(t):
        g = (t - stream.start_time) / stream.scanner.scan_time
        alpha = g * stream.scanner.rotation_step
        return np.array(OFFSET), ss.quaternion_matrix(ss.laser_quaternion(alpha))
    return pose_at


def test_mount_puts_beam_angle_zero_on_the_zenith_and_the_fan_in_the_plane_at_alpha():
    rot = ss.quaternion_matrix(ss.MOUNT_QUATERNION)
    np.testing.assert_allclose(np.linalg.det(rot), 1.0)
    np.testing.assert_allclose(rot @ [1, 0, 0], [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(rot @ [0, 1, 0], [1, 0, 0], atol=1e-12)
    alpha = 0.7
    rz = np.array([[math.cos(alpha), -math.sin(alpha), 0], [math.sin(alpha), math.cos(alpha), 0], [0, 0, 1]])
    np.testing.assert_allclose(ss.quaternion_matrix(ss.laser_quaternion(alpha)), rz @ rot, atol=1e-12)


def test_geometry_is_the_utm30_beam_grid(stream):
    g = stream.geometry
    assert math.isclose(math.degrees(g.angle_increment), 0.25, rel_tol=1e-9)
    assert math.isclose(g.angle_min + 1079 * g.angle_increment, g.angle_max, abs_tol=1e-9)
    assert math.isclose(g.time_increment, 0.025 / 1440)
    assert (g.range_min, g.range_max) == (0.1, 30.0)


@pytest.mark.parametrize('j', [0, 1])
def test_projecting_every_beam_with_tf_reproduces_the_sweep(stream, j):
    sweep = stream.sweep(j)
    truth = stream.ground_truth(sweep)
    n = sweep.num_beams
    gt = truth.ground_truth
    expected = np.stack([xyz(gt[:n]), xyz(gt[n:])], axis=1)  # (n, 2, 3), in the sweep frame
    pose_at = interpolated_pose(stream)
    scans = stream.scans(j, sweep)
    assert len(scans) == stream.scans_per_sweep
    got = np.concatenate([ss.project_scan(s, stream.geometry, pose_at) for s in scans])
    assert got.shape == expected.shape
    finite = np.isfinite(expected)
    np.testing.assert_array_equal(np.isfinite(got), finite)
    np.testing.assert_allclose(got[finite], expected[finite], atol=2e-5)
    # The assembled sweep's last scan carries the sweep's stamp.
    assert scans[-1].stamp == stream.sweep_stamp(j)
    assert truth.frame_id == 'base_link'


def test_echo_lists_have_zero_one_or_two_echoes(stream):
    sweep = stream.sweep(0)
    ranges, intensities = ss.beam_echoes(sweep)
    counts = np.array([len(r) for r in ranges])
    assert set(np.unique(counts)) == {1, 2}  # a closed room: every beam returns
    assert np.isfinite(sweep.echo1['x']).all()
    empty = sweep.echo1.copy()
    empty['x'][:3] = np.nan
    assert [len(r) for r in ss.beam_echoes(ss.replace(sweep, echo1=empty, echo2=empty))[0][:4]] == [0, 0, 0, 1]
    assert [len(i) for i in intensities] == list(counts)
    two = [r for r in ranges if len(r) == 2]
    assert all(r[0] <= r[1] for r in two)  # first = nearest


def test_ground_truth_objects_move_with_the_frame(stream):
    sweep = stream.sweep(0)
    truth = stream.ground_truth(sweep)
    for before, after in zip(sweep.objects, truth.objects):
        np.testing.assert_allclose(after['corners'], before['corners'] + np.array(OFFSET))
        plane = after['plane']
        np.testing.assert_allclose(after['corners'] @ plane[:3] + plane[3], 0, atol=1e-9)
        assert np.array(OFFSET) @ plane[:3] + plane[3] > 0  # the normal still points at the sensor
