"""Evaluator maths: the filter's output of one sweep against the simulator's ground truth (numpy only).

Inputs are structured arrays or dicts of equal-length arrays (field access by
name), and object dicts:

* ground_truth: 2 N entries with x y z true_x true_y true_z label object_id
  echo beam (simulate.GROUND_TRUTH_DTYPE).
* labelled: label, echo, beam per point (x y z optional) - every point of both echoes.
* cleaned: x y z label echo beam per kept point; a single-return beam's return
  appears once (echo 1, or echo 2 if a filter chose so).
* objects / ground_truth_objects: dicts with type, corners (4, 3), width,
  height, plane (a, b, c, d); id optional.

Everything is counted per *physical return*: a beam with two distinct
returns counts twice, a beam with one return once (its duplicated echo 2 is
ignored), a beam without return once (as nanPoint).

Label comparison. The full confusion matrix has ground-truth labels as rows
and the filter's labels as columns (plus `missing`: no labelled point for
that return). The coarse matrix maps both sides to comparable classes:

* valid: valid
* surface: errorSurface, reflectiveSurface, transparentSurface
* behind: behindErrorS, behindReflective, behindTransparent, and `error` -
  the filter's far echo of a discontinuous beam outside every object is an
  artefact it detected and drops, like a phantom
* invalid: nanPoint
* unchecked / missing: columns only (the filter did not decide).

Phantoms are ground-truth behindReflective returns; they are "at a wrong
place" when they are in `cleaned` more than `tolerance` (5 cm) from their true
position. Real points are ground-truth valid, reflectiveSurface,
transparentSurface and behindTransparent returns; "lost" when not in
`cleaned`, "displaced" when in it but more than `tolerance` from their true
position. The back-projection error is the distance between a back-projected
phantom (cleaned label behindReflective) and its true position.

Intersection over union, per class of points: the ground truth's surface
points (reflectiveSurface, transparentSurface) against the filter's
(errorSurface, reflectiveSurface, transparentSurface), its phantoms
(behindReflective) against the filter's behindReflective, its points behind
glass (behindTransparent) against the filter's behindTransparent; counted over
all physical returns, and over the returns of beams with two echoes (the
double-echo points, where the filter can compare echoes at all).
"Double-echo phantoms" are the phantoms among those.

Objects: every ground-truth object is matched to at most one detection whose
normal is within `max_normal_angle_deg` and whose centroid lies within
`max_match_distance` of the ground-truth rectangle (distance to the
rectangle, so a partial detection inside a large pane matches), the closest
first. Sizes are compared as reported (width along the more horizontal side)
and orientation-agnostic (sorted sides).
"""
import itertools

import numpy as np

from .labels import Label

TOLERANCE = 0.05

LABEL_NAMES = [Label(i).name.lower() for i in range(10)]
MISSING = 10  # column index for "no labelled point"

COARSE_NAMES = ['valid', 'surface', 'behind', 'invalid', 'unchecked', 'missing']
_COARSE = np.array([
    4,  # unchecked
    0,  # valid
    1,  # errorSurface
    2,  # behindErrorS
    1,  # reflectiveSurface
    2,  # behindReflective
    1,  # transparentSurface
    2,  # behindTransparent
    3,  # nanPoint
    2,  # error
    5,  # missing
])

REAL_LABELS = (Label.VALID, Label.REFLECTIVE_SURFACE, Label.TRANSPARENT_SURFACE, Label.BEHIND_TRANSPARENT)

# (class, ground-truth labels, filter labels) of the IoU figures.
IOU_CLASSES = (
    ('surface', (Label.REFLECTIVE_SURFACE, Label.TRANSPARENT_SURFACE),
     (Label.ERROR_SURFACE, Label.REFLECTIVE_SURFACE, Label.TRANSPARENT_SURFACE)),
    ('phantom', (Label.BEHIND_REFLECTIVE,), (Label.BEHIND_REFLECTIVE,)),
    ('behind_glass', (Label.BEHIND_TRANSPARENT,), (Label.BEHIND_TRANSPARENT,)),
)
IOU_SETS = ('double_echo', 'all')


