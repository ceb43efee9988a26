"""`make evaluate`'s machinery (scene_evaluation.py): the cases it runs, how the filter's outputs are
keyed to the ground truth in both input modes, the table and its files. Small runs only: the benchmark
itself is `make evaluate`, not a test."""
import json

import numpy as np
import pytest

from ohm_mirror_detector3d import metrics, scene_evaluation as ev
from ohm_mirror_detector3d.labels import Label


def test_cases_cover_every_family_with_the_same_random_scenes_and_the_named_ones():
    cases = ev.cases(ev.resolve_families([]), count=5, seed=10)
    families = {c.family for c in cases}
    assert families == set(ev.INPUT_MODES)
    for family in families:
        mine = [c for c in cases if c.family == family]
        assert [c.scene for c in mine if c.kind == 'random'] == ['random_%d' % s for s in range(10, 15)]
        assert len([c for c in mine if c.kind == 'named']) >= 11
    scans = [ev.hokuyo_scans(s) for s in range(300)]
    assert min(scans) >= 100 and max(scans) <= 1000 and min(scans) < 150 and max(scans) > 800
    assert ev.hokuyo_scans(42) == ev.hokuyo_scans(42)
    assert ev.resolve_families(['hokuyo', 'hesai']) == ['hokuyo_utm30lx_ew', 'hesai_qt64']
    with pytest.raises(ValueError):
        ev.resolve_families(['leica'])


@pytest.fixture(scope='module')
def core():
    return pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')


@pytest.mark.parametrize('family', ['hesai_qt64', 'hokuyo_utm30lx_ew'])
def test_outputs_are_keyed_to_the_ground_truth_in_both_input_modes(core, family):
    from ohm_mirror_detector3d import scene, simulate
    case = ev.Case(family, 'random_3', 'random', 3, 100 if family == ev.HOKUYO else None)
    sweep = simulate.SweepSimulator(scene.get(case.scene), ev.scanner_of(case)).sweep(seed=3)
    # Loose enough that points survive: the keys are under test, not the filter.
    pipeline = core.Pipeline(outlierFilter_minNeighbors=1, outlierFilter_searchRadius=1.0)
    gt, labelled, cleaned, objects = ev.filter_case(pipeline, sweep, ev.INPUT_MODES[family])
    result = metrics.evaluate_sweep(gt, labelled, cleaned, objects, simulate.ground_truth_objects(sweep))
    # Every physical return has a labelled point (no 'missing' column) ...
    full = np.array(result['confusion']['matrix'])
    assert full[:, metrics.MISSING].sum() == 0 and full.sum() == result['physical_returns']
    # ... and every cleaned point kept as measured sits where the ground truth measured its return.
    n = len(gt) // 2
    keyed = np.full(2 * n, -1)
    keyed[(gt['echo'].astype(int) - 1) * n + gt['beam'].astype(int)] = np.arange(2 * n)
    c_echo, c_beam = np.asarray(cleaned['echo'], int), np.asarray(cleaned['beam'], int)
    assert ((c_echo == 1) | (c_echo == 2)).all()
    entry = keyed[(c_echo - 1) * n + c_beam]
    as_measured = np.asarray(cleaned['label']) != Label.BEHIND_REFLECTIVE
    measured = np.stack([gt['x'], gt['y'], gt['z']], axis=1)[entry]
    got = np.stack([cleaned['x'], cleaned['y'], cleaned['z']], axis=1).astype(float)
    np.testing.assert_allclose(got[as_measured], measured[as_measured], atol=1e-5)
    assert result['counts']['real_lost'] < 0.2 * result['counts']['real']


def test_a_small_run_writes_the_table_with_the_targets(core, tmp_path, capsys):
    code = ev.main(['--scenes', '1', '--seed', '3', '--families', 'hesai', '--no-named', '--out', str(tmp_path)])
    assert code == 0
    text = (tmp_path / 'evaluation.md').read_text()
    assert capsys.readouterr().out.startswith(text)   # the same table on stdout
    for what, target in (('surface IoU, double-echo points', '≥ 0.85'), ('real points lost', '≤ 0.3 %'),
                         ('object types right', '≥ 90 %'), ('phantom IoU, double-echo points', '≥ 0.80')):
        line = [l for l in text.splitlines() if l.startswith('| ' + what)]
        assert line and target in line[0], what
    data = json.loads((tmp_path / 'evaluation.json').read_text())
    summary = data['summary']['hesai_qt64']['all']
    assert summary['sweeps'] == 1 and data['sweeps'][0]['scene'] == 'random_3'
    for key in ('iou', 'real_lost_fraction', 'object_types', 'false_objects'):
        assert key in summary
    lone = [l for l in text.splitlines() if l.startswith('| objects of the type figure with no double echo')]
    types = summary['object_types']
    assert lone and '%d of %d (%d right)' % (types['no_double_echo'], types['objects'],
                                             types['no_double_echo_right']) in lone[0]
    assert ev.main(['--families', 'leica']) == 2
    assert ev.main(['--params', str(tmp_path / 'missing.yaml')]) == 2


def test_realism_figures_of_the_random_scenes():
    """The figures compared with SENSORS.md's real frames: the 64-ring lidar stores a second return only
    at least ~0.9 m beyond its first, and some of its double echoes lie on ordinary geometry."""
    figures = ev.realism(['hesai_qt64'], count=3, seed=3)['hesai_qt64']
    assert 20000 < figures['points_per_sweep'] < 60000
    assert 0.9 - 0.06 < figures['second_return_gap_min'] < figures['second_return_gap_median']
    assert 0.0 < figures['second_return_share'] < 0.2
    assert 0.0 < figures['second_returns_on_ordinary_geometry'] < 0.5
    table = ev.realism_table({'hesai_qt64': figures})
    assert 'about a fifth' in table and 'hesai_qt64' in table.splitlines()[0]


def test_a_window_with_nothing_in_range_behind_it_gives_surface_echoes_without_a_second_echo():
    """The evaluator tells these panes apart (type_accuracy's no_double_echo): the 32-ring lidar's
    random_4 sees a window to the sky head-on (surface echoes, none with a second echo) and two mirrors
    and shiny metal whose surface echoes nearly all come with their phantom as second echo."""
    from ohm_mirror_detector3d import scene
    from ohm_mirror_detector3d.simulate import SweepSimulator, ground_truth_objects
    case = ev.cases(['velodyne_hdl32e'], 1, 4, named=False)[0]
    sweep = SweepSimulator(scene.get(case.scene), ev.scanner_of(case)).sweep(seed=case.seed)
    truth = [t for t in ground_truth_objects(sweep) if t['surface_points'] >= ev.MIN_SURFACE_POINTS]
    windows = [t for t in truth if t['name'].startswith('window_')]
    reflective = [t for t in truth if t['type'] == 1]
    assert windows and all(t['double_echo_surface_points'] == 0 for t in windows)
    assert len(reflective) == 3
    assert all(t['double_echo_surface_points'] >= 0.9 * t['surface_points'] for t in reflective)
