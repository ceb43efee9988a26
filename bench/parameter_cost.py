#!/usr/bin/python3
"""What one parameter costs: the core's time per sweep with the parameter as given beside the
defaults, side by side in one process, over random scenes of the evaluation's sensor families.

Each sweep (simulated once, realistic physics, the input mode a user of the sensor picks) goes
through both pipelines in turn, --rounds times; printed per family: the median and the maximum of
the core's time (stats['seconds']) and of the object stages' (stage_seconds['object_stages']),
and the ratio of the medians. Not a timed test: the machine is shared, quote medians.

    source .ws/devel/setup.bash
    /usr/bin/python3 bench/parameter_cost.py --set phantom_plane_share=0 --scenes 20 --seed 4000
"""
import argparse
import dataclasses
import statistics

from ohm_mirror_detector3d import core, scene_evaluation as se
from ohm_mirror_detector3d import scene as scenes
from ohm_mirror_detector3d.dual_return_cloud import dual_return_arrays
from ohm_mirror_detector3d.simulate import SweepSimulator


def parse_setting(text):
    name, _, value = text.partition('=')
    return name, (float(value) if '.' in value or 'e' in value else int(value))


def time_family(family, pipelines, count, seed, rounds):
    times = {key: {'core': [], 'object_stages': []} for key in pipelines}
    for case in se.cases([family], count, seed, named=False):
        sweep = SweepSimulator(scenes.get(case.scene), se.scanner_of(case)).sweep(seed=case.seed)
        if se.INPUT_MODES[family] == 'pair':
            shape = (sweep.rows, sweep.cols)
            run = lambda p: p.filter(sweep.echo1.reshape(shape), sweep.echo2.reshape(shape))  # noqa: E731
        else:
            cloud = dual_return_arrays(sweep)[0]
            run = lambda p: p.filter_dual_return(cloud)  # noqa: E731
        for _ in range(rounds):
            for key, pipeline in pipelines.items():
                stats = run(pipeline).stats
                times[key]['core'].append(stats['seconds'])
                times[key]['object_stages'].append(stats['stage_seconds']['object_stages'])
    return times


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--set', action='append', required=True, metavar='NAME=VALUE',
                        help='a parameter (the Params field name) and its value; repeatable')
    parser.add_argument('--families', default='hokuyo,hesai,ouster,velodyne')
    parser.add_argument('--scenes', type=int, default=20)
    parser.add_argument('--seed', type=int, default=4000)
    parser.add_argument('--rounds', type=int, default=3)
    args = parser.parse_args()
    changed = dataclasses.replace(core.Params(), **dict(parse_setting(s) for s in args.set))
    pipelines = {'defaults': core.Pipeline(core.Params()), 'given': core.Pipeline(changed)}
    print('given: %s; %d random scenes from %d, %d rounds; times in ms' %
          (', '.join(args.set), args.scenes, args.seed, args.rounds))
    print('| family | core, defaults: median / max | core, given: median / max | ratio of medians '
          '| object stages, defaults: median / max | given: median / max |')
    print('|---|---|---|---|---|---|')
    for family in se.resolve_families(args.families.split(',')):
        t = time_family(family, pipelines, args.scenes, args.seed, args.rounds)
        ms = lambda v: '%.2f / %.2f' % (1000 * statistics.median(v), 1000 * max(v))  # noqa: E731
        ratio = statistics.median(t['given']['core']) / statistics.median(t['defaults']['core'])
        print('| %s | %s | %s | %.3f | %s | %s |' % (family, ms(t['defaults']['core']), ms(t['given']['core']), ratio,
                                                     ms(t['defaults']['object_stages']),
                                                     ms(t['given']['object_stages'])))


if __name__ == '__main__':
    main()
