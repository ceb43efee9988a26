#!/usr/bin/python3
"""Issue 14's speed targets, this build beside another (e.g. main's) in one run: median times of
the same frames through the Python bindings of each build, and their ratio.

Frames (simulated once, here, with this checkout's simulator, then handed to every build):
- 1080x400 two_mirrors_and_glass, RotatingHokuyo, ideal physics, launch/rotating_hokuyo_params.yaml
  (the frame and parameters of make bench's 1080x400 row): the core's time (stats['seconds']);
- the same frame with the default parameters;
- a 64x600 dual-return frame of a Hesai PandarQT64-class lidar (scanner.preset('hesai_qt64'),
  realistic physics, a random indoor scene with glass, ~34k points), default parameters (only
  input_mode given): the wall time of filter_dual_return, i.e. binning, the pipeline and the
  output records (what prefilter_bag does per frame besides (de)serialising the messages), and
  the core's time.

A build with the `threads` parameter runs each frame twice: threads automatic (the machine's cores,
at most 4; what a user gets) and threads 1 (rows ", threads 1"); an older build once.

Every build runs in a process of its own (its bindings first on PYTHONPATH), the builds in turn,
--rounds times, so that load on the machine hits both alike.

  /usr/bin/python3 bench/side_by_side.py --other /work/main/.ws/devel/lib/python3/dist-packages
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
HOKUYO_PARAMS = os.path.join(REPO, 'launch', 'rotating_hokuyo_params.yaml')


def simulate_frames(path):
    sys.path.insert(0, os.path.join(REPO, 'src'))
    from ohm_mirror_detector3d import scanner, simulate
    from ohm_mirror_detector3d.dual_return_cloud import dual_return_arrays
    from ohm_mirror_detector3d.physics import PhysicsParams
    hokuyo = simulate.simulate_sweep('two_mirrors_and_glass', scanner.RotatingHokuyo(scans=400, range_noise=0.01),
                                     seed=0, physics=PhysicsParams.ideal())
    # Organised (rows, cols, 3), as make bench's sweeps and the driver's clouds are.
    shape = (hokuyo.rows, hokuyo.cols, 3)
    e1 = np.stack([hokuyo.echo1[c] for c in ('x', 'y', 'z')], axis=-1).reshape(shape)
    e2 = np.stack([hokuyo.echo2[c] for c in ('x', 'y', 'z')], axis=-1).reshape(shape)
    lidar = scanner.preset('hesai_qt64')
    dual = simulate.simulate_sweep('random_3', lidar, seed=3)
    cloud, _, _ = dual_return_arrays(dual)
    np.savez(path, e1=e1.astype(np.float32), e2=e2.astype(np.float32),
             i1=hokuyo.echo1['intensity'].reshape(shape[:2]), i2=hokuyo.echo2['intensity'].reshape(shape[:2]), cloud_xyz=np.stack([cloud[c] for c in ('x', 'y', 'z')], axis=-1),
             cloud_intensity=cloud['intensity'], cloud_return=cloud['return'], cloud_ring=cloud['ring'],
             dual_shape=np.array([dual.rows, dual.cols]))


def worker(frames_path, repeats):
    import dataclasses
    import time
    from ohm_mirror_detector3d import core
    f = np.load(frames_path)
    out = {'module': core.__file__}
    # A build with the `threads` parameter runs every frame with it automatic (the machine's cores,
    # at most 4) and with one thread; an older build as it is.
    has_threads = 'threads' in {field.name for field in dataclasses.fields(core.Params)}
    variants = [('', None)] + ([(', threads 1', 1)] if has_threads else [])
    cases = {}
    for suffix, threads in variants:
        def pipeline(params):
            return core.Pipeline(params if threads is None else dataclasses.replace(params, threads=threads))
        hokuyo = pipeline(core.Params.from_yaml(HOKUYO_PARAMS))
        defaults = pipeline(core.Params())
        dual = pipeline(core.Params())
        cases['1080x400 hokuyo params' + suffix] = lambda p=hokuyo: p.filter(f['e1'], f['e2'], f['i1'], f['i2'])
        cases['1080x400 defaults' + suffix] = lambda p=defaults: p.filter(f['e1'], f['e2'], f['i1'], f['i2'])
        cases['64x600 dual_return defaults' + suffix] = lambda p=dual: p.filter_dual_return(
            f['cloud_xyz'], f['cloud_return'], f['cloud_ring'], f['cloud_intensity'])
    for name, run in cases.items():
        run()
        core_s, wall_s = [], []
        for _ in range(repeats):
            start = time.perf_counter()
            r = run()
            wall_s.append(time.perf_counter() - start)
            core_s.append(r.stats['seconds'])
        out[name] = {'core_ms': 1e3 * float(np.median(core_s)), 'wall_ms': 1e3 * float(np.median(wall_s)),
                     'objects': len(r.objects), 'points': int(len(r.labelled))}
    print(json.dumps(out))


def run_build(pythonpath, frames_path, repeats):
    env = dict(os.environ)
    env['PYTHONPATH'] = pythonpath + os.pathsep + env.get('PYTHONPATH', '')
    # The build's own core library (devel/lib), not the one a sourced workspace puts first.
    devel_lib = os.path.dirname(os.path.dirname(os.path.abspath(pythonpath)))
    env['LD_LIBRARY_PATH'] = devel_lib + os.pathsep + env.get('LD_LIBRARY_PATH', '')
    text = subprocess.run([sys.executable, os.path.abspath(__file__), '--worker', frames_path, '--repeats',
                           str(repeats)], env=env, check=True, stdout=subprocess.PIPE, universal_newlines=True).stdout
    return json.loads(text.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--this', default=os.path.join(REPO, '.ws', 'devel', 'lib', 'python3', 'dist-packages'),
                        help='this build\'s dist-packages (default: .ws of this checkout)')
    parser.add_argument('--other', required=False, help='the other build\'s dist-packages')
    parser.add_argument('--repeats', type=int, default=15)
    parser.add_argument('--rounds', type=int, default=2)
    parser.add_argument('--worker', help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        return worker(args.worker, args.repeats)
    builds = [('this', args.this)] + ([('other', args.other)] if args.other else [])
    with tempfile.TemporaryDirectory() as tmp:
        frames = os.path.join(tmp, 'frames.npz')
        simulate_frames(frames)
        results = {name: [] for name, _ in builds}
        for _ in range(args.rounds):
            for name, path in builds:
                results[name].append(run_build(path, frames, args.repeats))
    cases = [k for k in results['this'][0] if k != 'module']
    print('| frame | objects (this / other) | points | this core ms | other core ms | core ratio other/this '
          '| this wall ms | other wall ms | wall ratio other/this |')
    print('|---|---|---|---|---|---|---|---|---|')
    for case in cases:
        def has(name):
            return name in results and case in results[name][0]

        def median(name, key):
            return float(np.median([r[case][key] for r in results[name]])) if has(name) else float('nan')
        this_core, other_core = median('this', 'core_ms'), median('other', 'core_ms')
        this_wall, other_wall = median('this', 'wall_ms'), median('other', 'wall_ms')
        objects = '%d / %s' % (results['this'][0][case]['objects'],
                               results['other'][0][case]['objects'] if has('other') else '-')
        print('| %s | %s | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |' % (
            case, objects, results['this'][0][case]['points'], this_core, other_core, other_core / this_core,
            this_wall, other_wall, other_wall / this_wall))
    for name, _ in builds:
        print('%s: %s' % (name, results[name][0]['module']))


if __name__ == '__main__':
    main()
