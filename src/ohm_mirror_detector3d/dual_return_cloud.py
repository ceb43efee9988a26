"""A simulated sweep as ONE dual-return PointCloud2, as dual-return lidar drivers publish it.

Input mode `dual_return` of the pre-filter. The cloud (`dual_return_arrays`) has the fields
x y z intensity (float32), return (uint8) and ring (uint16), one point per return:

* order: per azimuth column (0 .. cols-1), per ring (0 .. rows-1), the beam's return 1,
  then its return 2 - stored only when the beam has a second, different return (most
  drivers drop a second return equal to the first). Beams without any return are left
  out, unless `keep_empty` (then a NaN return-1 point stands for them, REP-117).
* return 1 is, with first_return='strongest' (default), the stronger of the two returns
  (a driver in "strongest + last" mode: in general the near echo on some beams and the far
  echo on others; the simulator's mirror and glass surfaces happen to be always stronger
  than what is behind them). With first_return='mixed' it is the near echo on even azimuth
  columns and the far echo on odd ones, so both orders certainly occur. Return 2 is the
  other one. Values 1/2, or 0/1 with `zero_based`.

Ground truth: the 2 N layout of simulate.GROUND_TRUTH_DTYPE, keyed like the pre-filter's
grid in this mode: beam = ring * cols + azimuth column, echo = the return index (1, 2). The
entry (2, beam) of a beam with one return is NaN with label nanPoint (no such point is in
the cloud). The pre-filter's `labelled` carries that same echo and beam for every input
point in a grid cell, so metrics.evaluate_sweep scores it unchanged.

Only the scanner.DualReturnLidar model makes sense here (rows = rings, cols = azimuth steps
over 360 deg, starting at +x); its azimuth step is the pre-filter's azimuth_resolution_deg.
"""
import numpy as np

from .labels import Label
from .simulate import xyz

DUAL_RETURN_DTYPE = np.dtype([('x', '<f4'), ('y', '<f4'), ('z', '<f4'), ('intensity', '<f4'),
                              ('return', 'u1'), ('ring', '<u2')])

TOPIC_POINTS = 'points'

_GT_POINT_FIELDS = ('x', 'y', 'z', 'true_x', 'true_y', 'true_z')


FIRST_RETURN_CHOICES = ('strongest', 'mixed')


def dual_return_arrays(sweep, zero_based=False, keep_empty=False, first_return='strongest'):
    """(cloud, ground_truth, point_keys) of a sweep.

    cloud: structured array (DUAL_RETURN_DTYPE) in driver order; ground_truth: 2 N entries
    (see module doc); point_keys: (echo, beam) of every cloud point, int arrays, as the
    pre-filter's grid has them.
    """
    n, rows, cols = sweep.num_beams, sweep.rows, sweep.cols
    e1, e2 = sweep.echo1, sweep.echo2
    p1, p2 = xyz(e1), xyz(e2)
    has1 = np.isfinite(p1).all(axis=1)
    two = np.isfinite(p2).all(axis=1) & ~np.all(p1 == p2, axis=1)
    # The simulator's echo 1 is the near return: swap where return 1 is to be the far one.
    if first_return == 'strongest':
        with np.errstate(invalid='ignore'):
            swap = two & (e2['intensity'] > e1['intensity'])
    elif first_return == 'mixed':
        swap = two & (np.arange(n) % cols % 2 == 1)
    else:
        raise ValueError('first_return must be one of %s, not %r' % (FIRST_RETURN_CHOICES, first_return))

    r1, r2 = e1.copy(), e2.copy()
    r1[swap], r2[swap] = e2[swap], e1[swap]
    g1, g2 = sweep.ground_truth[:n].copy(), sweep.ground_truth[n:].copy()
    g1[swap], g2[swap] = sweep.ground_truth[n:][swap], sweep.ground_truth[:n][swap]
    for name in _GT_POINT_FIELDS:
        g2[name][~two] = np.nan
    g2['label'][~two] = Label.NAN_POINT
    g2['object_id'][~two] = -1
    g1['echo'], g2['echo'] = 1, 2
    g1['beam'] = g2['beam'] = np.arange(n)
    ground_truth = np.concatenate([g1, g2])

    # Driver order: column-major over the grid, return 1 then return 2 of each beam.
    order = (np.arange(rows)[None, :] * cols + np.arange(cols)[:, None]).ravel()
    base = 0 if zero_based else 1
    slots = np.zeros((n, 2), DUAL_RETURN_DTYPE)
    for k, r in enumerate((r1, r2)):
        for name in ('x', 'y', 'z', 'intensity'):
            slots[name][:, k] = r[name][order]
        slots['return'][:, k] = base + k
        slots['ring'][:, k] = order // cols
    keep = np.stack([has1[order] | keep_empty, two[order]], axis=1)
    cloud = slots[keep]
    echo = np.broadcast_to(np.array([1, 2]), (n, 2))[keep]
    beam = np.broadcast_to(order[:, None], (n, 2))[keep]
    return cloud, ground_truth, (echo.astype(np.int64), beam.astype(np.int64))


def dual_return_messages(sweep, stamp, frame_id=None, zero_based=False, keep_empty=False, first_return='strongest'):
    """Messages of one sweep keyed by topic: points (the dual-return cloud), ground_truth (keyed like the
    grid, see the module doc) and ground_truth_objects, all with one header."""
    from . import ros_io
    header = ros_io.make_header(stamp, frame_id or sweep.frame_id)
    cloud, ground_truth, _ = dual_return_arrays(sweep, zero_based, keep_empty, first_return)
    return {
        TOPIC_POINTS: ros_io.array_to_cloud(cloud, header),
        ros_io.TOPIC_GROUND_TRUTH: ros_io.array_to_cloud(ground_truth, header),
        ros_io.TOPIC_GROUND_TRUTH_OBJECTS: ros_io.objects_to_msg(ros_io.ground_truth_objects(sweep), header),
    }
