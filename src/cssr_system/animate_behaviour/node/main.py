"""The animateBehaviour program: starts the node, waits for a signal or ROS shutdown, stops the robot, exits.
"""
import signal
import sys
import time
from typing import List, Optional

import rospy

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import ConfigurationError
from cssr_system.animate_behaviour.contract import NODE_NAME
from cssr_system.animate_behaviour.node.parameters import (config_file_parameter, load_node_configuration,
                                                           parameter_overrides)
from cssr_system.animate_behaviour.node.supervisor import AnimateBehaviour


SHUTDOWN_FLUSH_TIME = 0.3  # s left for the last messages to leave before the node exits


def print_banner(version: str) -> None:
    rospy.loginfo("%s %s: makes the Pepper robot look alive with small random movements.",
                  NODE_NAME, version)
    rospy.loginfo("%s: start-up.", NODE_NAME)


def main(argv: Optional[List[str]] = None) -> int:
    argv = rospy.myargv(sys.argv if argv is None else argv)
    # The node handles SIGINT and SIGTERM itself: it stops the robot before rospy shuts down.
    rospy.init_node(NODE_NAME, disable_signals=True)
    try:
        node = AnimateBehaviour()
    except OSError as error:
        rospy.logerr("%s: cannot open the log file: %s", NODE_NAME, error)
        return 1
    print_banner(node.version)
    node.log.write(contract.NODE_STARTED, version=node.version, node=rospy.get_name(),
                   config_file=config_file_parameter(), log_file=node.log.path,
                   parameters={key: str(value) for key, value in parameter_overrides().items()},
                   arguments=argv[1:])
    try:
        config_file, config, topics = load_node_configuration()
    except ConfigurationError as error:
        print("{}: invalid configuration: {}".format(NODE_NAME, error), file=sys.stderr, flush=True)
        node.log.write(contract.CONFIGURATION_INVALID, file=config_file_parameter(),
                       problems=list(error.problems))
        rospy.signal_shutdown("invalid configuration")
        return 1
    node.start(config_file, config, topics)

    stop_reason = []
    signal.signal(signal.SIGINT, lambda number, frame: stop_reason.append("SIGINT"))
    signal.signal(signal.SIGTERM, lambda number, frame: stop_reason.append("SIGTERM"))
    while not stop_reason and not rospy.is_shutdown():
        time.sleep(0.02)
    reason = stop_reason[0] if stop_reason else "ROS shutdown"
    node.request_shutdown(reason)
    time.sleep(SHUTDOWN_FLUSH_TIME)  # let the cancel, home goals and zero twist leave
    node.log.write(contract.NODE_STOPPED, reason=reason)
    node.log.close()
    rospy.signal_shutdown(reason)
    return 0
