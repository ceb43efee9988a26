"""The evaluator's maths on hand-made cases and on a simulated sweep."""
import numpy as np
import pytest

from ohm_mirror_detector3d import metrics, report
from ohm_mirror_detector3d.labels import Label
from ohm_mirror_detector3d.simulate import GROUND_TRUTH_DTYPE

V, RS, BR, NAN = Label.VALID, Label.REFLECTIVE_SURFACE, Label.BEHIND_REFLECTIVE, Label.NAN_POINT


def hand_made_ground_truth():
    """Three beams: 0 a single valid return, 1 mirror surface + phantom, 2 no return."""
    nan = [np.nan] * 3
    rows = [  # measured, true, label, object, echo, beam, double echo
        ([1, 0, 0], [1, 0, 0], V, -1, 1, 0, 0), ([2, 0, 0], [2, 0, 0], RS, 0, 1, 1, 1), (nan, nan, NAN, -1, 1, 2, 0),
        ([1, 0, 0], [1, 0, 0], V, -1, 2, 0, 0), ([5, 0, 0], [-1, 0, 0], BR, 0, 2, 1, 1), (nan, nan, NAN, -1, 2, 2, 0),
    ]
    gt = np.zeros(len(rows), GROUND_TRUTH_DTYPE)
    for i, (m, t, lab, obj, echo, beam, double) in enumerate(rows):
        gt[i] = (*m, *t, lab, obj, echo, beam, double)
    return gt


def cloud(points):
    """cleaned/labelled dict from (x, y, z, label, echo, beam) tuples."""
    a = np.array(points, float).reshape(-1, 6)
    return {'x': a[:, 0], 'y': a[:, 1], 'z': a[:, 2], 'label': a[:, 3].astype(np.uint8),
            'echo': a[:, 4].astype(np.uint8), 'beam': a[:, 5].astype(np.uint32)}


MIRROR = {'id': 0, 'type': 1, 'width': 0.6, 'height': 0.4, 'plane': [-1.0, 0, 0, 2.0],
          'corners': [[2, -0.3, -0.2], [2, 0.3, -0.2], [2, 0.3, 0.2], [2, -0.3, 0.2]]}


def test_perfect_output_scores_perfect():
    gt = hand_made_ground_truth()
    out = metrics.oracle_filter_output(gt, [MIRROR])
    r = metrics.evaluate_sweep(gt, out['labelled'], out['cleaned'], out['objects'], [MIRROR])
    assert r['physical_returns'] == 4  # beam 0 once, beam 1 twice, beam 2 once (no return)
    assert r['phantom_wrong_place_fraction'] == 0.0 and r['real_lost_fraction'] == 0.0
    assert r['counts']['phantoms_back_projected_correctly'] == 1
    m = np.array(r['confusion']['matrix'])
    assert m.trace() == m.sum() == 4
    assert r['backprojection_error']['median'] == 0.0
    obj = r['objects'][0]
    assert obj['matched'] and obj['type_correct'] and obj['corner_error_max'] == 0.0 and not r['false_positive_objects']


def test_a_filter_that_keeps_phantoms_in_place_scores_the_phantom_fraction_exactly():
    gt = hand_made_ground_truth()
    out = metrics.passthrough_filter_output(gt)
    r = metrics.evaluate_sweep(gt, out['labelled'], out['cleaned'])
    assert r['phantom_wrong_place_fraction'] == 1.0
    assert r['cleaned_wrong_place_fraction'] == pytest.approx(1 / 3)  # 3 cleaned points, one phantom
    assert r['real_lost_fraction'] == 0.0
    coarse = np.array(r['confusion_coarse']['matrix'])
    assert coarse[2, 0] == 1 and coarse[1, 0] == 1  # behind and surface taken for valid


def test_lost_points_are_counted_once_per_physical_return():
    gt = hand_made_ground_truth()
    # Drops beam 0 (a single return, present twice in labelled) and keeps the phantom back-projected.
    cleaned = cloud([(2, 0, 0, RS, 1, 1), (-1, 0, 0, BR, 2, 1)])
    r = metrics.evaluate_sweep(gt, None, cleaned)
    assert r['counts']['real'] == 2 and r['counts']['real_lost'] == 1 and r['real_lost_fraction'] == 0.5
    # The single return may come as echo 2 instead of echo 1; a duplicate does not count twice.
    cleaned = cloud([(1, 0, 0, V, 2, 0), (2, 0, 0, RS, 1, 1), (-1, 0, 0, BR, 2, 1)])
    r = metrics.evaluate_sweep(gt, None, cleaned)
    assert r['counts']['real_lost'] == 0
    assert r['counts']['phantoms_back_projected_correctly'] == 1


