"""The paper's method (grow_objects 0: an object is its surface-echo patch; max_reflections 0: a
phantom is reflected across its first mirror only) beside extent growth (grow_objects 1) and
growth with reflection chains (max_reflections 3) on the same sweeps: the scenes and figures of
issue 16.

Each scene is simulated once (rotating Hokuyo, `scans` scans per half rotation, range noise 1 cm,
realistic physics unless told otherwise, noise seed 1) and filtered through the C++ core
(core.Pipeline, the nodelet's code) in the `pair` input mode, with the parameters given (default:
launch/rotating_hokuyo_params.yaml) in each setting of SETTINGS. Per scene and setting:

* phantoms left in `cleaned` at a wrong place (> 5 cm), of all phantoms (double echo or not);
* per ground-truth mirror or pane: the detected rectangle's width and height against the truth
  (sides sorted, so that the comparison does not depend on which side is called width);
* behind glass: the share of the points behind a pane labelled behindTransparent;
* real points lost from `cleaned`, and objects reported in a scene without any reflective surface.

    /usr/bin/python3 -m ohm_mirror_detector3d.growth_comparison [--scans 400] [--out DIR]
"""
import argparse
import dataclasses
import json
import os
import sys

from . import core, metrics
from . import scanner as scanners
from . import scene as scenes
from .labels import Label
from .physics import PhysicsParams
from .scene_evaluation import filter_case
from .simulate import SweepSimulator, ground_truth_objects

# The scenes of issue 16 ("Must show"): mirrors, panes, and scenes that must get no object.
MIRROR_SCENES = ('facing_tall_mirrors', 'wall_mirror', 'experiment3')
GLASS_SCENES = ('pane_in_wall', 'experiment2')
PLAIN_SCENES = ('empty_room', 'office', 'doorway_room')
# (name, grow_objects, max_reflections): the paper's method, growth, growth with reflection chains.
SETTINGS = (('off', 0, 0), ('on', 1, 0), ('on+chains', 1, 3))
SCENES = MIRROR_SCENES + GLASS_SCENES + PLAIN_SCENES
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEFAULT_PARAMS = os.path.join(REPO, 'launch', 'rotating_hokuyo_params.yaml')
NOISE = 0.01


def behind_glass_labelled(result):
    """Share of the ground truth's behindTransparent points the filter labelled behindTransparent."""
    confusion = result.get('confusion')
    if confusion is None:
        return None
    name = metrics.LABEL_NAMES[Label.BEHIND_TRANSPARENT]
    row = confusion['matrix'][confusion['rows'].index(name)]
    total = sum(row)
    return row[confusion['cols'].index(name)] / total if total else None


def object_sizes(result):
    """(truth name, truth sides, detected sides or None, detected patch sides or None) per truth object."""
    out = []
    for match in result.get('objects', []):
        truth = sorted([match['truth_width'], match['truth_height']], reverse=True)
        detected = None
        if match['matched']:
            detected = sorted([match['detected_width'], match['detected_height']], reverse=True)
        out.append({'name': match['truth_name'], 'truth': truth, 'detected': detected,
                    'type_correct': match.get('type_correct')})
    return out


def score(scene_name, sweep, pipeline, reflective):
    ground_truth, labelled, cleaned, objects = filter_case(pipeline, sweep, 'pair')
    result = metrics.evaluate_sweep(ground_truth, labelled, cleaned, objects, ground_truth_objects(sweep))
    return {
        'scene': scene_name,
        'phantoms': result['counts']['phantoms'],
        'phantom_wrong_place_fraction': result['phantom_wrong_place_fraction'],
        'real_lost_fraction': result['real_lost_fraction'],
        'behind_glass_labelled': behind_glass_labelled(result),
        'objects': object_sizes(result),
        'reported_objects': len(objects),
        'false_objects': 0 if reflective else len(objects),
        'capped': sum(bool(o.get('growth_capped')) for o in objects),
    }


def run(scene_names=SCENES, scans=400, params=None, physics=None, seed=1):
    """One dict per scene: setting name -> score."""
    base = params if params is not None else core.Params.from_yaml(DEFAULT_PARAMS)
    pipelines = {setting: core.Pipeline(dataclasses.replace(base, grow_objects=grow, max_reflections=reflections))
                 for setting, grow, reflections in SETTINGS}
    rows = []
    for name in scene_names:
        scene = scenes.get(name)
        hokuyo = scanners.preset('hokuyo_utm30lx_ew', scans=scans, range_noise=NOISE)
        sweep = SweepSimulator(scene, hokuyo, physics).sweep(seed=seed)
        rows.append({setting: score(name, sweep, pipeline, bool(scene.objects()))
                     for setting, pipeline in pipelines.items()})
    return rows


def _percent(x):
    return '–' if x is None else '%.1f %%' % (100.0 * x)


def _sides(entry):
    if entry['detected'] is None:
        return 'not found'
    return '%.2f × %.2f' % tuple(entry['detected'])


def markdown(rows):
    names = [setting for setting, _, _ in SETTINGS]
    arrow = ' → '.join(names)
    lines = ['| scene | phantoms | left at a wrong place, %s | real lost, %s | behind glass labelled, %s | '
             'objects (truth → %s, m) | objects in a plain scene, %s |' % ((arrow,) * 5),
             '|---|---|---|---|---|---|---|']
    for row in rows:
        by = [row[name] for name in names]
        first = by[0]

        def each(key, form=_percent):
            return ' → '.join(form(r[key]) for r in by)

        sizes = '; '.join('%s %.2f × %.2f → %s' % (matches[0]['name'], matches[0]['truth'][0], matches[0]['truth'][1],
                                                   ' → '.join(_sides(m) for m in matches))
                          for matches in zip(*(r['objects'] for r in by)))
        plain = each('false_objects', str) if first['scene'] in PLAIN_SCENES else ''
        lines.append('| %s | %d | %s | %s | %s | %s | %s |' % (
            first['scene'], first['phantoms'], each('phantom_wrong_place_fraction'), each('real_lost_fraction'),
            each('behind_glass_labelled'), sizes or '–', plain))
    return '\n'.join(lines)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('--scans', type=int, default=400, help="the Hokuyo's scans per half rotation")
    p.add_argument('--params', default=DEFAULT_PARAMS,
                   help='parameter file (grow_objects and max_reflections are set as SETTINGS says)')
    p.add_argument('--scenes', default=','.join(SCENES), help='comma-separated scene names')
    p.add_argument('--physics', choices=('realistic', 'ideal'), default='realistic')
    p.add_argument('--out', help='directory for growth.md and growth.json')
    args = p.parse_args(argv)
    physics = PhysicsParams.ideal() if args.physics == 'ideal' else PhysicsParams()
    rows = run([s for s in args.scenes.split(',') if s], args.scans, core.Params.from_yaml(args.params), physics)
    text = markdown(rows)
    print(text)
    if args.out:
        os.makedirs(args.out, exist_ok=True)
        with open(os.path.join(args.out, 'growth.md'), 'w') as f:
            f.write(text + '\n')
        with open(os.path.join(args.out, 'growth.json'), 'w') as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == '__main__':
    sys.exit(main())
