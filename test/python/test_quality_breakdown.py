"""scripts/quality_breakdown: its breakdown accounts for exactly the points the evaluator counts."""
import os
from importlib.machinery import SourceFileLoader

import pytest

core = pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')

from ohm_mirror_detector3d import metrics  # noqa: E402
from ohm_mirror_detector3d import scene as scenes  # noqa: E402
from ohm_mirror_detector3d import scene_evaluation as ev  # noqa: E402
from ohm_mirror_detector3d.simulate import SweepSimulator, ground_truth_objects  # noqa: E402

SCRIPT = os.path.join(os.path.dirname(__file__), '..', '..', 'scripts', 'quality_breakdown')


def test_the_breakdown_counts_what_the_evaluator_counts():
    breakdown = SourceFileLoader('quality_breakdown', SCRIPT).load_module()
    case = ev.cases(['hesai_qt64'], 1, 3, named=False)[0]
    pipeline = core.Pipeline()
    b = breakdown.breakdown(case, pipeline)
    sweep = SweepSimulator(scenes.get(case.scene), ev.scanner_of(case)).sweep(seed=case.seed)
    gt, labelled, cleaned, objects = ev.filter_case(pipeline, sweep, ev.INPUT_MODES[case.family])
    score = metrics.evaluate_sweep(gt, labelled, cleaned, objects, ground_truth_objects(sweep))
    counts = score['counts']
    assert counts['double_echo_phantoms_wrong_place'] > 0, 'a scene without the case the breakdown explains'
    assert sum(b['phantom'].values()) == counts['double_echo_phantoms_wrong_place']
    assert b['counts']['double-echo phantoms'] == counts['double_echo_phantoms']
    # Every ground-truth object with enough surface echoes appears once in the type confusion.
    assert len(b['types']) == metrics.type_accuracy([score], ev.MIN_SURFACE_POINTS)['objects']


def test_the_scenes_by_loss_account_for_every_phantom_at_a_wrong_place_worst_first():
    breakdown = SourceFileLoader('quality_breakdown', SCRIPT).load_module()
    pipeline = core.Pipeline()
    per_scene = [(case.scene, breakdown.breakdown(case, pipeline))
                 for case in ev.cases(['hesai_qt64'], 2, 3, named=False)]
    rows = breakdown.scenes_by_loss(per_scene)
    assert [row[0] for row in rows] == sorted((scene for scene, _ in per_scene),
                                              key=lambda scene: -sum(dict(per_scene)[scene]['phantom'].values()))
    assert sum(row[2] for row in rows) == sum(sum(b['phantom'].values()) for _, b in per_scene)
    assert rows[0][2] > 0, 'no scene with phantoms at a wrong place to rank'
    for scene, phantoms, wrong, groups in rows:
        assert wrong <= phantoms
        assert sum(n for _, n in groups) <= wrong


def test_the_scenes_by_loss_of_points_behind_glass_account_for_every_one_not_labelled_behind_transparent():
    breakdown = SourceFileLoader('quality_breakdown', SCRIPT).load_module()
    pipeline = core.Pipeline()
    per_scene = [(case.scene, breakdown.breakdown(case, pipeline))
                 for case in ev.cases(['hesai_qt64'], 2, 3, named=False)]
    rows = breakdown.scenes_by_loss(per_scene, 'glass')
    assert sum(row[2] for row in rows) == sum(sum(b['glass'].values()) for _, b in per_scene)
    assert rows[0][2] > 0, 'no scene with points behind glass labelled otherwise to rank'
    assert [row[2] for row in rows] == sorted((row[2] for row in rows), reverse=True)
    for scene, behind, lost, groups in rows:
        assert behind == dict(per_scene)[scene]['counts']['double-echo behind glass']
        assert lost <= behind
        assert sum(n for _, n in groups) <= lost
