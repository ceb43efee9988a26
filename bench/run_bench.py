#!/usr/bin/python3
"""`make bench`: times the core pipeline (single-threaded, Release) on simulated sweeps of growing size.

Sizes: RotatingHokuyo 1080 x 100 / 400 / 1000 and DualReturnLidar 128 x 2048 (two echoes per beam), each
for `empty_room` (no reflective object) and `two_mirrors_and_glass`; seed 0, range noise 0.01 m. Every
size uses the parameters of launch/rotating_hokuyo_params.yaml (outlier radius 0.2 m, 5 neighbours).
The sweeps go to a temporary directory as binary files (int64 rows, cols; echo 1 and echo 2 as N x 4
float32 x y z intensity) and bench_pipeline times each one in a process of its own (so that peak RSS is
per sweep). In the same process the same sweep runs again with grow_objects 1 (extent growth of mirrors
too; the defaults, 2, grow panes only: the object stages' time is reported beside the total), and with post_filter 1 against a map of 20 objects (the
post-filter stage, the cone labelling and the total beside the single-sweep total). Right after ours, the PCL baseline (bench/pcl_baseline.cpp: the same
stages with PCL's generic tools) is timed on the same sweep, with few repeats because it is slow (--baseline-repeats;
1 at the big sizes), and the ratio baseline/ours is reported. Then the resident set after 100 and after 10,000 sweeps
of 1080 x 100 with objects through one pipeline (--rss-sweeps). Last, the latency of the real nodelet in a
nodelet manager (bench/nodelet_latency.py, --latency-sweeps), measured twice: with the driver in the same
manager (bench/nodelet_latency_inprocess, messages by pointer) and with the driver in another process
(serialised over TCP); --only-latency runs only that part. Prints Markdown tables and writes the JSON (default
bench/results.json).
"""
import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'src'))

from ohm_mirror_detector3d.physics import PhysicsParams  # noqa: E402
from ohm_mirror_detector3d.scanner import DualReturnLidar, RotatingHokuyo  # noqa: E402
from ohm_mirror_detector3d.simulate import SweepSimulator  # noqa: E402

SCENES = ('empty_room', 'two_mirrors_and_glass')
STAGES = ('range_gate', 'outlier_filter', 'echo_comparison', 'object_extraction', 'type_analysis',
          'cone_labelling', 'cleaned_output')
SHORT = {'range_gate': 'gate', 'outlier_filter': 'outlier', 'echo_comparison': 'echo', 'object_extraction': 'extract',
         'type_analysis': 'type', 'cone_labelling': 'cones', 'cleaned_output': 'cleaned'}
NOISE = 0.01
SEED = 0
# The sweeps of the ideal physics (the simulator before issue 14): timings stay comparable with earlier runs.
PHYSICS = PhysicsParams.ideal()


def scanners():
    return [('1080x100', RotatingHokuyo(scans=100, range_noise=NOISE)),
            ('1080x400', RotatingHokuyo(scans=400, range_noise=NOISE)),
            ('1080x1000', RotatingHokuyo(scans=1000, range_noise=NOISE)),
            ('128x2048', DualReturnLidar(rings=128, azimuth_steps=2048, range_noise=NOISE))]


def write_sweep(path, sweep):
    with open(path, 'wb') as f:
        np.array([sweep.rows, sweep.cols], '<i8').tofile(f)
        for echo in (sweep.echo1, sweep.echo2):
            a = np.stack([echo['x'], echo['y'], echo['z'], echo['intensity']], axis=1).astype('<f4')
            a.tofile(f)


def machine():
    model = platform.processor() or 'unknown'
    try:
        with open('/proc/cpuinfo') as f:
            for line in f:
                if line.startswith('model name'):
                    model = line.split(':', 1)[1].strip()
                    break
    except OSError:
        pass
    return {'cpu_model': model, 'nproc': os.cpu_count(), 'usable_cores': len(os.sched_getaffinity(0)),
            'kernel': platform.release(), 'python': platform.python_version(),
            'load_average': ' '.join('%.1f' % v for v in os.getloadavg())}


