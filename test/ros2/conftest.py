"""Fixtures of the ROS 2 tests (rclpy is imported where used: without it, each test module skips itself)."""
import pytest

from domains import claim_domain


@pytest.fixture
def node(request):
    """An rclpy node of a context of its own, on a domain of its own, named after the test; its executor, if it was
    given one, is shut down after the test."""
    from rclpy import init, shutdown
    from rclpy.context import Context
    from rclpy.node import Node
    context = Context()
    init(context=context, domain_id=claim_domain())
    made = Node(request.node.name.split("[")[0][:60], context=context)
    yield made
    if made.executor is not None:
        made.executor.shutdown(timeout_sec=1.0)
    made.destroy_node()
    shutdown(context=context)
