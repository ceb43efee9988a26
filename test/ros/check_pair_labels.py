#!/usr/bin/python3
"""rostest checker: publishes the hand-made EchoPair to a running pre-filter (node or
nodelet, whichever the .test started) and checks `labelled` and `cleaned`. With
~input_mode two_topics it publishes the two echo clouds on `echo1` and `echo2` instead."""
import os
import sys
import unittest

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import Header

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pair_fixture import BEAMS, make_pair, read_output  # noqa: E402

from ohm_mirror_detector3d.labels import Label  # noqa: E402
from ohm_mirror_detector3d.msg import EchoPair  # noqa: E402


class PairLabels(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_pair_labels')
        cls.outputs = {}
        subscribers = [rospy.Subscriber(topic, PointCloud2, cls.outputs.setdefault(topic, []).append)
                       for topic in ('labelled', 'cleaned')]
        cls.header = Header(frame_id='laser_optical_centre', stamp=rospy.Time(1234, 5678))
        pair = make_pair(cls.header)
        if rospy.get_param('~input_mode', 'pair') == 'two_topics':
            publishers = [(rospy.Publisher('echo1', PointCloud2, queue_size=1), pair.echo1),
                          (rospy.Publisher('echo2', PointCloud2, queue_size=1), pair.echo2)]
        else:
            publishers = [(rospy.Publisher('input', EchoPair, queue_size=1), pair)]
        deadline = rospy.Time.now() + rospy.Duration(20.0)
        # The pre-filter subscribes lazily once it sees our subscribers: publish until it answers.
        while not all(cls.outputs[t] for t in cls.outputs) and rospy.Time.now() < deadline:
            for publisher, message in publishers:
                publisher.publish(message)
            rospy.sleep(0.3)
        for subscriber in subscribers:
            subscriber.unregister()

    def labelled(self):
        self.assertTrue(self.outputs['labelled'], 'no message on labelled')
        return self.outputs['labelled'][0]

    def cleaned(self):
        self.assertTrue(self.outputs['cleaned'], 'no message on cleaned')
        return self.outputs['cleaned'][0]

    def test_labelled_keeps_the_input_header(self):
        for cloud in (self.labelled(), self.cleaned()):
            self.assertEqual(cloud.header.frame_id, self.header.frame_id)
            self.assertEqual(cloud.header.stamp, self.header.stamp)

    def test_labelled_holds_every_point_of_both_echoes_with_its_expected_label(self):
        points = read_output(self.labelled())
        self.assertEqual(len(points), 2 * len(BEAMS))
        for echo in (1, 2):
            of_echo = points[points['echo'] == echo]
            np.testing.assert_array_equal(of_echo['beam'], np.arange(len(BEAMS)))
            expected = [int(beam[1 + echo]) for beam in BEAMS]
            self.assertEqual([int(v) for v in of_echo['label']], expected, 'labels of echo %d' % echo)
            np.testing.assert_allclose(of_echo['intensity'], 10.0 * np.arange(len(BEAMS)) + echo)

    def test_labelled_keeps_the_measured_positions(self):
        points = read_output(self.labelled())
        first = points[(points['echo'] == 2) & (points['beam'] == 0)][0]
        self.assertAlmostEqual(float(first['x']), 3.5, places=5)

    def test_cleaned_drops_error_and_nan_points_and_repeated_single_returns(self):
        points = read_output(self.cleaned())
        kept = {(int(p['beam']), int(p['echo'])) for p in points}
        self.assertEqual(kept, {(0, 1), (1, 2), (2, 1), (3, 1), (6, 1), (6, 2)})
        self.assertNotIn(Label.ERROR, points['label'])
        self.assertEqual(len(points), len(kept))
        self.assertNotIn(Label.NAN_POINT, points['label'])
        self.assertTrue(np.all(np.isfinite(points['x'])))


if __name__ == '__main__':
    rostest.rosrun('ohm_mirror_detector3d', 'pair_labels', PairLabels)
