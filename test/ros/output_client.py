"""rostest helper: publishes one input message to a running pre-filter and collects its outputs
of the same stamp (the pre-filter subscribes lazily, so it waits until the input is listened to)."""
import rospy
from sensor_msgs.msg import PointCloud2

from ohm_mirror_detector3d.msg import ReflectiveObjectArray

OUTPUT_TYPES = {'labelled': PointCloud2, 'cleaned': PointCloud2, 'objects': ReflectiveObjectArray}


def wait_until_connected(publisher, subscribers, deadline):
    """Until the pre-filter listens to `publisher` and each of its outputs reaches `subscribers` (it
    subscribes lazily, and an output published before its connection is up is lost: a fresh clone's
    growth_scenes once got experiment3's labelled, objects and markers only), or `deadline`."""
    while (publisher.get_num_connections() == 0 or
           any(s.get_num_connections() == 0 for s in subscribers)) and rospy.Time.now() < deadline:
        rospy.sleep(0.1)


class OutputClient:
    def __init__(self, input_topic, input_type, outputs=('labelled', 'cleaned', 'objects')):
        self.wanted = tuple(outputs)
        self.received = {}
        self.subscribers = [rospy.Subscriber(topic, OUTPUT_TYPES[topic], self._on_output, callback_args=topic,
                                             queue_size=5, buff_size=2 ** 26) for topic in self.wanted]
        self.publisher = rospy.Publisher(input_topic, input_type, queue_size=1)

    def _on_output(self, msg, topic):
        self.received.setdefault(msg.header.stamp, {})[topic] = msg

    def run(self, message, timeout=90.0, stamp=None):
        """The outputs {topic: message} answering `message` (matched by `stamp`, default its header's)."""
        stamp = stamp if stamp is not None else message.header.stamp
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        wait_until_connected(self.publisher, self.subscribers, deadline)
        self.publisher.publish(message)
        while len(self.received.get(stamp, {})) < len(self.wanted) and rospy.Time.now() < deadline:
            rospy.sleep(0.05)
        got = self.received.pop(stamp, {})
        if len(got) < len(self.wanted):
            raise AssertionError('no complete answer from the pre-filter within %.0f s (got %s)'
                                 % (timeout, sorted(got)))
        return got
