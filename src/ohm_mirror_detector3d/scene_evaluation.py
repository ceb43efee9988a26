"""`make evaluate`: the pre-filter on many random scenes and the named scenes, per sensor family,
scored against the simulator's ground truth, with the targets of issue 14 beside the figures.

No master: the filter is the C++ core through the Python bindings (core.Pipeline, exactly the
nodelet's code), in the input mode a user of each family would choose: the rotating Hokuyo's
sweeps as an organised pair of echo clouds (`pair`), the dual-return lidars as one cloud with
both returns (`dual_return`, as their drivers publish it: return 1 the stronger echo).

Scenes: random_scenes.random_scene(seed) for `count` seeds from `seed` on (the same scenes for
every family; the rotating Hokuyo turns at a number of scans per half rotation drawn from the
scene's seed, 100-1000, log-uniform), plus every named scene (the Hokuyo at 400 scans). Realistic
physics unless told otherwise. The noise seed of a sweep is its scene's seed.

Figures per family (metrics.py says how each is counted), pooled over the sweeps:

* IoU of surface points, of phantoms, of points behind glass, among the double-echo points and
  among all;
* phantoms left at a wrong place in `cleaned` (> 5 cm), as a share of the double-echo phantoms
  and of all phantoms;
* real points lost from `cleaned`;
* object types right, of the ground-truth objects with at least 50 surface echoes (an object is
  right when a detection matched it and has its type; shiny metal counts as a mirror), and beside
  it how many of those objects gave no double echo on their surface at all (a pane with nothing
  behind it in range), so that what one sweep's echo comparison cannot see is told apart;
* scenes without any reflective surface in which the filter reported an object.
"""
import json
import math
import os
import sys
import time
from dataclasses import dataclass
from typing import Optional

import numpy as np

from . import metrics, report
from . import scanner as scanners
from . import scene as scenes
from .physics import PhysicsParams
from .simulate import SweepSimulator, ground_truth_objects

DEFAULT_SCENES = 50
MIN_SURFACE_POINTS = 50
HOKUYO = 'hokuyo_utm30lx_ew'
HOKUYO_SCANS = (100, 1000)
NAMED_HOKUYO_SCANS = 400
_SCANS_STREAM = 141   # the Hokuyo's scans per scene: a random stream apart from the scene's own

INPUT_MODES = {HOKUYO: 'pair', 'hesai_qt64': 'dual_return', 'ouster_os0_128': 'dual_return',
               'velodyne_hdl32e': 'dual_return'}

# (key, what, target, is met) of the main table; the key is a path into a family's summary.
TARGETS = (
    (('iou', 'surface', 'double_echo'), 'surface IoU, double-echo points', '≥ 0.85', lambda v: v >= 0.85),
    (('iou', 'surface', 'all'), 'surface IoU, all points', '', None),
    (('iou', 'phantom', 'double_echo'), 'phantom IoU, double-echo points', '≥ 0.80', lambda v: v >= 0.80),
    (('iou', 'phantom', 'all'), 'phantom IoU, all points', '', None),
    (('iou', 'behind_glass', 'double_echo'), 'behind-glass IoU, double-echo points', '≥ 0.80',
     lambda v: v >= 0.80),
    (('iou', 'behind_glass', 'all'), 'behind-glass IoU, all points', '', None),
    (('double_echo_phantom_wrong_place_fraction',), 'phantoms left at a wrong place, of the double-echo phantoms',
     '≤ 2 %', lambda v: v <= 0.02),
    (('phantom_wrong_place_fraction',), 'phantoms left at a wrong place, of all phantoms', '', None),
    (('real_lost_fraction',), 'real points lost', '≤ 0.3 %', lambda v: v <= 0.003),
    (('object_types', 'fraction'), 'object types right (objects with ≥ 50 surface echoes)', '≥ 90 %',
     lambda v: v >= 0.90),
    (('false_objects', 'fraction'), 'scenes without reflective surfaces that got an object', '≤ 5 %',
     lambda v: v <= 0.05),
)
_PERCENT = {'double_echo_phantom_wrong_place_fraction', 'phantom_wrong_place_fraction', 'real_lost_fraction'}