def points_xyz(a, prefix=''):
    return np.stack([np.asarray(a[prefix + 'x'], float), np.asarray(a[prefix + 'y'], float),
                     np.asarray(a[prefix + 'z'], float)], axis=-1)


def _keys(a, n):
    """(echo, beam) -> index into the 2 N ground-truth layout (echo-1 block, then echo-2 block)."""
    echo = np.asarray(a['echo'], np.int64)
    beam = np.asarray(a['beam'], np.int64)
    ok = ((echo == 1) | (echo == 2)) & (beam >= 0) & (beam < n)
    return np.where(ok, (echo - 1) * n + beam, -1)


def _ratio(num, den):
    return float(num) / den if den else None


def _stats(errors):
    errors = np.asarray(errors, float)
    if errors.size == 0:
        return {'count': 0, 'median': None, 'p95': None, 'mean': None, 'max': None}
    return {'count': int(errors.size), 'median': float(np.median(errors)),
            'p95': float(np.percentile(errors, 95)), 'mean': float(errors.mean()), 'max': float(errors.max())}


def ground_truth_layout(ground_truth):
    """(n_beams, physical-return mask over 2 N, two-return mask over N), the GT sorted by (echo, beam)."""
    gt = ground_truth
    n = len(gt['label']) // 2
    keys = _keys(gt, n)
    if len(gt['label']) != 2 * n or np.any(keys < 0) or len(np.unique(keys)) != 2 * n:
        raise ValueError('ground truth must hold every (echo, beam) of both echoes exactly once')
    pos = np.empty((2 * n, 3))
    pos[keys] = points_xyz(gt)
    two = np.isfinite(pos[n:]).all(axis=1) & ~np.all(pos[:n] == pos[n:], axis=1)
    physical = np.r_[np.ones(n, bool), two]
    return n, keys, physical, two


