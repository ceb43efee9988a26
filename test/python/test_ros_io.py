"""numpy <-> PointCloud2 <-> numpy, the sweep's messages, and bags (skipped when the messages are not built)."""
import numpy as np
import pytest

from ohm_mirror_detector3d import metrics
from ohm_mirror_detector3d.scanner import RotatingHokuyo
from ohm_mirror_detector3d.simulate import GROUND_TRUTH_DTYPE, simulate_sweep

FILTER_DTYPE = np.dtype([('x', '<f4'), ('y', '<f4'), ('z', '<f4'), ('intensity', '<f4'), ('label', 'u1'),
                         ('echo', 'u1'), ('beam', '<u4')])


@pytest.fixture(scope='module')
def small_sweep():
    return simulate_sweep('mirror_and_glass', RotatingHokuyo(scans=30), seed=2)


def same(a, b):
    assert a.dtype.names == b.dtype.names
    for name in a.dtype.names:
        np.testing.assert_array_equal(a[name], b[name])


def test_structured_array_round_trip(ros_messages):
    a = np.zeros(6, [('x', '<f4'), ('label', 'u1'), ('object_id', '<i4'), ('beam', '<u4'), ('v', '<f8')])
    a['x'] = [1, np.nan, 3, 4, 5, 6]
    a['label'], a['object_id'], a['beam'], a['v'] = 5, -1, np.arange(6), 0.5
    msg = ros_messages.array_to_cloud(a, ros_messages.make_header(12.5, 'laser'), height=2)
    assert (msg.height, msg.width, msg.point_step) == (2, 3, a.dtype.itemsize)
    same(ros_messages.cloud_to_array(msg), a)
    assert list(ros_messages.cloud_to_array(msg, ['beam', 'x']).dtype.names) == ['beam', 'x']
    with pytest.raises(KeyError):
        ros_messages.cloud_to_array(msg, ['nope'])


def test_ground_truth_recorded_before_the_double_echo_field_gets_it(ros_messages, small_sweep):
    gt = small_sweep.ground_truth
    assert gt['double_echo'].any() and not gt['double_echo'].all()
    names = [n for n in gt.dtype.names if n != 'double_echo']
    old = np.zeros(len(gt), [(n, gt.dtype[n]) for n in names])
    for n in names:
        old[n] = gt[n]
    msg = ros_messages.array_to_cloud(old, ros_messages.make_header(1.0, 'laser'))
    same(ros_messages.ground_truth_from_cloud(msg), gt)


def test_sweep_messages_round_trip(ros_messages, small_sweep):
    msgs = ros_messages.sweep_to_messages(small_sweep, 42.0, 'laser')
    pair = msgs['echo_pair']
    assert pair.header.stamp.to_sec() == 42.0 and pair.header.frame_id == 'laser'
    for cloud in (pair.echo1, pair.echo2, msgs['echo1'], msgs['ground_truth']):
        assert cloud.header.stamp == pair.header.stamp
    assert (pair.echo1.height, pair.echo1.width) == (30, 1080)
    assert [f.name for f in pair.echo1.fields] == ['x', 'y', 'z', 'intensity'] and not pair.echo1.is_dense
    e1, e2 = ros_messages.echo_pair_to_arrays(pair)
    same(e1, small_sweep.echo1)
    same(e2, small_sweep.echo2)
    gt = ros_messages.ground_truth_from_cloud(msgs['ground_truth'])
    assert gt.dtype == GROUND_TRUTH_DTYPE
    same(gt, small_sweep.ground_truth)
    objects = ros_messages.objects_from_msg(msgs['ground_truth_objects'])
    assert [o['type'] for o in objects] == [1, 2]
    for got, want in zip(objects, small_sweep.objects):
        np.testing.assert_allclose(got['corners'], want['corners'])
        np.testing.assert_allclose(got['plane'], want['plane'])
        assert np.isclose(got['width'], want['width']) and np.isclose(got['height'], want['height'])
        assert got['surface_points'] > 0


def test_bag_write_read_and_evaluation(ros_messages, small_sweep, tmp_path):
    import rosbag
    from ohm_mirror_detector3d import evaluation
    in_bag, out_bag = str(tmp_path / 'in.bag'), str(tmp_path / 'out.bag')
    stamps = ros_messages.write_sweeps_bag(in_bag, [small_sweep, small_sweep], start_time=100.0, period=0.5)
    data = ros_messages.read_bag_by_stamp(in_bag, ['/echo_pair', '/ground_truth', '/ground_truth_objects'])
    assert sorted(data['/echo_pair']) == stamps and [s.to_sec() for s in stamps] == [100.0, 100.5]
    same(ros_messages.ground_truth_from_cloud(data['/ground_truth'][stamps[0]]), small_sweep.ground_truth)
    # A fake filter: perfect on the first sweep, pass-through on the second.
    with rosbag.Bag(out_bag, 'w') as bag:
        for stamp, make in zip(stamps, (lambda g: metrics.oracle_filter_output(g, small_sweep.objects),
                                        metrics.passthrough_filter_output)):
            out = make(small_sweep.ground_truth)
            header = ros_messages.make_header(stamp, 'laser')
            for name in ('labelled', 'cleaned'):
                a = np.zeros(len(out[name]['x']), FILTER_DTYPE)
                for k, v in out[name].items():
                    a[k] = v
                bag.write('/prefilter/' + name, ros_messages.array_to_cloud(a, header), stamp)
            bag.write('/prefilter/objects', ros_messages.objects_to_msg(out['objects'], header), stamp)
    results, summary, last = evaluation.evaluate_bags(out_bag, in_bag)
    assert len(results) == 2
    assert results[0]['phantom_wrong_place_fraction'] == 0.0 and results[0]['objects'][0]['matched']
    assert results[1]['phantom_wrong_place_fraction'] == 1.0
    assert summary['objects'][0]['detection_rate'] == 0.5 and last.stamp == stamps[1]
