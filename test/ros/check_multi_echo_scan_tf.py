#!/usr/bin/python3
"""rostest checker of input mode multi_echo_scan around tf: scans published before their transforms wait
(with a warning naming the frames) and are assembled once tf comes; scans whose transforms can never come
(older than everything tf still holds) are dropped with an error; with sweep_period the sweeps are cut by
time. Also checks that the mode refuses to start without sweep_frame or with a negative sweep_period."""
import math
import subprocess
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import LaserEcho, MultiEchoLaserScan, PointCloud2
from tf2_msgs.msg import TFMessage

from ohm_mirror_detector3d import ros_io

BEAMS = 90
SCAN_TIME = 0.025


def scan(stamp):
    msg = MultiEchoLaserScan()
    msg.header = ros_io.make_header(rospy.Time.from_sec(stamp), 'laser')
    msg.angle_min, msg.angle_increment = -math.pi / 2, math.pi / (BEAMS - 1)
    msg.angle_max = msg.angle_min + (BEAMS - 1) * msg.angle_increment
    msg.time_increment, msg.scan_time = SCAN_TIME / 4 / BEAMS, SCAN_TIME
    msg.range_min, msg.range_max = 0.1, 30.0
    # Beam 0 without return, beam 1 with three echoes, the others one or two.
    msg.ranges = [LaserEcho(echoes=[]), LaserEcho(echoes=[1.0, 1.5, 2.0])] + \
        [LaserEcho(echoes=[2.0] if i % 2 else [2.0, 3.0]) for i in range(2, BEAMS)]
    return msg


def tf(stamp, z=0.5):
    return ros_io.transform_msg(stamp, (0.0, 0.0, z), (0.0, 0.0, 0.0, 1.0), 'base_link', 'laser')


class MultiEchoScanTf(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.log = []
        cls.labelled = []
        cls.subs = [rospy.Subscriber('/rosout', Log, lambda m: cls.log.append(m), queue_size=1000),
                    rospy.Subscriber('/prefilter/labelled', PointCloud2, lambda m: cls.labelled.append(m),
                                     queue_size=10, buff_size=2 ** 24)]
        cls.scans = rospy.Publisher('/prefilter/input', MultiEchoLaserScan, queue_size=100)
        cls.tf = rospy.Publisher('/tf', TFMessage, queue_size=100)
        deadline = time.time() + 30
        while time.time() < deadline and not (cls.scans.get_num_connections() and cls.tf.get_num_connections()):
            time.sleep(0.1)
        time.sleep(0.5)

    def wait_for(self, predicate, timeout=10.0):
        deadline = time.time() + timeout
        while time.time() < deadline and not predicate():
            time.sleep(0.05)
        return predicate()

    def messages(self, level, text):
        return [m.msg for m in self.log if m.level == level and text in m.msg]

    def test_1_scans_wait_for_late_tf_then_sweeps_are_cut_by_sweep_period(self):
        t0 = 2000.0
        # 9 scans, 0.025 s apart: sweeps of 0.1 s = 4 scans; scan 8 completes the second sweep.
        for k in range(9):
            self.scans.publish(scan(t0 + k * SCAN_TIME))
        self.assertTrue(self.wait_for(lambda: self.messages(Log.WARN, 'waiting for the transform from laser to '
                                                                      'base_link'), 5.0),
                        [m.msg for m in self.log])
        self.assertEqual(self.labelled, [])
        for k in range(10):
            self.tf.publish(tf(t0 + k * SCAN_TIME))
        self.assertTrue(self.wait_for(lambda: len(self.labelled) >= 2, 10.0), 'sweeps: %d' % len(self.labelled))
        first = self.labelled[0]
        self.assertEqual(first.header.frame_id, 'base_link')
        self.assertEqual(first.header.stamp, rospy.Time.from_sec(t0 + 3 * SCAN_TIME))  # its last scan
        self.assertEqual(first.width * first.height, 2 * 4 * BEAMS)
        self.assertEqual(self.labelled[1].header.stamp, rospy.Time.from_sec(t0 + 7 * SCAN_TIME))

    def test_2_scans_older_than_tf_holds_are_dropped_with_an_error(self):
        self.tf.publish(tf(2100.0))
        self.tf.publish(tf(2100.1))
        time.sleep(0.5)
        self.scans.publish(scan(2100.05))  # time is fine...
        self.scans.publish(scan(2100.06))
        for k in range(3):
            self.tf.publish(tf(2200.0 + k))  # ...but tf jumps on by 100 s: the cache forgets 2100
        time.sleep(0.5)
        self.scans.publish(scan(2199.0 - 50))  # older than anything the tf buffer holds now
        self.assertTrue(self.wait_for(lambda: self.messages(Log.ERROR, 'no transform from laser to base_link '
                                                                       'will come'), 5.0),
                        [m.msg for m in self.log if m.level >= Log.WARN])

    def test_3_missing_sweep_frame_and_bad_sweep_period_and_axis_are_refused(self):
        rospy.set_param('/bad_scan_params/rotation_axis', [0, 0, 0])  # roscpp reads no lists from the command line
        node = subprocess.Popen(['rosrun', 'ohm_mirror_detector3d', 'ohm_mirror_prefilter3d', '__name:=bad_scan_params',
                                 '_input_mode:=multi_echo_scan', '_sweep_period:=-1'],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            output, _ = node.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            node.kill()
            self.fail('the node kept running with bad parameters')
        self.assertNotEqual(node.returncode, 0, output)
        self.assertIn('/bad_scan_params/sweep_frame is required in input_mode multi_echo_scan', output)
        self.assertIn('/bad_scan_params/sweep_period = -1.000000 is out of range: allowed >= 0', output)
        self.assertIn('/bad_scan_params/rotation_axis must be a finite, non-zero vector', output)


if __name__ == '__main__':
    rospy.init_node('check_multi_echo_scan_tf')
    rostest.rosrun('ohm_mirror_detector3d', 'multi_echo_scan_tf', MultiEchoScanTf)
