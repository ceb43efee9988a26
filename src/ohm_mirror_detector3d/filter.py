"""The pre-filter on point cloud files, no ROS needed:

    python3 -m ohm_mirror_detector3d.filter IN [IN ...] [--out OUT] [--mode pair|dual_return]
                                            [--params FILE.yaml]

(`ohm-mirror-filter` with the same arguments after `pip install` of the repository.)

IN is a .ply (ascii or binary), .pcd (ascii or binary) or .npz file, a folder (every such file
in it) or a glob pattern. For each input it writes the labelled cloud in the input's own format
and encoding, with a `label` field (uint8, the labels of the README) added to every point, and a
JSON file of the objects found (mirrors, glass, unknown) with the label counts.

Input layouts:
* pair (two echoes of every beam): PLY/PCD points with an `echo` field (1 or 2; the points of
  echo 1 and of echo 2, each in file order, are index-aligned beams), or without it the first
  half of the points echo 1 and the second half echo 2; NPZ arrays `echo1`, `echo2` ((N, 3)
  float32 or structured with x y z [intensity]) and optional `intensity1`, `intensity2`.
* dual_return (one cloud holding both returns): per point a return index (field `return`,
  `return_type` or `echo`: 1/2 or 0/1) and a ring (`ring` or `channel`); NPZ: a structured
  `points` array with those fields, or arrays `points` (N, 3), `returns`, `rings` [`intensities`].
Without --mode: dual_return when the points have a ring field, else the params file's
input_mode, else pair. x y z are float32 in the sensor frame (origin = optical centre);
`intensity` is used when present.

Outputs: with one input file, --out names the labelled file (default IN's name + `.labelled`, e.g.
scan.labelled.ply) and the objects go to the same name with `.objects.json`; with several
inputs, a folder or a glob --out is a folder (default: beside each input). NPZ outputs hold the input's arrays plus
`label1`/`label2` (pair) or `label` (dual_return), and `cleaned` (the points for mapping).
"""
import argparse
import glob
import json
import os
import sys
import time

import numpy as np

from . import cloud_files
from .core import MODES, Params, Pipeline, read_yaml

RETURN_FIELDS = ('return', 'return_type', 'echo')
RING_FIELDS = ('ring', 'channel')
LABELLED_SUFFIX = '.labelled'
# The console script of the pip install (pyproject.toml), named in --help when run as that.
CONSOLE_SCRIPT = 'ohm-mirror-filter'


def _xyz(points, path):
    names = points.dtype.names or ()
    missing = [f for f in 'xyz' if f not in names]
    if missing:
        raise ValueError('%s: no %s field (fields: %s)' % (path, '/'.join(missing), ', '.join(names)))
    return np.stack([points['x'], points['y'], points['z']], axis=-1).astype(np.float32, copy=False)


def _field(points, names):
    return next((points[n] for n in names if n in (points.dtype.names or ())), None)


def detect_mode(cloud, default):
    if cloud.format == 'npz':
        a = cloud.arrays
        if 'echo1' in a or 'echo2' in a:
            return 'pair'
        if 'rings' in a or ('points' in a and a['points'].dtype.names and
                            any(n in a['points'].dtype.names for n in RING_FIELDS)):
            return 'dual_return'
        return default
    return 'dual_return' if _field(cloud.points, RING_FIELDS) is not None else default


def filter_cloud(pipeline, cloud, mode):
    """(result, labelled input points for writing, extra NPZ arrays) of one file."""
    path = cloud.path
    if cloud.format == 'npz':
        a = cloud.arrays
        if mode == 'pair':
            if 'echo1' not in a or 'echo2' not in a:
                raise ValueError('%s: mode pair needs arrays echo1 and echo2 (has: %s)' % (path, ', '.join(a)))
            result = pipeline.filter(a['echo1'], a['echo2'], a.get('intensity1'), a.get('intensity2'))
            n = len(result.labelled) // 2
            labels = result.labelled['label']
            return result, None, {'label1': labels[:n].reshape(a['echo1'].shape[:-1] if a['echo1'].dtype.names is None
                                                                else a['echo1'].shape),
                                  'label2': labels[n:].reshape(a['echo2'].shape[:-1] if a['echo2'].dtype.names is None
                                                               else a['echo2'].shape),
                                  'cleaned': result.cleaned}
        if 'points' not in a:
            raise ValueError('%s: mode dual_return needs an array points (has: %s)' % (path, ', '.join(a)))
        result = pipeline.filter_dual_return(a['points'], a.get('returns'), a.get('rings'), a.get('intensities'))
        return result, None, {'label': result.labelled['label'].copy(), 'cleaned': result.cleaned}

    points = cloud.points
    xyz = _xyz(points, path)
    intensity = _field(points, ('intensity',))
    if mode == 'dual_return':
        returns, rings = _field(points, RETURN_FIELDS), _field(points, RING_FIELDS)
        if returns is None or rings is None:
            raise ValueError('%s: mode dual_return needs a return field (%s) and a ring field (%s)'
                             % (path, '/'.join(RETURN_FIELDS), '/'.join(RING_FIELDS)))
        result = pipeline.filter_dual_return(xyz, returns, rings, intensity)
        labels = result.labelled['label']
    else:
        echo = _field(points, ('echo',))
        if echo is not None:
            first, second = np.flatnonzero(echo == 1), np.flatnonzero(echo == 2)
            if len(first) + len(second) != len(points) or len(first) != len(second):
                raise ValueError('%s: mode pair needs as many points with echo 1 as with echo 2 and no other '
                                 'echo values (found %d, %d and %d others)'
                                 % (path, len(first), len(second), len(points) - len(first) - len(second)))
        else:
            if len(points) % 2:
                raise ValueError('%s: mode pair without an echo field needs an even number of points (the first '
                                 'half echo 1, the second half echo 2); found %d' % (path, len(points)))
            half = len(points) // 2
            first, second = np.arange(half), np.arange(half, len(points))
        result = pipeline.filter(xyz[first], xyz[second], None if intensity is None else intensity[first],
                                 None if intensity is None else intensity[second])
        labels = np.empty(len(points), np.uint8)
        n = len(first)
        labels[first], labels[second] = result.labelled['label'][:n], result.labelled['label'][n:]
    return result, cloud_files.append_field(points, 'label', labels), None


