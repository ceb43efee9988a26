"""Intensity features of a mirror or pane in one sweep, and their mirror/glass model (numpy only).

The features and the model of the core's intensity_evidence stage (core/intensity_evidence.h),
computed here for a KNOWN rectangle, so that scripts/calibrate_intensity can fit the model:

* the object's echoes: every return of either echo within `plane_threshold` of its plane and
  inside its rectangle (a beam's far echo only when it lies `echo_threshold` beyond its near one);
  incidence i = the angle between the beam and the plane's normal;
* lit = intensity * range^2 / reference / cos(i), the reference being the median of intensity *
  range^2 over the sweep's returns (a diffuse surface's, roughly: the scanner's gain and units
  cancel);
* `faint_share`: of the echoes beyond the specular peak (i > OFF_PEAK_DEG), the share that is
  faint (FAINT_MIN <= lit < FAINT): a mirror's silvered back gives a faint haze over its whole
  face (about 2 % of the reference in the simulator), glass almost nothing off its peak: what lies
  on its plane there is its frame, as bright as a wall, or its own far fainter haze, seen close by
  only; NaN with fewer than MIN_ECHOES echoes beyond the peak;
* `haze`: the median lit of those faint echoes; NaN with fewer than MIN_ECHOES;
* `echo_ratio`: the median far / near intensity over the beams whose near echo is on the object
  and whose far echo lies behind it; NaN with fewer than MIN_ECHOES beams.

The model (the parameters intensity_haze_*, intensity_faint_share_*, intensity_echo_ratio_*): per
feature a Gaussian per type with one spread, of log10(haze), faint_share and log10(echo_ratio).
The log-odds of mirror against glass is the sum over the features a sweep has of their
log-likelihood ratios, each clamped to +-MAX_FEATURE_LOG_ODDS, the sum to +-MAX_LOG_ODDS.
"""
import math

import numpy as np

OFF_PEAK_DEG = 5.0
FAINT = 0.1
FAINT_MIN = 0.004
MIN_ECHOES = 5
MAX_FEATURE_LOG_ODDS = 3.0
MAX_LOG_ODDS = 6.0
# Feature -> (how it enters its Gaussian, its parameters' stem in the parameter table).
FEATURES = {'haze': (math.log10, 'intensity_haze'), 'faint_share': (float, 'intensity_faint_share'),
            'echo_ratio': (math.log10, 'intensity_echo_ratio')}


def _xyz(cloud):
    return np.stack([cloud['x'], cloud['y'], cloud['z']], axis=-1).astype(float)


def intensity_reference(echo1, echo2):
    """Median intensity * range^2 over every return of the sweep (NaN when none has an intensity)."""
    values = []
    for cloud in (echo1, echo2):
        p = _xyz(cloud)
        r2 = np.einsum('ij,ij->i', p, p)
        v = cloud['intensity'].astype(float) * r2
        values.append(v[np.isfinite(v) & (v > 0)])
    values = np.concatenate(values)
    return float(np.median(values)) if len(values) else float('nan')


def _rectangle(obj):
    corners = np.asarray(obj['corners'], float).reshape(4, 3)
    centre = corners.mean(axis=0)
    u, v = corners[1] - corners[0], corners[3] - corners[0]
    width, height = np.linalg.norm(u), np.linalg.norm(v)
    plane = np.asarray(obj['plane'], float)
    return centre, u / width, v / height, width, height, plane[:3] / np.linalg.norm(plane[:3]), plane[3] / np.linalg.norm(plane[:3])


def on_object(points, obj, plane_threshold):
    """Mask of the points within plane_threshold of the object's plane and inside its rectangle."""
    centre, u, v, width, height, normal, d = _rectangle(obj)
    with np.errstate(invalid='ignore'):
        near = np.abs(points @ normal + d) <= plane_threshold
        rel = points - centre
        inside = (np.abs(rel @ u) <= width / 2) & (np.abs(rel @ v) <= height / 2)
    return near & inside & np.isfinite(points).all(axis=1)


