#!/usr/bin/python3
"""rostest checker: the scenes of issue 16 through three real pre-filter nodelets in one manager, the
paper's method (`paper/`, grow_objects 0, max_reflections 0), extent growth (`grown/`, grow_objects 1)
and growth with reflection chains (`chained/`, grow_objects 1, max_reflections 3), the same sweep to
each (rotating Hokuyo, ~scans scans, noise 1 cm, fixed seed), scored by the evaluator.

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
SETTINGS = ('paper', 'grown', 'chained')


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
        arrow = ' → '.join(SETTINGS)
        lines = ['| scene (physics) | phantoms left at a wrong place, %s | real points lost, %s '
                 '| behind glass labelled behindTransparent, %s | objects: truth → %s (m) |' % ((arrow,) * 4),
                 '|---|---|---|---|---|']
        for name, by in cls.results.items():
            results = [by[setting] for setting in SETTINGS]

            def pct(key, phantoms=False):
                return ' → '.join('–' if r.get(key) is None or (phantoms and not r['counts']['phantoms'])
                                  else '%.1f %%' % (100 * r[key]) for r in results)

            def found(match):
                return '%.2f × %.2f' % tuple(sides(match)) if match['matched'] else 'not found'

            objects = '; '.join('%s %.2f × %.2f → %s' % (matches[0]['truth_name'], *truth_sides(matches[0]),
                                                         ' → '.join(found(m) for m in matches))
                                for matches in zip(*(r.get('objects', []) for r in results))) or \
                'none; reported %s' % ' → '.join(str(len(r['false_positive_objects'])) for r in results)
            lines.append('| %s (%s) | %s | %s | %s | %s |' % (
                name, 'ideal' if PHYSICS.get(name) is IDEAL else 'realistic',
                pct('phantom_wrong_place_fraction', phantoms=True), pct('real_lost_fraction'), pct('behind_glass'),
                objects))
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
            for setting in ('grown', 'chained'):
                self.assertEqual(len(by[setting]['false_positive_objects']),
                                 len(by['paper']['false_positive_objects']), (name, setting))
                self.assertLessEqual(by[setting]['real_lost_fraction'], 0.003, (name, setting))

    def test_reflection_chains_clean_the_twice_reflected_phantoms_of_facing_mirrors(self):
        # Measured 31.5 % -> 22.0 %: the twice reflected phantoms inside the grown mirrors are
        # back-projected through both; what is left lies outside them (the parts of the mirrors
        # that show only the floor and the ceiling are not grown into, README).
        by = self.scene('facing_tall_mirrors')
        self.assertLessEqual(by['chained']['phantom_wrong_place_fraction'],
                             0.8 * by['grown']['phantom_wrong_place_fraction'])
        self.assertLessEqual(by['chained']['real_lost_fraction'], 0.003)

    def test_experiments_are_reported(self):
        for name in ('experiment3', 'experiment2'):
            by = self.scene(name)
            for setting in ('grown', 'chained'):
                self.assertLessEqual(by[setting]['real_lost_fraction'], 0.003, (name, setting))


if __name__ == '__main__':
    rospy.init_node('check_growth_scenes')
    rostest.rosrun('ohm_mirror_detector3d', 'growth_scenes', GrowthScenes)