def evaluate_sweep(ground_truth, labelled=None, cleaned=None, objects=None, ground_truth_objects=None,
                   tolerance=TOLERANCE, max_normal_angle_deg=30.0, max_match_distance=0.3):
    """Scores one sweep of the filter against the ground truth. Returns a JSON-friendly dict (see module doc);
    raw per-point errors are under '_raw' (for aggregate_results; dropped from JSON)."""
    gt = ground_truth
    n, keys, physical, two = ground_truth_layout(gt)
    gt_label = np.empty(2 * n, np.int64)
    gt_label[keys] = np.asarray(gt['label'])
    gt_true = np.empty((2 * n, 3))
    gt_true[keys] = points_xyz(gt, 'true_')
    gt_obj = np.empty(2 * n, np.int64)
    gt_obj[keys] = np.asarray(gt['object_id'])

    result = {'beams': int(n), 'physical_returns': int(physical.sum()),
              'ground_truth_counts': {LABEL_NAMES[l]: int(((gt_label == l) & physical).sum())
                                      for l in range(10) if ((gt_label == l) & physical).any()}}
    raw = {}

    # Labels.
    if labelled is not None:
        filt = np.full(2 * n, MISSING, np.int64)
        lk = _keys(labelled, n)
        ok = lk >= 0
        filt[lk[ok]] = np.clip(np.asarray(labelled['label'], np.int64)[ok], 0, 9)
        rows, cols = gt_label[physical], filt[physical]
        full = np.zeros((10, 11), np.int64)
        np.add.at(full, (rows, cols), 1)
        coarse = np.zeros((6, 6), np.int64)
        np.add.at(coarse, (_COARSE[rows], _COARSE[cols]), 1)
        result['confusion'] = _confusion_dict(full, LABEL_NAMES, LABEL_NAMES + ['missing'])
        result['confusion_coarse'] = _confusion_dict(coarse, COARSE_NAMES, COARSE_NAMES)
        raw['confusion'], raw['confusion_coarse'] = full, coarse
        raw['iou_counts'] = iou_counts(gt_label, filt, physical, np.r_[two, two])
        result['iou'] = _iou(raw['iou_counts'])

    # Points in cleaned.
    if cleaned is not None:
        ck = _keys(cleaned, n)
        index = np.full(2 * n, -1, np.int64)
        ok = ck >= 0
        index[ck[ok][::-1]] = np.nonzero(ok)[0][::-1]   # first occurrence wins
        single = ~two
        # A single return may be carried as echo 1 or as echo 2.
        index[:n] = np.where(single & (index[:n] < 0), index[n:], index[:n])
        c_xyz = points_xyz(cleaned)
        c_label = np.asarray(cleaned['label'], np.int64)
        present = index >= 0
        dist = np.full(2 * n, np.nan)
        dist[present] = np.linalg.norm(c_xyz[index[present]] - gt_true[present], axis=1)

        phantom = physical & (gt_label == Label.BEHIND_REFLECTIVE)
        kept = phantom & present
        wrong = kept & (dist > tolerance)
        back = kept & (c_label[np.maximum(index, 0)] == Label.BEHIND_REFLECTIVE)
        double_echo = np.r_[two, two]
        n_cleaned = int(len(c_label))
        counts = {
            'phantoms': int(phantom.sum()), 'phantoms_in_cleaned': int(kept.sum()),
            'phantoms_wrong_place': int(wrong.sum()), 'phantoms_dropped': int((phantom & ~present).sum()),
            'double_echo_phantoms': int((phantom & double_echo).sum()),
            'double_echo_phantoms_wrong_place': int((wrong & double_echo).sum()),
            'phantoms_back_projected': int(back.sum()),
            'phantoms_back_projected_correctly': int((back & (dist <= tolerance)).sum()),
            'cleaned_points': n_cleaned,
        }
        real = physical & np.isin(gt_label, REAL_LABELS)
        lost = real & ~present
        displaced = real & present & (dist > tolerance)
        counts.update({
            'real': int(real.sum()), 'real_lost': int(lost.sum()), 'real_displaced': int(displaced.sum()),
        })
        result['real_lost_by_label'] = {LABEL_NAMES[l]: int((lost & (gt_label == l)).sum()) for l in REAL_LABELS}
        raw['counts'] = counts
        raw['backprojection_errors'] = dist[back]
        result.update(_point_fractions(counts))
        result['backprojection_error'] = _stats(dist[back])

    # Objects.
    if ground_truth_objects is not None:
        matches, false_pos = match_objects(ground_truth_objects, objects or [], max_normal_angle_deg,
                                           max_match_distance)
        result['objects'] = matches
        result['false_positive_objects'] = false_pos
    result['_raw'] = raw
    return result


def iou_counts(gt_label, filter_label, physical, double_echo):
    """{class: {'double_echo' | 'all': [intersection, union]}} over the physical returns (IOU_CLASSES)."""
    out = {}
    for name, truth_labels, filter_labels in IOU_CLASSES:
        g = np.isin(gt_label, truth_labels) & physical
        f = np.isin(filter_label, filter_labels) & physical
        out[name] = {which: [int((g & f & m).sum()), int(((g | f) & m).sum())]
                     for which, m in (('double_echo', double_echo), ('all', np.ones_like(physical)))}
    return out


def _iou(counts):
    return {name: {which: _ratio(*c[which]) for which in IOU_SETS} for name, c in counts.items()}


def _confusion_dict(matrix, rows, cols):
    return {'rows': rows, 'cols': cols, 'matrix': matrix.tolist()}


