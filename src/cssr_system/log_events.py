"""Names of the events in animateBehaviourLogFile.log: the node writes them, the test harness and
the plotting tool read them. The README's log-format section lists them with their fields."""

NODE_STARTED = "node_started"  # version, node, parameters, config_file, log_file
CONFIGURATION_LOADED = "configuration_loaded"  # file, items (every key -> value as in the file)
CONFIGURATION_INVALID = "configuration_invalid"  # file, problems
ACTIVATION_REQUEST = "activation_request"  # state (as received), reply
BEHAVIOUR_STARTED = "behaviour_started"  # behaviour, platform, parts, wheels
BEHAVIOUR_ENDED = "behaviour_ended"  # reason ("disabled", "shutdown", "reconfigured"), home
# Values of the `purpose` field of goal_sent, goal_finished and base_command.
PURPOSE_ANIMATE = "animate"  # random motion (goals and base turns)
PURPOSE_HOME = "home"  # a part's return to its centre after disable
PURPOSE_RETURN = "return"  # the base's turn back to its heading at enable

GOAL_SENT = "goal_sent"  # part, label, action, purpose, joints, centre, lower, upper, moving, times, positions
GOAL_FINISHED = "goal_finished"  # part, action, purpose, goal, state, error_code, error_string
CONTROLLER_CONNECTED = "controller_connected"  # part, action
CONTROLLER_WAITING = "controller_waiting"  # part, action, seconds
BASE_COMMAND = "base_command"  # topic, kind, purpose, angle, target_heading, period, velocities
ERROR = "error"  # where, message
NODE_STOPPED = "node_stopped"  # reason
