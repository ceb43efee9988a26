#!/usr/bin/python3
"""rostest checker: every parameter of the nodelet, given a bad value, is refused at start-up with
a message naming it and its allowed range (the nodelet fails to load, its manager keeps running),
and refused on dynamic_reconfigure with the previous configuration kept; reconfigure hammered
while sweeps stream is safe (every sweep is answered under one of the configurations in turn)."""
import os
import subprocess
import sys
import threading
import time
import unittest

import dynamic_reconfigure.client
import rospy
import rostest
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import Header

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pair_fixture import BEAMS, make_pair, read_output  # noqa: E402

from ohm_mirror_detector3d.labels import Label  # noqa: E402
from ohm_mirror_detector3d.msg import EchoPair  # noqa: E402

NAN = float('nan')
# parameter: (bad value, text of its allowed range in the message)
BAD_VALUES = {
    'min_measure_distance': (-0.1, 'must be finite and >= 0 m'),
    'max_measure_distance': (0.0, 'must be finite and > 0 m'),
    'outlierFilter_searchRadius': (-0.5, 'must be finite and > 0 m'),
    # 0 of r, n_inlier and n_object is no error: it leaves them to the sensor (automatic).
    'outlierFilter_minNeighbors': (-1, 'must be finite and >= 1 points, or 0: automatic'),
    'substract_threshold_distance': (0.0, 'must be finite and > 0 m'),
    'planeDetection_threshold_distance': (-1.0, 'must be finite and > 0 m'),
    'planeDetection_minAmountPoints': (2, 'must be finite and >= 3 points'),
    'visionCone_threshold': (-0.01, 'must be finite and >= 0 m'),
    'max_Dist_ICP': (0.0, 'must be finite and > 0 m'),
    'fitness_Fct_ICP': (-0.005, 'must be finite and > 0 m^2'),
    'icp_min_points': (1, 'must be finite and >= 3 points'),
    'icp_min_inlier_fraction': (1.5, 'must be in (0, 1]'),
}
DOUBLES = [name for name, (value, _) in BAD_VALUES.items() if isinstance(value, float)]


def load_nodelet(name, params, timeout=40.0):
    """`nodelet load` of a pre-filter with `params` into the test's manager; (exit code, output)."""
    args = ['rosrun', 'nodelet', 'nodelet', 'load', 'ohm_mirror_detector3d/PreFilterNodelet', '/manager',
            '__name:=' + name] + ['_%s:=%s' % (k, v) for k, v in params.items()]
    node = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        output, _ = node.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        node.kill()
        output, _ = node.communicate()
        return None, output
    return node.returncode, output


