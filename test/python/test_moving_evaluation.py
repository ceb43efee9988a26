"""The moving-sensor evaluation: every sweep of a path is simulated at its pose and scored like a single
sweep; the pipeline is made fresh per path; the pose goes to the pipeline only when asked for; objects
are judged by the last detection that matched them on their path."""
import numpy as np
import pytest

from ohm_mirror_detector3d import core, metrics
from ohm_mirror_detector3d import moving_evaluation as me
from ohm_mirror_detector3d import scanner as scanners
from ohm_mirror_detector3d import scene as scenes
from ohm_mirror_detector3d.scene_evaluation import filter_case
from ohm_mirror_detector3d.sensor_path import scene_path
from ohm_mirror_detector3d.simulate import SweepSimulator, ground_truth_objects

FAMILY = 'velodyne_hdl32e'   # the lightest dual-return family


class PoseRecordingPipeline(core.Pipeline):
    """The real pipeline, which also accepts and records the pose a post-filter would get."""

    def __init__(self, made):
        super().__init__()
        self.poses = []
        made.append(self)

    def filter_dual_return(self, points, pose=None, **kwargs):
        self.poses.append(pose)
        return super().filter_dual_return(points, **kwargs)


@pytest.fixture(scope='module')
def wall_mirror_pass():
    made = []
    sequence = me.Sequence(FAMILY, 'wall_mirror', 'named', 1, 3)
    return sequence, made, me.run_sequence(sequence, lambda: PoseRecordingPipeline(made), pass_pose=True)


def test_each_sweep_is_the_single_sweep_evaluation_at_its_pose(wall_mirror_pass):
    sequence, _, results = wall_mirror_pass
    path = scene_path('wall_mirror', 3, 1)
    simulator = SweepSimulator(scenes.get('wall_mirror'), scanners.preset(FAMILY))
    assert [r['sweep'] for r in results] == [0, 1, 2]
    for k in (0, 2):
        sweep = simulator.sweep(seed=1 + k, pose=path.poses[k])
        expected = metrics.evaluate_sweep(*filter_case(core.Pipeline(), sweep, 'dual_return'),
                                          ground_truth_objects(sweep))
        assert results[k]['counts'] == expected['counts']
        assert results[k]['scene'] == 'wall_mirror' and results[k]['family'] == FAMILY
    # The mirror is seen from three places: its phantoms differ from sweep to sweep.
    assert len({r['counts']['phantoms'] for r in results}) > 1


def test_pipeline_gets_each_sweeps_fixed_from_sweep_only_when_asked(wall_mirror_pass):
    _, made, _ = wall_mirror_pass
    path = scene_path('wall_mirror', 3, 1)
    assert len(made) == 1, 'one pipeline per path'
    for k, pose in enumerate(made[0].poses):
        np.testing.assert_allclose(pose, path.fixed_from_sweep(k))
    made.clear()
    me.run_sequence(me.Sequence(FAMILY, 'wall_mirror', 'named', 1, 2), lambda: PoseRecordingPipeline(made))
    assert made[0].poses == [None, None]


def test_summary_judges_each_object_by_its_last_matching_detection(wall_mirror_pass):
    _, _, results = wall_mirror_pass
    summary = me.summarise(results)[FAMILY]
    assert summary['sweeps'] == 3 and summary['paths'] == 1
    assert summary['objects'] == 1
    extent = summary['object_extents'][0]
    last = max((r for r in results if r['objects'][0]['matched']), key=lambda r: r['sweep'])
    m = last['objects'][0]
    assert extent['last_matched_sweep'] == last['sweep']
    assert extent['extent_error'] == pytest.approx(max(abs(m['width_error']), abs(m['height_error'])))
    assert summary['objects_within_tolerance'] == int(extent['extent_error'] <= me.EXTENT_TOLERANCE)
    pooled = metrics.aggregate_results(results)
    assert summary['phantom_wrong_place_fraction'] == pooled['phantom_wrong_place_fraction']
    assert '| phantoms left at a wrong place, of all phantoms | ≤ 1 % |' in me.table(me.summarise(results))


def test_sequences_are_random_walks_then_the_named_passes():
    todo = me.sequences([FAMILY, 'hokuyo_utm30lx_ew'], count=2, seed=10, named=('experiment2',), sweeps=4)
    assert [(s.family, s.scene, s.kind) for s in todo] == [
        (FAMILY, 'random_10', 'random'), (FAMILY, 'random_11', 'random'), (FAMILY, 'experiment2', 'named'),
        ('hokuyo_utm30lx_ew', 'random_10', 'random'), ('hokuyo_utm30lx_ew', 'random_11', 'random'),
        ('hokuyo_utm30lx_ew', 'experiment2', 'named')]
    assert todo[2].scans is None and todo[5].scans == 400 and 100 <= todo[3].scans <= 1000
