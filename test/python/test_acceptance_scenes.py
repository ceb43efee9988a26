"""Acceptance of issue 14: the figures of `make evaluate` (the filter's default parameters, realistic
physics, every sensor family) on fixed-seed scenes.

* test_subset_holds (run by `make test`): random scenes 0-7 of every family. Where the filter meets
  issue 14's target on them, the target is asserted; where it does not yet, the level it reached
  on these scenes is asserted with a little slack, so that a regression fails while the target
  stays in view (SUBSET_LEVELS; each one names the target it falls short of). Raise a level when
  the filter gets better; replace it by the target when the target is met.
* test_target_is_met (OHM_ACCEPTANCE=1 only): the targets themselves on random scenes 0-11 and the
  named scenes; not met yet (see the README's issue-14 table):

    source .ws/devel/setup.bash && OHM_ACCEPTANCE=1 /usr/bin/python3 -m pytest test/python/test_acceptance_scenes.py
"""
import os

import pytest

core = pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')

from ohm_mirror_detector3d import scanner  # noqa: E402
from ohm_mirror_detector3d import scene_evaluation as ev  # noqa: E402

RANDOM_SCENES = 12
SEED = 0

SUBSET_SCENES = 8
SUBSET_SEED = 0

_IOU_SURFACE = ('iou', 'surface', 'double_echo')
_IOU_PHANTOM = ('iou', 'phantom', 'double_echo')
_IOU_GLASS = ('iou', 'behind_glass', 'double_echo')
_WRONG_PLACE = ('double_echo_phantom_wrong_place_fraction',)
_TYPES = ('object_types', 'fraction')

# Per family, the figures whose issue-14 target the filter does not meet on the subset yet: the
# bound it must still hold (the level reached on scenes 0-7 at stop 50, less 0.03 of an IoU, 3
# percentage points of phantoms left at a wrong place, 8 points of types right: one or two
# objects). Reached then: rotating Hokuyo surface IoU 0.758, phantom IoU 0.759, behind-glass IoU
# 0.595, phantoms left 32.3 %, types 86 %; Hesai phantom IoU 0.787, phantoms left 20.8 %, types
# 77 %; Ouster phantoms left 15.2 %, types 82 %; Velodyne surface IoU 0.835, phantom IoU 0.698,
# behind-glass IoU 0.750, phantoms left 33.4 %, types 81 % (the levels of stop 32, far below
# these, had not been raised since). The Ouster's phantom IoU (0.823) meets the target by less than
# the slack: held by a level of 0.79 (too close to assert on another CPU, whose simulator's last
# bits differ, see test/golden/golden.py). The Hesai's and the Ouster's behind-glass IoU (0.884,
# 0.914) meet the target, which is asserted instead.
# The targets: surface IoU >= 0.85, phantom and behind-glass IoU >= 0.80, phantoms left at a wrong
# place <= 2 %, types right >= 90 %. Every other target (surface IoU where met, real points lost
# <= 0.3 %, false objects in <= 5 % of the scenes without reflective surfaces) is asserted as it is.
SUBSET_LEVELS = {
    'hokuyo_utm30lx_ew': {_IOU_SURFACE: 0.72, _IOU_PHANTOM: 0.72, _IOU_GLASS: 0.56, _WRONG_PLACE: 0.36,
                          _TYPES: 0.77},
    'hesai_qt64': {_IOU_PHANTOM: 0.75, _WRONG_PLACE: 0.24, _TYPES: 0.69},
    'ouster_os0_128': {_IOU_PHANTOM: 0.79, _WRONG_PLACE: 0.19, _TYPES: 0.74},
    'velodyne_hdl32e': {_IOU_SURFACE: 0.80, _IOU_PHANTOM: 0.66, _IOU_GLASS: 0.72, _WRONG_PLACE: 0.37,
                        _TYPES: 0.73},
}

_TARGETS = [t for t in ev.TARGETS if t[3] is not None]


@pytest.fixture(scope='module', params=scanner.FAMILIES)
def subset_summary(request):
    _, summaries = ev.run([request.param], SUBSET_SCENES, SUBSET_SEED, named=False)
    return request.param, summaries[request.param]['all']


@pytest.mark.parametrize('target', _TARGETS, ids=lambda t: '-'.join(t[0]))
def test_subset_holds(subset_summary, target):
    family, summary = subset_summary
    key, what, bound, met = target
    value = ev.figure(summary, key)
    assert value is not None, '%s: %s was not measured' % (family, what)
    level = SUBSET_LEVELS[family].get(key)
    if level is None:
        assert met(value), '%s: %s = %.4g, target %s' % (family, what, value, bound)
    elif bound.startswith('≥'):
        assert value >= level, '%s: %s = %.4g fell below the level reached, %.4g (target %s)' % (
            family, what, value, level, bound)
    else:
        assert value <= level, '%s: %s = %.4g rose above the level reached, %.4g (target %s)' % (
            family, what, value, level, bound)


def test_subset_levels_name_targets_only():
    """A level stands in only for a target: a figure without one, or a level already past its
    target (which is then to be asserted instead), is a mistake in SUBSET_LEVELS."""
    targets = {t[0]: t for t in _TARGETS}
    assert set(SUBSET_LEVELS) == set(scanner.FAMILIES)
    for family, levels in SUBSET_LEVELS.items():
        for key, level in levels.items():
            assert key in targets, '%s: %s has no target' % (family, key)
            assert not targets[key][3](level), '%s: the level %.4g of %s meets its target %s: assert the target' % (
                family, level, targets[key][1], targets[key][2])


@pytest.fixture(scope='module', params=scanner.FAMILIES)
def family_summary(request):
    _, summaries = ev.run([request.param], RANDOM_SCENES, SEED)
    return request.param, summaries


@pytest.mark.skipif(os.environ.get('OHM_ACCEPTANCE') != '1',
                    reason="issue 14's targets are not met yet on every family; OHM_ACCEPTANCE=1 runs it")
@pytest.mark.parametrize('target', _TARGETS, ids=lambda t: '-'.join(t[0]))
def test_target_is_met(family_summary, target):
    family, summaries = family_summary
    key, what, bound, met = target
    value = ev.figure(summaries[family]['all'], key)
    assert value is not None, '%s: %s was not measured' % (family, what)
    assert met(value), '%s: %s = %.4g, target %s' % (family, what, value, bound)
