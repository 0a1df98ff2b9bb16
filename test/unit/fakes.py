"""Fakes shared by the unit tests of the streams and the supervisor: a controller client (core/goals.py) and its goal
handles, and the event log."""
from cssr_system.ros1.trajectory_client import goal_message, goal_state_name


class FakeHandle:
    """A goal sent (the ROS 1 message, as ros1/trajectory_client.py builds it), and its end when `finish` reports
    it."""

    def __init__(self, goal, done):
        self.goal = goal
        self.done = done
        self.cancelled = False

    def cancel(self):
        self.cancelled = True

    def release(self):
        self.goal.trajectory.points = []

    def finish(self, status, error_code=None, error_string=""):
        """The controller reports the goal's end: `status` an actionlib_msgs/GoalStatus value, with a result when
        `error_code` is given."""
        self.done(goal_state_name(status), error_code, error_string if error_code is not None else "")


class FakeClient:
    """A controller client: every goal sent, as a FakeHandle; `server_up` is what `ready()` says."""

    def __init__(self):
        self.handles = []
        self.server_up = True

    def ready(self):
        return self.server_up

    @staticmethod
    def goal(joints, timed):
        return goal_message(joints, timed)

    def send(self, goal, done):
        self.handles.append(FakeHandle(goal, done))
        return self.handles[-1]


class FakeLog:
    """The event log: every line written, by event."""

    def __init__(self):
        self.entries = []

    def write(self, event, **fields):
        self.entries.append((event, fields))

    def events(self, name):
        return [fields for event, fields in self.entries if event == name]


class FakeJointStates:
    """Where the joints are, as a test says (`measure(joints)`: the positions, or None when unknown); what the
    streams tell of their own motion is recorded."""

    def __init__(self, measure):
        self.measure = measure
        self.moved = []  # the joints of each motion of ours, in order
        self.settled = []  # (joints, positions) where each succeeded goal left them

    def positions(self, joints):
        return self.measure(joints)

    def moving(self, joints):
        self.moved.append(tuple(joints))

    def settle(self, joints, positions):
        self.settled.append((tuple(joints), [float(position) for position in positions]))
