#!/usr/bin/python3
"""rostest checker: with sensor_frame, tf that is late never blocks the nodelet.

Experiment 1 moved into base_link (frame_fixture.py, as in check_sensor_frame.py) is sent before any transform
base_link <- laser exists. While the sweep waits for it, dynamic_reconfigure must answer at once
(tf is waited for outside the pipeline and its lock, never in a callback). The transform comes
LATE seconds after the sweep, and the waiting sweep is then processed: the mirror is found as
with the transform there from the start. A sweep in a frame that tf never links to the scanner's
is dropped after its wait with an error naming both frames; reconfigure still answers meanwhile.
"""
import os
import sys
import time
import unittest

import dynamic_reconfigure.client
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from rosgraph_msgs.msg import Log

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_scenes import FilterClient  # noqa: E402
from frame_fixture import OFFSET, moved  # noqa: E402

from ohm_mirror_detector3d import scene as scenes  # noqa: E402
from ohm_mirror_detector3d.metrics import evaluate_sweep  # noqa: E402
from ohm_mirror_detector3d.ros_io import filter_output_from_msgs, ground_truth_objects, sweep_to_messages  # noqa: E402
from ohm_mirror_detector3d.scanner import RotatingHokuyo  # noqa: E402
# Pinned to the ideal physics until the filter work of issue 14, as check_sensor_frame.py (README, "Pinned tests").
from ohm_mirror_detector3d.physics import PhysicsParams  # noqa: E402
from ohm_mirror_detector3d.simulate import simulate_sweep  # noqa: E402

LATE = 4.0  # [s] the transform comes this long after the sweep
PROMPT = 1.5  # [s] a reconfigure must be answered within this (the tf wait alone is LATE)
MAX_WAIT = 5.0  # [s] SensorPoseQueue::kMaxWaitSeconds


class LateTf(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.log = []
        rospy.Subscriber('/rosout', Log, cls.log.append, queue_size=1000)
        cls.client = FilterClient()
        cls.reconfigure = dynamic_reconfigure.client.Client('prefilter', timeout=60)
        cls.config = cls.reconfigure.get_configuration(timeout=30)
        cls.tf = tf2_ros.StaticTransformBroadcaster()
        deadline = time.time() + 60
        while cls.client.publisher.get_num_connections() == 0 and time.time() < deadline:
            time.sleep(0.1)  # the pre-filter subscribes once its outputs have subscribers
        cls.sweep = moved(simulate_sweep(scenes.get('experiment1'), RotatingHokuyo(scans=200, range_noise=0.01),
                                         seed=1, physics=PhysicsParams.ideal()), OFFSET)

    def send(self, frame_id):
        stamp = rospy.Time.now()
        self.client.publisher.publish(sweep_to_messages(self.sweep, stamp, frame_id)['echo_pair'])
        return stamp

    def reconfigure_seconds(self):
        """Seconds one reconfigure round trip takes (the loaded parameters again: no change of output)."""
        start = time.time()
        answer = self.reconfigure.update_configuration({'visionCone_threshold': self.config['visionCone_threshold']})
        self.assertAlmostEqual(answer['visionCone_threshold'], self.config['visionCone_threshold'])
        return time.time() - start

    def answer(self, stamp, timeout):
        deadline = time.time() + timeout
        while len(self.client.outputs.get(stamp, {})) < 4 and time.time() < deadline:
            time.sleep(0.05)
        return self.client.outputs.get(stamp, {})

    def test_1_a_sweep_waits_for_a_late_transform_while_reconfigure_answers(self):
        sent = time.time()
        stamp = self.send('base_link')
        time.sleep(1.0)
        self.assertLess(self.reconfigure_seconds(), PROMPT)
        time.sleep(max(0.0, sent + LATE - time.time()))
        self.assertEqual(self.client.outputs, {}, 'answered before the transform existed')
        laser = TransformStamped()
        laser.header.stamp = rospy.Time.now()
        laser.header.frame_id, laser.child_frame_id = 'base_link', 'laser'
        laser.transform.translation.x, laser.transform.translation.y, laser.transform.translation.z = OFFSET
        laser.transform.rotation.w = 1.0
        self.tf.sendTransform(laser)

        got = self.answer(stamp, 60.0)
        self.assertEqual(sorted(got), ['cleaned', 'labelled', 'markers', 'objects'],
                         [m.msg for m in self.log if m.level >= Log.WARN])
        self.assertEqual(got['labelled'].header.frame_id, 'base_link')
        output = filter_output_from_msgs(got['labelled'], got['cleaned'], got['objects'])
        result = evaluate_sweep(self.sweep.ground_truth, output['labelled'], output['cleaned'], output['objects'],
                                ground_truth_objects(self.sweep))
        mirror, = result['objects']
        self.assertTrue(mirror['matched'])
        self.assertEqual(mirror['detected_type'], 1)
        self.assertLessEqual(abs(mirror['width_error']), 0.02)
        self.assertLessEqual(result['phantom_wrong_place_fraction'], 0.01)

    def test_2_a_sweep_whose_transform_never_comes_is_dropped_naming_both_frames(self):
        start = len(self.log)
        sent = time.time()
        stamp = self.send('odom')  # tf links nothing to odom
        time.sleep(1.0)
        self.assertLess(self.reconfigure_seconds(), PROMPT)
        wanted = "no transform from sensor_frame 'laser' to the cloud's frame 'odom'"
        deadline = sent + MAX_WAIT + 20.0
        while not any(wanted in m.msg for m in self.log[start:] if m.level >= Log.ERROR) and time.time() < deadline:
            time.sleep(0.1)
        errors = [m.msg for m in self.log[start:] if m.level >= Log.ERROR and wanted in m.msg]
        self.assertTrue(errors, [m.msg for m in self.log[start:]])
        self.assertIn('dropping sweep on ' + rospy.resolve_name('input'), errors[0])
        self.assertGreaterEqual(time.time() - sent, MAX_WAIT - 0.5)  # it waited its time first
        self.assertNotIn(stamp, self.client.outputs)


if __name__ == '__main__':
    rospy.init_node('check_sensor_frame_late_tf')
    rostest.rosrun('ohm_mirror_detector3d', 'sensor_frame_late_tf', LateTf)
