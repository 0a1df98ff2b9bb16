"""The only place where the node relies on more of rospy and actionlib than their documented calls.

Each function says why the node needs it; test/unit/test_rospy_compat.py checks every assumption it makes about
the installed rospy and actionlib, so that a new version that breaks one fails a test instead of the robot.
test/unit/test_private_access.py keeps such access out of every other module.
"""
from typing import Any

import rospy


def caller_of(message: Any) -> str:
    """The caller id of the node that published a received message ("" when unknown).

    Another node's motion is told apart from ours by its publisher; rospy gives a received message the connection
    header it came with, whose "callerid" names that node (rospy's documented way to learn a message's sender)."""
    header = getattr(message, "_connection_header", None) or {}
    return header.get("callerid", "")


def caller_of_goal(goal_id: str) -> str:
    """The node that sent an action goal, from its id: actionlib's clients make ids ``<node name>-<number>-<time>``
    (an action server's status lists goals by id alone)."""
    parts = goal_id.rsplit("-", 2)
    return parts[0] if len(parts) == 3 and parts[0] else goal_id


def server_ready(client) -> bool:
    """actionlib's own test in ``ActionClient.wait_for_server``, made once without waiting.

    wait_for_server sleeps on ROS time, so a simulation clock that stands still would hold the caller; the node must
    never block. The test: a status message came from the server, our goal and cancel topics reach that server, and
    its result topic reaches us, so that a goal sent now is neither lost nor left without its result."""
    status = client.last_status_msg
    if status is None:
        return False
    server = caller_of(status)
    return (client.pub_goal.impl.has_connection(server) and client.pub_cancel.impl.has_connection(server)
            and any(connection.callerid_pub == server for connection in client.result_sub.impl.connections))


def ignore_feedback(client) -> None:
    """Stops an ActionClient receiving its server's feedback, which the node does not use: a controller publishes
    it for every active goal at its state rate, and each message would wake and cost the node a decode."""
    client.feedback_sub.unregister()


def write_at_once(publisher) -> None:
    """Makes `publisher.publish` write to every subscriber before it returns, instead of handing the message to a
    writer thread per subscriber (what rospy does for a publisher made with a queue size, as actionlib makes its
    goal and cancel publishers). A stop is then on the wire when the node goes on to exit, and the node keeps no
    thread per connection. Call it before the publisher's first connection: rospy wraps each new connection as the
    queue size says at that moment."""
    publisher.impl.set_queue_size(None)


def has_subscriber_other_than(publisher, caller_id: str) -> bool:
    """Whether a node other than `caller_id` is connected to `publisher`.

    The node subscribes to the JointAngles topic it publishes on (to notice other nodes' calls), so the subscriber
    count alone would find naoqi_driver even where none runs. rospy names each subscriber connection of a publisher
    by the subscriber's caller id (the ``endpoint_id`` that `has_connection` compares)."""
    return any(connection.endpoint_id != caller_id for connection in list(publisher.impl.connections))


def quiet_at_shutdown(callback, event) -> None:
    """A timer's `callback`; publishing to a closed topic is expected only at shutdown, and then ignored."""
    try:
        callback(event)
    except rospy.ROSException:
        if not rospy.core.is_shutdown_requested():
            raise
