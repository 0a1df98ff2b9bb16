"""naoqi_driver's JointAngles topic on ROS 1: the node's one publisher of it, shared by the joint-angle streams
(core/joint_angle_stream.py), each of whose setAngles calls becomes one JointAnglesWithSpeed message."""
import rospy
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed

from cssr_system.motion import joint_angle_stream as streaming
from cssr_system.ros1.rospy_compat import has_subscriber_other_than, write_at_once


def joint_angles_message(angles: streaming.JointAngles, now: float) -> JointAnglesWithSpeed:
    """The message of one setAngles call (stamped `now`; naoqi_driver reads only the names, angles and speed)."""
    message = JointAnglesWithSpeed(joint_names=list(angles.joint_names), joint_angles=list(angles.joint_angles),
                                   speed=angles.speed, relative=angles.relative)
    message.header.stamp = rospy.Time.from_sec(now) if now > 0.0 else rospy.Time(0)
    return message


class JointAnglesTopic:
    """The node's one publisher of the JointAngles topic, shared by the part streams."""

    def __init__(self, name: str, own_caller_id: str) -> None:
        self.name = name
        self._own = own_caller_id
        self.publisher = rospy.Publisher(name, JointAnglesWithSpeed, queue_size=10)
        write_at_once(self.publisher)  # a stop's call is on the wire when publish returns

    def send(self, angles: streaming.JointAngles, now: float) -> None:
        self.publisher.publish(joint_angles_message(angles, now))

    def listened(self) -> bool:
        """naoqi_driver (any node but this one, which watches the topic for other nodes' calls) subscribes."""
        return has_subscriber_other_than(self.publisher, self._own)
