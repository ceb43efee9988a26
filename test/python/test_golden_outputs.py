"""labelled, cleaned and objects are byte for byte what test/golden/digests.json recorded, on every
named scene in every input mode (stored inputs, see test/golden/golden.py).

A change meant to keep behaviour must pass this unchanged. A change meant to alter the outputs
re-records the digests (`/usr/bin/python3 test/golden/golden.py record` after sourcing the workspace)
and says why in its commit message.
"""
import os
import sys

import pytest

from test_prefilter_bag import REPO, binary  # noqa: F401 (fixture)

sys.path.insert(0, os.path.join(REPO, 'test', 'golden'))
import golden  # noqa: E402


def recorded_for_this_platform():
    recorded = golden.load_digests()
    key = golden.platform_key()
    if key not in recorded:
        pytest.skip('no golden digests for %s (recorded for %s): record them with test/golden/golden.py record'
                    % (key, ', '.join(sorted(recorded))))
    return recorded[key]


def test_outputs_are_as_recorded(binary, tmp_path):  # noqa: F811
    from ohm_mirror_detector3d import scene
    recorded = recorded_for_this_platform()
    current = golden.digests(binary, str(tmp_path))
    assert set(current) == set(recorded)
    differences = golden.differences(recorded, current, scene.names())
    assert not differences, ('outputs differ from test/golden/digests.json (re-record with test/golden/golden.py '
                             'record if the change is meant):\n' + '\n'.join(differences))


def test_the_recorded_cases_cover_every_scene_and_mode():
    from ohm_mirror_detector3d import scene
    recorded = recorded_for_this_platform()
    modes = {case.split()[0] for case in recorded}
    assert modes == {'pair', 'two_topics', 'hokuyo3d_legacy', 'dual_return', 'multi_echo_scan'}
    for case, sweeps in recorded.items():
        if not case.startswith('multi_echo_scan'):
            assert len(sweeps) == len(scene.names()), case
        assert all(set(outputs) == set(golden.OUTPUT_TOPICS) for outputs in sweeps.values()), case