def test_misplaced_back_projection_and_dropped_phantom():
    gt = hand_made_ground_truth()
    off = cloud([(1, 0, 0, V, 1, 0), (2, 0, 0, RS, 1, 1), (-1, 0.1, 0, BR, 2, 1)])
    r = metrics.evaluate_sweep(gt, None, off)
    assert r['phantom_wrong_place_fraction'] == 1.0
    assert r['backprojection_error']['median'] == pytest.approx(0.1)
    dropped = cloud([(1, 0, 0, V, 1, 0), (2, 0, 0, RS, 1, 1)])
    r = metrics.evaluate_sweep(gt, None, dropped)
    assert r['phantom_wrong_place_fraction'] == 0.0 and r['counts']['phantoms_dropped'] == 1


def test_confusion_maps_filter_labels_to_classes():
    gt = hand_made_ground_truth()
    labelled = cloud([(1, 0, 0, V, 1, 0), (2, 0, 0, Label.ERROR_SURFACE, 1, 1), (np.nan,) * 3 + (NAN, 1, 2),
                      (1, 0, 0, V, 2, 0), (5, 0, 0, Label.ERROR, 2, 1)])  # beam 2 echo 2 missing: not counted
    r = metrics.evaluate_sweep(gt, labelled)
    full = np.array(r['confusion']['matrix'])
    assert full[RS, Label.ERROR_SURFACE] == 1 and full[BR, Label.ERROR] == 1 and full[NAN, NAN] == 1
    coarse = np.array(r['confusion_coarse']['matrix'])
    assert np.trace(coarse) == 4


def test_iou_among_double_echo_points_and_among_all():
    gt = hand_made_ground_truth()
    # The filter finds the mirror's surface echo and its phantom, and takes beam 0's valid return
    # for a surface point too.
    labelled = cloud([(1, 0, 0, Label.ERROR_SURFACE, 1, 0), (2, 0, 0, Label.ERROR_SURFACE, 1, 1),
                      (np.nan,) * 3 + (NAN, 1, 2), (1, 0, 0, Label.ERROR_SURFACE, 2, 0), (5, 0, 0, BR, 2, 1),
                      (np.nan,) * 3 + (NAN, 2, 2)])
    r = metrics.evaluate_sweep(gt, labelled)
    assert r['iou']['surface'] == {'double_echo': 1.0, 'all': 0.5}
    assert r['iou']['phantom'] == {'double_echo': 1.0, 'all': 1.0}
    assert r['iou']['behind_glass'] == {'double_echo': None, 'all': None}   # none on either side
    # The phantom taken for a valid point: no phantom IoU at all; pooled over two sweeps: 1 / 2.
    missed = cloud([(1, 0, 0, V, 1, 0), (2, 0, 0, RS, 1, 1), (5, 0, 0, V, 2, 1)])
    r2 = metrics.evaluate_sweep(gt, missed)
    assert r2['iou']['phantom']['double_echo'] == 0.0
    summary = metrics.aggregate_results([r, r2])
    assert summary['iou']['phantom']['double_echo'] == 0.5
    assert summary['iou_counts']['surface']['all'] == [2, 3]


def test_double_echo_phantoms_left_at_a_wrong_place():
    gt = hand_made_ground_truth()
    out = metrics.passthrough_filter_output(gt)
    r = metrics.evaluate_sweep(gt, out['labelled'], out['cleaned'])
    assert r['counts']['double_echo_phantoms'] == 1 and r['double_echo_phantom_wrong_place_fraction'] == 1.0
    # The same phantom as a single echo (its beam without the surface echo) is no double-echo phantom.
    single = gt[[0, 1, 2, 3, 4, 5]].copy()
    single[1] = single[4]
    single[1]['echo'], single[1]['beam'] = 1, 1
    single[4] = single[1]
    single[4]['echo'] = 2
    single['double_echo'] = 0
    out = metrics.passthrough_filter_output(single)
    r = metrics.evaluate_sweep(single, out['labelled'], out['cleaned'])
    assert r['counts']['phantoms'] == 1 and r['counts']['double_echo_phantoms'] == 0
    assert r['phantom_wrong_place_fraction'] == 1.0 and r['double_echo_phantom_wrong_place_fraction'] is None