class StartUp(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.log = []
        cls.rosout = rospy.Subscriber('/rosout', Log, cls.log.append, queue_size=100)
        rospy.sleep(1.0)

    def manager_log(self):
        return '\n'.join(m.msg for m in self.log if m.level >= Log.ERROR)

    def assert_refused(self, name, params, expected):
        code, output = load_nodelet(name, params)
        self.assertIsNotNone(code, 'the nodelet kept loading with bad parameters: %s' % output)
        self.assertNotEqual(code, 0, output)
        self.assertIn('Failed to load nodelet', output)
        # The reason is logged by the manager, which must still be alive for the next nodelet.
        deadline = rospy.Time.now() + rospy.Duration(10.0)
        missing = expected
        while missing and rospy.Time.now() < deadline:
            log = self.manager_log()
            missing = [text for text in expected if text not in log]
            rospy.sleep(0.2)
        self.assertEqual(missing, [], 'not in the refusal message')

    def test_every_parameter_out_of_range_is_named_with_its_range(self):
        params = {name: value for name, (value, _) in BAD_VALUES.items()}
        expected = ['refusing to start, bad parameters'] + [
            '%s (' % name for name in BAD_VALUES] + [text for _, text in BAD_VALUES.values()]
        self.assert_refused('all_bad', params, expected)

    def test_nan_refused_for_every_real_parameter(self):
        params = {name: 'nan' for name in DOUBLES}
        self.assert_refused('all_nan', params, ['%s (' % name for name in DOUBLES])

    def test_min_range_not_below_max_range_and_unknown_mode_and_bad_mode_options(self):
        self.assert_refused('crossed', {'min_measure_distance': 3.0, 'max_measure_distance': 2.0},
                            ['min_measure_distance (d_min) = 3 must be smaller than max_measure_distance (d_max) = 2'])
        self.assert_refused('unknown_mode', {'input_mode': 'smoke_signals'},
                            ["input_mode 'smoke_signals' is unknown: allowed values are 'pair', 'two_topics'"])
        self.assert_refused('bad_azimuth', {'input_mode': 'dual_return', 'azimuth_resolution_deg': -1.0},
                            ['azimuth_resolution_deg = -1 is out of range'])
        self.assert_refused('bad_scan', {'input_mode': 'multi_echo_scan', 'sweep_frame': 'map', 'sweep_period': -2.0},
                            ['sweep_period = -2.000000 is out of range: allowed >= 0'])

    def test_manager_still_loads_a_good_nodelet_afterwards(self):
        code, output = load_nodelet('good_after_bad', {'input_mode': 'pair'}, timeout=8.0)
        # `nodelet load` of a good nodelet keeps running (it unloads on exit): a timeout is success.
        self.assertIsNone(code, output)


class Reconfigure(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.client = dynamic_reconfigure.client.Client('prefilter', timeout=30)
        cls.labelled = []
        cls.subscriber = rospy.Subscriber('prefilter/labelled', PointCloud2, cls.labelled.append, queue_size=100)
        cls.publisher = rospy.Publisher('prefilter/input', EchoPair, queue_size=5)
        deadline = rospy.Time.now() + rospy.Duration(30.0)
        while cls.publisher.get_num_connections() == 0 and rospy.Time.now() < deadline:
            rospy.sleep(0.1)

    def beam0_labels(self):
        del self.labelled[:]
        deadline = rospy.Time.now() + rospy.Duration(20.0)
        while not self.labelled and rospy.Time.now() < deadline:
            self.publisher.publish(make_pair(Header(frame_id='laser', stamp=rospy.Time.now())))
            rospy.sleep(0.2)
        self.assertTrue(self.labelled, 'no labelled sweep')
        points = read_output(self.labelled[-1])
        return [int(label) for label in points[points['beam'] == 0]['label']]

    def test_1_every_bad_value_refused_keeping_the_previous_configuration(self):
        good = self.client.update_configuration({'substract_threshold_distance': 2.0})
        self.assertEqual(self.beam0_labels(), [Label.VALID, Label.VALID])
        for name, (value, _) in BAD_VALUES.items():
            for bad in ([value, NAN] if name in DOUBLES else [value]):
                config = self.client.update_configuration({name: bad})
                for key in BAD_VALUES:
                    self.assertEqual(config[key], good[key], 'after %s = %s: %s changed' % (name, bad, key))
        # Only values that are bad together: d_min >= d_max.
        config = self.client.update_configuration({'min_measure_distance': 10.0, 'max_measure_distance': 5.0})
        self.assertEqual(config['max_measure_distance'], good['max_measure_distance'])
        self.assertEqual(self.beam0_labels(), [Label.VALID, Label.VALID])

    def test_2_reconfigure_hammered_while_sweeps_stream(self):
        """Sweeps at ~30 Hz while reconfigure switches d_thres between 2.0 (beam 0 valid+valid)
        and 0.05 (valid+error), with refused values in between: every sweep is whole and labelled
        under one of the two configurations; afterwards the last one is in force."""
        stop = threading.Event()
        sent = [0]

        def stream():
            rate = rospy.Rate(30)
            while not stop.is_set() and not rospy.is_shutdown():
                self.publisher.publish(make_pair(Header(frame_id='laser', stamp=rospy.Time.now())))
                sent[0] += 1
                rate.sleep()

        del self.labelled[:]
        streamer = threading.Thread(target=stream)
        streamer.start()
        try:
            # At least 60 rounds, and on until 60 sweeps went out while reconfiguring (30 s at most):
            # on a quiet machine 60 rounds take less than a second. Ends on an odd round (d_thres 2.0).
            started = time.monotonic()
            i = 0
            while True:
                self.client.update_configuration({'substract_threshold_distance': 2.0 if i % 2 else 0.05})
                self.client.update_configuration({'outlierFilter_searchRadius': -1.0 if i % 3 else NAN})
                if i % 2 == 1 and i >= 59 and (sent[0] >= 60 or time.monotonic() - started > 30.0):
                    break
                i += 1
        finally:
            stop.set()
            streamer.join()
        rospy.sleep(1.0)
        received = list(self.labelled)
        self.assertGreater(len(received), 20, 'sweeps answered while reconfiguring (sent %d)' % sent[0])
        allowed = ([Label.VALID, Label.VALID], [Label.VALID, Label.ERROR])
        for cloud in received:
            points = read_output(cloud)
            self.assertEqual(len(points), 2 * len(BEAMS))
            self.assertIn([int(label) for label in points[points['beam'] == 0]['label']], allowed)
        # The last valid update (an odd round: d_thres 2.0) is in force.
        self.assertEqual(self.beam0_labels(), [Label.VALID, Label.VALID])
        self.client.update_configuration({'substract_threshold_distance': 0.05})
        self.assertEqual(self.beam0_labels(), [Label.VALID, Label.ERROR])


def all_tests():
    loader = unittest.TestLoader()
    return unittest.TestSuite([loader.loadTestsFromTestCase(StartUp), loader.loadTestsFromTestCase(Reconfigure)])


if __name__ == '__main__':
    rospy.init_node('check_parameter_ranges')
    rostest.rosrun('ohm_mirror_detector3d', 'parameter_ranges', '__main__.all_tests')