@dataclass(frozen=True)
class Case:
    family: str
    scene: str          # a named scene or random_SEED
    kind: str           # 'random' or 'named'
    seed: int           # noise seed (the scene's seed for random scenes)
    scans: Optional[int] = None   # the Hokuyo's scans per half rotation


def resolve_families(names):
    """Full family names from names or unique prefixes ('hokuyo', 'hesai', ...); all when empty."""
    if not names:
        return list(scanners.FAMILIES)
    out = []
    for name in names:
        matches = [f for f in scanners.FAMILIES if f == name or f.startswith(name)]
        if len(matches) != 1:
            raise ValueError('unknown sensor family %r; known: %s' % (name, ', '.join(scanners.FAMILIES)))
        out.append(matches[0])
    return out


def hokuyo_scans(scene_seed):
    """Scans per half rotation of the rotating Hokuyo in a random scene: log-uniform over 100-1000."""
    rng = np.random.default_rng([_SCANS_STREAM, scene_seed])
    lo, hi = HOKUYO_SCANS
    return int(round(math.exp(rng.uniform(math.log(lo), math.log(hi)))))


def cases(families, count=DEFAULT_SCENES, seed=0, named=True):
    """The cases to run, family by family: `count` random scenes from `seed` on, then the named scenes."""
    out = []
    for family in families:
        hokuyo = family == HOKUYO
        for s in range(seed, seed + count):
            out.append(Case(family, '%s%d' % (scenes.RANDOM_PREFIX, s), 'random', s,
                            hokuyo_scans(s) if hokuyo else None))
        if named:
            out += [Case(family, name, 'named', 1, NAMED_HOKUYO_SCANS if hokuyo else None)
                    for name in scenes.names()]
    return out


def scanner_of(case):
    if case.scans is not None:
        return scanners.preset(case.family, scans=case.scans)
    return scanners.preset(case.family)


def filter_case(pipeline, sweep, mode, pose=None):
    """The sweep through the pipeline in `mode`: (ground truth, labelled, cleaned, objects), with
    labelled and cleaned keyed by the ground truth's (echo, beam). `pose` (the sweep's 4 x 4
    fixed_from_sweep) is passed on as `pose=` when given; a single-sweep pipeline gets none."""
    extra = {} if pose is None else {'pose': pose}
    if mode == 'pair':
        shape = (sweep.rows, sweep.cols)
        result = pipeline.filter(sweep.echo1.reshape(shape), sweep.echo2.reshape(shape), **extra)
        return sweep.ground_truth, result.labelled, result.cleaned, result.objects
    from .dual_return_cloud import dual_return_arrays
    cloud, ground_truth, (echo, beam) = dual_return_arrays(sweep)
    result = pipeline.filter_dual_return(cloud, **extra)
    labelled, cleaned = result.labelled, result.cleaned
    # labelled keeps the cloud's order; its echo and beam name the filter's grid cell, which the
    # cleaned points carry too: map cells to cloud points, cloud points to ground-truth keys.
    cell = labelled['echo'].astype(np.int64) * (1 << 32) + labelled['beam'].astype(np.int64)
    in_cell = (labelled['echo'] == 1) | (labelled['echo'] == 2)
    points = np.flatnonzero(in_cell)
    order = np.argsort(cell[points])
    sorted_cells = cell[points][order]
    wanted = cleaned['echo'].astype(np.int64) * (1 << 32) + cleaned['beam'].astype(np.int64)
    at = np.clip(np.searchsorted(sorted_cells, wanted), 0, max(len(sorted_cells) - 1, 0))
    found = (sorted_cells[at] == wanted) if len(sorted_cells) else np.zeros(len(wanted), bool)
    source = points[order][at]
    keyed_labelled = {'label': labelled['label'], 'echo': echo, 'beam': beam}
    keyed_cleaned = {'x': cleaned['x'], 'y': cleaned['y'], 'z': cleaned['z'], 'label': cleaned['label'],
                     'echo': np.where(found, echo[source], 0), 'beam': np.where(found, beam[source], 0)}
    return ground_truth, keyed_labelled, keyed_cleaned, result.objects


