"""The simulator's dual-return cloud (input mode dual_return) and its ground truth."""
import numpy as np
import pytest

from ohm_mirror_detector3d import metrics, scanner, simulate
from ohm_mirror_detector3d.dual_return_cloud import dual_return_arrays
from ohm_mirror_detector3d.labels import Label


@pytest.fixture(scope='module')
def sweep():
    lidar = scanner.DualReturnLidar(rings=32, azimuth_steps=1024, vertical_fov_deg=(-20.0, 20.0))
    return simulate.simulate_sweep('experiment1', lidar, seed=3)


def test_one_point_per_return_in_column_then_ring_order(sweep):
    cloud, gt, (echo, beam) = dual_return_arrays(sweep)
    counts = sweep.counts()
    assert len(cloud) == counts['beams_with_return'] + counts['beams_with_two_returns']
    assert counts['beams_with_two_returns'] > 50
    column, ring = beam % sweep.cols, beam // sweep.cols
    np.testing.assert_array_equal(cloud['ring'], ring)
    np.testing.assert_array_equal(cloud['return'], echo)
    position = column * sweep.rows * 2 + ring * 2 + (echo - 1)
    assert np.all(np.diff(position) > 0)  # per column, per ring, return 1 before return 2
    # A second return only where it differs from the first.
    two = echo == 2
    assert two.sum() == counts['beams_with_two_returns']


def test_ground_truth_is_keyed_by_return_index_and_grid_cell(sweep):
    for first_return in ('strongest', 'mixed'):
        cloud, gt, (echo, beam) = dual_return_arrays(sweep, first_return=first_return)
        n = sweep.num_beams
        index = (echo - 1) * n + beam
        np.testing.assert_array_equal(gt['echo'][index], echo)
        np.testing.assert_array_equal(gt['beam'][index], beam)
        for name in 'xyz':
            np.testing.assert_array_equal(gt[name][index], cloud[name])
        # A filter labelling every input point with its true label scores perfectly.
        result = metrics.evaluate_sweep(gt, {'label': gt['label'][index], 'echo': echo, 'beam': beam})
        coarse = np.array(result['confusion_coarse']['matrix'])
        assert coarse.trace() == coarse.sum() == result['physical_returns']
        assert result['physical_returns'] == len(cloud)


def test_mixed_order_puts_the_far_echo_first_on_odd_columns(sweep):
    cloud, gt, (echo, beam) = dual_return_arrays(sweep, first_return='mixed')
    n = sweep.num_beams
    range_of = np.linalg.norm(np.stack([gt['x'], gt['y'], gt['z']], axis=1), axis=1)
    two = np.isfinite(range_of[n:])
    odd = (np.arange(n) % sweep.cols) % 2 == 1
    assert np.all(range_of[:n][two & odd] > range_of[n:][two & odd])
    assert np.all(range_of[:n][two & ~odd] < range_of[n:][two & ~odd])
    # Second-return entries of single-return beams are empty.
    assert np.all(gt['label'][n:][~two] == Label.NAN_POINT)


def test_zero_based_returns(sweep):
    cloud, _, (echo, _) = dual_return_arrays(sweep, zero_based=True)
    np.testing.assert_array_equal(cloud['return'], echo - 1)


def test_unknown_first_return_order_is_refused(sweep):
    with pytest.raises(ValueError, match='first_return'):
        dual_return_arrays(sweep, first_return='last')
