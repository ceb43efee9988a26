#!/usr/bin/python3
"""rostest checker: the scenes of issue 16 through two real pre-filter nodelets in one manager, the
paper's method (`paper/`, grow_objects 0) and extent growth (`grown/`, grow_objects 1), the same
sweep to both (rotating Hokuyo, ~scans scans, noise 1 cm, fixed seed), scored by the evaluator.

The mirror scenes use the ideal physics: a mirror gives surface echoes only near perpendicular
incidence there, the case growth is for (the realistic physics' haze makes a mirror within a few
metres echo all over, README "Extent growth"). The pane and the plain scenes use the realistic
physics. With ~report DIR it writes growth.md and growth.json (the README's table).
"""
import json
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_scenes import FilterClient  # noqa: E402

from ohm_mirror_detector3d import scene as scenes  # noqa: E402
from ohm_mirror_detector3d.growth_comparison import behind_glass_labelled  # noqa: E402
from ohm_mirror_detector3d.metrics import strip_raw  # noqa: E402
from ohm_mirror_detector3d.physics import PhysicsParams  # noqa: E402
from ohm_mirror_detector3d.scanner import RotatingHokuyo  # noqa: E402
from ohm_mirror_detector3d.simulate import simulate_sweep  # noqa: E402

MIRROR, GLASS = 1, 2
IDEAL, REALISTIC = PhysicsParams.ideal(), PhysicsParams()
PHYSICS = {'wall_mirror': IDEAL, 'facing_tall_mirrors': IDEAL, 'experiment3': IDEAL}
SETTINGS = ('paper', 'grown')


def sides(match):
    return sorted([match['detected_width'], match['detected_height']], reverse=True)


def truth_sides(match):
    return sorted([match['truth_width'], match['truth_height']], reverse=True)


class GrowthScenes(unittest.TestCase):
    results = {}

    @classmethod
    def setUpClass(cls):
        cls.clients = {s: FilterClient(s + '/') for s in SETTINGS}
        cls.scans = rospy.get_param('~scans', 300)
        cls.seed = rospy.get_param('~seed', 1)

    @classmethod
    def tearDownClass(cls):
        report = rospy.get_param('~report', '')
        if not report:
            return
        os.makedirs(report, exist_ok=True)
        lines = ['| scene (physics) | phantoms left at a wrong place, paper → grown | real points lost, paper → grown '
                 '| behind glass labelled behindTransparent, paper → grown | objects: truth → paper → grown (m) |',
                 '|---|---|---|---|---|']
        for name, by in cls.results.items():
            paper, grown = by['paper'], by['grown']

            def pct(r, key):
                return '–' if r.get(key) is None else '%.1f %%' % (100 * r[key])

            objects = '; '.join('%s %.2f × %.2f → %s → %s' % (
                a['truth_name'], *truth_sides(a), '%.2f × %.2f' % tuple(sides(a)) if a['matched'] else 'not found',
                '%.2f × %.2f' % tuple(sides(b)) if b['matched'] else 'not found')
                for a, b in zip(paper.get('objects', []), grown.get('objects', []))) or \
                'none; reported %d → %d' % (len(paper['false_positive_objects']), len(grown['false_positive_objects']))
            lines.append('| %s (%s) | %s → %s | %s → %s | %s → %s | %s |' % (
                name, 'ideal' if PHYSICS.get(name) is IDEAL else 'realistic',
                pct(paper, 'phantom_wrong_place_fraction') if paper['counts']['phantoms'] else '–',
                pct(grown, 'phantom_wrong_place_fraction') if grown['counts']['phantoms'] else '–',
                pct(paper, 'real_lost_fraction'), pct(grown, 'real_lost_fraction'),
                pct(paper, 'behind_glass'), pct(grown, 'behind_glass'), objects))
        with open(os.path.join(report, 'growth.md'), 'w') as f:
            f.write('\n'.join(lines) + '\n')
        with open(os.path.join(report, 'growth.json'), 'w') as f:
            json.dump(cls.results, f, indent=1, default=float)
        print('\n'.join(lines))

    def scene(self, name):
        """The evaluator's result of the sweep of `name` from both nodelets."""
        if name not in self.results:
            sweep = simulate_sweep(scenes.get(name), RotatingHokuyo(scans=self.scans, range_noise=0.01),
                                   seed=self.seed, physics=PHYSICS.get(name, REALISTIC))
            by = {}
            for setting in SETTINGS:
                result = self.clients[setting].run(sweep)
                result.pop('_messages')
                result['behind_glass'] = behind_glass_labelled(result)
                by[setting] = strip_raw(result)
            self.results[name] = by
        return self.results[name]

    def test_wall_mirror_grows_to_its_size_and_its_phantoms_are_cleaned(self):
        by = self.scene('wall_mirror')
        match = by['grown']['objects'][0]
        self.assertTrue(match['matched'])
        self.assertEqual(match['detected_type'], MIRROR)
        for detected, truth in zip(sides(match), truth_sides(match)):
            self.assertLessEqual(abs(detected - truth), 0.05, match)
        self.assertLessEqual(by['grown']['phantom_wrong_place_fraction'], 0.05)
        # The paper's method leaves the phantoms outside the patch's cone.
        self.assertGreater(by['paper']['phantom_wrong_place_fraction'], 0.2)

    def test_pane_in_a_wall_grows_to_within_10cm(self):
        match = self.scene('pane_in_wall')['grown']['objects'][0]
        self.assertTrue(match['matched'])
        self.assertEqual(match['detected_type'], GLASS)
        for detected, truth in zip(sides(match), truth_sides(match)):
            self.assertLessEqual(abs(detected - truth), 0.10, match)

    def test_growth_adds_no_object_and_loses_no_real_point_in_plain_scenes(self):
        for name in ('empty_room', 'office', 'doorway_room'):
            by = self.scene(name)
            self.assertEqual(len(by['grown']['false_positive_objects']), len(by['paper']['false_positive_objects']),
                             name)
            self.assertLessEqual(by['grown']['real_lost_fraction'], 0.003, name)

    def test_facing_mirrors_and_experiments_are_reported(self):
        # Measured for the README (multiple reflections are not explained by one mirror yet).
        for name in ('facing_tall_mirrors', 'experiment3', 'experiment2'):
            by = self.scene(name)
            self.assertLessEqual(by['grown']['real_lost_fraction'], 0.003, name)


if __name__ == '__main__':
    rospy.init_node('check_growth_scenes')
    rostest.rosrun('ohm_mirror_detector3d', 'growth_scenes', GrowthScenes)
