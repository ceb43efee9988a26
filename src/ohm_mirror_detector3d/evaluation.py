"""The evaluator's ROS layer: collects the filter's outputs and the ground truth (from bags or live),
pairs them by header stamp and scores each sweep with metrics.evaluate_sweep.

Imports rospy (through ros_io); the maths stays in metrics.py.
"""
import threading

import rospy
from sensor_msgs.msg import PointCloud2

from ohm_mirror_detector3d.msg import ReflectiveObjectArray

from . import metrics, ros_io

DEFAULT_PREFIX = '/prefilter'
DEFAULT_GROUND_TRUTH = '/ground_truth'
DEFAULT_GROUND_TRUTH_OBJECTS = '/ground_truth_objects'


def filter_topics(prefix=DEFAULT_PREFIX):
    prefix = prefix.rstrip('/')
    return {k: '%s/%s' % (prefix, k) for k in ros_io.FILTER_OUTPUTS}


class SweepData:
    """The messages of one stamp, converted: ground truth, its objects and the filter's outputs."""

    def __init__(self, stamp, ground_truth_msg, ground_truth_objects_msg, labelled_msg, cleaned_msg, objects_msg):
        self.stamp = stamp
        self.ground_truth = ros_io.ground_truth_from_cloud(ground_truth_msg)
        self.ground_truth_objects = (ros_io.objects_from_msg(ground_truth_objects_msg)
                                     if ground_truth_objects_msg is not None else [])
        out = ros_io.filter_output_from_msgs(labelled_msg, cleaned_msg, objects_msg)
        self.labelled, self.cleaned, self.objects = out['labelled'], out['cleaned'], out['objects']

    def evaluate(self, **kwargs):
        r = metrics.evaluate_sweep(self.ground_truth, self.labelled, self.cleaned, self.objects,
                                   self.ground_truth_objects, **kwargs)
        r['stamp'] = self.stamp.to_sec()
        return r


def evaluate_bags(filter_bag, ground_truth_bag=None, prefix=DEFAULT_PREFIX, ground_truth_topic=DEFAULT_GROUND_TRUTH,
                  ground_truth_objects_topic=DEFAULT_GROUND_TRUTH_OBJECTS, max_sweeps=None, progress=None,
                  **metric_kwargs):
    """Scores every stamp present in both bags (ground truth defaults to the filter bag).

    progress: optional callable(total) -> progress.Progress, told of every sweep scored.
    Returns (per-sweep results, aggregated summary, SweepData of the last sweep or None).
    """
    topics = filter_topics(prefix)
    out = ros_io.read_bag_by_stamp(filter_bag, list(topics.values()))
    gt = ros_io.read_bag_by_stamp(ground_truth_bag or filter_bag, [ground_truth_topic, ground_truth_objects_topic])
    stamps = sorted(set(gt[ground_truth_topic]) & set(out[topics['labelled']]) & set(out[topics['cleaned']]))
    if max_sweeps:
        stamps = stamps[:max_sweeps]
    results, last = [], None
    shown = progress(len(stamps)) if progress is not None else None
    for stamp in stamps:
        last = SweepData(stamp, gt[ground_truth_topic][stamp], gt[ground_truth_objects_topic].get(stamp),
                         out[topics['labelled']][stamp], out[topics['cleaned']][stamp],
                         out[topics['objects']].get(stamp))
        results.append(last.evaluate(**metric_kwargs))
        if shown is not None:
            shown.update(len(results))
    if shown is not None:
        shown.finish()
    return results, metrics.aggregate_results(results), last


class LiveEvaluator:
    """Subscribes to the ground truth and the filter's outputs and scores each complete stamp.

    The objects topic is waited for only when `require_objects` is set (a filter may publish none).
    """

    def __init__(self, prefix=DEFAULT_PREFIX, ground_truth_topic='ground_truth',
                 ground_truth_objects_topic='ground_truth_objects', require_objects=True, **metric_kwargs):
        self.metric_kwargs = metric_kwargs
        self.require_objects = require_objects
        self.results, self.last = [], None
        self._pending = {}
        self._lock = threading.Lock()
        self._cond = threading.Condition(self._lock)
        topics = filter_topics(prefix)
        self._subs = [
            rospy.Subscriber(ground_truth_topic, PointCloud2, self._cb, 'gt', queue_size=10, buff_size=2 ** 26),
            rospy.Subscriber(ground_truth_objects_topic, ReflectiveObjectArray, self._cb, 'gt_objects',
                             queue_size=10),
            rospy.Subscriber(topics['labelled'], PointCloud2, self._cb, 'labelled', queue_size=10,
                             buff_size=2 ** 26),
            rospy.Subscriber(topics['cleaned'], PointCloud2, self._cb, 'cleaned', queue_size=10, buff_size=2 ** 26),
            rospy.Subscriber(topics['objects'], ReflectiveObjectArray, self._cb, 'objects', queue_size=10),
        ]

    def _cb(self, msg, key):
        with self._cond:
            entry = self._pending.setdefault(msg.header.stamp, {})
            entry[key] = msg
            needed = {'gt', 'gt_objects', 'labelled', 'cleaned'} | ({'objects'} if self.require_objects else set())
            if not needed <= set(entry):
                return
            del self._pending[msg.header.stamp]
            # Older incomplete stamps will not complete any more.
            for s in [s for s in self._pending if s < msg.header.stamp]:
                del self._pending[s]
        data = SweepData(msg.header.stamp, entry['gt'], entry['gt_objects'], entry['labelled'], entry['cleaned'],
                         entry.get('objects'))
        result = data.evaluate(**self.metric_kwargs)
        with self._cond:
            self.results.append(result)
            self.last = data
            self._cond.notify_all()

    def wait(self, count, timeout=None, progress=None):
        """Blocks until `count` sweeps are scored (or timeout s / shutdown); returns the results so far.

        progress: optional progress.Progress, told of the sweeps scored while waiting."""
        deadline = None if timeout is None else rospy.get_time() + timeout
        with self._cond:
            while len(self.results) < count and not rospy.is_shutdown():
                if deadline is not None and rospy.get_time() > deadline:
                    break
                self._cond.wait(0.2)
                if progress is not None:
                    progress.update(len(self.results))
            if progress is not None:
                progress.update(len(self.results), last=True)
            return list(self.results)

    def close(self):
        for s in self._subs:
            s.unregister()