def found_objects(pipeline, sweep, family):
    """The sweep of a `family` sensor through `pipeline`: ({ground-truth object name: the detected
    object matched to it}, the evaluator's counts of the sweep)."""
    ground_truth, labelled, cleaned, objects = filter_case(pipeline, sweep, INPUT_MODES[family])
    truth = ground_truth_objects(sweep)
    matches, _ = metrics.match_objects(truth, objects)
    found = {t['name']: objects[m['detected_id']] for t, m in zip(truth, matches) if m['matched']}
    return found, metrics.evaluate_sweep(ground_truth, labelled, cleaned, objects, truth)['counts']


def run_case(case, pipeline, physics=None):
    """Simulates and filters one case; the evaluator's result (with _raw) plus the case and timings."""
    started = time.perf_counter()
    scene = scenes.get(case.scene)
    sweep = SweepSimulator(scene, scanner_of(case), physics).sweep(seed=case.seed)
    simulated = time.perf_counter() - started
    started = time.perf_counter()
    ground_truth, labelled, cleaned, objects = filter_case(pipeline, sweep, INPUT_MODES[case.family])
    filtered = time.perf_counter() - started
    result = metrics.evaluate_sweep(ground_truth, labelled, cleaned, objects, ground_truth_objects(sweep))
    result.update(family=case.family, scene=case.scene, kind=case.kind, seed=case.seed, scans=case.scans,
                  beams=sweep.num_beams, reflective=bool(scene.objects()),
                  seconds={'simulate': round(simulated, 3), 'filter': round(filtered, 3)})
    return result


def summarise(results):
    """Per family: the figures over all its sweeps, over the random and over the named ones."""
    out = {}
    for family in dict.fromkeys(r['family'] for r in results):
        mine = [r for r in results if r['family'] == family]
        out[family] = {which: _summary([r for r in mine if which == 'all' or r['kind'] == which])
                       for which in ('all', 'random', 'named')}
    return out


def _summary(results):
    if not results:
        return {'sweeps': 0}
    agg = metrics.aggregate_results(results)
    agg.pop('objects', None)   # per truth id: meaningless across scenes
    agg.pop('false_positive_objects_per_sweep', None)
    agg['object_types'] = metrics.type_accuracy(results, MIN_SURFACE_POINTS)
    agg['false_objects'] = metrics.false_object_scenes(results)
    agg['scenes'] = {'random': sum(r['kind'] == 'random' for r in results),
                     'named': sum(r['kind'] == 'named' for r in results),
                     'without_reflective_surfaces': agg['false_objects']['scenes']}
    agg['seconds'] = {k: round(sum(r['seconds'][k] for r in results), 1) for k in ('simulate', 'filter')}
    return agg


def figure(summary, key):
    """The figure at `key` (a path of TARGETS) of a family's summary, or None."""
    for k in key:
        if not isinstance(summary, dict) or k not in summary:
            return None
        summary = summary[k]
    return summary


def _format(key, value, summary):
    if value is None:
        return '–'
    if key[0] in _PERCENT:
        return '%.2f %%' % (100 * value)
    if key[0] == 'object_types':
        t = summary['object_types']
        return '%.0f %% (%d of %d)' % (100 * value, t['right'], t['objects'])
    if key[0] == 'false_objects':
        f = summary['false_objects']
        return '%.0f %% (%d of %d)' % (100 * value, f['with_false_objects'], f['scenes'])
    return '%.3f' % value


def table(summaries, which='all'):
    """Markdown table: one row per figure, the target, one column per family (✓ met, ✗ not)."""
    families = list(summaries)
    lines = ['| figure | target | ' + ' | '.join(families) + ' |', '|---|---|' + '---|' * len(families)]
    for key, what, target, met in TARGETS:
        cells = []
        for family in families:
            s = summaries[family][which]
            v = figure(s, key)
            cell = _format(key, v, s)
            if met is not None and v is not None:
                cell += ' ✓' if met(v) else ' ✗'
            cells.append(cell)
        lines.append('| %s | %s | %s |' % (what, target or '–', ' | '.join(cells)))
    counts = []
    for family in families:
        s = summaries[family][which]
        c = s.get('scenes', {})
        counts.append('%d random + %d named (%d without reflective surfaces)' % (
            c.get('random', 0), c.get('named', 0), c.get('without_reflective_surfaces', 0)))
    lines.append('| scenes | – | %s |' % ' | '.join(counts))
    lines.append('| double-echo phantoms, of all phantoms | – | %s |' % ' | '.join(
        _share(summaries[f][which].get('counts', {}), 'double_echo_phantoms', 'phantoms') for f in families))
    lines.append('| objects of the type figure with no double echo on their surface (right) | – | %s |' % ' | '.join(
        _no_double_echo(summaries[f][which].get('object_types', {})) for f in families))
    return '\n'.join(lines) + '\n'


