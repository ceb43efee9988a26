"""Windows met head-on with nothing in range behind them (stop 46, core/specular_spots.h).

Random scenes 4 and 44 of the 32-ring lidar each have a window to the sky that the sensor sees
head-on: the pane returns a patch of surface echoes and the beams through it return nothing, so
no beam there has a second echo and the echo comparison finds nothing. Until stop 45 these panes
made no object at all. The specular spot (the bright head-on returns, planar, met within 10
degrees of perpendicular, with rays going through the plane around it) now makes the object, and
with no phantom behind it the pane is glass.
"""
import pytest

core = pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')

from ohm_mirror_detector3d import metrics  # noqa: E402
from ohm_mirror_detector3d.simulate import ground_truth_objects  # noqa: E402

GLASS = 2
FAMILY = 'velodyne_hdl32e'


@pytest.mark.parametrize('scene, pane', [('random_4', 'window_0_pane'), ('random_44', 'window_1_pane')])
def test_a_window_to_the_sky_met_head_on_is_found_and_typed_glass(evaluation_sweep, filtered_and_scored, scene,
                                                                   pane):
    sweep = evaluation_sweep(FAMILY, scene)
    truth = ground_truth_objects(sweep)
    # What the test is about: the pane's surface echoes come without any second echo.
    window = max((t for t in truth if t['name'] == pane), key=lambda t: t['surface_points'])
    assert window['surface_points'] >= 50 and window['double_echo_surface_points'] == 0, window

    figures, objects = filtered_and_scored(FAMILY, sweep)
    matches, _ = metrics.match_objects(truth, objects)
    match = next(m for t, m in zip(truth, matches) if t is window)
    assert match['matched'], match
    found = objects[match['detected_id']]
    assert found['type'] == GLASS and found['typed_as_open_spot'], found

    # Without the stage the pane is not found; with it no real point more is lost or displaced.
    figures_without, without = filtered_and_scored(FAMILY, sweep, core.Params(specular_spot_ratio=0.0))
    assert not metrics.match_objects([window], without)[0][0]['matched']
    for count in ('real_lost', 'real_displaced'):
        assert figures['counts'][count] <= figures_without['counts'][count], count
