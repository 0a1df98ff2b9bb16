"""What other programs rely on: the node's name, its service and topic names, the requests and replies
of setActivation, its private parameters, and the names of the events in its log file. The README's
"The service", "Topics, actions and services" and "Log file" sections describe them."""
from typing import Optional

NODE_NAME = "animateBehaviour"
# The node's own interfaces are private names: under the node's name, in its namespace (README: "Several robots").
SET_ACTIVATION = "setActivation"  # cssr_system/setActivation
SET_ENABLED = "set_enabled"  # std_srvs/SetBool, the ROS NAOqi wrappers' convention
ANIMATE_ACTION = "animate"  # cssr_system/Animate (README: "The animate action")
STATUS = "status"  # cssr_system/AnimateBehaviourStatus, latched
# Where they are for a node of the default name, relative to its namespace: for the programs that call it.
SERVICE_NAME = NODE_NAME + "/" + SET_ACTIVATION
SERVICE_PATH = "/" + SERVICE_NAME  # where it is when the node runs in the root namespace
SET_ENABLED_SERVICE_NAME = NODE_NAME + "/" + SET_ENABLED
ANIMATE_ACTION_NAME = NODE_NAME + "/" + ANIMATE_ACTION
STATUS_TOPIC = NODE_NAME + "/" + STATUS
DIAGNOSTICS_TOPIC = "/diagnostics"  # diagnostic_msgs/DiagnosticArray: one for the whole graph, as ROS has it
ROBOT = "pepper"  # the diagnostics' hardware id of a node at the root; in a namespace, the namespace names the robot


def interface_of(node: str, name: str) -> str:
    """The full name of the private interface `name` of the node whose resolved name is `node`."""
    return "{}/{}".format(node.rstrip("/"), name)


def robot_of(namespace: str) -> str:
    """The robot a node in `namespace` drives, for diagnostics: its namespace, or ROBOT at the root."""
    return namespace.strip("/") or ROBOT


ENABLED = "enabled"
DISABLED = "disabled"
ACCEPTED_STATES = (ENABLED, DISABLED)
REPLY_SUCCESS = "1"
REPLY_FAILURE = "0"


def parse_activation_state(requested: str) -> Optional[str]:
    """ENABLED or DISABLED for a valid request (blanks around it and letter case ignored), else None."""
    state = (requested or "").strip().lower()
    return state if state in ACCEPTED_STATES else None


# Events of animateBehaviourLogFile.log: the node writes them, the harness and the plot read them.
NODE_STARTED = "node_started"  # version, node, namespace, parameters, config_file, log_file
CONFIGURATION_LOADED = "configuration_loaded"  # file, items (every key -> value as in the file)
CONFIGURATION_INVALID = "configuration_invalid"  # file, problems
ACTIVATION_REQUEST = "activation_request"  # state (as received), reply
BEHAVIOUR_STARTED = "behaviour_started"  # behaviour, platform, parts, wheels
BEHAVIOUR_ENDED = "behaviour_ended"  # reason ("disabled", "shutdown", "reconfigured"), home
# Values of the `purpose` field of goal_sent, goal_finished and base_command.
PURPOSE_ANIMATE = "animate"  # the motion itself (goals and base turns)
PURPOSE_HOME = "home"  # after a disable: a part's return to its centre, the base's turn back to its heading at enable

GOAL_SENT = "goal_sent"  # part, label, action, purpose, joints, centre, lower, upper, moving, times, positions
GOAL_FINISHED = "goal_finished"  # part, action, purpose, goal, state, error_code, error_string, reached
# part, topic, messages, seconds: a part's /joint_angles stream (actuation joint_angles) is summed up once a second,
# since one line per message (ten or more a second per part) would drown the log.
ANGLES_SENT = "angles_sent"
CONTROLLER_CONNECTED = "controller_connected"  # part, action
CONTROLLER_WAITING = "controller_waiting"  # part, action, seconds
CONTROLLER_LOST = "controller_lost"  # part, action
BASE_COMMAND = "base_command"  # topic, kind, purpose, angle, target_heading, period, velocities
ERROR = "error"  # where, message
NODE_STOPPED = "node_stopped"  # reason
PART_YIELDED = "part_yielded"  # part, controller, caller, kind (goal, command, twist or joint_angles)
PART_RESUMED = "part_resumed"  # part, controller, caller, seconds (how long it yielded)
SETTING_CHANGED = "setting_changed"  # key, old, new, by (who asked: README "Live settings")
# mode, old, by (who or what changed it: a live setting's or the action's caller, the configuration, a source of the
# conversation), setting (the mode setting: auto, or the mode set by hand); README: "Modes"
MODE_CHANGED = "mode_changed"
ANIMATE_GOAL = "animate_goal"  # outcome (accepted: by, duration; succeeded or preempted: animated, reason)
LOG_EVENTS = (NODE_STARTED, CONFIGURATION_LOADED, CONFIGURATION_INVALID, ACTIVATION_REQUEST, BEHAVIOUR_STARTED,
              BEHAVIOUR_ENDED, GOAL_SENT, GOAL_FINISHED, ANGLES_SENT, CONTROLLER_CONNECTED, CONTROLLER_WAITING,
              CONTROLLER_LOST, BASE_COMMAND,
              PART_YIELDED, PART_RESUMED, SETTING_CHANGED, MODE_CHANGED, ANIMATE_GOAL, ERROR, NODE_STOPPED)
JOINT_STATES_TOPIC = "joint_states"  # relative: in the node's namespace (/joint_states at the root)
# Private parameters that are not overrides of configuration keys: the node's own, and dynamic_reconfigure's
# names of the live settings (live_settings.SETTING_KEYS).
# actionlib's rate of the animate action's status list, which it searches from the node's private namespace up.
STATUS_FREQUENCY_PARAMETER = "actionlib_status_frequency"
NODE_PARAMETERS = ("configFile", "logFile", "intensity", "tempo", "style", "arms", "hands", "leg", "base", "mode",
                   STATUS_FREQUENCY_PARAMETER)