def _no_double_echo(types):
    if 'no_double_echo' not in types:
        return '–'
    return '%d of %d (%d right)' % (types['no_double_echo'], types['objects'], types['no_double_echo_right'])


def _share(counts, part, whole):
    if not counts.get(whole):
        return '–'
    return '%d of %d' % (counts[part], counts[whole])


def targets_met(summaries, which='all'):
    """The figures that miss their target: [(family, what, value)]."""
    misses = []
    for family, s in summaries.items():
        for key, what, _, met in TARGETS:
            v = figure(s[which], key)
            if met is not None and v is not None and not met(v):
                misses.append((family, what, v))
    return misses


def markdown(summaries, title, command, params_name, physics):
    lines = ['# %s' % title, '',
             'Command: `%s`' % command, '',
             'Parameters: %s. Physics: %s. Scored against the simulator\'s ground truth '
             '(src/ohm_mirror_detector3d/metrics.py, scene_evaluation.py).' % (params_name, physics), '',
             '## All scenes (random and named)', '', table(summaries, 'all')]
    for which, heading in (('random', 'Random scenes only'), ('named', 'Named scenes only')):
        if any(s[which].get('sweeps') for s in summaries.values()):
            lines += ['## %s' % heading, '', table(summaries, which)]
    return '\n'.join(lines)


def write(out_dir, summaries, results, md_text, meta):
    """DIR/evaluation.md and DIR/evaluation.json: meta, the summaries (indented) and one line per sweep
    (its figures without the confusion matrices, which the summaries pool)."""
    os.makedirs(out_dir, exist_ok=True)
    json_path, md_path = os.path.join(out_dir, 'evaluation.json'), os.path.join(out_dir, 'evaluation.md')
    sweeps = [_rounded(report.jsonable(_sweep_line(r))) for r in results]
    with open(json_path, 'w') as f:
        f.write('{"meta": %s,\n"summary": %s,\n"sweeps": [\n%s\n]}\n' % (
            json.dumps(report.jsonable(meta)), json.dumps(report.jsonable(summaries), indent=1),
            ',\n'.join(json.dumps(r, separators=(',', ':')) for r in sweeps)))
    with open(md_path, 'w') as f:
        f.write(md_text)
    return json_path, md_path


_OBJECT_KEYS = ('truth_name', 'truth_type', 'truth_surface_points', 'truth_double_echo_surface_points', 'matched', 'detected_type', 'width_error',
                'height_error', 'corner_error_max')


def _sweep_line(result):
    """A sweep's figures for the JSON: without confusion matrices and error statistics (the summaries
    pool them), objects with the keys that say what was found."""
    line = {k: v for k, v in metrics.strip_raw(result).items()
            if k not in ('confusion', 'confusion_coarse', 'objects', 'false_positive_objects', 'ground_truth_counts',
                         'backprojection_error')}
    line['backprojection_error_median'] = (result.get('backprojection_error') or {}).get('median')
    line['objects'] = [{k: m[k] for k in _OBJECT_KEYS if k in m} for m in result.get('objects', [])]
    line['false_objects'] = [{'type': f['detected_type'], 'width': f['width'], 'height': f['height']}
                             for f in result.get('false_positive_objects', [])]
    return line


def _rounded(x, digits=4):
    """Floats to `digits` significant digits (the per-sweep lines stay short)."""
    if isinstance(x, dict):
        return {k: _rounded(v, digits) for k, v in x.items()}
    if isinstance(x, list):
        return [_rounded(v, digits) for v in x]
    if isinstance(x, float):
        return float('%.*g' % (digits, x))
    return x


def run(families, count=DEFAULT_SCENES, seed=0, params=None, named=True, physics=None, progress=None):
    """Runs every case; returns (per-sweep results, summaries)."""
    from . import core
    pipeline = core.Pipeline(params)
    todo = cases(families, count, seed, named)
    shown = progress(len(todo)) if progress is not None else None
    results = []
    for case in todo:
        results.append(run_case(case, pipeline, physics))
        if shown is not None:
            shown.update(len(results))
    if shown is not None:
        shown.finish()
    return results, summarise(results)


