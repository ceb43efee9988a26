"""The pre-filter from Python, without ROS: the C++ core pipeline on numpy arrays.

    from ohm_mirror_detector3d.core import Params, Pipeline
    pipeline = Pipeline(Params(outlierFilter_minNeighbors=5, outlierFilter_searchRadius=0.2))
    result = pipeline.filter(echo1, echo2)          # (N, 3) float32 each, index-aligned beams
    result.labels                                   # (2, N) uint8: labels of echo 1 and echo 2
    result.cleaned, result.objects                  # points for mapping, mirrors and glass found

`Params` has the names and defaults of the ROS parameters (the original launch file's names;
the paper's names such as `d_min` or `r` are accepted by `Params.from_dict` and as keyword
arguments of `Pipeline`) and is validated by the same C++ code as the nodelet's parameters.
Values given there under the original's names that meant something else in the original
(`outlierFilter_minNeighbors` 50 within `outlierFilter_searchRadius` 0.1, `max_Dist_ICP` 0.01)
are mapped to what they meant, as the node and prefilter_bag map them, each with a
LegacyValueWarning saying so (README "Replacing the original node").

A `Pipeline` runs exactly the nodelet's code (core::Pipeline): the same input gives the same
labels, bit for bit. It copies the input once into the core's sweep (which it reuses from call
to call) and releases the GIL while the core runs. Input rules, checked before anything runs
(TypeError / ValueError with the reason, never a crash):

* points: float32 (native byte order), shape (N, 3), or (rows, cols, 3) for an organised pair;
  a structured array with x y z (and intensity) fields is converted first (a copy);
* a missing return is non-finite in all of x y z (NaN or Inf, REP-117); a point with some
  coordinates finite and others not is refused;
* intensities: optional, any real dtype, one per point (NaN allowed);
* dual-return data: `returns` (1/2 or 0/1) and `rings`, integer arrays, one per point.

Outputs are numpy structured arrays with the fields of the nodelet's `labelled` and `cleaned`
PointCloud2s (x y z intensity label echo beam, the same 24-byte layout) and objects as dicts
with the fields of ReflectiveObject.msg (plus type_name and centre).
"""
import dataclasses
import re
import warnings
from dataclasses import dataclass
from typing import Any, Dict, List, Optional

import numpy as np

from . import _core
from .labels import Label

# One point of `labelled` and `cleaned`: the core's record (core/output_records.h), which the
# nodelet's PointCloud2s carry too.
OUTPUT_DTYPE = _core.OUTPUT_DTYPE

OBJECT_TYPE_NAMES = {0: 'unknown', 1: 'mirror', 2: 'glass'}
MODES = ('pair', 'dual_return')

# Every parameter of the pre-filter (core/param_table.h), one dict per row in the table's order:
# name (the ROS name), names (every name it is accepted under), symbol, type ('real', 'integer',
# 'text', 'real_list'), scope ('pipeline', 'core_input', 'ros_input', 'node'), default, ranges,
# unit, doc, and for pipeline parameters the field of the core's Params.
PARAMETER_TABLE = tuple(_core.parameter_table())

_KINDS = {'real': float, 'integer': int}
# The rows this module's Params holds: the pipeline's and those of the core's input adapters.
_ROWS = tuple(row for row in PARAMETER_TABLE if row['scope'] in ('pipeline', 'core_input'))

# Every pipeline parameter: ROS name (original launch file, cfg/PreFilter.cfg), paper symbol or
# other accepted name (None when it has none), the field of the core's Params, and its type.
PARAMETERS = tuple((row['name'], (row['names'][1:] or [None])[0], row['field'], _KINDS[row['type']])
                   for row in PARAMETER_TABLE if row['scope'] == 'pipeline')

# Names of the ROS parameter files that are the node's and prefilter_bag's only (input mode,
# frames, topic names, ...): accepted by Params.from_dict and not used here.
ROS_ONLY_KEYS = frozenset(name for row in PARAMETER_TABLE if row not in _ROWS for name in row['names'])

