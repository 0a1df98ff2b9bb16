"""The node's /joint_states subscription, made and ended from the joint-state switch's thread while the node's
executor spins (ros2/animate_behaviour_node.py's Subscription, core/joint_states.py's SubscriptionSwitch): the
executor survives every switch and goes on serving the node, and no callback group keeps the ended subscriptions.

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2 -q
"""
import time

import pytest

rclpy = pytest.importorskip("rclpy")

from rclpy.context import Context  # noqa: E402 (after the skips)
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402

from cssr_system.ros2.animate_behaviour_node import ExecutorThread, Subscription  # noqa: E402
from domains import claim_domain  # noqa: E402
from processes import fail_on_error, wait_until  # noqa: E402

DOMAIN = claim_domain()
SWITCHES = 600


def test_switching_the_joint_state_subscription_from_another_thread_leaves_the_executor_serving():
    context = Context()
    rclpy.init(context=context, domain_id=DOMAIN)
    node = Node("joint_state_switch_test", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    spinning = ExecutorThread(node, fail_on_error)
    spinning.spin(executor)
    try:
        publisher = node.create_publisher(JointState, "/joint_states", 10)
        ticks = []
        node.create_timer(0.001, lambda: ticks.append(publisher.publish(JointState(name=["HipPitch"],
                                                                                   position=[0.0]))))
        kept = len(node.default_callback_group.entities)
        for switch in range(SWITCHES):
            subscription = Subscription(node, JointState, "/joint_states", lambda message: None, 1, spinning.run)
            time.sleep(0.001 * (switch % 4))  # messages come in, and the executor waits on the subscription
            subscription.unregister()
        served = len(ticks)
        assert not spinning.ended(), "the executor died"
        assert wait_until(lambda: len(ticks) > served + 10, 5.0), "the executor no longer serves the node"
        assert wait_until(lambda: not list(node.subscriptions), 5.0), "every subscription ended"
        assert len(node.default_callback_group.entities) == kept
    finally:
        executor.shutdown(timeout_sec=1.0)
        node.destroy_node()
        rclpy.shutdown(context=context)
        time.sleep(0.1)