def object_features(echo1, echo2, obj, reference, plane_threshold=0.05, echo_threshold=0.05):
    """{'echoes', 'off_peak_share', 'haze', 'echo_ratio'} of one object (a dict with corners (4, 3)
    in order around the rectangle and plane (a, b, c, d)) in one sweep, in the sweep's frame with the
    sensor at the origin; echo1 / echo2 structured arrays x y z intensity, index-aligned."""
    p1, p2 = _xyz(echo1), _xyz(echo2)
    i1, i2 = echo1['intensity'].astype(float), echo2['intensity'].astype(float)
    r1, r2 = np.linalg.norm(p1, axis=1), np.linalg.norm(p2, axis=1)
    # The near echo first, whatever order the input had.
    swap = np.isfinite(r1) & np.isfinite(r2) & (r2 < r1)
    near_p, far_p = np.where(swap[:, None], p2, p1), np.where(swap[:, None], p1, p2)
    near_i, far_i = np.where(swap, i2, i1), np.where(swap, i1, i2)
    near_r, far_r = np.where(swap, r2, r1), np.where(swap, r1, r2)
    two = np.isfinite(near_r) & np.isfinite(far_r) & (far_r - near_r > echo_threshold)
    on_near = on_object(near_p, obj, plane_threshold)
    on_far = on_object(far_p, obj, plane_threshold) & two
    _, _, _, _, _, normal, _ = _rectangle(obj)
    points = np.concatenate([near_p[on_near], far_p[on_far]])
    intensity = np.concatenate([near_i[on_near], far_i[on_far]])
    ranges = np.linalg.norm(points, axis=1)
    cos_i = np.abs(points @ normal) / np.maximum(ranges, 1e-9)
    incidence = np.degrees(np.arccos(np.clip(cos_i, 0.0, 1.0)))
    q = intensity * ranges ** 2 / reference
    off = (incidence > OFF_PEAK_DEG) & np.isfinite(q) & (q > 0)
    lit = q / np.maximum(cos_i, 1e-3)
    faint = off & (lit < FAINT) & (lit >= FAINT_MIN)
    out = {'echoes': int(len(points)), 'off_peak': int(off.sum()),
           'faint_share': float(faint.sum() / off.sum()) if off.sum() >= MIN_ECHOES else float('nan'),
           'haze': float(np.median(lit[faint])) if faint.sum() >= MIN_ECHOES else float('nan')}
    pairs = on_near & two
    ratio = far_i[pairs] / near_i[pairs]
    ratio = ratio[np.isfinite(ratio) & (ratio > 0)]
    out['echo_ratio'] = float(np.median(ratio)) if len(ratio) >= MIN_ECHOES else float('nan')
    return out


def log_odds(features, params):
    """Log-odds of mirror against glass from one sweep's features (NaN features say nothing) under the
    model in `params` (a dict or an object with the parameter table's intensity_* names)."""
    get = params.get if isinstance(params, dict) else lambda name: getattr(params, name)
    total = 0.0
    for name, (transform, stem) in FEATURES.items():
        value = features.get(name, float('nan'))
        if not (value >= 0) or (transform is math.log10 and value <= 0):
            continue
        x = transform(value)
        mirror, glass, sigma = get(stem + '_mirror'), get(stem + '_glass'), get(stem + '_sigma')
        ratio = 0.5 * (((x - glass) / sigma) ** 2 - ((x - mirror) / sigma) ** 2)
        total += max(-MAX_FEATURE_LOG_ODDS, min(MAX_FEATURE_LOG_ODDS, ratio))
    return max(-MAX_LOG_ODDS, min(MAX_LOG_ODDS, total))


def fit_model(samples, min_sigma=0.05):
    """The model's parameters from samples [(type 'mirror' / 'glass', features)]: per feature the mean of
    each type and their pooled standard deviation (at least min_sigma), under the parameter table's
    names; a feature without two samples of each type is left out. Returns (parameters, counts)."""
    params, counts = {}, {}
    for name, (transform, stem) in FEATURES.items():
        values = {}
        for kind in ('mirror', 'glass'):
            v = [f.get(name, float('nan')) for t, f in samples if t == kind]
            values[kind] = [transform(x) for x in v if x >= 0 and not (transform is math.log10 and x <= 0)]
        counts[name] = {kind: len(v) for kind, v in values.items()}
        if min(len(v) for v in values.values()) < 2:
            continue
        residuals = np.concatenate([np.asarray(v) - np.mean(v) for v in values.values()])
        sigma = math.sqrt(float(residuals @ residuals) / (len(residuals) - 2))
        params[stem + '_mirror'] = float(np.mean(values['mirror']))
        params[stem + '_glass'] = float(np.mean(values['glass']))
        params[stem + '_sigma'] = float(max(sigma, min_sigma))
    return params, counts
