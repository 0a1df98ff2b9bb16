"""The /joint_angles message this package sends must be wire-compatible with the robot's naoqi_driver: the
checksum of JointAnglesWithSpeed (the real package's, or tools/naoqi_bridge_msgs where the system lacks it) must
equal that of the real naoqi_bridge_msgs (ROS 1)."""
import pytest

naoqi_bridge_msgs = pytest.importorskip("naoqi_bridge_msgs.msg", reason="source the workspace (make test does)")

# The real naoqi_bridge_msgs' checksum of JointAnglesWithSpeed: genmsg's md5 of its published definition.
REAL_CHECKSUM = "052ca11f74a00ad6745dfff6ebc2b4d8"


def test_checksum_equals_real_naoqi_bridge_msgs():
    assert naoqi_bridge_msgs.JointAnglesWithSpeed._md5sum == REAL_CHECKSUM


def test_fields_in_the_real_order_and_types():
    message = naoqi_bridge_msgs.JointAnglesWithSpeed
    assert message.__slots__ == ["header", "joint_names", "joint_angles", "speed", "relative"]
    assert message._slot_types == ["std_msgs/Header", "string[]", "float32[]", "float32", "uint8"]
