"""A stand-in for ROS 1's ``rospy``, enough to run a dispatch script off ROS: it records what the script does.

``Publisher`` takes rospy's own arguments (``rospy.topics.Publisher(name, data_class, subscriber_listener=None,
tcp_nodelay=False, latch=False, headers=None, queue_size=None)``); anything else is a TypeError, as in rospy.
A subscriber connects after ``connect_after`` calls of ``get_num_connections`` (0: at once)."""

published = []
"""(topic, message) for every ``Publisher.publish``."""
publishers = []
"""(topic, message class, queue_size, latch) for every ``Publisher`` made."""
nodes = []
"""(name, anonymous) for every ``init_node``."""
slept = []
calls = []
"""What the script called, in order: ``publish``, ``get_num_connections``, ``sleep``."""
connect_after = 0


class ROSInterruptException(Exception):
    pass


class Publisher:
    def __init__(self, name, data_class, subscriber_listener=None, tcp_nodelay=False, latch=False, headers=None,
                 queue_size=None):
        self.topic = name
        self.data_class = data_class
        self.polled = 0
        publishers.append((name, data_class, queue_size, latch))

    def publish(self, message):
        if not isinstance(message, self.data_class):
            raise TypeError(f"published a {type(message).__name__} on a {self.data_class.__name__} publisher")
        calls.append("publish")
        published.append((self.topic, message))

    def get_num_connections(self):
        calls.append("get_num_connections")
        self.polled += 1
        return 1 if self.polled > connect_after else 0


def init_node(name, anonymous=False):
    nodes.append((name, anonymous))


def is_shutdown():
    return False


def sleep(seconds):
    calls.append("sleep")
    slept.append(seconds)
