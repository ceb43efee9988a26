"""Faint reflections at oblique incidence in a pane that was not found (src/core/cone_labelling.cpp,
obliqueFaintSurface), on a whole sweep through the Python bindings with the default parameters
(realistic physics).

The rotating Hokuyo's random scene 43008 (held out from make evaluate's scenes): a window seen
sideways gives no surface echo; it reflects a surface of the room (the first echo, a phantom
nearer than what the beam meets through the window) and lets the beam through to the outside (the
second echo, real). The phantoms' layer makes an object of its own, typed glass by what lies behind
it. Until stop 50 its 3165 phantoms stayed in `cleaned` as that object's surface (3379 of the
sweep's 3380 double-echo phantoms at a wrong place); glass returns no surface echo that far from
perpendicular, so its faint echoes there are now dropped (214 left), and what was seen through the
window stays.
"""
import pytest

pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')


@pytest.fixture(scope='module')
def window_seen_sideways(evaluation_sweep, filtered_and_scored):
    return filtered_and_scored('hokuyo_utm30lx_ew', evaluation_sweep('hokuyo_utm30lx_ew', 'random_43008'))


def test_the_faint_reflections_of_a_window_seen_sideways_are_dropped(window_seen_sideways):
    figures, objects = window_seen_sideways
    counts = figures['counts']
    assert counts['double_echo_phantoms'] > 3000, counts
    assert counts['double_echo_phantoms_wrong_place'] < 0.1 * counts['double_echo_phantoms'], counts
    assert counts['phantoms_dropped'] > 3000, counts
    layers = [o for o in objects if o['intensity_oblique_faint_surface']]
    assert len(layers) == 1 and layers[0]['type_name'] == 'glass', [(o['type_name'], o['intensity_faint_share']) for o in objects]


def test_what_was_seen_through_the_window_stays(window_seen_sideways):
    figures, _ = window_seen_sideways
    counts = figures['counts']
    assert counts['real_lost'] < 100, counts
    assert counts['real_lost'] < 1e-3 * counts['real'], counts