def _point_fractions(c):
    return {
        'counts': dict(c),
        'phantom_wrong_place_fraction': _ratio(c['phantoms_wrong_place'], c['phantoms']),
        'double_echo_phantom_wrong_place_fraction': _ratio(c['double_echo_phantoms_wrong_place'],
                                                           c['double_echo_phantoms']),
        'cleaned_wrong_place_fraction': _ratio(c['phantoms_wrong_place'], c['cleaned_points']),
        'real_lost_fraction': _ratio(c['real_lost'], c['real']),
        'real_displaced_fraction': _ratio(c['real_displaced'], c['real']),
    }


# ---------------------------------------------------------------------------------------------
# Objects

def rectangle_frame(obj):
    """centre, unit normal, unit side directions (u, v) and half extents of an object's rectangle."""
    c = np.asarray(obj['corners'], float).reshape(4, 3)
    centre = c.mean(axis=0)
    u, v = c[1] - c[0], c[3] - c[0]
    lu, lv = np.linalg.norm(u), np.linalg.norm(v)
    normal = np.asarray(obj['plane'], float)[:3] if 'plane' in obj else np.cross(u, v)
    normal = normal / np.linalg.norm(normal)
    return centre, normal, u / max(lu, 1e-12), v / max(lv, 1e-12), lu / 2, lv / 2


def distance_to_rectangle(point, obj):
    centre, normal, u, v, hu, hv = rectangle_frame(obj)
    d = np.asarray(point, float) - centre
    a, b = np.clip(d @ u, -hu, hu), np.clip(d @ v, -hv, hv)
    return float(np.linalg.norm(d - a * u - b * v))


def corner_errors(detected, truth):
    """Mean and max corner distance under the best correspondence (cyclic order, both directions)."""
    dc = np.asarray(detected['corners'], float).reshape(4, 3)
    tc = np.asarray(truth['corners'], float).reshape(4, 3)
    best = None
    for start, step in itertools.product(range(4), (1, -1)):
        perm = [(start + step * i) % 4 for i in range(4)]
        e = np.linalg.norm(dc[perm] - tc, axis=1)
        if best is None or e.mean() < best.mean():
            best = e
    return float(best.mean()), float(best.max())


def compare_objects(detected, truth):
    """Size, corner, pose and type errors of a detection against a ground-truth object."""
    dcen, dn, *_ = rectangle_frame(detected)
    tcen, tn, *_ = rectangle_frame(truth)
    mean_c, max_c = corner_errors(detected, truth)
    d_sides = sorted([float(detected['width']), float(detected['height'])], reverse=True)
    t_sides = sorted([float(truth['width']), float(truth['height'])], reverse=True)
    return {
        'detected_id': int(detected.get('id', -1)),
        'detected_type': int(detected.get('type', 0)),
        'type_correct': int(detected.get('type', 0)) == int(truth.get('type', 0)),
        'detected_width': float(detected['width']), 'detected_height': float(detected['height']),
        'width_error': float(detected['width']) - float(truth['width']),
        'height_error': float(detected['height']) - float(truth['height']),
        'sorted_sides_error': [d_sides[0] - t_sides[0], d_sides[1] - t_sides[1]],
        'corner_error_mean': mean_c, 'corner_error_max': max_c,
        'centroid_error': float(np.linalg.norm(dcen - tcen)),
        'normal_angle_deg': float(np.degrees(np.arccos(np.clip(abs(dn @ tn), 0.0, 1.0)))),
    }