_DECIMAL = re.compile(r'^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$')


class LegacyValueWarning(UserWarning):
    """A value given under the original node's name was mapped to what it meant there (the line
    the node and prefilter_bag log at start-up)."""


class _ParamsMethods:
    """The methods of Params (a dataclass made from the parameter table below)."""

    def type_errors(self) -> List[str]:
        """One message per value of the wrong type (an int is a number; a number is not an int)."""
        errors = []
        for row in _ROWS:
            kind = _KINDS[row['type']]
            value = getattr(self, row['name'])
            ok = (isinstance(value, (int, np.integer)) if kind is int else
                  isinstance(value, (int, float, np.integer, np.floating))) and not isinstance(value, bool)
            if not ok:
                errors.append('parameter %s = %r has the wrong type: expected %s'
                              % (row['name'], value, 'an integer' if kind is int else 'a number'))
        return errors

    def to_core(self):
        """The core's Params (C++ names). Raises TypeError for values of the wrong type."""
        errors = self.type_errors()
        if errors:
            raise TypeError('invalid pre-filter parameters:\n  ' + '\n  '.join(errors))
        out = _core.Params()
        for ros, _, core_name, kind in PARAMETERS:
            setattr(out, core_name, kind(getattr(self, ros)))
        return out

    def validate(self) -> List[str]:
        """One message per bad value, the nodelet's messages (Params::validate and the input
        adapters' checks); empty when all are fine."""
        errors = self.type_errors()
        if errors:
            return errors
        errors = list(self.to_core().validate())
        for row in _ROWS:
            if row['scope'] != 'pipeline':
                problem = _core.check_start_up(row['name'], float(getattr(self, row['name'])))
                errors += [problem] if problem else []
        return errors

    def check(self):
        """Raises TypeError (wrong types) or ValueError (out of range) naming every bad value."""
        self.to_core()
        errors = self.validate()
        if errors:
            raise ValueError('invalid pre-filter parameters:\n  ' + '\n  '.join(errors))
        return self

    @classmethod
    def from_dict(cls, values: Dict[str, Any], base: Optional['Params'] = None, source: str = 'parameters',
                  ignore=ROS_ONLY_KEYS) -> 'Params':
        """Params from any name a parameter is accepted under (ROS name, paper symbol, alias; as
        the nodelet reads them); keys in `ignore` are skipped. Raises ValueError for unknown names
        and for two names of one parameter that disagree, TypeError for values of the wrong type."""
        params = dataclasses.replace(base) if base is not None else cls()
        values = dict(values)
        given_names = list(values)
        errors, type_errors = [], []
        for row in _ROWS:
            kind = _KINDS[row['type']]
            given = [(n, values.pop(n)) for n in row['names'] if n in values]
            converted = []
            for name, value in given:
                # PyYAML reads plain `5e-3` as a string; the nodelet's YAML reader takes it as a number.
                if kind is float and isinstance(value, str) and _DECIMAL.match(value.strip()):
                    value = float(value)
                is_int = isinstance(value, (int, np.integer)) and not isinstance(value, bool)
                is_num = is_int or isinstance(value, (float, np.floating))
                if not (is_int if kind is int else is_num):
                    type_errors.append('parameter %s = %r (in %s) has the wrong type: expected %s'
                                       % (name, value, source, 'an integer' if kind is int else 'a number'))
                    continue
                converted.append((name, kind(value)))
            disagreeing = [other for other in converted[1:] if other[1] != converted[0][1]]
            for other in disagreeing:
                errors.append('parameters %s = %s and %s = %s (in %s) name the same value and disagree; give only one'
                              % (converted[0] + other + (source,)))
            if converted and not disagreeing:
                setattr(params, row['name'], converted[0][1])
        unknown = sorted(k for k in values if k not in ignore)
        if unknown:
            errors.append('unknown parameter%s in %s: %s (known: %s)' % (
                's' if len(unknown) > 1 else '', source, ', '.join(unknown), ', '.join(row['name'] for row in _ROWS)))
        if type_errors:
            raise TypeError('invalid pre-filter parameters:\n  ' + '\n  '.join(type_errors + errors))
        if errors:
            raise ValueError('invalid pre-filter parameters:\n  ' + '\n  '.join(errors))
        return params._with_legacy_values_mapped(given_names, source)

    def _with_legacy_values_mapped(self, given_names, source):
        """The original's values given under its names alone mapped to what they meant there
        (core/legacy_values.h), a LegacyValueWarning each. Refused values stay as given (check()
        names them), as the node maps only values it accepted."""
        if self.validate():
            return self
        mapped, lines = _core.map_legacy_values(self.to_core(), given_names)
        for line in lines:
            warnings.warn('%s (in %s)' % (line, source), LegacyValueWarning, stacklevel=4)
        for ros, _, core_name, kind in PARAMETERS:
            setattr(self, ros, kind(getattr(mapped, core_name)))
        return self

    @classmethod
    def from_yaml(cls, path: str) -> 'Params':
        """Params from a ROS parameter file such as launch/rotating_hokuyo_params.yaml."""
        return cls.from_dict(read_yaml(path), source=str(path))


