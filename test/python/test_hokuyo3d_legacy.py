"""The simulator's ohm_hokuyo3d/CoordDistMulti writer (input mode hokuyo3d_legacy)."""
import io
import os
import sys

import numpy as np
import pytest

from ohm_mirror_detector3d import scanner, simulate


def test_message_round_trips_through_a_class_generated_from_its_definition(ros_messages):
    genpy_dynamic = pytest.importorskip('genpy.dynamic')
    from ohm_mirror_detector3d.hokuyo3d_legacy import LEGACY_TYPE, legacy_definition, legacy_message
    # The walls are 2 m and more away: beyond max_range, those beams have no return.
    lidar = scanner.BeamList([[1, 0, 0], [0, 1, 0], [0, 0, -1]], max_range=1.5)
    sweep = simulate.simulate_sweep('experiment1', lidar, seed=0)
    header = ros_messages.make_header(12.5, 'laser')
    buffer = io.BytesIO()
    legacy_message(sweep, header).serialize(buffer)
    plain = genpy_dynamic.generate_dynamic(LEGACY_TYPE, legacy_definition())[LEGACY_TYPE]
    msg = plain().deserialize(buffer.getvalue())
    assert len(msg.coorddist) == 2
    for coord_dist, echo in zip(msg.coorddist, (sweep.echo1, sweep.echo2)):
        coord = coord_dist.coord
        assert coord.header.frame_id == 'laser' and coord.header.stamp.to_sec() == 12.5
        points = np.stack([echo['x'], echo['y'], echo['z']], axis=1)
        mask = np.isfinite(points).all(axis=1)
        assert mask.any() and not mask.all()
        np.testing.assert_array_equal(np.array(coord.mask, bool), mask)
        coords = np.array(coord.coords, np.float32).reshape(-1, 3)
        np.testing.assert_array_equal(coords[mask], points[mask].astype(np.float32))
        assert np.all(coords[~mask] == 0.0)  # empty beams: zeros, the mask says so
        assert len(coord.intensity) == len(coord.objectType) == len(coord_dist.dist.dists) == sweep.num_beams


def test_definition_is_that_of_the_reconstructed_msg_files(ros_messages):
    """The simulator's driver, the nodelet's built-in output type (checked in legacy_output.test)
    and test/legacy_msgs describe the same types: same md5sums, as genmsg computes them."""
    genpy_dynamic = pytest.importorskip('genpy.dynamic')
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'legacy_msgs'))
    import legacy_msgs
    from ohm_mirror_detector3d.hokuyo3d_legacy import LEGACY_TYPE, legacy_definition
    classes = genpy_dynamic.generate_dynamic(LEGACY_TYPE, legacy_definition())
    for name in legacy_msgs.TYPES:
        full_name = legacy_msgs.PACKAGE + '/' + name
        assert classes[full_name]._md5sum == legacy_msgs.md5sum(full_name), full_name
