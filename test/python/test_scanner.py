"""Scanner models: beam counts, grid layout and angular coverage."""
import math

import numpy as np

from ohm_mirror_detector3d import scanner
from ohm_mirror_detector3d.scene import Pose


def test_hokuyo_beam_count_and_layout():
    s = scanner.RotatingHokuyo(scans=400)
    d = s.directions()
    assert (s.rows, s.cols) == (400, 1080) and d.shape == (400 * 1080, 3)
    np.testing.assert_allclose(np.linalg.norm(d, axis=1), 1.0)
    # Within a scan, beams are 0.25 deg apart, spanning 270 deg; all beams of row k lie in one vertical plane.
    steps = np.degrees(np.diff(s.beam_angles()))
    np.testing.assert_allclose(steps, 0.25)
    assert math.isclose(np.degrees(s.beam_angles()[-1] - s.beam_angles()[0]) + 0.25, 270.0)
    row = d.reshape(400, 1080, 3)[37]
    normal = np.cross(row[100], row[900])
    np.testing.assert_allclose(row @ normal / np.linalg.norm(normal), 0, atol=1e-12)
    assert abs(normal[2]) < 1e-12  # the scan plane contains the vertical axis


def test_hokuyo_half_rotation_covers_the_sphere_except_a_cone_below():
    s = scanner.RotatingHokuyo(scans=90)  # 2 deg between scans
    d = s.directions()
    # Nothing looks into the 45 deg cone straight down (the mount) ...
    down_angle = np.degrees(np.arccos(np.clip(-d[:, 2], -1, 1)))
    assert down_angle.min() > 44.8
    # ... and every other direction has a beam within ~1.5 deg.
    rng = np.random.default_rng(1)
    probe = rng.normal(size=(3000, 3))
    probe /= np.linalg.norm(probe, axis=1, keepdims=True)
    probe = probe[np.degrees(np.arccos(-probe[:, 2])) > 46.0]
    worst = 0.0
    for chunk in np.array_split(probe, 60):
        worst = max(worst, np.degrees(np.arccos(np.clip((chunk @ d.T).max(axis=1), -1, 1))).max())
    assert worst < 1.5


def test_dual_return_lidar_grid():
    s = scanner.DualReturnLidar(rings=16, azimuth_steps=360, vertical_fov_deg=(-15.0, 15.0))
    d = s.directions().reshape(16, 360, 3)
    el = np.degrees(np.arcsin(d[..., 2]))
    np.testing.assert_allclose(el[:, 0], np.linspace(-15, 15, 16))
    np.testing.assert_allclose(el.std(axis=1), 0, atol=1e-9)  # rows = rings
    az = np.degrees(np.arctan2(d[3, :, 1], d[3, :, 0])) % 360
    np.testing.assert_allclose(az, np.arange(360.0), atol=1e-9)  # cols = azimuth steps


def test_pose_rotates_and_translates_rays():
    s = scanner.BeamList([[1, 0, 0], [0, 0, 1]])
    origin, d = scanner.world_rays(s, Pose((1.0, 2.0, 3.0), (0.0, 0.0, math.pi / 2)))
    np.testing.assert_allclose(origin, [1, 2, 3])
    np.testing.assert_allclose(d, [[0, 1, 0], [0, 0, 1]], atol=1e-12)


def test_make_scanner_by_name():
    assert scanner.make_scanner('hokuyo', scans=10).rows == 10
    lidar = scanner.make_scanner('dual_return', scans=32)
    assert (lidar.rows, lidar.cols) == (32, 2048)