Params = dataclasses.make_dataclass(
    'Params', [(row['name'], _KINDS[row['type']], dataclasses.field(default=row['default'])) for row in _ROWS],
    bases=(_ParamsMethods,), namespace={'__module__': __name__})
Params.__doc__ = ('Pre-filter parameters under their ROS names, with the nodelet\'s defaults: one field per '
                  'pipeline and core input row of the parameter table (PARAMETER_TABLE).')


def read_yaml(path) -> Dict[str, Any]:
    """The map of a YAML parameter file ({} when empty). ValueError when it is not a map."""
    import yaml
    with open(str(path)) as f:
        try:
            data = yaml.safe_load(f)
        except yaml.YAMLError as e:
            raise ValueError('parameter file %s is not valid YAML: %s' % (path, e))
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise ValueError('parameter file %s must be a map of parameter names to values' % path)
    return data


@dataclass
class FilterResult:
    """What the pipeline made of one sweep.

    labelled: every input point (pair: echo 1 then echo 2, each in beam order; dual_return: the
      input's order), OUTPUT_DTYPE, positions as measured; a dual-return point in no grid cell is
      nanPoint with echo 0 and beam 0xFFFFFFFF.
    cleaned: the points for mapping (OUTPUT_DTYPE), mirror phantoms back-projected.
    objects: one dict per mirror/glass/unknown rectangle (id, type, type_name, corners (4, 3),
      width, height, the surface-echo patch patch_corners (4, 3), patch_width, patch_height (the
      rectangle itself unless grow_objects grew it), growth_capped, plane (a, b, c, d), centre, the counts surface_points, behind_points,
      phantom_points, transmitted_points, ambiguous_points, undecided_points, the type's evidence
      mirrored_points, tested_points, inlier_fraction, real_fraction, landing_fitness,
      phantom_share_points, phantom_intensity_share, dim_phantom_fraction, typed_by_dim_phantoms
      (the sampled phantoms' brightness against what they land on; glass when enough are too dim
      for a mirror), typed_as_open_spot (glass: a specular spot with nothing behind it), phantom_brightness, transmitted_brightness and landing_brightness (median intensity x range^2 of
      the sampled phantoms, the points seen through, what the phantoms land on), seen_through_brightness
      (the one of the last two the brightness rules compare with behind glass), plane_refined, plane_correction, mean_surface_intensity, and with intensity_evidence the intensity
      features intensity_echoes, intensity_off_peak, intensity_faint_share, intensity_haze,
      intensity_echo_ratio, intensity_log_odds (mirror against glass, this sweep) and intensity_typed).
    stats: point counts of the stages and the core's wall time; "warnings": a sentence for each stage
      that removed an implausible share of the sweep (e.g. the outlier filter more than 10 % of the points
      in range), naming the parameter and the share (what the node logs and reports on /diagnostics).
    """
    mode: str
    labelled: np.ndarray
    cleaned: np.ndarray
    objects: List[dict]
    stats: dict
    shape: tuple

    @property
    def warnings(self) -> List[str]:
        """stats['warnings']: empty when every stage removed a plausible share of the sweep."""
        return list(self.stats.get('warnings', []))

    @property
    def labels(self) -> np.ndarray:
        """uint8 labels (a view of labelled): (2, N) or (2, rows, cols) for a pair, (N,) for dual_return."""
        return self.labelled['label'].reshape(self.shape)

    @property
    def cleaned_points(self) -> np.ndarray:
        """(M, 3) float32 positions of the cleaned points."""
        return np.stack([self.cleaned['x'], self.cleaned['y'], self.cleaned['z']], axis=-1)

    def label_counts(self) -> Dict[str, int]:
        """Points per label name (errorSurface, ...), labels that occur only."""
        counts = np.bincount(self.labelled['label'], minlength=10)
        return {Label(k).design_name: int(c) for k, c in enumerate(counts) if c}


