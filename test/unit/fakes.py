"""Fakes shared by the unit tests of the streams and the supervisor: an actionlib client and its goal handles, and
the event log."""
from actionlib.action_client import CommState
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import FollowJointTrajectoryResult


class FakeHandle:
    """An actionlib ClientGoalHandle: the goal sent, and its end when `finish` reports it."""

    def __init__(self, goal, callback):
        self.goal = goal
        self.callback = callback
        self.cancelled = False
        self.status = GoalStatus.ACTIVE
        self.result = None

    def cancel(self):
        self.cancelled = True

    def get_comm_state(self):
        return CommState.DONE

    def get_goal_status(self):
        return self.status

    def get_result(self):
        return self.result

    def finish(self, status, error_code=None, error_string=""):
        """What actionlib does when the server reports the goal's end (with a result when `error_code` is given)."""
        self.status = status
        if error_code is not None:
            self.result = FollowJointTrajectoryResult(error_code=error_code, error_string=error_string)
        self.callback(self)


class FakeClient:
    """An actionlib ActionClient: every goal sent, as a FakeHandle."""

    def __init__(self):
        self.handles = []

    def send_goal(self, goal, transition_cb):
        self.handles.append(FakeHandle(goal, transition_cb))
        return self.handles[-1]


class FakeLog:
    """The event log: every line written, by event."""

    def __init__(self):
        self.entries = []

    def write(self, event, **fields):
        self.entries.append((event, fields))

    def events(self, name):
        return [fields for event, fields in self.entries if event == name]
