"""What the ROS 2 graph says about the topics the node publishes on."""


def subscribed_by_another_node(node, topic: str) -> bool:
    """Whether a node other than `node` subscribes to `topic`: the robot's driver or a simulator. The node's own
    subscription (its watch of the topic for other nodes' commands) does not count."""
    own = node.get_fully_qualified_name()
    return any("%s/%s" % (info.node_namespace.rstrip("/"), info.node_name) != own
               for info in node.get_subscriptions_info_by_topic(topic))
