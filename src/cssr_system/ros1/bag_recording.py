"""A recording (`recording.Recording`) from a ROS 1 bag of /joint_states and odometry, e.g. recorded on the robot
with ``rosbag record /joint_states /pepper_dcm/odom`` (doc/figure.md)."""
import math
from typing import Optional

import numpy

from cssr_system.recording.recording import Recording

JOINT_STATE_TYPE = "sensor_msgs/JointState"
ODOMETRY_TYPE = "nav_msgs/Odometry"


def _topic_of(info, wanted_type: str, preferred: Optional[str]) -> Optional[str]:
    """`preferred` when given, else the bag's topic of that type (the one with the most messages)."""
    if preferred:
        return preferred
    topics = [(info.topics[name].message_count, name) for name in info.topics
              if info.topics[name].msg_type == wanted_type]
    return max(topics)[1] if topics else None


def _yaw(orientation) -> float:
    return math.atan2(2.0 * (orientation.w * orientation.z + orientation.x * orientation.y),
                      1.0 - 2.0 * (orientation.y ** 2 + orientation.z ** 2))


def recording_from_bag(path: str, joint_states_topic: Optional[str] = None,
                       odometry_topic: Optional[str] = None) -> Recording:
    """The joints and heading of the bag at `path` (times from its first joint state); ValueError without any."""
    import rosbag
    with rosbag.Bag(path) as bag:
        info = bag.get_type_and_topic_info()
        joints_topic = _topic_of(info, JOINT_STATE_TYPE, joint_states_topic)
        heading_topic = _topic_of(info, ODOMETRY_TYPE, odometry_topic)
        if joints_topic is None:
            raise ValueError("%s: no %s topic" % (path, JOINT_STATE_TYPE))
        names, rows, times, heading_times, headings = [], [], [], [], []
        wanted = [name for name in (joints_topic, heading_topic) if name]
        for topic, message, stamp in bag.read_messages(topics=wanted):
            moment = message.header.stamp.to_sec() or stamp.to_sec()
            if topic == joints_topic:
                names.extend(name for name in message.name if name not in names)
                rows.append(dict(zip(message.name, message.position)))
                times.append(moment)
            else:
                heading_times.append(moment)
                headings.append(_yaw(message.pose.pose.orientation))
    if not rows:
        raise ValueError("%s: no message on %s" % (path, joints_topic))
    start = times[0]
    positions = numpy.array([[row.get(name, numpy.nan) for name in names] for row in rows], dtype=float)
    order = numpy.argsort(times, kind="stable")
    return Recording(start_epoch=start, joint_names=tuple(names), times=numpy.array(times)[order] - start,
                     positions=positions[order], heading_times=numpy.array(heading_times) - start,
                     headings=numpy.unwrap(numpy.array(headings, dtype=float)),
                     info={"source": "bag " + path.rsplit("/", 1)[-1]}, heading_topic=heading_topic or "")