def table(results):
    head = ['size', 'scene', 'beams', 'objects', 'total median ms', 'total p95 ms', 'CPU median ms', 'Mbeams/s'] + \
           ['%s ms' % SHORT[s] for s in STAGES] + ['peak RSS MB', 'PCL baseline ms (runs)', 'speed-up']
    lines = ['| ' + ' | '.join(head) + ' |', '|' + '---|' * len(head)]
    for r in results:
        st = r['stages']
        row = [r['size'], r['scene'], str(r['beams']), str(r['objects']),
               '%.1f' % (1e3 * st['total']['median_s']), '%.1f' % (1e3 * st['total']['p95_s']),
               '%.1f' % (1e3 * r['cpu_median_s']),
               '%.2f' % (r['beams_per_s'] / 1e6)] + ['%.1f' % (1e3 * st[s]['median_s']) for s in STAGES] + \
              ['%.0f' % r['peak_rss_mb']]
        b = r.get('baseline')
        row += ['%.0f (%d)' % (1e3 * b['stages']['total']['median_s'], b['repeats']), '%.0fx' % b['speedup']] \
            if b else ['–', '–']
        lines.append('| ' + ' | '.join(row) + ' |')
    return '\n'.join(lines)


def extent_growth_table(results):
    """The object stages with grow_objects 1 (mirror and glass growth) and the reflection chains, beside the
    whole pipeline with the defaults (grow_objects 2: panes only)."""
    lines = ['| size | scene | objects | growth stages median ms | p95 ms | reflection chains median ms | '
             'growth + chains median ms | total with growth median ms | total with the defaults median ms |',
             '|---|---|---|---|---|---|---|---|---|']
    for r in results:
        g = r.get('growth')
        if g:
            lines.append('| %s | %s | %d | %.2f | %.2f | %.2f | %.2f | %.1f | %.1f |' % (
                r['size'], r['scene'], r['objects'], 1e3 * g['object_stages_median_s'],
                1e3 * g['object_stages_p95_s'], 1e3 * g['reflection_chains_median_s'],
                1e3 * g['growth_and_chains_median_s'], 1e3 * g['total_median_s'],
                1e3 * r['stages']['total']['median_s']))
    return '\n'.join(lines)


def post_filter_table(results):
    """The post-filter (post_filter 1) against a map of 20 objects: its stage, the cone labelling with
    the map's objects, the whole pipeline, beside the pipeline without it."""
    lines = ['| size | scene | map objects | labelling objects | post-filter stage median ms | p95 ms '
             '| cone labelling median ms | total median ms | total without median ms | cost per sweep ms |',
             '|---|---|---|---|---|---|---|---|---|---|']
    for r in results:
        p = r.get('post_filter')
        if p:
            without = r['stages']['total']['median_s']
            lines.append('| %s | %s | %d | %d | %.2f | %.2f | %.1f | %.1f | %.1f | %.1f |' % (
                r['size'], r['scene'], p['map_objects'], p['labelling_objects'], 1e3 * p['object_stages_median_s'],
                1e3 * p['object_stages_p95_s'], 1e3 * p['cone_labelling_median_s'], 1e3 * p['total_median_s'],
                1e3 * without, 1e3 * (p['total_median_s'] - without)))
    return '\n'.join(lines)


def growth(results):
    """Time per beam across the Hokuyo sizes, per scene, and the fitted exponent of t ~ N^k."""
    out = {}
    for scene in SCENES:
        rs = [r for r in results if r['scene'] == scene and r['size'].startswith('1080x')]
        n = np.array([r['beams'] for r in rs], float)
        t = np.array([r['stages']['total']['median_s'] for r in rs])
        k = float(np.polyfit(np.log(n), np.log(t), 1)[0]) if len(rs) >= 2 else float('nan')
        out[scene] = {'beams': n.astype(int).tolist(), 'us_per_beam': (1e6 * t / n).round(4).tolist(),
                      'exponent': round(k, 3)}
    return out


def measure_latency(args):
    """bench/nodelet_latency.py twice on the same sweep: with the driver in the same nodelet manager
    (nodelet_latency_inprocess, beside --binary: the deployment of a driver nodelet, input and output by
    pointer) and with the driver in another process (rospy, input serialised over TCP)."""
    inprocess = os.path.join(os.path.dirname(os.path.abspath(args.binary)), 'nodelet_latency_inprocess')
    latency = {'target': 'input stamp -> cleaned published <= 1.2 x core (median)'}
    for key, extra in (('same_manager', ['--inprocess', inprocess]), ('other_process', [])):
        print('nodelet latency (%s): %d sweeps through a nodelet manager ...' % (key, args.latency_sweeps),
              file=sys.stderr, flush=True)
        out = subprocess.run([sys.executable, os.path.join(HERE, 'nodelet_latency.py'), '--sweeps',
                              str(args.latency_sweeps)] + extra, check=True, stdout=subprocess.PIPE,
                             universal_newlines=True).stdout
        latency[key] = json.loads(out.strip().splitlines()[-1])
    return latency


