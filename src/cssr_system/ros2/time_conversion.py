"""Seconds on the node's clock to and from ROS 2's time messages."""
from builtin_interfaces.msg import Time


def time_message(seconds: float) -> Time:
    """A stamp of `seconds` (0 or less: the zero stamp, "now")."""
    if seconds <= 0.0:
        return Time()
    nanoseconds = int(round(seconds * 1e9))
    return Time(sec=nanoseconds // 1000000000, nanosec=nanoseconds % 1000000000)


def seconds_of(stamp) -> float:
    """A builtin_interfaces/Time (or Duration) in seconds."""
    return stamp.sec + stamp.nanosec * 1e-9


def clock_seconds(node) -> float:
    """The node's clock (ROS time: simulated with use_sim_time) in seconds."""
    return node.get_clock().now().nanoseconds * 1e-9
