#!/usr/bin/python3
"""rostest checker of input mode multi_echo_scan: the sweeps the nodelet assembles from the simulator's
scans + tf are scored by the evaluator against the simulator's ground truth (paired by stamp, so a sweep
that does not end at the last scan of a half rotation finds no ground truth), and the malformed scan
sent in between must have given an error naming the problem."""
import sys
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import PointCloud2

from ohm_mirror_detector3d import metrics, report
from ohm_mirror_detector3d.evaluation import LiveEvaluator

MIRROR = 1


class MultiEchoScan(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.sweeps = rospy.get_param('~sweeps', 2)
        cls.scans = rospy.get_param('~scans', 200)
        cls.log = []
        cls.labelled = []
        subs = [rospy.Subscriber('/rosout', Log, lambda m: cls.log.append(m), queue_size=1000),
                rospy.Subscriber('/prefilter/labelled', PointCloud2, lambda m: cls.labelled.append(
                    (m.header.stamp, m.header.frame_id, m.width * m.height)), queue_size=10)]
        live = LiveEvaluator('/prefilter', 'ground_truth', 'ground_truth_objects')
        cls.results = live.wait(cls.sweeps, timeout=200.0)
        rospy.sleep(3.0)  # a spurious extra sweep would come now
        live.close()
        for s in subs:
            s.unregister()
        cls.summary = metrics.aggregate_results(cls.results)
        print(report.to_markdown(report.jsonable(cls.summary), 'multi_echo_scan, experiment1'), file=sys.stderr)

    def test_one_sweep_per_half_rotation_stamped_like_the_ground_truth(self):
        self.assertEqual(len(self.results), self.sweeps, 'sweeps scored (matched to the ground truth by stamp)')
        self.assertEqual(len(self.labelled), self.sweeps, 'labelled clouds published: %s' % self.labelled)
        for stamp, frame, points in self.labelled:
            self.assertEqual(frame, 'base_link')
            self.assertEqual(points, 2 * self.scans * 1080)  # both echoes of rows = scans x cols = beams

    def test_mirror_found_as_a_mirror_within_3cm(self):
        for r in self.results:
            self.assertEqual(len(r['objects']), 1)
            match = r['objects'][0]
            self.assertTrue(match['matched'], r['objects'])
            self.assertEqual(match['detected_type'], MIRROR, match)
            self.assertLessEqual(abs(match['width_error']), 0.03, match)
            self.assertLessEqual(abs(match['height_error']), 0.03, match)
            self.assertEqual(r['false_positive_objects'], [])

    def test_phantoms_back_projected_and_no_real_point_lost(self):
        for r in self.results:
            self.assertGreater(r['counts']['phantoms'], 400)
            self.assertLessEqual(r['phantom_wrong_place_fraction'], 0.01)
            self.assertGreaterEqual(r['counts']['phantoms_back_projected_correctly'], 0.95 * r['counts']['phantoms'])
            self.assertLessEqual(r['real_lost_fraction'], 0.005)
            self.assertLess(r['backprojection_error']['median'], 0.03)

    def test_malformed_scan_gave_an_error_and_later_scans_still_work(self):
        errors = [m.msg for m in self.log if m.level == Log.ERROR and 'dropping scan' in m.msg]
        self.assertTrue(any('intensities' in e for e in errors), 'errors logged: %s' % errors)
        # The later scans of that sweep still made it (the sweep is scored above with all its rows).
        self.assertEqual(len(self.results), self.sweeps)


if __name__ == '__main__':
    rospy.init_node('check_multi_echo_scan')
    rostest.rosrun('ohm_mirror_detector3d', 'multi_echo_scan', MultiEchoScan)
