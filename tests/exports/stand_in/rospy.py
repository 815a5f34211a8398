"""A stand-in for ROS 1's ``rospy``, enough to run a dispatch script off ROS: it records what the script does."""

published = []
"""(topic, message) for every ``Publisher.publish``."""
publishers = []
"""(topic, message class, queue_size) for every ``Publisher`` made."""
nodes = []
"""(name, anonymous) for every ``init_node``."""
slept = []


class ROSInterruptException(Exception):
    pass


class Publisher:
    def __init__(self, topic, data_class, queue_size=None):
        self.topic = topic
        self.data_class = data_class
        publishers.append((topic, data_class, queue_size))

    def publish(self, message):
        if not isinstance(message, self.data_class):
            raise TypeError(f"published a {type(message).__name__} on a {self.data_class.__name__} publisher")
        published.append((self.topic, message))


def init_node(name, anonymous=False):
    nodes.append((name, anonymous))


def sleep(seconds):
    slept.append(seconds)
