"""The Python bindings give the nodelet's output bit for bit.

prefilter_bag runs the nodelet's MessagePipeline (the very code the nodelet runs on its topics)
over a bag with no master; the same simulated sweep goes through ohm_mirror_detector3d.core, and
`labelled` and `cleaned` must be byte-identical to the messages' data, objects field for field.
Skipped when prefilter_bag or the bindings are not built.
"""
import os

import numpy as np
import pytest

core = pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')

from ohm_mirror_detector3d import scanner, simulate  # noqa: E402
from ohm_mirror_detector3d.physics import PhysicsParams  # noqa: E402
from test_prefilter_bag import find_binary, run  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HOKUYO_PARAMS = os.path.join(REPO, 'launch', 'rotating_hokuyo_params.yaml')
DUAL_RETURN_PARAMS = os.path.join(REPO, 'launch', 'dual_return_params.yaml')
# The mirror-finding assertions below are pinned to the ideal physics (glass never reflects, no mixed
# pixels) until the filter work of issue 14: with the realistic physics today's filter also reports a
# false glass object in experiment 1 (README, "Pinned tests").
IDEAL = PhysicsParams.ideal()
OBJECT_FIELDS = ('id', 'type', 'width', 'height', 'surface_points', 'behind_points', 'phantom_points',
                 'transmitted_points', 'ambiguous_points', 'undecided_points', 'mirrored_points', 'tested_points',
                 'inlier_fraction', 'real_fraction', 'landing_fitness', 'plane_refined', 'plane_correction',
                 'mean_surface_intensity', 'patch_width', 'patch_height', 'growth_capped')


@pytest.fixture(scope='module')
def binary(ros_messages):
    path = find_binary()
    if path is None:
        pytest.skip('prefilter_bag is not built')
    return path


def nodelet_outputs(binary, in_bag, out_bag, *args):
    """{output: [message per sweep]} of prefilter_bag on in_bag."""
    import rosbag
    run(binary, in_bag, out_bag, '--only-outputs', *args)
    out = {}
    with rosbag.Bag(str(out_bag)) as bag:
        for topic, msg, _ in bag.read_messages():
            out.setdefault(topic.rsplit('/', 1)[-1], []).append(msg)
    return out


def assert_same_output(result, labelled, cleaned, objects):
    assert labelled.point_step == core.OUTPUT_DTYPE.itemsize == 24
    assert result.labelled.tobytes() == bytes(labelled.data)
    assert result.cleaned.tobytes() == bytes(cleaned.data)
    assert len(result.objects) == len(objects.objects)
    from ohm_mirror_detector3d import ros_io
    for mine, theirs in zip(result.objects, ros_io.objects_from_msg(objects)):
        for key in OBJECT_FIELDS:
            np.testing.assert_array_equal(mine[key], theirs[key], err_msg=key)
        # float32 in the core; the message holds them as float64 (corners) and float32 (plane).
        np.testing.assert_array_equal(mine['corners'], theirs['corners'])
        np.testing.assert_array_equal(mine['plane'].astype(np.float32), theirs['plane'].astype(np.float32))


def test_pair_mode_labels_are_the_nodelets_bit_for_bit(binary, ros_messages, tmp_path):
    sweeps = [simulate.simulate_sweep('experiment1', scanner.RotatingHokuyo(scans=120, range_noise=0.01), seed=k,
                                      physics=IDEAL) for k in (1, 2)] + \
        [simulate.simulate_sweep('mirror_and_glass', scanner.RotatingHokuyo(scans=120), seed=4, physics=IDEAL)]
    in_bag = tmp_path / 'in.bag'
    ros_messages.write_sweeps_bag(str(in_bag), sweeps)
    out = nodelet_outputs(binary, in_bag, tmp_path / 'out.bag', '--params', HOKUYO_PARAMS)
    # One Pipeline for all sweeps, as the nodelet: its reused buffers must not leak between sweeps.
    pipeline = core.Pipeline(core.Params.from_yaml(HOKUYO_PARAMS))
    types = []
    for k, sweep in enumerate(sweeps):
        # Organised as the bag's clouds: the per-point evidence takes its angular step from the grid.
        grid = (sweep.rows, sweep.cols)
        result = pipeline.filter(sweep.echo1.reshape(grid), sweep.echo2.reshape(grid))
        assert_same_output(result, out['labelled'][k], out['cleaned'][k], out['objects'][k])
        types.append(sorted(o['type_name'] for o in result.objects))
    assert types[:2] == [['mirror'], ['mirror']]  # a sweep that exercises every stage
    assert 'glass' in types[2]


def test_dual_return_mode_labels_are_the_nodelets_bit_for_bit(binary, ros_messages, tmp_path):
    from ohm_mirror_detector3d.dual_return_cloud import dual_return_arrays, dual_return_messages
    lidar = scanner.DualReturnLidar(rings=64, azimuth_steps=1024, vertical_fov_deg=(-45.0, 45.0), range_noise=0.01)
    sweep = simulate.simulate_sweep('experiment1', lidar, seed=1, physics=IDEAL)
    params = tmp_path / 'params.yaml'
    params.write_text(open(DUAL_RETURN_PARAMS).read().replace('azimuth_resolution_deg: 0.17578125',
                                                              'azimuth_resolution_deg: 0.3515625'))
    in_bag = tmp_path / 'in.bag'
    ros_messages.write_sweeps_bag(str(in_bag), [sweep], to_messages=lambda s, stamp, frame: dual_return_messages(
        s, stamp, frame, first_return='mixed'))
    out = nodelet_outputs(binary, in_bag, tmp_path / 'out.bag', '--params', params, '--input-mode', 'dual_return')
    cloud, _, _ = dual_return_arrays(sweep, first_return='mixed')
    result = core.Pipeline(core.Params.from_yaml(str(params))).filter_dual_return(cloud)
    assert [o['type_name'] for o in result.objects] == ['mirror']
    assert_same_output(result, out['labelled'][0], out['cleaned'][0], out['objects'][0])