def _points_of(array, name):
    """(points, intensities or None): structured arrays with x y z fields are split (a copy)."""
    if isinstance(array, np.ndarray) and array.dtype.names is not None:
        missing = [f for f in 'xyz' if f not in array.dtype.names]
        if missing:
            raise TypeError('%s is a structured array without field%s %s' % (
                name, 's' if len(missing) > 1 else '', ', '.join(missing)))
        points = np.stack([array['x'], array['y'], array['z']], axis=-1)
        if points.dtype != np.float32:
            raise TypeError('%s has x y z of dtype %s; expected float32' % (name, points.dtype))
        intensity = array['intensity'] if 'intensity' in array.dtype.names else None
        return points, intensity
    return array, None


class Pipeline:
    """The pre-filter (core::Pipeline) with its parameters; reuse it from sweep to sweep.

    Pipeline(params=None, **overrides): overrides are ROS or paper parameter names. Raises
    TypeError / ValueError naming every bad value, as the nodelet refuses them.
    """

    def __init__(self, params: Optional[Params] = None, **overrides):
        self._params = self._resolve(params, overrides)
        self._pipeline = _core.Pipeline(self._params.to_core())

    @staticmethod
    def _resolve(params, overrides):
        if params is not None and not isinstance(params, Params):
            raise TypeError('params must be an ohm_mirror_detector3d.core.Params, not %s' % type(params).__name__)
        params = Params.from_dict(overrides, base=params, source='keyword arguments', ignore=())
        return params.check()

    @property
    def params(self) -> Params:
        return dataclasses.replace(self._params)

    def set_params(self, params: Optional[Params] = None, **overrides):
        """New parameters; on failure (TypeError / ValueError) the previous ones stay in force."""
        resolved = self._resolve(params if params is not None else self._params, overrides)
        self._pipeline.set_params(resolved.to_core())
        self._params = resolved

    def filter(self, echo1, echo2, intensity1=None, intensity2=None, pose=None) -> FilterResult:
        """Two index-aligned echoes (input modes pair / two_topics): point i of echo1 and point i of
        echo2 are the same beam. Intensities default to the `intensity` field of structured input.
        pose: with post_filter=1, the sweep's place in the fixed frame (a 4 x 4 rigid transform,
        fixed_from_sweep); without it the sweep is processed single-sweep."""
        echo1, own1 = _points_of(echo1, 'echo1')
        echo2, own2 = _points_of(echo2, 'echo2')
        intensity1 = own1 if intensity1 is None else intensity1
        intensity2 = own2 if intensity2 is None else intensity2
        labelled, cleaned, objects, stats = self._pipeline.filter_pair(echo1, echo2, intensity1, intensity2, pose)
        grid = echo1.shape[:-1] if echo1.ndim == 3 else (echo1.shape[0],)
        return FilterResult('pair', labelled, cleaned, objects, stats, (2,) + tuple(grid))

    def filter_dual_return(self, points, returns=None, rings=None, intensities=None, pose=None) -> FilterResult:
        """One cloud holding both returns of every beam (input mode dual_return): `returns` (1/2 or
        0/1) and `rings` per point; a structured `points` array may carry them as fields
        (return / return_type / echo, ring / channel). Echoes are paired per ring and azimuth bin
        of azimuth_resolution_deg; `labelled` keeps the input's order. pose: as for filter()."""
        fields = points.dtype.names if isinstance(points, np.ndarray) and points.dtype.names else ()
        if returns is None:
            returns = next((points[f] for f in ('return', 'return_type', 'echo') if f in fields), None)
        if rings is None:
            rings = next((points[f] for f in ('ring', 'channel') if f in fields), None)
        if returns is None or rings is None:
            raise TypeError('dual_return needs a return index and a ring per point: pass returns= and rings= '
                            '(or a structured array with fields return/return_type/echo and ring/channel)')
        points, own = _points_of(points, 'points')
        intensities = own if intensities is None else intensities
        labelled, cleaned, objects, stats = self._pipeline.filter_dual_return(
            points, returns, rings, intensities, float(self._params.azimuth_resolution_deg), pose)
        return FilterResult('dual_return', labelled, cleaned, objects, stats, (len(labelled),))

    def map_objects(self, viewpoint=(0.0, 0.0, 0.0)):
        """The post-filter's object map in the fixed frame: object dicts (as FilterResult.objects,
        stable ids, the bounding rectangle of each object's extent) with sweeps_seen and
        mirror_log_odds; plane normals point towards `viewpoint`."""
        return self._pipeline.map_objects([float(v) for v in viewpoint])

    def save_map(self, path, fixed_frame):
        """Writes the object map as YAML (the nodelet's ~save_map format); raises OSError with
        the problem."""
        problem = self._pipeline.save_map(str(path), str(fixed_frame))
        if problem:
            raise OSError(problem)

    def load_map(self, path, fixed_frame):
        """Replaces the object map by a file's; a file that cannot be read or does not fit raises
        ValueError and leaves the map empty."""
        problem = self._pipeline.load_map(str(path), str(fixed_frame))
        if problem:
            raise ValueError(problem)


