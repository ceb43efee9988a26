#!/usr/bin/python3
"""rostest checker: bad parameters are refused at start-up and on dynamic_reconfigure
with a message naming them, paper names are accepted, and a refused reconfigure leaves
the previous configuration in force."""
import os
import re
import subprocess
import sys
import unittest

import dynamic_reconfigure.client
import numpy as np
import rospy
import rostest
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import Header

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pair_fixture import make_pair, read_output  # noqa: E402

from ohm_mirror_detector3d.labels import Label  # noqa: E402
from ohm_mirror_detector3d.msg import EchoPair  # noqa: E402


def start_node(name, *params):
    return subprocess.Popen(['rosrun', 'ohm_mirror_detector3d', 'ohm_mirror_prefilter3d', '__name:=' + name]
                            + list(params), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


class StartUpParameters(unittest.TestCase):
    def assert_refused(self, name, params, *mentioned):
        node = start_node(name, *params)
        try:
            output, _ = node.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            node.kill()
            self.fail('the node kept running with bad parameters %s' % (params,))
        self.assertNotEqual(node.returncode, 0, output)
        for text in mentioned:
            self.assertIn(text, output)

    def test_refuses_a_negative_radius_naming_it_and_the_allowed_range(self):
        self.assert_refused('negative_radius', ['_outlierFilter_searchRadius:=-0.5'],
                            'outlierFilter_searchRadius (r) = -0.5', 'must be finite and > 0')

    def test_refuses_min_range_not_below_max_range(self):
        self.assert_refused('crossed_ranges', ['_min_measure_distance:=5.0', '_max_measure_distance:=2.0'],
                            'min_measure_distance (d_min) = 5', 'max_measure_distance (d_max)')

    def test_refuses_negative_neighbours_given_under_the_paper_name(self):
        # 0 is no error: it leaves n_inlier to the sensor (automatic).
        self.assert_refused('negative_neighbours', ['_n_inlier:=-1'], 'outlierFilter_minNeighbors (n_inlier) = -1')

    def test_refuses_a_value_of_the_wrong_type(self):
        self.assert_refused('wrong_type', ['_planeDetection_minAmountPoints:=many'],
                            'planeDetection_minAmountPoints has the wrong type')

    def test_refuses_an_unknown_input_mode(self):
        self.assert_refused('unknown_mode', ['_input_mode:=carrier_pigeon'], "input_mode 'carrier_pigeon' is unknown")

    def test_the_node_and_prefilter_bag_know_the_same_input_modes(self):
        """Both take their modes from one table (ros/input_mode.h): the node's refusal and prefilter_bag's
        refusal and --help list the same modes in the same order."""
        node = start_node('unknown_mode_list', '_input_mode:=carrier_pigeon')
        node_output, _ = node.communicate(timeout=30)
        bag = subprocess.run(['rosrun', 'ohm_mirror_detector3d', 'prefilter_bag', 'in.bag', 'out.bag',
                              '--input-mode', 'carrier_pigeon'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             text=True, timeout=30)
        self.assertEqual(bag.returncode, 2, bag.stdout)
        allowed = re.compile(r"input_mode 'carrier_pigeon' is unknown: allowed values are ((?:'\w+'(?:, )?)+)")
        node_modes = allowed.search(node_output)
        bag_modes = allowed.search(bag.stdout)
        self.assertIsNotNone(node_modes, node_output)
        self.assertIsNotNone(bag_modes, bag.stdout)
        modes = re.findall(r"'(\w+)'", node_modes.group(1))
        self.assertEqual(modes, re.findall(r"'(\w+)'", bag_modes.group(1)))
        self.assertEqual(modes, ['pair', 'two_topics', 'dual_return', 'hokuyo3d_legacy', 'multi_echo_scan'])
        help_text = subprocess.run(['rosrun', 'ohm_mirror_detector3d', 'prefilter_bag', '--help'],
                                   stdout=subprocess.PIPE, text=True, timeout=30).stdout
        listed = help_text.split('--input-mode MODE')[1].split('\n  --input-topic T')[0]
        self.assertEqual(re.findall(r'^ {25}(\w+): ', listed, re.M), modes)

    def test_refuses_a_too_fine_azimuth_resolution_naming_it_and_the_allowed_range(self):
        # 0 is no error: it works the step out from each cloud.
        self.assert_refused('fine_azimuth', ['_input_mode:=dual_return', '_azimuth_resolution_deg:=0.001'],
                            'azimuth_resolution_deg = 0.001 is out of range', '0.01 .. 10')

    def test_accepts_paper_names_and_publishes_them_under_the_original_names(self):
        node = start_node('paper_names', '_d_thres:=0.3', '_n_object:=250')
        try:
            deadline = rospy.Time.now() + rospy.Duration(20.0)
            while not rospy.has_param('/paper_names/substract_threshold_distance') and rospy.Time.now() < deadline:
                rospy.sleep(0.2)
            self.assertAlmostEqual(rospy.get_param('/paper_names/substract_threshold_distance'), 0.3)
            self.assertEqual(rospy.get_param('/paper_names/planeDetection_minAmountPoints'), 250)
            self.assertIsNone(node.poll(), 'the node stopped with valid parameters')
        finally:
            node.terminate()
            node.wait(10)


class Reconfigure(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.client = dynamic_reconfigure.client.Client('prefilter', timeout=20)
        cls.labelled = []
        cls.subscriber = rospy.Subscriber('prefilter/labelled', PointCloud2, cls.labelled.append)
        cls.publisher = rospy.Publisher('prefilter/input', EchoPair, queue_size=1)

    def first_beam_labels(self):
        """Labels of beam 0 (echoes 2.0 m and 3.5 m apart by 1.5 m) in the next labelled sweep."""
        del self.labelled[:]
        deadline = rospy.Time.now() + rospy.Duration(20.0)
        while not self.labelled and rospy.Time.now() < deadline:
            self.publisher.publish(make_pair(Header(frame_id='laser', stamp=rospy.Time.now())))
            rospy.sleep(0.3)
        self.assertTrue(self.labelled, 'no labelled sweep')
        points = read_output(self.labelled[-1])
        beam0 = points[points['beam'] == 0]
        return [int(label) for label in beam0['label']]

    def test_a_refused_value_leaves_the_previous_configuration_in_force(self):
        self.client.update_configuration({'substract_threshold_distance': 2.0})
        self.assertEqual(self.first_beam_labels(), [Label.VALID, Label.VALID])

        config = self.client.update_configuration({'substract_threshold_distance': -1.0})
        self.assertAlmostEqual(config['substract_threshold_distance'], 2.0)
        config = self.client.update_configuration({'outlierFilter_searchRadius': float('nan')})
        self.assertTrue(np.isfinite(config['outlierFilter_searchRadius']))
        self.assertEqual(self.first_beam_labels(), [Label.VALID, Label.VALID])

        self.client.update_configuration({'substract_threshold_distance': 0.05})
        self.assertEqual(self.first_beam_labels(), [Label.VALID, Label.ERROR])


def all_tests():
    loader = unittest.TestLoader()
    return unittest.TestSuite([loader.loadTestsFromTestCase(StartUpParameters),
                               loader.loadTestsFromTestCase(Reconfigure)])


if __name__ == '__main__':
    rospy.init_node('check_parameters')
    rostest.rosrun('ohm_mirror_detector3d', 'parameters', '__main__.all_tests')
