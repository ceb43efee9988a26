#!/usr/bin/python3
"""rostest checker: sends good EchoPairs, then a broken one, to a running pre-filter and reads
what it reports on /diagnostics after each."""
import os
import sys
import threading
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import Header

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pair_fixture import make_pair  # noqa: E402

from ohm_mirror_detector3d.msg import EchoPair  # noqa: E402

GOOD_SWEEPS = 3


class Diagnostics(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_diagnostics')
        cls.lock = threading.Lock()
        cls.reports = []
        cls.labelled = []
        rospy.Subscriber('/diagnostics', DiagnosticArray, cls.on_diagnostics)
        rospy.Subscriber('labelled', PointCloud2, lambda cloud: cls.labelled.append(cloud))
        cls.input = rospy.Publisher('input', EchoPair, queue_size=10)
        cls.idle = cls.wait_for_report(lambda status: True)
        # The pre-filter subscribes lazily once it sees our subscriber: publish until it answers.
        deadline = rospy.Time.now() + rospy.Duration(20.0)
        stamp = 1
        while len(cls.labelled) < GOOD_SWEEPS and rospy.Time.now() < deadline:
            cls.input.publish(make_pair(Header(frame_id='laser', stamp=rospy.Time(stamp))))
            stamp += 1
            rospy.sleep(0.3)
        cls.after_good = cls.wait_for_report(lambda status: int(values(status)['sweeps processed']) >= GOOD_SWEEPS)
        broken = make_pair(Header(frame_id='laser', stamp=rospy.Time(stamp)))
        broken.echo2.width -= 1
        broken.echo2.data = broken.echo2.data[:-broken.echo2.point_step]
        broken.echo2.row_step = broken.echo2.width * broken.echo2.point_step
        cls.input.publish(broken)
        cls.after_bad = cls.wait_for_report(lambda status: int(values(status)['inputs dropped']) >= 1)

    @classmethod
    def on_diagnostics(cls, array):
        with cls.lock:
            cls.reports.extend(s for s in array.status if s.name.endswith('pre-filter'))

    @classmethod
    def wait_for_report(cls, condition, timeout=15.0):
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        while rospy.Time.now() < deadline and not rospy.is_shutdown():
            with cls.lock:
                matching = [status for status in cls.reports if condition(status)]
            if matching:
                return matching[-1]
            rospy.sleep(0.1)
        return None

    def test_reports_before_any_input(self):
        self.assertIsNotNone(self.idle, 'no pre-filter status on /diagnostics')
        self.assertEqual(self.idle.hardware_id, rospy.resolve_name('input'))
        for key in ('input rate (sweeps/s)', 'sweeps processed', 'inputs dropped', 'mean processing time (ms)',
                    'objects in last sweep'):
            self.assertIn(key, values(self.idle))

    def test_reports_processed_sweeps_with_their_time_and_rate(self):
        self.assertIsNotNone(self.after_good, 'diagnostics never counted %d processed sweeps' % GOOD_SWEEPS)
        status = self.after_good
        self.assertEqual(status.level, DiagnosticStatus.OK, status.message)
        found = values(status)
        self.assertEqual(found['inputs dropped'], '0')
        self.assertGreater(float(found['last processing time (ms)']), 0.0)
        self.assertGreater(float(found['max processing time (ms)']), 0.0)
        self.assertEqual(found['objects in last sweep'], '0')  # the fixture's beams are too few for an object
        self.assertEqual(int(found['points in last sweep']), 2 * 7)
        self.assertEqual(found['input subscribed'], 'True')
        # Some report of the run saw sweeps arrive.
        with self.lock:
            rates = [float(values(s)['input rate (sweeps/s)']) for s in self.reports]
        self.assertGreater(max(rates), 0.0)

    def test_a_dropped_sweep_warns_with_its_reason(self):
        self.assertIsNotNone(self.after_bad, 'diagnostics never counted the broken sweep')
        self.assertIn(self.after_bad.level, (DiagnosticStatus.WARN, DiagnosticStatus.ERROR))
        self.assertIn('echo1 has 7 points but echo2 has 6', self.after_bad.message)
        self.assertIn('echo2 has 6', values(self.after_bad)['last drop reason'])


def values(status):
    return {pair.key: pair.value for pair in status.values}


if __name__ == '__main__':
    rostest.rosrun('ohm_mirror_detector3d', 'nodelet_diagnostics', Diagnostics)
