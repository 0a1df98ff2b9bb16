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