def realism(families, count=DEFAULT_SCENES, seed=0, physics=None):
    """What the simulated random scenes look like, in the terms SENSORS.md describes real frames in
    (no filter involved): {family: figures}."""
    from .labels import Label
    out = {}
    for family in families:
        t = dict(points=0, sweeps=0, second=0, second_ordinary=0, gaps=[], glass_phantoms=0, glass_phantoms_bare=0,
                 behind_glass=0, behind_glass_single=0, panes_seen=0, panes_with_surface=0, pane_surface=[])
        for case in cases([family], count, seed, named=False):
            sweep = SweepSimulator(scenes.get(case.scene), scanner_of(case), physics).sweep(seed=case.seed)
            gt, n = sweep.ground_truth, sweep.num_beams
            label, obj = gt['label'], gt['object_id']
            double = gt['double_echo'][:n].astype(bool)
            has = np.isfinite(gt['x'][:n])
            t['sweeps'] += 1
            t['points'] += int(has.sum() + double.sum())
            t['second'] += int(double.sum())
            t['second_ordinary'] += int((double & (label[:n] == Label.VALID) & (label[n:] == Label.VALID)).sum())
            r1 = np.linalg.norm(np.stack([gt['x'][:n], gt['y'][:n], gt['z'][:n]], 1)[double], axis=1)
            r2 = np.linalg.norm(np.stack([gt['x'][n:], gt['y'][n:], gt['z'][n:]], 1)[double], axis=1)
            t['gaps'].append(r2 - r1)
            for o in sweep.objects:
                if o['material'] != scenes.GLASS:
                    continue
                mine = obj == o['id']
                surface_beams = np.zeros(n, bool)
                surface_beams[np.flatnonzero(mine & (label == Label.TRANSPARENT_SURFACE)) % n] = True
                beams2 = np.r_[surface_beams, surface_beams]
                phantom = mine & (label == Label.BEHIND_REFLECTIVE) & np.r_[np.ones(n, bool), double]
                behind = mine & (label == Label.BEHIND_TRANSPARENT) & np.r_[np.ones(n, bool), double]
                t['glass_phantoms'] += int(phantom.sum())
                t['glass_phantoms_bare'] += int((phantom & ~beams2).sum())
                t['behind_glass'] += int(behind.sum())
                t['behind_glass_single'] += int((behind & ~np.r_[double, double]).sum())
                seen = int((mine & (label != Label.NAN_POINT)).sum())
                if seen:
                    t['panes_seen'] += 1
                    if surface_beams.any():
                        t['panes_with_surface'] += 1
                        t['pane_surface'].append(int(surface_beams.sum()))
        gaps = np.concatenate(t['gaps']) if t['gaps'] else np.zeros(0)
        out[family] = {
            'points_per_sweep': t['points'] / max(t['sweeps'], 1),
            'second_return_share': _ratio(t['second'], t['points']),
            'second_return_gap_min': float(gaps.min()) if len(gaps) else None,
            'second_return_gap_median': float(np.median(gaps)) if len(gaps) else None,
            'panes_with_surface_echo_share': _ratio(t['panes_with_surface'], t['panes_seen']),
            'surface_echo_beams_per_pane_median': float(np.median(t['pane_surface'])) if t['pane_surface'] else None,
            'glass_reflections_without_surface_echo': _ratio(t['glass_phantoms_bare'], t['glass_phantoms']),
            'behind_glass_single_echo': _ratio(t['behind_glass_single'], t['behind_glass']),
            'second_returns_on_ordinary_geometry': _ratio(t['second_ordinary'], t['second']),
        }
    return out


