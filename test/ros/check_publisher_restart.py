#!/usr/bin/python3
"""rostest checker: the input publisher dies (SIGKILL, no clean unregistration) and comes back; the
pre-filter (in its manager) keeps running and answers the new publisher's sweeps correctly."""
import os
import signal
import subprocess
import sys
import unittest

import rospy
import rostest
from sensor_msgs.msg import PointCloud2

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pair_fixture import BEAMS, read_output  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


class PublisherRestart(unittest.TestCase):
    def setUp(self):
        self.labelled = []
        self.subscriber = rospy.Subscriber('prefilter/labelled', PointCloud2, self.labelled.append, queue_size=50)

    def start_publisher(self):
        return subprocess.Popen(['/usr/bin/python3', os.path.join(HERE, 'fixture_publisher.py'),
                                 'input:=prefilter/input', '__name:=fixture_publisher'],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    def wait_for_sweeps(self, count, after, timeout=30.0):
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        while rospy.Time.now() < deadline:
            new = [m for m in self.labelled if m.header.stamp > after]
            if len(new) >= count:
                return new
            rospy.sleep(0.05)
        return [m for m in self.labelled if m.header.stamp > after]

    def assert_correct(self, clouds):
        for cloud in clouds:
            points = read_output(cloud)
            self.assertEqual(len(points), 2 * len(BEAMS))
            self.assertEqual([int(x) for x in points['label'][:len(BEAMS)]], [int(b[2]) for b in BEAMS])

    def test_processing_resumes_after_the_publisher_dies_and_comes_back(self):
        start = rospy.Time.now()
        for attempt in range(2):
            publisher = self.start_publisher()
            try:
                got = self.wait_for_sweeps(5, start)
                self.assertGreaterEqual(len(got), 5, 'attempt %d: sweeps answered: %d' % (attempt, len(got)))
                self.assert_correct(got)
            finally:
                publisher.send_signal(signal.SIGKILL)
                publisher.wait(10)
            rospy.sleep(1.0)
            start = rospy.Time.now()
            rospy.sleep(1.0)
            self.assertEqual([m for m in self.labelled if m.header.stamp > start], [], 'answers with no publisher')
        # The pre-filter is still registered and alive.
        self.assertIn('/prefilter', subprocess.run(['rosnode', 'list'], stdout=subprocess.PIPE, text=True).stdout)


if __name__ == '__main__':
    rospy.init_node('check_publisher_restart')
    rostest.rosrun('ohm_mirror_detector3d', 'publisher_restart', PublisherRestart)