def print_latency(latency):
    print('\nNodelet latency through the real nodelet in a nodelet manager (%s, %d sweeps each, medians; '
          'target: input stamp -> `cleaned` published <= 1.2 x core):\n'
          % (latency['same_manager']['sweep'], latency['same_manager']['sweeps']))
    print('| driver | core | stamp -> `cleaned` published | ratio | p95 published | stamp -> received |')
    print('|---|---:|---:|---:|---:|---:|')
    for key in ('same_manager', 'other_process'):
        r = latency[key]
        print('| %s | %.1f ms | %.1f ms | %.2f x | %.1f ms | %.1f ms (%s) |'
              % (r['driver'], r['core_ms'], r['in_nodelet_ms'], r['ratio'], r['in_nodelet_p95_ms'],
                 r['received_ms'], r['receiver']))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--binary', required=True, help='bench_pipeline executable')
    ap.add_argument('--output', default=os.path.join(HERE, 'results.json'))
    ap.add_argument('--repeats', type=int, default=20)
    ap.add_argument('--threads', type=int, default=0,
                    help="the pipeline's threads parameter (0: automatic, the machine's cores up to 4)")
    ap.add_argument('--warmup', type=int, default=2)
    ap.add_argument('--budget', type=float, default=30.0,
                    help='seconds of measured runs per sweep after which fewer repeats (>= 5) suffice')
    ap.add_argument('--sizes', nargs='*', help='subset of sizes, e.g. 1080x100')
    ap.add_argument('--baseline-repeats', type=int, default=3,
                    help='runs of the PCL baseline per sweep at 1080x100 (1 at the bigger sizes; 0: no baseline)')
    ap.add_argument('--rss-sweeps', type=int, default=10000,
                    help='sweeps of 1080x100 with objects for the memory check (0: skip)')
    ap.add_argument('--latency-sweeps', type=int, default=30,
                    help='sweeps through the real nodelet for bench/nodelet_latency.py (0: skip; needs the '
                         'workspace sourced)')
    ap.add_argument('--only-latency', action='store_true',
                    help='run only the nodelet latency part and replace the nodelet_latency section of an '
                         'existing --output JSON (the other sections stay as they were)')
    args = ap.parse_args()
    if args.only_latency:
        load_average = ' '.join(open('/proc/loadavg').read().split()[:3])
        latency = measure_latency(args)
        with open(args.output) as f:
            report = json.load(f)
        latency['measured'] = ('alone by run_bench.py --only-latency on %s UTC (load average %s at its start), '
                               'not in the run that produced the rest of this file'
                               % (time.strftime('%Y-%m-%d %H:%M', time.gmtime()), load_average))
        report['nodelet_latency'] = latency
        with open(args.output, 'w') as f:
            json.dump(report, f, indent=1)
        print_latency(latency)
        print('\nJSON: %s (nodelet_latency replaced, the rest from its earlier run)' % args.output)
        return

    results = []
    rss = None
    rss_path = None
    with tempfile.TemporaryDirectory(prefix='ohm_bench_') as tmp:
        for size, scanner in scanners():
            if args.sizes and size not in args.sizes:
                continue
            for scene in SCENES:
                started = time.perf_counter()
                sweep = SweepSimulator(scene, scanner, PHYSICS).sweep(seed=SEED, noise=NOISE)
                path = os.path.join(tmp, '%s_%s.bin' % (size, scene))
                write_sweep(path, sweep)
                del sweep
                simulated = time.perf_counter() - started
                baseline = args.baseline_repeats if size == '1080x100' else min(args.baseline_repeats, 1)
                out = subprocess.run([args.binary, '--repeats', str(args.repeats), '--warmup', str(args.warmup),
                                      '--budget', str(args.budget), '--baseline', str(baseline),
                                      '--threads', str(args.threads), path],
                                     check=True, stdout=subprocess.PIPE, universal_newlines=True).stdout
                r = json.loads(out.strip().splitlines()[-1])
                r.update(size=size, scene=scene, scanner=scanner.name, simulation_s=round(simulated, 2))
                del r['file']
                if size == '1080x100' and scene == 'two_mirrors_and_glass' and args.rss_sweeps > 0:
                    rss_path = path
                else:
                    os.remove(path)
                results.append(r)
                print('%s %s: %d runs, median %.1f ms (simulated in %.1f s)'
                      % (size, scene, r['repeats'], 1e3 * r['stages']['total']['median_s'], simulated),
                      file=sys.stderr, flush=True)
        if rss_path:
            print('memory: %d sweeps of 1080x100 two_mirrors_and_glass ...' % args.rss_sweeps, file=sys.stderr, flush=True)
            out = subprocess.run([args.binary, '--rss-sweeps', str(args.rss_sweeps), rss_path], check=True,
                                 stdout=subprocess.PIPE, universal_newlines=True).stdout
            rss = json.loads(out.strip().splitlines()[-1])
            del rss['file']
            rss.update(size='1080x100', scene='two_mirrors_and_glass', within_1mb=abs(rss['growth_mb']) <= 1.0)

    latency = measure_latency(args) if args.latency_sweeps > 0 else None

    report = {
        'machine': machine(),
        'settings': {'threads': args.threads or 'automatic (%d)' % min(4, os.cpu_count() or 1), 'build_type': 'Release', 'warmup': args.warmup, 'repeats': args.repeats,
                     'budget_s': args.budget, 'seed': SEED, 'range_noise_m': NOISE,
                     'params': 'launch/rotating_hokuyo_params.yaml (outlier radius 0.2 m, 5 neighbours, '
                               'd_min 0.1, d_max 30) for every size',
                     'timed': 'core::Pipeline::process only (no ROS, no conversion, no file I/O)'},
        'results': results,
        'growth': growth(results),
        'baseline': {'what': 'bench/pcl_baseline.cpp: pcl::RadiusOutlierRemoval (kd-tree) on every in-range point '
                             'of both echoes, pcl::SACSegmentation RANSAC planes on all candidates, '
                             'pcl::IterativeClosestPoint (30 iterations) of the mirrored points behind each plane '
                             'against the whole scene in front of it; same parameters, same sweep, same process',
                     'repeats': 'median of %d runs at 1080x100, %d run(s) at the bigger sizes (it is slow)'
                                % (args.baseline_repeats, min(args.baseline_repeats, 1))},
        'memory': rss,
        'nodelet_latency': latency,
    }
    with open(args.output, 'w') as f:
        json.dump(report, f, indent=1)

    m = report['machine']
    print('Machine: %s, %d cores (nproc), load average %s at the start, threads %s. Parameters: '
          'rotating_hokuyo_params.yaml (outlier radius 0.2 m, 5 neighbours) for all sizes. Times are wall-clock '
          '(steady_clock) medians; CPU = the process\'s CPU time (all threads), less sensitive to other load on '
          'the machine. PCL baseline (single-threaded): median of %d run(s) at 1080x100, 1 run at the bigger sizes '
          '(it is slow).\n'
          % (m['cpu_model'], m['nproc'], m['load_average'], report['settings']['threads'], args.baseline_repeats))
    print(table(results))
    print('\nExtent growth (grow_objects 1: mirror and glass growth; the defaults grow panes only) and reflection '
          'chains, the same sweeps and repeats:\n')
    print(extent_growth_table(results))
    print('\nPost-filter (post_filter 1, a map of 20 objects around the sensor), the same sweeps and repeats:\n')
    print(post_filter_table(results))
    print('\nGrowth (median time per beam, RotatingHokuyo 1080 x R; exponent k of t ~ N^k):\n')
    for scene, g in report['growth'].items():
        print('- %s: %s us/beam at %s beams, k = %.2f'
              % (scene, ' / '.join('%.3f' % v for v in g['us_per_beam']), ' / '.join(map(str, g['beams'])),
                 g['exponent']))
    if rss:
        print('\nMemory: resident set %.2f MB after 100 sweeps, %.2f MB after %d sweeps (%+.2f MB, %s) of %s %s.'
              % (rss['rss_after_100_mb'], rss['rss_after_all_mb'], rss['sweeps'], rss['growth_mb'],
                 'within 1 MB' if rss['within_1mb'] else 'MORE than 1 MB', rss['size'], rss['scene']))
    if latency:
        print_latency(latency)
    print('\nJSON: %s' % args.output)


if __name__ == '__main__':
    main()
