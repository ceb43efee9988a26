"""pytest configuration: the rostest checkers under test/ros need a master and are run by
rostest, not collected here."""
collect_ignore_glob = ['../ros/*']

import pytest


@pytest.fixture(scope='session')
def experiment1_sweep():
    """A noisy experiment1 sweep at r = 200 (216000 beams), shared by the simulator and evaluator tests."""
    from ohm_mirror_detector3d import scanner, simulate
    return simulate.simulate_sweep('experiment1', scanner.RotatingHokuyo(scans=200), seed=7)


@pytest.fixture(scope='session')
def experiment1_sweep_noiseless():
    from ohm_mirror_detector3d import scanner, simulate
    return simulate.simulate_sweep('experiment1', scanner.RotatingHokuyo(scans=200, range_noise=0.0), seed=7)


@pytest.fixture(scope='session')
def ros_messages():
    """Skips ROS-IO tests when the package's messages are not built (numpy-only runs)."""
    pytest.importorskip('rospy')
    pytest.importorskip('rosbag')
    pytest.importorskip('ohm_mirror_detector3d.msg')
    from ohm_mirror_detector3d import ros_io
    return ros_io
