#!/usr/bin/python3
"""`make bench`, part 2: end-to-end latency of the real nodelet in a real nodelet manager.

Starts its own master (roslaunch on a free port) with a nodelet manager and the pre-filter nodelet
(launch/rotating_hokuyo_params.yaml, input_mode pair), publishes simulated sweeps (RotatingHokuyo
1080 x SCANS, two_mirrors_and_glass, noise 0.01 m) as EchoPair with header.stamp = now, subscribes to
`cleaned` and to the nodelet's `timing` topic, and reports medians of:
- core: core::Pipeline::process as timed inside the nodelet;
- in-nodelet: input stamp -> `cleaned` published, as seen by the nodelet (includes this script's
  serialisation and the TCP transfer of the input, the conversion to a Sweep, the core, the
  conversion to PointCloud2 and the publish call);
- received: input stamp -> `cleaned` received by this (Python) subscriber, which adds the transfer
  of the output and rospy's deserialisation.
The ratio in-nodelet / core is the issue's target (<= 1.2). Prints a table, one JSON line last.

Two deployments:
- default, 'driver in another process (serialised over TCP)': the manager comes from roslaunch and
  this Python process plays the driver, so the input is serialised by rospy and sent over TCP;
- --inprocess BINARY, 'driver in the same manager (by pointer)': the same sweep goes into a bag, a
  bare master (rosmaster --core) is started and BINARY (bench/nodelet_latency_inprocess.cpp) is the
  nodelet manager: it loads the nodelet with the same parameters and publishes the sweep as a
  ConstPtr from inside the process, as a driver nodelet in the same manager does; `received` is then
  its own in-process (C++, by pointer) subscriber.
"""
import argparse
import json
import os
import socket
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

LAUNCH = """<launch>
  <node pkg="nodelet" type="nodelet" name="manager" args="manager"/>
  <node pkg="nodelet" type="nodelet" name="prefilter" args="load ohm_mirror_detector3d/PreFilterNodelet manager">
    <rosparam command="load" file="%s"/>
  </node>
</launch>
"""


