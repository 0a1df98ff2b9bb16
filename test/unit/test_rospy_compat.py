"""The assumptions rospy_compat makes about the installed rospy and actionlib, one test each: a new version that
breaks one fails here (src/cssr_system/ros1/rospy_compat.py)."""
import inspect
from types import SimpleNamespace

import actionlib
import rospy.impl.tcpros_base
import rospy.topics
from actionlib_msgs.msg import GoalStatusArray

from cssr_system.ros1.rospy_compat import caller_of, has_subscriber_other_than, server_ready

ACTION_CLIENT_SOURCE = inspect.getsource(actionlib.ActionClient.__init__)


def test_rospy_gives_each_received_message_its_connection_header():
    source = inspect.getsource(rospy.impl.tcpros_base.TCPROSTransport.receive_once)
    assert "_connection_header = self.header" in source
    message = GoalStatusArray()
    assert caller_of(message) == ""
    message._connection_header = {"callerid": "/gestureExecution"}
    assert caller_of(message) == "/gestureExecution"


def test_an_action_client_keeps_the_last_status_and_its_topics():
    for attribute in ("self.last_status_msg", "self.pub_goal", "self.pub_cancel", "self.result_sub",
                      "self.feedback_sub"):
        assert attribute in ACTION_CLIENT_SOURCE, attribute


def test_a_publisher_knows_its_subscribers_and_a_subscriber_its_publishers():
    assert callable(rospy.topics._PublisherImpl.has_connection)
    assert "self.connections = []" in inspect.getsource(rospy.topics._TopicImpl.__init__)
    assert "self.callerid_pub" in inspect.getsource(rospy.impl.tcpros_base.TCPROSTransport.__init__)
    assert callable(rospy.topics.Subscriber.unregister)


def test_a_publishers_connections_are_named_by_their_subscribers():
    assert "if c.endpoint_id == endpoint_id" in inspect.getsource(rospy.topics._PublisherImpl.has_connection)
    assert "self.endpoint_id = endpoint_id" in inspect.getsource(rospy.impl.tcpros_base.TCPROSTransport.set_socket)


class FakeSubscriberConnection:
    def __init__(self, caller):
        self.endpoint_id = caller


def test_another_subscriber_than_ourselves():
    publisher = SimpleNamespace(impl=SimpleNamespace(connections=[]))
    assert not has_subscriber_other_than(publisher, "/animateBehaviour")
    publisher.impl.connections.append(FakeSubscriberConnection("/animateBehaviour"))
    assert not has_subscriber_other_than(publisher, "/animateBehaviour")
    publisher.impl.connections.append(FakeSubscriberConnection("/naoqi_driver"))
    assert has_subscriber_other_than(publisher, "/animateBehaviour")


def test_a_publisher_without_a_queue_size_writes_each_connection_itself():
    assert callable(rospy.topics._PublisherImpl.set_queue_size)
    adding = inspect.getsource(rospy.topics._PublisherImpl.add_connection)
    assert "if self.queue_size is not None" in adding and "QueuedConnection(" in adding


class FakeConnection:
    def __init__(self, caller):
        self.callerid_pub = caller


class FakeImpl:
    def __init__(self, callers):
        self.connections = [FakeConnection(caller) for caller in callers]

    def has_connection(self, caller):
        return any(connection.callerid_pub == caller for connection in self.connections)


class FakeTopic:
    def __init__(self, *callers):
        self.impl = FakeImpl(callers)


class FakeClient:
    def __init__(self, status_from, goal_to, cancel_to, result_from):
        self.last_status_msg = None
        if status_from:
            self.last_status_msg = GoalStatusArray()
            self.last_status_msg._connection_header = {"callerid": status_from}
        self.pub_goal, self.pub_cancel = FakeTopic(*goal_to), FakeTopic(*cancel_to)
        self.result_sub = FakeTopic(*result_from)


def test_a_server_is_ready_once_every_connection_reaches_the_one_that_sent_the_status():
    server, recorder = "/pepper_dcm/controller_manager", "/recorder"
    assert server_ready(FakeClient(server, [server], [server], [server]))
    assert not server_ready(FakeClient(None, [server], [server], [server])), "no status yet"
    assert not server_ready(FakeClient(server, [recorder], [server], [server])), "goals reach another node only"
    assert not server_ready(FakeClient(server, [server], [], [server])), "cancels reach nobody"
    assert not server_ready(FakeClient(server, [server], [server], [recorder])), "results come from another node"
