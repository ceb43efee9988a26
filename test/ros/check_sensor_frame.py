#!/usr/bin/python3
"""rostest checker: clouds in a frame other than the scanner's, with sensor_frame and tf.

Simulated experiment 1 is moved into `base_link`, in which the scanner (`laser`) sits at
OFFSET (frame_fixture.py; the static transform of the .test). The pre-filter must take the
vision cones from the scanner's position, which only tf tells it, and still find and measure
the mirror.

prefilter_bag with sensor_frame must give the same result from a bag holding the same sweep and
the transform on /tf, recorded late (TF_LATENCY after its stamp, so the sweep waits for it in
bag order): the same input path, the same code.
"""
import io
import os
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_scenes import FilterClient  # noqa: E402
from frame_fixture import OFFSET, moved  # noqa: E402

from ohm_mirror_detector3d import ros_io  # noqa: E402
from ohm_mirror_detector3d import scene as scenes  # noqa: E402
from ohm_mirror_detector3d.physics import PhysicsParams  # noqa: E402
from ohm_mirror_detector3d.scanner import RotatingHokuyo  # noqa: E402
from ohm_mirror_detector3d.simulate import simulate_sweep  # noqa: E402

TF_LATENCY = rospy.Duration(0.2)
PARAMS = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), 'launch',
                      'rotating_hokuyo_params.yaml')
OUTPUTS = ('labelled', 'cleaned', 'objects', 'markers')


def prefilter_bag_outputs(sweep, stamp, directory):
    """prefilter_bag's outputs ({name: (message, bag time)}) on a bag with the sweep at `stamp` and the
    transform base_link <- laser on /tf every 0.1 s around it, each recorded TF_LATENCY late."""
    in_bag, out_bag = os.path.join(directory, 'in.bag'), os.path.join(directory, 'out.bag')
    with rosbag.Bag(in_bag, 'w') as bag:
        bag.write('/echo_pair', ros_io.sweep_to_messages(sweep, stamp)['echo_pair'], stamp)
        for k in range(-10, 11):
            at = stamp + rospy.Duration(0, 100000000) * k
            transform = ros_io.transform_msg(0.0, OFFSET, (0.0, 0.0, 0.0, 1.0), 'base_link', 'laser')
            transform.transforms[0].header.stamp = at  # to the nanosecond: one lies exactly at the sweep's stamp
            bag.write('/tf', transform, at + TF_LATENCY)
    params = os.path.join(directory, 'params.yaml')
    with open(PARAMS) as f, open(params, 'w') as out:
        out.write(f.read() + '\nsensor_frame: laser\n')
    p = subprocess.run(['rosrun', 'ohm_mirror_detector3d', 'prefilter_bag', in_bag, out_bag, '--params', params,
                        '--only-outputs'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
    assert p.returncode == 0, p.stdout
    assert 'sweeps processed: 1' in p.stdout and 'sweeps dropped:   0' in p.stdout, p.stdout
    with rosbag.Bag(out_bag) as bag:
        return {topic.rsplit('/', 1)[1]: (msg, t) for topic, msg, t in bag.read_messages()}


def serialized(msg):
    buffer = io.BytesIO()
    msg.serialize(buffer)
    return buffer.getvalue()


# Pinned to the ideal physics (glass never reflects, no mixed pixels) until the filter work of
# issue 14: with the realistic physics today's filter misses these thresholds (README, "Pinned tests").
PHYSICS = PhysicsParams.ideal()


class SensorFrame(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.sweep = moved(simulate_sweep(scenes.get('experiment1'), RotatingHokuyo(scans=200, range_noise=0.01),
                                         seed=1, physics=PHYSICS), OFFSET)
        cls.result = FilterClient().run(cls.sweep)
        cls.messages = cls.result.pop('_messages')

    def test_the_mirror_is_found_from_the_scanners_position_given_by_tf(self):
        result = self.result
        self.assertEqual(self.messages['labelled'].header.frame_id, 'base_link')
        self.assertEqual(len(result['objects']), 1)
        mirror = result['objects'][0]
        self.assertTrue(mirror['matched'])
        self.assertEqual(mirror['detected_type'], 1)
        self.assertLessEqual(abs(mirror['width_error']), 0.02)
        self.assertLessEqual(abs(mirror['height_error']), 0.02)
        self.assertLessEqual(result['phantom_wrong_place_fraction'], 0.01)
        self.assertEqual(result['counts']['real_lost'], 0)

    def test_prefilter_bag_with_sensor_frame_gives_the_nodelets_result(self):
        answered = self.messages['labelled'].header.stamp
        stamp = rospy.Time(answered.secs, answered.nsecs)
        with tempfile.TemporaryDirectory() as directory:
            outputs = prefilter_bag_outputs(self.sweep, stamp, directory)
        for name in OUTPUTS:
            message, bag_time = outputs[name]
            # It waited for the transform at its stamp, which came TF_LATENCY later.
            self.assertEqual(bag_time, stamp + TF_LATENCY, name)
            self.assertEqual(serialized(message), serialized(self.messages[name]), name)


if __name__ == '__main__':
    rospy.init_node('check_sensor_frame')
    rostest.rosrun('ohm_mirror_detector3d', 'sensor_frame', SensorFrame)
