"""Intensity evidence on vs off on the same simulated sweeps (scene_evaluation's cases)."""
import sys, json, time
from ohm_mirror_detector3d import core, metrics, scene_evaluation as se, scene as scenes
from ohm_mirror_detector3d.simulate import SweepSimulator, ground_truth_objects
count = int(sys.argv[1]); seed = int(sys.argv[2]); named = sys.argv[3] == 'named'
pipes = {'off': core.Pipeline(), 'on': core.Pipeline(intensity_evidence=1)}
results = {k: [] for k in pipes}
typing = {k: {'unknown': 0, 'typed_right': 0, 'typed_wrong': 0} for k in pipes}
t0 = time.time()
for case in se.cases(se.resolve_families([]), count, seed, named):
    scene = scenes.get(case.scene)
    sweep = SweepSimulator(scene, se.scanner_of(case)).sweep(seed=case.seed)
    for k, p in pipes.items():
        gt, lab, cl, objs = se.filter_case(p, sweep, se.INPUT_MODES[case.family])
        r = metrics.evaluate_sweep(gt, lab, cl, objs, ground_truth_objects(sweep))
        r.update(family=case.family, scene=case.scene, kind=case.kind, seed=case.seed, scans=case.scans,
                 beams=sweep.num_beams, reflective=bool(scene.objects()), seconds={'simulate': 0, 'filter': 0})
        results[k].append(r)
        for o in objs:
            if k == 'on' and o.get('intensity_typed'):
                m = [x for x in r['objects'] if x.get('matched') and x.get('detected_id') == o['id']]
                right = bool(m) and m[0]['type_correct']
                typing[k]['typed_right' if right else 'typed_wrong'] += 1
                print('typed', case.family, case.scene, o['type_name'], 'right' if right else ('wrong' if m else 'unmatched'),
                      'lo=%.2f fs=%.2f haze=%.4f' % (o['intensity_log_odds'], o['intensity_faint_share'], o['intensity_haze']), flush=True)
            if o['type'] == 0:
                typing[k]['unknown'] += 1
summ = {k: se.summarise(v) for k, v in results.items()}
for k in pipes:
    print('## intensity_evidence %s' % k)
    print(se.table(summ[k], 'all'))
    print(typing[k])
for which in ('random', 'named'):
    for k in pipes:
        print('## %s, intensity_evidence %s' % (which, k))
        print(se.table(summ[k], which))
print('seconds', time.time() - t0)
