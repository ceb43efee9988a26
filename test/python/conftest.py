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


@pytest.fixture(scope='session')
def evaluation_sweep():
    """A function (family, scene) -> the sweep of one of the evaluation's random scenes (realistic
    physics, its own seed), as make evaluate simulates it."""
    from ohm_mirror_detector3d import scene as scenes
    from ohm_mirror_detector3d import scene_evaluation as ev
    from ohm_mirror_detector3d.simulate import SweepSimulator

    def sweep(family, scene):
        case = ev.cases([family], 1, int(scene.rsplit('_', 1)[1]), named=False)[0]
        return SweepSimulator(scenes.get(case.scene), ev.scanner_of(case)).sweep(seed=case.seed)
    return sweep


@pytest.fixture(scope='session')
def filtered_and_scored():
    """A function (family, sweep, params=None) -> (figures, objects): the sweep filtered through the
    Python bindings as the evaluation does (the defaults without params), scored by its metrics."""
    core = pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')
    from ohm_mirror_detector3d import metrics
    from ohm_mirror_detector3d import scene_evaluation as ev
    from ohm_mirror_detector3d.simulate import ground_truth_objects

    def filtered(family, sweep, params=None):
        ground_truth, labelled, cleaned, objects = ev.filter_case(
            core.Pipeline(params if params is not None else core.Params()), sweep, ev.INPUT_MODES[family])
        return metrics.evaluate_sweep(ground_truth, labelled, cleaned, objects, ground_truth_objects(sweep)), objects
    return filtered


@pytest.fixture(scope='session')
def defaults_beside(evaluation_sweep, filtered_and_scored):
    """A function (family, scene, **params) -> ((figures, objects) with the default parameters,
    (figures, objects) with the given ones) on one of the evaluation's random scenes
    (evaluation_sweep, filtered_and_scored). For the tests of one stage on a whole sweep, with the
    stage on and off."""
    import dataclasses

    core = pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')

    def run(family, scene, **params):
        sweep = evaluation_sweep(family, scene)
        return filtered_and_scored(family, sweep), filtered_and_scored(
            family, sweep, dataclasses.replace(core.Params(), **params))
    return run
