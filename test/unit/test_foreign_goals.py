"""Unit tests of the core's view of other clients' goals (core/foreign_goals.py), shared by both ROS's watches."""
from cssr_system.core.events import ForeignGoal, ForeignResult
from cssr_system.core.foreign_goals import ForeignGoals

ACTION = "/pepper_dcm/RightArm_controller/follow_joint_trajectory"


def test_a_goal_is_posted_when_first_seen_running_and_its_end_once():
    posted, named = [], []
    goals = ForeignGoals(posted.append)

    def caller_of(goal_id):
        named.append(goal_id)
        return "/gestureExecution"

    goals.status_list(ACTION, [("g1", True), ("g0", False)], caller_of)  # g0 ended before it was seen running
    goals.status_list(ACTION, [("g1", True)], caller_of)  # the same list again, as a server repeats it
    assert posted == [ForeignGoal(ACTION, "g1", "/gestureExecution", None)] and named == ["g1"]
    goals.status_list(ACTION, [("g1", False)], caller_of)
    goals.status_list(ACTION, [("g1", False)], caller_of)
    assert posted[1:] == [ForeignResult(ACTION, "g1")]


def test_a_running_goal_gone_from_the_list_has_ended_and_actions_are_apart():
    posted = []
    goals = ForeignGoals(posted.append)
    goals.status_list(ACTION, [("g1", True)], lambda goal_id: "a client")
    goals.status_list("/other/follow_joint_trajectory", [], lambda goal_id: "a client")
    assert posted == [ForeignGoal(ACTION, "g1", "a client", None)]
    goals.status_list(ACTION, [], lambda goal_id: "a client")
    assert posted[1:] == [ForeignResult(ACTION, "g1")]


def test_a_goal_that_began_and_ended_between_two_lists_is_told_as_both_but_not_in_the_first_list():
    posted = []
    goals = ForeignGoals(posted.append)
    goals.status_list(ACTION, [("old", False)], lambda goal_id: "a client")  # before the node's time: no news
    goals.status_list(ACTION, [("old", False), ("hand", False)], lambda goal_id: "a client")
    assert posted == [ForeignGoal(ACTION, "hand", "a client", None), ForeignResult(ACTION, "hand")]
    assert goals.started(ACTION) == 1


def test_the_last_look_sends_only_while_no_other_clients_goal_runs_or_came_since_the_decision():
    posted, sent = [], []
    goals = ForeignGoals(posted.append)
    send = lambda: sent.append("ours")  # noqa: E731
    assert goals.send_unless_foreign(ACTION, send, goals.started(ACTION)) is None and sent == ["ours"]
    decided = goals.started(ACTION)
    goals.status_list(ACTION, [("g1", True)], lambda goal_id: "a client")
    assert goals.send_unless_foreign(ACTION, send, decided) == "g1" and sent == ["ours"]
    assert goals.send_unless_foreign("/other/follow_joint_trajectory", send) is None, "other actions are apart"
    goals.status_list(ACTION, [("g1", False)], lambda goal_id: "a client")
    assert goals.send_unless_foreign(ACTION, send, decided) == "g1", "it came after the send was decided"
    assert goals.send_unless_foreign(ACTION, send, goals.started(ACTION)) is None
    assert sent == ["ours", "ours", "ours"]


def test_a_status_list_that_comes_during_a_send_waits_until_the_goal_has_left():
    """The check and the send are one step for the status callback: a list handed over meanwhile (another thread,
    as rospy's) is applied after the send, and the next look sees it."""
    import threading
    goals, order = ForeignGoals(lambda event: order.append(type(event).__name__)), []
    sending, listed = threading.Event(), threading.Event()

    def send():
        sending.set()
        assert not listed.wait(0.2), "the list was applied in the middle of the send"
        order.append("sent")

    def status():
        sending.wait(5.0)
        goals.status_list(ACTION, [("g1", True)], lambda goal_id: "a client")
        listed.set()
    thread = threading.Thread(target=status)
    thread.start()
    assert goals.send_unless_foreign(ACTION, send) is None
    thread.join(5.0)
    assert order == ["sent", "ForeignGoal"]
    assert goals.send_unless_foreign(ACTION, lambda: order.append("sent again")) == "g1"


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def test_a_goal_told_on_its_way_runs_at_once_and_ends_with_the_list_that_shows_its_end():
    posted, clock = [], Clock()
    goals = ForeignGoals(posted.append, clock)
    goals.goal_sent(ACTION, "g1", lambda goal_id: "/gestureExecution")
    assert posted == [ForeignGoal(ACTION, "g1", "/gestureExecution", None)]
    assert goals.send_unless_foreign(ACTION, lambda: posted.append("sent")) == "g1", "the last look sees it"
    clock.now += 0.01
    goals.status_list(ACTION, [], lambda goal_id: "a client")  # a list made before the server took it
    goals.status_list(ACTION, [("g1", True)], lambda goal_id: "a client")  # then listed: no second start
    goals.goal_sent(ACTION, "g1", lambda goal_id: "a client")  # the same goal again (a latched topic, say)
    assert posted == [ForeignGoal(ACTION, "g1", "/gestureExecution", None)]
    goals.status_list(ACTION, [("g1", False)], lambda goal_id: "a client")
    assert posted[1:] == [ForeignResult(ACTION, "g1")]
    assert goals.send_unless_foreign(ACTION, lambda: posted.append("sent")) is None and posted[-1] == "sent"


def test_a_goal_told_on_its_way_that_no_list_names_within_the_grace_has_ended():
    from cssr_system.core.foreign_goals import UNLISTED_GRACE
    posted, clock = [], Clock()
    goals = ForeignGoals(posted.append, clock)
    goals.goal_sent(ACTION, "g1", lambda goal_id: "a client")
    clock.now += UNLISTED_GRACE - 0.01
    goals.status_list(ACTION, [], lambda goal_id: "a client")
    assert posted == [ForeignGoal(ACTION, "g1", "a client", None)]
    clock.now += 0.02
    goals.status_list(ACTION, [], lambda goal_id: "a client")
    assert posted[1:] == [ForeignResult(ACTION, "g1")]


def test_a_goal_already_listed_or_without_an_id_is_not_told_again_on_its_way():
    posted = []
    goals = ForeignGoals(posted.append, Clock())
    goals.status_list(ACTION, [("g1", False)], lambda goal_id: "a client")  # the first list: old news
    goals.goal_sent(ACTION, "g1", lambda goal_id: "a client")
    goals.goal_sent(ACTION, "", lambda goal_id: "a client")
    assert posted == []
