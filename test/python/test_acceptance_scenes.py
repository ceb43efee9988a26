"""Acceptance of issue 14: the targets of `make evaluate` on a fixed-seed subset (random scenes 0-11 and
the named scenes, every sensor family, the filter's default parameters, realistic physics).

NOT run by `make test` yet: today's filter misses the targets (evaluation/baseline_defaults/), and the
filter work of issue 14 (sensor-adaptive defaults, the per-point decision) is what is to meet them.
It runs with OHM_ACCEPTANCE=1:

    source .ws/devel/setup.bash && OHM_ACCEPTANCE=1 /usr/bin/python3 -m pytest test/python/test_acceptance_scenes.py

and is enabled for good by deleting `pytestmark` below.
"""
import os

import pytest

pytestmark = pytest.mark.skipif(os.environ.get('OHM_ACCEPTANCE') != '1',
                                reason="issue 14's targets are not met by today's filter; OHM_ACCEPTANCE=1 runs it")

core = pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')

from ohm_mirror_detector3d import scanner  # noqa: E402
from ohm_mirror_detector3d import scene_evaluation as ev  # noqa: E402

RANDOM_SCENES = 12
SEED = 0


@pytest.fixture(scope='module', params=scanner.FAMILIES)
def family_summary(request):
    _, summaries = ev.run([request.param], RANDOM_SCENES, SEED)
    return request.param, summaries


@pytest.mark.parametrize('target', [t for t in ev.TARGETS if t[3] is not None], ids=lambda t: '-'.join(t[0]))
def test_target_is_met(family_summary, target):
    family, summaries = family_summary
    key, what, bound, met = target
    value = ev.figure(summaries[family]['all'], key)
    assert value is not None, '%s: %s was not measured' % (family, what)
    assert met(value), '%s: %s = %.4g, target %s' % (family, what, value, bound)
