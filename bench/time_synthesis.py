#!/usr/bin/python3
"""How long the simulator takes for one 1080 x R sweep (trace + noise) and for a re-noised sweep of the
same pose (the trace is cached). Usage: time_synthesis.py [SCENE] [R] (default experiment1 400)."""
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'src'))

from ohm_mirror_detector3d.scanner import RotatingHokuyo  # noqa: E402
from ohm_mirror_detector3d.simulate import SweepSimulator  # noqa: E402


def main():
    name = sys.argv[1] if len(sys.argv) > 1 else 'experiment1'
    scans = int(sys.argv[2]) if len(sys.argv) > 2 else 400
    started = time.perf_counter()
    simulator = SweepSimulator(name, RotatingHokuyo(scans=scans))
    sweep = simulator.sweep(seed=0)
    first = time.perf_counter() - started
    started = time.perf_counter()
    simulator.sweep(seed=1)
    again = time.perf_counter() - started
    print('%s, 1080 x %d = %d beams, %d rectangles: first sweep %.2f s, re-noised sweep %.2f s'
          % (name, scans, sweep.num_beams, len(simulator.scene.rectangles), first, again))


if __name__ == '__main__':
    main()