def match_objects(truth_objects, detected_objects, max_normal_angle_deg=30.0, max_match_distance=0.3):
    """Per ground-truth object its best detection (greedy, one-to-one) and the unmatched detections."""
    candidates = []
    for i, t in enumerate(truth_objects):
        _, tn, *_ = rectangle_frame(t)
        tcen = rectangle_frame(t)[0]
        for j, d in enumerate(detected_objects):
            dcen, dn, *_ = rectangle_frame(d)
            angle = np.degrees(np.arccos(np.clip(abs(dn @ tn), 0.0, 1.0)))
            dist = distance_to_rectangle(dcen, t)
            if angle <= max_normal_angle_deg and dist <= max_match_distance:
                candidates.append((dist + 0.1 * np.linalg.norm(dcen - tcen), i, j))
    candidates.sort()
    used_t, used_d, pairs = set(), set(), {}
    for _, i, j in candidates:
        if i not in used_t and j not in used_d:
            used_t.add(i)
            used_d.add(j)
            pairs[i] = j
    matches = []
    for i, t in enumerate(truth_objects):
        entry = {'truth_id': int(t.get('id', i)), 'truth_type': int(t.get('type', 0)),
                 'truth_name': t.get('name', ''), 'truth_width': float(t['width']),
                 'truth_height': float(t['height']), 'matched': i in pairs}
        if 'surface_points' in t:
            entry['truth_surface_points'] = int(t['surface_points'])
        if 'double_echo_surface_points' in t:
            entry['truth_double_echo_surface_points'] = int(t['double_echo_surface_points'])
        if i in pairs:
            entry.update(compare_objects(detected_objects[pairs[i]], t))
        matches.append(entry)
    false_pos = [{'detected_id': int(d.get('id', j)), 'detected_type': int(d.get('type', 0)),
                  'width': float(d['width']), 'height': float(d['height']),
                  'centroid': rectangle_frame(d)[0].tolist()}
                 for j, d in enumerate(detected_objects) if j not in used_d]
    return matches, false_pos


# ---------------------------------------------------------------------------------------------
# Several sweeps

def aggregate_results(results):
    """Combines per-sweep results: sums counts and confusion matrices, pools back-projection errors,
    and per ground-truth object (by truth_id) the detection rate and mean errors."""
    out = {'sweeps': len(results)}
    if not results:
        return out
    out['physical_returns'] = int(sum(r['physical_returns'] for r in results))
    for key, names in (('confusion', (LABEL_NAMES, LABEL_NAMES + ['missing'])),
                       ('confusion_coarse', (COARSE_NAMES, COARSE_NAMES))):
        mats = [r['_raw'][key] for r in results if key in r.get('_raw', {})]
        if mats:
            out[key] = _confusion_dict(np.sum(mats, axis=0), *names)
    ious = [r['_raw']['iou_counts'] for r in results if 'iou_counts' in r.get('_raw', {})]
    if ious:
        total = {name: {which: np.sum([c[name][which] for c in ious], axis=0).tolist() for which in IOU_SETS}
                 for name in ious[0]}
        out['iou_counts'] = total
        out['iou'] = _iou(total)
    counts = [r['_raw']['counts'] for r in results if 'counts' in r.get('_raw', {})]
    if counts:
        total = {k: int(sum(c[k] for c in counts)) for k in counts[0]}
        out.update(_point_fractions(total))
        out['backprojection_error'] = _stats(np.concatenate([r['_raw']['backprojection_errors'] for r in results
                                                             if 'backprojection_errors' in r['_raw']]))
    per_object = {}
    for r in results:
        for m in r.get('objects', []):
            per_object.setdefault(m['truth_id'], []).append(m)
    if per_object:
        out['objects'] = []
        numeric = ('detected_width', 'detected_height', 'width_error', 'height_error', 'corner_error_mean',
                   'corner_error_max', 'centroid_error', 'normal_angle_deg')
        for tid, ms in sorted(per_object.items()):
            hit = [m for m in ms if m['matched']]
            entry = {k: ms[0][k] for k in ('truth_id', 'truth_type', 'truth_name', 'truth_width', 'truth_height')}
            entry['detection_rate'] = len(hit) / len(ms)
            entry['type_correct_rate'] = _ratio(sum(m['type_correct'] for m in hit), len(hit))
            for k in numeric:
                entry['mean_' + k] = float(np.mean([m[k] for m in hit])) if hit else None
            if hit:
                entry['mean_sorted_sides_error'] = np.mean([m['sorted_sides_error'] for m in hit], axis=0).tolist()
            out['objects'].append(entry)
        out['false_positive_objects_per_sweep'] = float(np.mean([len(r.get('false_positive_objects', []))
                                                                 for r in results]))
    return out


