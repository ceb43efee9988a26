"""Intensity features of a mirror or pane in one sweep, and their mirror/glass model.

The features are the core's intensity_evidence stage's (core/intensity_evidence.h), computed by
that stage's own code for a KNOWN rectangle (`object_features`, through the bindings), so that
scripts/calibrate_intensity fits the model on exactly what the stage measures:

* the object's echoes: every return of either echo within `plane_threshold` of its plane and
  inside its rectangle (a beam's far echo only when it lies `echo_threshold` beyond its near one);
  incidence i = the angle between the beam and the plane's normal;
* lit = intensity * range^2 / reference / cos(i), the reference being the median of intensity *
  range^2 over the sweep's returns (a diffuse surface's, roughly: the scanner's gain and units
  cancel);
* `faint_share`: of the echoes beyond the specular peak, the share that is faint: a mirror's
  silvered back gives a faint haze over its whole face, glass almost nothing off its peak;
* `haze`: the median lit of those faint echoes;
* `echo_ratio`: the median far / near intensity over the beams whose near echo is on the object
  and whose far echo lies behind it;
each NaN with too few echoes for it.

The model (the parameters intensity_haze_*, intensity_faint_share_*, intensity_echo_ratio_*): per
feature a Gaussian per type with one spread, of log10(haze), faint_share and log10(echo_ratio).
The log-odds of mirror against glass is the sum over the features a sweep has of their
log-likelihood ratios, each clamped to +-MAX_FEATURE_LOG_ODDS, the sum to +-MAX_LOG_ODDS.
"""
import math

import numpy as np

from . import _core
from .core import _points_of

# As the core's kMaxFeatureLogOdds and kMaxLogOdds (core/intensity_evidence.h).
MAX_FEATURE_LOG_ODDS = 3.0
MAX_LOG_ODDS = 6.0
# Feature -> (how it enters its Gaussian, its parameters' stem in the parameter table).
FEATURES = {'haze': (math.log10, 'intensity_haze'), 'faint_share': (float, 'intensity_faint_share'),
            'echo_ratio': (math.log10, 'intensity_echo_ratio')}


def object_features(echo1, echo2, obj, plane_threshold=0.05, echo_threshold=0.05):
    """{'echoes', 'off_peak', 'faint_share', 'haze', 'echo_ratio'} of one object (a dict with corners
    (4, 3) in order around the rectangle and plane (a, b, c, d)) in one sweep, in the sweep's frame
    with the sensor at the origin; echo1 / echo2 structured float32 arrays x y z intensity,
    index-aligned. The reference intensity is the sweep's, as the stage takes it."""
    points1, intensity1 = _points_of(echo1, 'echo1')
    points2, intensity2 = _points_of(echo2, 'echo2')
    corners = np.asarray(obj['corners'], float).reshape(4, 3).tolist()
    plane = [float(v) for v in obj['plane']]
    return _core.intensity_features(points1, points2, intensity1, intensity2, corners, plane,
                                    float(plane_threshold), float(echo_threshold))


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
