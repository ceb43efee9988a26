#!/usr/bin/python3
"""original_launch.test: a legacy robot that changes nothing. The node is started by the
reconstructed original launch file (test/legacy_launch/ohm_mirror_detector3D.launch, included
unchanged: no input_mode, the driver's topic /dist_coord_multi, the original's values and pub_*
outputs). A driver publishes the original's kind of sweep (rotating Hokuyo, 200 scans per half
rotation, experiment 1: a 60 x 40 cm mirror about 2.4 m away) as ohm_hokuyo3d/CoordDistMulti, of
the definition of the reconstructed .msg files (test/legacy_msgs). Subscribers that know only
those definitions receive every original output in the original's type, with the content of the
node's own outputs (labelled, cleaned, objects) of the same sweep."""
import os
import sys
import unittest

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import PointCloud2
from visualization_msgs.msg import Marker

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'legacy_msgs'))
import legacy_msgs  # noqa: E402

from ohm_mirror_detector3d import ros_io, scanner  # noqa: E402
from ohm_mirror_detector3d.hokuyo3d_legacy import LEGACY_TYPE, legacy_classes, legacy_message  # noqa: E402
from ohm_mirror_detector3d.labels import Label  # noqa: E402
from ohm_mirror_detector3d.msg import ReflectiveObjectArray  # noqa: E402
from ohm_mirror_detector3d.simulate import simulate_sweep  # noqa: E402

NODE = '/ohm_mirror_prefilter3d2/'
COORD_DIST = 'ohm_hokuyo3d/CoordDist'
SCANS = 200
TIMEOUT = 120.0

# The original's outputs as the reconstructed launch file names them, and the labels of their points.
SURFACES = (Label.ERROR_SURFACE, Label.REFLECTIVE_SURFACE, Label.TRANSPARENT_SURFACE)
BEHIND = (Label.BEHIND_ERROR_S, Label.BEHIND_REFLECTIVE, Label.BEHIND_TRANSPARENT)
MEASURED_SETS = {
    '/object_scan': SURFACES,
    '/transp_scan': (Label.TRANSPARENT_SURFACE,),
    '/mirror_scan': (Label.REFLECTIVE_SURFACE,),
    '/affected_scan': BEHIND,
    '/behTransp_scan': (Label.BEHIND_TRANSPARENT,),
    '/behMirror_scan': (Label.BEHIND_REFLECTIVE,),
}
POINT_SETS = tuple(MEASURED_SETS) + ('/backprojMirror_scan', '/cleaned_scan')