def objects_json(result, path, mode):
    def plain(value):
        if isinstance(value, np.ndarray):
            return value.tolist()
        if isinstance(value, (np.floating, float)):
            return None if not np.isfinite(value) else float(value)
        if isinstance(value, np.integer):
            return int(value)
        return value
    return {
        'input': path, 'mode': mode, 'points': int(len(result.labelled)),
        'cleaned_points': int(len(result.cleaned)), 'label_counts': result.label_counts(),
        'objects': [{k: plain(v) for k, v in o.items()} for o in result.objects],
        'stats': {k: plain(v) for k, v in result.stats.items()},
    }


def expand_inputs(patterns):
    """Files of the arguments: files as given, folders' .ply/.pcd/.npz files, glob patterns;
    outputs of an earlier run (*.labelled.*) are skipped in folders and globs."""
    files = []
    for pattern in patterns:
        if os.path.isdir(pattern):
            found = sorted(os.path.join(pattern, f) for f in os.listdir(pattern))
        elif os.path.exists(pattern):
            files.append(pattern)
            continue
        else:
            found = sorted(glob.glob(pattern))
            if not found:
                raise ValueError('%s: no such file, folder or matching files' % pattern)
        files += [f for f in found if os.path.isfile(f) and cloud_files.format_of(f)
                  and not os.path.splitext(os.path.splitext(f)[0])[1] == LABELLED_SUFFIX]
    return files


def output_paths(path, out, many):
    stem, ext = os.path.splitext(path)
    if out is None:
        base = stem + LABELLED_SUFFIX
    elif many:
        base = os.path.join(out, os.path.splitext(os.path.basename(path))[0] + LABELLED_SUFFIX)
    else:
        base, out_ext = os.path.splitext(out)
        if out_ext and out_ext.lower() != ext.lower():
            raise ValueError('--out %s: the labelled cloud is written in the input\'s format (%s)' % (out, ext))
    return base + ext, (base[:-len(LABELLED_SUFFIX)] if base.endswith(LABELLED_SUFFIX) else base) + '.objects.json'


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog=(CONSOLE_SCRIPT if os.path.basename(sys.argv[0]) == CONSOLE_SCRIPT
              else 'python3 -m ohm_mirror_detector3d.filter'),
        description='Labels mirror and glass effects in multi-echo point cloud files (PLY, PCD, NPZ), without ROS.')
    parser.add_argument('inputs', nargs='+', metavar='IN', help='file, folder or glob pattern (quoted)')
    parser.add_argument('--out', help='labelled output file (one input) or folder (several inputs)')
    parser.add_argument('--mode', choices=MODES, help='input layout (default: dual_return when the points have '
                                                      'a ring field, else the params file\'s input_mode, else pair)')
    parser.add_argument('--params', help='YAML file of ROS parameters, e.g. launch/rotating_hokuyo_params.yaml')
    parser.add_argument('--quiet', action='store_true', help='no progress lines')
    args = parser.parse_args(argv)

    try:
        values = read_yaml(args.params) if args.params else {}
        default_mode = values.get('input_mode', 'pair')
        if default_mode not in MODES:
            raise ValueError('%s: input_mode %r is not supported here (%s)' % (args.params, default_mode,
                                                                              ', '.join(MODES)))
        pipeline = Pipeline(Params.from_dict(values, source=args.params or 'defaults'))
        files = expand_inputs(args.inputs)
    except (TypeError, ValueError, OSError) as e:
        print('error: %s' % e, file=sys.stderr)
        return 2
    if not files:
        print('error: no .ply, .pcd or .npz files in %s' % ' '.join(args.inputs), file=sys.stderr)
        return 2
    # A folder or a glob writes into a folder (--out), whatever the number of files it matched.
    many = (len(files) > 1 or any(not os.path.isfile(p) for p in args.inputs) or
            bool(args.out and os.path.isdir(args.out)))
    if many and args.out:
        os.makedirs(args.out, exist_ok=True)
    failed = 0
    for k, path in enumerate(files, 1):
        start = time.perf_counter()
        try:
            cloud = cloud_files.read_cloud(path)
            mode = args.mode or detect_mode(cloud, default_mode)
            result, labelled, extra = filter_cloud(pipeline, cloud, mode)
            cloud_out, json_out = output_paths(path, args.out, many)
            cloud_files.write_cloud(cloud_out, cloud, labelled, extra)
            with open(json_out, 'w') as f:
                json.dump(objects_json(result, path, mode), f, indent=1)
        except (TypeError, ValueError, OSError) as e:
            failed += 1
            print('[%d/%d] %s: error: %s' % (k, len(files), path, e), file=sys.stderr)
            continue
        if not args.quiet:
            kinds = [o['type_name'] for o in result.objects]
            found = ', '.join('%d %s' % (kinds.count(t), t) for t in ('mirror', 'glass', 'unknown') if t in kinds)
            print('[%d/%d] %s: %s, %d points, %s; %.2f s -> %s' % (
                k, len(files), path, mode, len(result.labelled), found or 'no objects',
                time.perf_counter() - start, cloud_out), file=sys.stderr)
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