REALISM_ROWS = (
    ('points_per_sweep', 'points per frame', 'about 34k', '%.0f'),
    ('second_return_share', 'second returns, share of all points', 'about 3 %', 'percent'),
    ('second_return_gap_min', 'second return beyond its first, at least [m]', '~0.9', '%.2f'),
    ('second_return_gap_median', 'second return beyond its first, median [m]', 'several metres', '%.2f'),
    ('panes_with_surface_echo_share', 'panes seen that give a surface echo at all', '–', 'percent'),
    ('surface_echo_beams_per_pane_median', 'beams with a surface echo per pane that gives one, median',
     'a few tens', '%.0f'),
    ('glass_reflections_without_surface_echo', 'reflections seen in glass without a surface echo', 'about 60 %',
     'percent'),
    ('behind_glass_single_echo', 'points behind glass that come as single echoes', 'about 40 %', 'percent'),
    ('second_returns_on_ordinary_geometry', 'second returns on ordinary geometry (both echoes real)',
     'about a fifth', 'percent'),
)


def realism_table(figures):
    families = list(figures)
    lines = ['| figure | real frames (64-ring lidar, SENSORS.md) | ' + ' | '.join(families) + ' |',
             '|---|---|' + '---|' * len(families)]
    for key, what, real, fmt in REALISM_ROWS:
        cells = []
        for family in families:
            v = figures[family][key]
            cells.append('–' if v is None else ('%.1f %%' % (100 * v) if fmt == 'percent' else fmt % v))
        lines.append('| %s | %s | %s |' % (what, real, ' | '.join(cells)))
    return '\n'.join(lines) + '\n'


def _ratio(a, b):
    return float(a) / b if b else None


def main(argv=None):
    import argparse
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('--params', help='a parameter file (e.g. launch/rotating_hokuyo_params.yaml); default: '
                                    'the filter\'s defaults')
    p.add_argument('--families', default='', help='comma-separated sensor families or prefixes (default all: %s)'
                                                  % ', '.join(scanners.FAMILIES))
    p.add_argument('--scenes', type=int, default=DEFAULT_SCENES, help='random scenes per family')
    p.add_argument('--seed', type=int, default=0, help='seed of the first random scene')
    p.add_argument('--no-named', action='store_true', help='random scenes only')
    p.add_argument('--physics', choices=('realistic', 'ideal'), default='realistic')
    p.add_argument('--out', help='directory for evaluation.md and evaluation.json')
    p.add_argument('--title', default='Pre-filter on random and named scenes')
    p.add_argument('--check', action='store_true', help='exit 1 when a target is not met')
    p.add_argument('--realism', action='store_true',
                   help='no filter: what the random scenes look like, beside what SENSORS.md says of real frames')
    args = p.parse_args(argv)
    from . import core
    from .progress import Progress
    try:
        families = resolve_families([f for f in args.families.split(',') if f])
        params = core.Params.from_yaml(args.params) if args.params else None
    except (ValueError, TypeError, OSError) as e:
        print('scene_evaluation: %s' % e, file=sys.stderr)
        return 2
    physics = PhysicsParams() if args.physics == 'realistic' else PhysicsParams.ideal()
    started = time.time()
    if args.realism:
        print(realism_table(realism(families, args.scenes, args.seed, physics)))
        return 0
    results, summaries = run(families, args.scenes, args.seed, params, not args.no_named, physics,
                             progress=lambda total: Progress('scene_evaluation', total))
    command = 'python3 -m ohm_mirror_detector3d.scene_evaluation --scenes %d --seed %d' % (args.scenes, args.seed)
    for flag, value in (('--params', args.params), ('--families', args.families)):
        if value:
            command += ' %s %s' % (flag, value)
    command += ' --physics ideal' if args.physics == 'ideal' else ''
    command += ' --no-named' if args.no_named else ''
    params_name = '`%s`' % args.params if args.params else 'the defaults (no parameter file)'
    text = markdown(summaries, args.title, command, params_name, args.physics)
    print(text)
    meta = {'command': command, 'params': args.params, 'families': families, 'scenes': args.scenes,
            'seed': args.seed, 'named': not args.no_named, 'physics': args.physics,
            'seconds': round(time.time() - started, 1)}
    if args.out:
        for path in write(args.out, summaries, results, text, meta):
            print('scene_evaluation: wrote %s' % path, file=sys.stderr)
    print('scene_evaluation: %d sweeps in %.0f s' % (len(results), time.time() - started), file=sys.stderr)
    if args.check:
        misses = targets_met(summaries)
        for family, what, value in misses:
            print('scene_evaluation: target missed: %s: %s = %.4g' % (family, what, value), file=sys.stderr)
        return 1 if misses else 0
    return 0


if __name__ == '__main__':
    sys.exit(main())
