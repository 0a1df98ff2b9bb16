"""What the ROS 2 graph says about a topic's publishers and subscribers."""


def endpoint_names(infos) -> set:
    """Fully qualified node names of a topic's publishers or subscribers (rclpy's endpoint infos)."""
    return {"%s/%s" % (info.node_namespace.rstrip("/"), info.node_name) for info in infos}


def subscribed_by_another_node(node, topic: str) -> bool:
    """Whether a node other than `node` subscribes to `topic`: the robot's driver or a simulator. The node's own
    subscription (its watch of the topic for other nodes' commands) does not count."""
    return bool(endpoint_names(node.get_subscriptions_info_by_topic(topic)) - {node.get_fully_qualified_name()})