def test_type_accuracy_counts_objects_with_enough_surface_echoes_and_false_objects_scenes_without_any():
    truth = [dict(MIRROR, surface_points=80), dict(MIRROR, id=1, surface_points=10,
                                                   corners=np.asarray(MIRROR['corners']) + [0, 2, 0])]
    glass_guess = dict(MIRROR, type=2)
    with_objects = metrics.evaluate_sweep(hand_made_ground_truth(), objects=[glass_guess], ground_truth_objects=truth)
    right = metrics.evaluate_sweep(hand_made_ground_truth(), objects=[MIRROR], ground_truth_objects=truth)
    assert with_objects['objects'][0]['truth_surface_points'] == 80
    # Only the first object has >= 50 surface echoes: typed glass once (wrong), mirror once (right).
    assert metrics.type_accuracy([with_objects, right], 50) == {'objects': 2, 'right': 1, 'fraction': 0.5}
    assert metrics.type_accuracy([with_objects], 5)['objects'] == 2
    # Told how many surface echoes came with a second echo, it counts the objects with none apart.
    lone = [dict(t, double_echo_surface_points=0) for t in truth]
    lone_wrong = metrics.evaluate_sweep(hand_made_ground_truth(), objects=[glass_guess], ground_truth_objects=lone)
    lone_right = metrics.evaluate_sweep(hand_made_ground_truth(), objects=[MIRROR], ground_truth_objects=lone)
    assert lone_wrong['objects'][0]['truth_double_echo_surface_points'] == 0
    assert metrics.type_accuracy([lone_wrong, lone_right], 50) == {
        'objects': 2, 'right': 1, 'fraction': 0.5, 'no_double_echo': 2, 'no_double_echo_right': 1}
    seen = [dict(t, double_echo_surface_points=t['surface_points']) for t in truth]
    seen_right = metrics.evaluate_sweep(hand_made_ground_truth(), objects=[MIRROR], ground_truth_objects=seen)
    assert metrics.type_accuracy([seen_right], 50)['no_double_echo'] == 0
    plain_clean = metrics.evaluate_sweep(hand_made_ground_truth(), objects=[], ground_truth_objects=[])
    plain_false = metrics.evaluate_sweep(hand_made_ground_truth(), objects=[MIRROR, glass_guess],
                                         ground_truth_objects=[])
    scored = metrics.false_object_scenes([with_objects, plain_clean, plain_false])
    assert scored == {'scenes': 2, 'with_false_objects': 1, 'fraction': 0.5, 'false_objects': 2}


def test_object_sizes_and_corner_errors():
    shifted = dict(MIRROR, corners=np.asarray(MIRROR['corners']) + [0, 0.02, 0], id=3)
    r = metrics.match_objects([MIRROR], [shifted])[0][0]
    assert r['matched'] and r['detected_id'] == 3
    assert r['corner_error_mean'] == pytest.approx(0.02) and r['width_error'] == 0.0
    # Reported with width and height swapped: the orientation-agnostic comparison still agrees.
    swapped = dict(MIRROR, width=0.4, height=0.6, corners=np.roll(MIRROR['corners'], 1, axis=0))
    r = metrics.match_objects([MIRROR], [swapped])[0][0]
    assert r['width_error'] == pytest.approx(-0.2) and r['sorted_sides_error'] == [0.0, 0.0]
    assert r['corner_error_max'] == pytest.approx(0.0)
    # Far away or turned 90 deg: no match, a false positive.
    far = dict(MIRROR, corners=np.asarray(MIRROR['corners']) + [0, 3, 0])
    matches, fps = metrics.match_objects([MIRROR], [far])
    assert not matches[0]['matched'] and len(fps) == 1
    # A small patch inside a big pane matches it.
    pane = dict(MIRROR, type=2, width=0.88, height=1.98,
                corners=[[2, -0.44, -0.99], [2, 0.44, -0.99], [2, 0.44, 0.99], [2, -0.44, 0.99]])
    patch = dict(MIRROR, type=2, width=0.3, height=0.24,
                 corners=[[2, -0.15, 0.3], [2, 0.15, 0.3], [2, 0.15, 0.54], [2, -0.15, 0.54]])
    assert metrics.match_objects([pane], [patch])[0][0]['matched']


def test_simulated_sweep_oracle_and_passthrough(experiment1_sweep):
    gt, objects = experiment1_sweep.ground_truth, experiment1_sweep.objects
    phantoms = int((gt['label'] == BR).sum())
    out = metrics.oracle_filter_output(gt, objects)
    perfect = metrics.evaluate_sweep(gt, out['labelled'], out['cleaned'], out['objects'], objects)
    assert perfect['phantom_wrong_place_fraction'] == 0.0 and perfect['real_lost_fraction'] == 0.0
    out = metrics.passthrough_filter_output(gt)
    naive = metrics.evaluate_sweep(gt, out['labelled'], out['cleaned'], out['objects'], objects)
    assert naive['counts']['phantoms'] == phantoms > 0
    assert naive['phantom_wrong_place_fraction'] == 1.0
    assert naive['cleaned_wrong_place_fraction'] == pytest.approx(phantoms / len(out['cleaned']['x']))
    assert not naive['objects'][0]['matched']
    summary = metrics.aggregate_results([perfect, naive])
    assert summary['sweeps'] == 2 and summary['phantom_wrong_place_fraction'] == pytest.approx(0.5)
    assert summary['objects'][0]['detection_rate'] == 0.5
    md = report.to_markdown(report.jsonable(summary))
    assert '| mirror |' in md and 'Confusion' in md


def test_report_files(tmp_path, experiment1_sweep):
    import json
    gt = experiment1_sweep.ground_truth
    out = metrics.oracle_filter_output(gt, experiment1_sweep.objects)
    r = metrics.evaluate_sweep(gt, out['labelled'], out['cleaned'], out['objects'], experiment1_sweep.objects)
    json_path, md_path = report.write_report(str(tmp_path), metrics.aggregate_results([r]), [r])
    data = json.load(open(json_path))
    assert data['summary']['real_lost_fraction'] == 0.0 and '_raw' not in data['sweeps'][0]
    assert open(md_path).read().startswith('# ')