def free_port():
    s = socket.socket()
    s.bind(('127.0.0.1', 0))
    port = s.getsockname()[1]
    s.close()
    return port


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--scans', type=int, default=100, help='scans of the simulated 1080 x SCANS sweep')
    ap.add_argument('--sweeps', type=int, default=30)
    ap.add_argument('--warmup', type=int, default=3)
    ap.add_argument('--output', help='also write the JSON here')
    ap.add_argument('--inprocess', metavar='BINARY',
                    help='nodelet_latency_inprocess executable: measure with the driver in the same manager')
    args = ap.parse_args()

    port = free_port()
    os.environ['ROS_MASTER_URI'] = 'http://127.0.0.1:%d' % port
    params = os.path.join(HERE, '..', 'launch', 'rotating_hokuyo_params.yaml')
    if args.inprocess:
        result = measure_inprocess(args, port, os.path.abspath(params))
        report(args, result)
        return
    with tempfile.NamedTemporaryFile('w', suffix='.launch', delete=False) as f:
        f.write(LAUNCH % os.path.abspath(params))
        launch_file = f.name
    launch = subprocess.Popen(['roslaunch', '-p', str(port), launch_file], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    try:
        result = measure(args)
    finally:
        stop(launch)
        os.remove(launch_file)
    report(args, result)


def stop(process):
    """Ends a roslaunch or rosmaster started here: SIGTERM, SIGKILL if it is still there after 20 s."""
    process.terminate()
    try:
        process.wait(timeout=20)
    except subprocess.TimeoutExpired:
        process.kill()


def report(args, result):
    print('Nodelet latency, %s (%s, %d sweeps, medians): core %.1f ms, input stamp -> cleaned published (in the '
          'nodelet) %.1f ms = %.2f x core, -> received by %s %.1f ms'
          % (result['driver'], result['sweep'], result['sweeps'], result['core_ms'], result['in_nodelet_ms'],
             result['ratio'], result['receiver'], result['received_ms']), file=sys.stderr)
    print(json.dumps(result))
    if args.output:
        with open(args.output, 'w') as f:
            json.dump(result, f, indent=1)


def wait_for_master():
    import rospy
    deadline = time.time() + 60
    while True:
        try:
            rospy.get_master().getSystemState()
            return
        except Exception:  # the master is not up yet
            if time.time() > deadline:
                raise RuntimeError('no ROS master on %s' % os.environ['ROS_MASTER_URI'])
            time.sleep(0.2)


def simulated_sweep(scans):
    from ohm_mirror_detector3d.physics import PhysicsParams
    from ohm_mirror_detector3d.scanner import RotatingHokuyo
    from ohm_mirror_detector3d.simulate import SweepSimulator
    # The ideal physics (the simulator before issue 14), as run_bench.py: comparable with earlier runs.
    return SweepSimulator('two_mirrors_and_glass', RotatingHokuyo(scans=scans, range_noise=0.01),
                          PhysicsParams.ideal()).sweep(seed=0, noise=0.01)


def measure_inprocess(args, port, params):
    from ohm_mirror_detector3d.ros_io import write_sweeps_bag

    tmp = tempfile.mkdtemp(prefix='ohm_latency_')
    bag = os.path.join(tmp, 'sweep.bag')
    write_sweeps_bag(bag, [simulated_sweep(args.scans)])
    master = subprocess.Popen(['rosmaster', '--core', '-p', str(port)], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    try:
        wait_for_master()
        out = subprocess.run([args.inprocess, '--bag', bag, '--params', params, '--sweeps', str(args.sweeps),
                              '--warmup', str(args.warmup)], check=True, stdout=subprocess.PIPE,
                             universal_newlines=True, timeout=600).stdout
    finally:
        stop(master)
        os.remove(bag)
        os.rmdir(tmp)
    result = json.loads(out.strip().splitlines()[-1])
    result.update(sweep='1080x%d two_mirrors_and_glass' % args.scans, driver='driver in the same manager (by pointer)',
                  receiver='a C++ subscriber in the same manager (by pointer)')
    return result


def measure(args):
    import rospy
    from sensor_msgs.msg import PointCloud2
    from std_msgs.msg import Float64MultiArray

    from ohm_mirror_detector3d.msg import EchoPair
    from ohm_mirror_detector3d.ros_io import sweep_to_messages

    wait_for_master()
    rospy.init_node('nodelet_latency', disable_signals=True)
    sweep = simulated_sweep(args.scans)
    pair = sweep_to_messages(sweep, rospy.Time.now())['echo_pair']

    lock = threading.Condition()
    received = {}
    timings = {}

    def on_cleaned(msg):
        now = rospy.Time.now()
        with lock:
            received[msg.header.stamp] = (now - msg.header.stamp).to_sec()
            lock.notify_all()

    def on_timing(msg):
        with lock:
            timings[len(timings)] = tuple(msg.data)
            lock.notify_all()

    rospy.Subscriber('/prefilter/cleaned', PointCloud2, on_cleaned, queue_size=5, buff_size=1 << 26)
    rospy.Subscriber('/prefilter/timing', Float64MultiArray, on_timing, queue_size=50)
    publisher = rospy.Publisher('/prefilter/input', EchoPair, queue_size=1)
    deadline = time.time() + 60
    while publisher.get_num_connections() == 0 and time.time() < deadline:
        time.sleep(0.1)
    time.sleep(1.0)  # the timing subscription connects too

    core, in_nodelet, latency = [], [], []
    for i in range(args.warmup + args.sweeps):
        with lock:
            before = len(timings)
        pair.header.stamp = rospy.Time.now()
        pair.echo1.header.stamp = pair.echo2.header.stamp = pair.header.stamp
        publisher.publish(pair)
        with lock:
            ok = lock.wait_for(lambda: pair.header.stamp in received and len(timings) > before, timeout=30)
        if not ok:
            raise RuntimeError('no cleaned/timing answer from the nodelet for sweep %d' % i)
        if i >= args.warmup:
            with lock:
                core.append(timings[before][0])
                in_nodelet.append(timings[before][1])
                latency.append(received[pair.header.stamp])
        time.sleep(0.2)
    rospy.signal_shutdown('done')
    core_ms = 1e3 * float(np.median(core))
    in_nodelet_ms = 1e3 * float(np.median(in_nodelet))
    return {'sweep': '1080x%d two_mirrors_and_glass' % args.scans, 'beams': 1080 * args.scans,
            'sweeps': args.sweeps, 'core_ms': round(core_ms, 2), 'in_nodelet_ms': round(in_nodelet_ms, 2),
            'ratio': round(in_nodelet_ms / core_ms, 3), 'received_ms': round(1e3 * float(np.median(latency)), 2),
            'in_nodelet_p95_ms': round(1e3 * float(np.percentile(in_nodelet, 95)), 2),
            'driver': 'driver in another process (serialised over TCP)',
            'receiver': 'a Python subscriber in another process (serialised over TCP)'}


if __name__ == '__main__':
    main()
