"""naoqi_driver2's JointAngles topic on ROS 2: the node's one publisher of it, shared by the joint-angle streams
(core/joint_angle_stream.py), each of whose setAngles calls becomes one naoqi_bridge_msgs/msg/JointAnglesWithSpeed."""
from typing import Tuple

import numpy
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed

from cssr_system.motion import joint_angle_stream as streaming
from cssr_system.ros2.rclpy_compat import subscribed_by_another_node
from cssr_system.ros2.rclpy_compat import OwnMessages
from cssr_system.ros2.time_conversion import time_message

QUEUE_DEPTH = 10  # naoqi_driver queues ten messages of the topic


def joint_angles_key(names, angles, speed: float) -> Tuple:
    """What tells one call from another once it has crossed the wire (the angles and speed travel as float32)."""
    return (tuple(names), tuple(numpy.float32(angles).tolist()), float(numpy.float32(speed)))


class JointAnglesTopic:
    """`own`: the messages this node sent, which its watch of the topic must not take for another node's."""

    def __init__(self, node, name: str, own: OwnMessages) -> None:
        self.name = name
        self._node = node
        self._own = own
        self.publisher = node.create_publisher(JointAnglesWithSpeed, name, QUEUE_DEPTH)

    def send(self, angles: streaming.JointAngles, now: float) -> None:
        message = JointAnglesWithSpeed(joint_names=list(angles.joint_names),
                                       joint_angles=[float(value) for value in angles.joint_angles],
                                       speed=float(angles.speed), relative=int(angles.relative))
        message.header.stamp = time_message(now)
        self._own.sent(joint_angles_key(message.joint_names, message.joint_angles, message.speed))
        self.publisher.publish(message)

    def listened(self) -> bool:
        """naoqi_driver2 (any node but this one, which watches the topic for other nodes' calls) subscribes."""
        return subscribed_by_another_node(self._node, self.name)