def type_accuracy(results, min_surface_points=50):
    """Over the ground-truth objects of all results with at least min_surface_points surface echoes:
    {'objects', 'right', 'fraction'}; an object is right when a detection matched it with its type.
    Where the truth says how many of an object's surface echoes came with a second echo, also
    'no_double_echo' and 'no_double_echo_right': the objects none of whose surface echoes did (a
    pane with nothing behind it in range: one sweep's echo comparison has nothing to go on there),
    and how many of those are right."""
    objects = [m for r in results for m in r.get('objects', [])
               if m.get('truth_surface_points', 0) >= min_surface_points]
    right = sum(1 for m in objects if _typed_right(m))
    out = {'objects': len(objects), 'right': right, 'fraction': _ratio(right, len(objects))}
    if objects and all('truth_double_echo_surface_points' in m for m in objects):
        lone = [m for m in objects if m['truth_double_echo_surface_points'] == 0]
        out.update(no_double_echo=len(lone), no_double_echo_right=sum(1 for m in lone if _typed_right(m)))
    return out


def _typed_right(match):
    return match['matched'] and match['type_correct']


def false_object_scenes(results):
    """Over results without any ground-truth object: {'scenes', 'with_false_objects', 'fraction',
    'false_objects'} (false_objects: how many in all)."""
    plain = [r for r in results if 'objects' in r and not r['objects']]
    with_false = sum(1 for r in plain if r.get('false_positive_objects'))
    return {'scenes': len(plain), 'with_false_objects': with_false, 'fraction': _ratio(with_false, len(plain)),
            'false_objects': int(sum(len(r.get('false_positive_objects', [])) for r in plain))}


def strip_raw(result):
    """The result without its raw arrays (for JSON)."""
    return {k: v for k, v in result.items() if not k.startswith('_')}


# ---------------------------------------------------------------------------------------------
# Reference outputs (tests, baselines)

def oracle_filter_output(ground_truth, ground_truth_objects=None):
    """What a perfect filter would publish for this ground truth: labelled = the true labels, cleaned = every
    return once at its true place (phantoms back-projected; nanPoint dropped), objects = the truth."""
    n, keys, physical, two = ground_truth_layout(ground_truth)
    gt = ground_truth
    labelled = {'x': np.asarray(gt['x']), 'y': np.asarray(gt['y']), 'z': np.asarray(gt['z']),
                'label': np.asarray(gt['label']), 'echo': np.asarray(gt['echo']), 'beam': np.asarray(gt['beam'])}
    keep = physical[keys] & (np.asarray(gt['label']) != Label.NAN_POINT)
    pos = points_xyz(gt, 'true_')[keep]
    cleaned = {'x': pos[:, 0], 'y': pos[:, 1], 'z': pos[:, 2], 'label': np.asarray(gt['label'])[keep],
               'echo': np.asarray(gt['echo'])[keep], 'beam': np.asarray(gt['beam'])[keep]}
    return {'labelled': labelled, 'cleaned': cleaned, 'objects': list(ground_truth_objects or [])}


def passthrough_filter_output(ground_truth):
    """A filter that does nothing: every return labelled valid and kept where it was measured."""
    n, keys, physical, two = ground_truth_layout(ground_truth)
    gt = ground_truth
    label = np.where(np.asarray(gt['label']) == Label.NAN_POINT, Label.NAN_POINT, Label.VALID).astype(np.uint8)
    keep = physical[keys] & (label != Label.NAN_POINT)
    labelled = {'x': np.asarray(gt['x']), 'y': np.asarray(gt['y']), 'z': np.asarray(gt['z']), 'label': label,
                'echo': np.asarray(gt['echo']), 'beam': np.asarray(gt['beam'])}
    cleaned = {k: np.asarray(v)[keep] for k, v in labelled.items()}
    return {'labelled': labelled, 'cleaned': cleaned, 'objects': []}