class OriginalLaunch(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_original_launch')
        cls.md5 = {name: legacy_msgs.md5sum(name) for name in (COORD_DIST, LEGACY_TYPE)}
        # Plain generated classes: rospy's numpy_msg cannot read bool[] with this numpy (np.bool is gone).
        point_set = legacy_msgs.message_class(COORD_DIST)
        scan = legacy_msgs.message_class(LEGACY_TYPE)
        cls.received = {}
        topics = {topic: point_set for topic in POINT_SETS}
        topics.update({'/prefiltered_scan': scan, '/marker': Marker, NODE + 'labelled': PointCloud2,
                       NODE + 'cleaned': PointCloud2, NODE + 'objects': ReflectiveObjectArray})
        subscribers = [rospy.Subscriber(topic, kind, lambda message, name: cls.received.setdefault(name, message),
                                        callback_args=topic, queue_size=2, buff_size=2 ** 27)
                       for topic, kind in topics.items()]
        # The driver: the .msg files' definition, as a node compiled against ohm_hokuyo3d sends it.
        driver_classes = legacy_classes(legacy_msgs.full_definition(LEGACY_TYPE))
        cls.sweep = simulate_sweep('experiment1', scanner.preset('hokuyo_utm30lx_ew', scans=SCANS), seed=1)
        cls.header = ros_io.make_header(rospy.Time(2000, 5000), 'laser')
        driver = rospy.Publisher('/dist_coord_multi', driver_classes[LEGACY_TYPE], queue_size=1)
        message = legacy_message(cls.sweep, cls.header, driver_classes)
        deadline = rospy.Time.now() + rospy.Duration(TIMEOUT)
        # The node subscribes once our subscribers are there; the same sweep again until every output came.
        while len(cls.received) < len(topics) and rospy.Time.now() < deadline and not rospy.is_shutdown():
            if driver.get_num_connections() > 0:
                driver.publish(message)
            rospy.sleep(1.5)
        for subscriber in subscribers:
            subscriber.unregister()
        missing = sorted(set(topics) - set(cls.received))
        if missing:
            raise AssertionError('no message on %s within %.0f s' % (', '.join(missing), TIMEOUT))
        cls.labelled = ros_io.cloud_to_array(cls.received[NODE + 'labelled'])
        cls.cleaned = ros_io.cloud_to_array(cls.received[NODE + 'cleaned'])

    def assert_point_set(self, message, xyz, intensity):
        coords = np.asarray(message.coord.coords, np.float32).reshape(-1, 3)
        np.testing.assert_array_equal(coords, xyz)
        np.testing.assert_array_equal(np.asarray(message.coord.intensity, np.float32), intensity)
        self.assertTrue(np.all(message.coord.mask) and np.all(message.dist.mask))
        np.testing.assert_allclose(message.dist.dists, np.linalg.norm(xyz, axis=1), rtol=1e-5, atol=1e-6)
        for header in (message.coord.header, message.dist.header):
            self.assertEqual((header.stamp, header.frame_id), (self.header.stamp, 'laser'))

    def test_every_output_comes_in_the_original_type(self):
        for topic in POINT_SETS:
            connection = self.received[topic]._connection_header
            self.assertEqual((connection['type'], connection['md5sum']), (COORD_DIST, self.md5[COORD_DIST]), topic)
        connection = self.received['/prefiltered_scan']._connection_header
        self.assertEqual((connection['type'], connection['md5sum']), (LEGACY_TYPE, self.md5[LEGACY_TYPE]))
        self.assertEqual(self.received['/marker']._connection_header['type'], 'visualization_msgs/Marker')

    def test_the_driver_type_is_read_without_input_mode(self):
        self.assertEqual(len(self.labelled), 2 * self.sweep.num_beams)
        self.assertEqual(self.received[NODE + 'labelled'].header.stamp, self.header.stamp)

    def test_cleaned_scan_holds_the_points_for_mapping(self):
        xyz = np.stack([self.cleaned[c] for c in 'xyz'], axis=1)
        self.assertGreater(len(xyz), self.sweep.num_beams // 2)
        self.assert_point_set(self.received['/cleaned_scan'], xyz, self.cleaned['intensity'])

    def test_back_projected_phantoms_are_those_of_cleaned(self):
        phantoms = self.cleaned[self.cleaned['label'] == Label.BEHIND_REFLECTIVE]
        self.assert_point_set(self.received['/backprojMirror_scan'], np.stack([phantoms[c] for c in 'xyz'], axis=1),
                              phantoms['intensity'])

    def test_prefiltered_scan_holds_both_echoes_with_the_removed_points_masked(self):
        scan = self.received['/prefiltered_scan']
        n = self.sweep.num_beams
        self.assertEqual(len(scan.coorddist), 2)
        for k, echo in enumerate(scan.coorddist):
            labelled = self.labelled[k * n:(k + 1) * n]
            kept = labelled['label'] != Label.NAN_POINT
            mask = np.asarray(echo.coord.mask, bool)
            np.testing.assert_array_equal(mask, kept)
            np.testing.assert_array_equal(np.asarray(echo.dist.mask, bool), kept)
            coords = np.asarray(echo.coord.coords, np.float32).reshape(-1, 3)
            np.testing.assert_array_equal(coords[kept], np.stack([labelled[c][kept] for c in 'xyz'], axis=1))
            np.testing.assert_array_equal(coords[~kept], 0.0)
            self.assertEqual(echo.coord.header.stamp, self.header.stamp)
        self.assertGreater(int(np.count_nonzero(scan.coorddist[0].coord.mask)), n // 2)

    def test_the_point_sets_hold_the_points_of_their_labels_as_measured(self):
        n = self.sweep.num_beams
        labels = self.labelled['label'].reshape(2, n)
        xyz = np.stack([self.labelled[c] for c in 'xyz'], axis=1).reshape(2, n, 3)
        intensity = self.labelled['intensity'].reshape(2, n)
        for topic, wanted in MEASURED_SETS.items():
            chosen = np.isin(labels, wanted)
            # A single return repeated in echo 2 is in the set once, as in cleaned.
            chosen[1] &= ~(chosen[0] & np.all(xyz[0] == xyz[1], axis=1))
            # Beam order, echo 1 before echo 2 of a beam.
            beam_major = chosen.T.ravel()
            self.assert_point_set(self.received[topic], xyz.transpose(1, 0, 2).reshape(-1, 3)[beam_major],
                                  intensity.T.ravel()[beam_major])

    def test_the_marker_outlines_the_objects(self):
        objects = self.received[NODE + 'objects'].objects
        marker = self.received['/marker']
        self.assertEqual(marker.header.frame_id, 'laser')
        if not objects:
            self.assertEqual(marker.action, Marker.DELETE)
            return
        self.assertEqual((marker.type, marker.action), (Marker.LINE_LIST, Marker.ADD))
        self.assertEqual(len(marker.points), 8 * len(objects))
        corners = [(c.x, c.y, c.z) for o in objects for c in o.corners]
        starts = [(p.x, p.y, p.z) for p in marker.points[::2]]
        np.testing.assert_allclose(starts, corners, atol=1e-5)


if __name__ == '__main__':
    rostest.rosrun('ohm_mirror_detector3d', 'original_launch', OriginalLaunch)
