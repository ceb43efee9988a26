#!/usr/bin/python3
"""legacy_output.test: subscribers that know only the original driver's message definitions
(classes generated at run time from test/legacy_msgs, md5sums computed by genmsg) receive what
legacy_output_test_publisher sends through the C++ writers of legacy_output.h: a point set of the
built-in definition, and a scan and a point set in the definition of a driver's connection."""
import os
import sys
import time
import unittest

import numpy as np
import rospy
import rostest
from std_msgs.msg import Header

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'legacy_msgs'))
import legacy_msgs  # noqa: E402

COORD_DIST = 'ohm_hokuyo3d/CoordDist'
COORD_DIST_MULTI = 'ohm_hokuyo3d/CoordDistMulti'
NODE = '/legacy_output_test_publisher/'
TIMEOUT = 30.0


class Inbox:
    def __init__(self, topic, message_class):
        self.messages = []
        self.subscriber = rospy.Subscriber(topic, message_class, self.messages.append, queue_size=5)

    def wait(self, while_waiting=None):
        deadline = time.time() + TIMEOUT
        while not self.messages and time.time() < deadline and not rospy.is_shutdown():
            if while_waiting:
                while_waiting()
            time.sleep(0.2)
        return self.messages[0] if self.messages else None


def header(frame, secs=0):
    return Header(seq=0, stamp=rospy.Time(secs, 250), frame_id=frame)


class LegacyOutputTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_legacy_output')
        cls.classes = {name: legacy_msgs.message_class(name) for name in (COORD_DIST, COORD_DIST_MULTI)}
        cls.md5 = {name: legacy_msgs.md5sum(name) for name in (COORD_DIST, COORD_DIST_MULTI)}

    def assert_original_type(self, message, datatype):
        """The connection announced the original's type and its md5sum as genmsg computes it."""
        self.assertEqual(message._connection_header['type'], datatype)
        self.assertEqual(message._connection_header['md5sum'], self.md5[datatype])
        self.assertEqual(self.classes[datatype]._md5sum, self.md5[datatype])

    def assert_point_set(self, message, points, intensities, frame):
        np.testing.assert_array_equal(np.asarray(message.coord.coords, np.float32).reshape(-1, 3), points)
        np.testing.assert_array_equal(np.asarray(message.coord.intensity, np.float32), intensities)
        self.assertEqual(list(message.coord.mask), [True] * len(points))
        self.assertEqual(list(message.dist.mask), [True] * len(points))
        np.testing.assert_allclose(message.dist.dists, np.linalg.norm(points, axis=1), rtol=1e-6)
        self.assertEqual((message.coord.header.frame_id, message.dist.header.frame_id), (frame, frame))
        self.assertEqual((message.coord.fragmentid, message.coord.fragmentsize), (0, 1))
        self.assertEqual((len(message.coord.normals), len(message.coord.objectType), len(message.dist.phi)), (0, 0, 0))

    def test_builtin_point_set_reaches_a_subscriber_of_the_original_type(self):
        message = Inbox(NODE + 'builtin_points', self.classes[COORD_DIST]).wait()
        self.assertIsNotNone(message, 'no ohm_hokuyo3d/CoordDist of the built-in definition arrived')
        self.assert_original_type(message, COORD_DIST)
        values = np.array(rospy.get_param(NODE + 'points'), np.float32).reshape(-1, 4)
        self.assert_point_set(message, values[:, :3], values[:, 3], 'laser')

    def test_scan_and_point_set_follow_the_definition_of_the_drivers_connection(self):
        coord_dist_multi = self.classes[COORD_DIST_MULTI]
        generated = legacy_msgs.classes_by_name(COORD_DIST_MULTI)
        echo1 = np.array([[1, 2, 3], [4, 5, 6], [0, 0, 0], [-1, 0.5, 2]], np.float32)
        echo2 = np.array([[2, 4, 6], [0, 0, 0], [0, 0, 0], [-2, 1, 4]], np.float32)
        masks = ([1, 1, 0, 1], [1, 0, 0, 1])
        intensities = (np.array([10, 20, 0, 40], np.float32), np.array([11, 0, 0, 41], np.float32))
        driver = coord_dist_multi()
        for points, mask, intensity in zip((echo1, echo2), masks, intensities):
            coord = generated['ohm_hokuyo3d/Coord'](header=header('hokuyo', 77), fragmentid=0, fragmentsize=1,
                                                    coords=points.ravel().tolist(), normals=[], mask=mask,
                                                    intensity=intensity.tolist(), objectType=[])
            dist = generated['ohm_hokuyo3d/Dist'](header=header('hokuyo', 77), dists=[], phi=[], mask=mask)
            driver.coorddist.append(generated[COORD_DIST](coord=coord, dist=dist))
        publisher = rospy.Publisher(NODE + 'driver', coord_dist_multi, queue_size=1)
        scans = Inbox(NODE + 'scan', coord_dist_multi)
        point_sets = Inbox(NODE + 'points', self.classes[COORD_DIST])

        def publish():
            publisher.publish(driver)

        scan = scans.wait(publish)
        point_set = point_sets.wait(publish)
        self.assertIsNotNone(scan, 'no scan arrived')
        self.assertIsNotNone(point_set, 'no point set arrived')
        self.assert_original_type(scan, COORD_DIST_MULTI)
        self.assert_original_type(point_set, COORD_DIST)

        self.assertEqual(len(scan.coorddist), 2)
        for written, points, mask, intensity in zip(scan.coorddist, (echo1, echo2), masks, intensities):
            np.testing.assert_array_equal(np.asarray(written.coord.coords, np.float32).reshape(-1, 3), points)
            self.assertEqual(list(written.coord.mask), [bool(m) for m in mask])
            self.assertEqual(list(written.dist.mask), [bool(m) for m in mask])
            np.testing.assert_array_equal(np.asarray(written.coord.intensity, np.float32), intensity)
            np.testing.assert_allclose(written.dist.dists, np.linalg.norm(points, axis=1), rtol=1e-6)
            self.assertEqual((written.coord.header.stamp, written.coord.header.frame_id), (rospy.Time(77, 250), 'hokuyo'))
        valid = np.array(masks[0], bool)
        self.assert_point_set(point_set, echo1[valid], intensities[0][valid], 'hokuyo')


if __name__ == '__main__':
    rostest.rosrun('ohm_mirror_detector3d', 'legacy_output', LegacyOutputTest)
