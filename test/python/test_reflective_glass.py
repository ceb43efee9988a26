"""Glass that reflects well, which the geometry of its points behind takes for a mirror, is glass by
its echoes: off its specular peak no mirror's faint haze, only its frame and the wall around it lit
like a wall, and far echoes tens of times as bright as near ones (intensity_evidence.h:
paneByItsEchoes). Random scene 13016 of the 32-ring lidar: a glass partition of three panes 1.2 m
wide, two of which show the room as phantoms that land where they should.
"""
import pytest

core = pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')

from ohm_mirror_detector3d import scene_evaluation as ev  # noqa: E402

MIRROR, GLASS = 1, 2
FAMILY = 'velodyne_hdl32e'
PANES = ('partition_pane_3', 'partition_pane_4')


@pytest.fixture(scope='module')
def sweep(evaluation_sweep):
    return evaluation_sweep(FAMILY, 'random_13016')


def test_glass_the_geometry_takes_for_a_mirror_is_glass_by_its_echoes(sweep):
    found, counts = ev.found_objects(core.Pipeline(), sweep, FAMILY)
    for name in PANES:
        pane = found[name]
        assert pane['type'] == GLASS, name
        assert pane['intensity_pane_by_echoes'] and not pane['intensity_typed'], name
        # What made it: echoes off the peak, hardly any of them faint, far echoes far brighter.
        assert pane['intensity_off_peak'] >= 20, name
        assert pane['intensity_faint_share'] < 0.3, name
        assert pane['intensity_echo_ratio'] >= 15, name
    # The pane the geometry typed glass needed no rule.
    assert found['partition_pane_2']['type'] == GLASS
    assert not found['partition_pane_2']['intensity_pane_by_echoes']

    # Without the intensities the geometry alone says mirror, and what is seen through the two
    # panes is back-projected as their reflections.
    off, counts_off = ev.found_objects(core.Pipeline(intensity_evidence=0), sweep, FAMILY)
    assert all(off[name]['type'] == MIRROR for name in PANES)
    assert counts['real_displaced'] + 1000 < counts_off['real_displaced']
    assert counts['double_echo_phantoms_wrong_place'] <= counts_off['double_echo_phantoms_wrong_place']