def filter_pair(echo1, echo2, intensity1=None, intensity2=None, params=None, **overrides) -> FilterResult:
    """One-shot Pipeline(params, **overrides).filter(...)."""
    return Pipeline(params, **overrides).filter(echo1, echo2, intensity1, intensity2)


def evaluate_sweep(sweep, pipeline: Optional[Pipeline] = None, **metric_kwargs):
    """Filters a simulated sweep (simulate.Sweep) with the bindings and scores it against its ground
    truth with the evaluator's metrics.evaluate_sweep, as the rostests score the nodelet, but with
    no master. Returns (the evaluator's result, the FilterResult)."""
    from . import metrics, simulate
    pipeline = pipeline if pipeline is not None else Pipeline()
    result = pipeline.filter(sweep.echo1, sweep.echo2)
    score = metrics.evaluate_sweep(sweep.ground_truth, result.labelled, result.cleaned, result.objects,
                                   simulate.ground_truth_objects(sweep), **metric_kwargs)
    return score, result


def evaluate_sweeps(sweeps, pipeline: Optional[Pipeline] = None, **metric_kwargs):
    """evaluate_sweep over many sweeps with one pipeline: (per-sweep results, the evaluator's
    aggregated summary, as evaluation.evaluate_bags returns them for bags)."""
    from . import metrics
    pipeline = pipeline if pipeline is not None else Pipeline()
    results = [evaluate_sweep(sweep, pipeline, **metric_kwargs)[0] for sweep in sweeps]
    return results, metrics.aggregate_results(results)
