"""A simulated sweep moved into base_link, where the scanner (laser) sits at OFFSET: clouds in a frame
other than the scanner's, for sensor_frame. Shared by the rostest checkers and test_prefilter_bag.py."""
import numpy as np

OFFSET = np.array([0.3, -0.2, 0.5])


def moved(sweep, offset=OFFSET, frame_id='base_link'):
    """The sweep with every point, true point and object translated by offset, framed frame_id."""
    for cloud in (sweep.echo1, sweep.echo2):
        for axis, delta in zip('xyz', offset):
            cloud[axis] += delta
    for axis, delta in zip('xyz', offset):
        sweep.ground_truth[axis] += delta
        sweep.ground_truth['true_' + axis] += delta
    for obj in sweep.objects:
        obj['corners'] = np.asarray(obj['corners']) + offset
        obj['centre'] = np.asarray(obj['centre']) + offset
        plane = np.asarray(obj['plane'], float)
        plane[3] -= plane[:3] @ offset
        obj['plane'] = plane
    sweep.frame_id = frame_id
    return sweep
