"""The node's two services (README: "The service"): `setActivation` (cssr_system/setActivation) and `set_enabled`
(std_srvs/SetBool). They run on rospy's service threads and only request transitions: an `enabled` is validated
here, so a reply never says "1" for a configuration that cannot be applied; the supervisor applies it."""
import threading
from typing import Callable, Tuple

import rospy
from std_srvs.srv import SetBool, SetBoolResponse

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import ConfigurationError
from cssr_system.animate_behaviour.contract import (ACCEPTED_STATES, DISABLED, ENABLED, NODE_NAME, REPLY_FAILURE,
                                                    REPLY_SUCCESS, SERVICE_NAME, SET_ENABLED_SERVICE_NAME,
                                                    parse_activation_state)
from cssr_system.animate_behaviour.node.events import Disable, Enable
from cssr_system.animate_behaviour.node.parameters import config_file_parameter, load_node_configuration
from cssr_system.srv import setActivation, setActivationResponse

SERVICE_REPLY_TIMEOUT = 0.08  # s a service waits for the supervisor to apply a request


class ActivationServices:
    def __init__(self, post: Callable[[object], None], log) -> None:
        self._post = post
        self._log = log
        self._services = []

    def withdraw(self) -> None:
        """Unregisters both services from the master at once, so callers see the node gone."""
        for service in self._services:
            service.shutdown("the node stops")

    def advertise(self) -> None:
        self._services = [rospy.Service(SERVICE_NAME, setActivation, self.handle_set_activation),
                          rospy.Service(SET_ENABLED_SERVICE_NAME, SetBool, self.handle_set_enabled)]
        rospy.loginfo("%s: service %s ready (requests: %s); %s ready.", NODE_NAME,
                      rospy.resolve_name(SERVICE_NAME), ", ".join(ACCEPTED_STATES),
                      rospy.resolve_name(SET_ENABLED_SERVICE_NAME))

    def handle_set_activation(self, request) -> setActivationResponse:
        accepted, _ = self.activate(request.state)
        reply = REPLY_SUCCESS if accepted else REPLY_FAILURE
        self._log.write(contract.ACTIVATION_REQUEST, state=request.state, reply=reply)
        return setActivationResponse(reply)

    def handle_set_enabled(self, request) -> SetBoolResponse:
        state = ENABLED if request.data else DISABLED
        accepted, message = self.activate(state)
        self._log.write(contract.ACTIVATION_REQUEST, state=state, reply=REPLY_SUCCESS if accepted else REPLY_FAILURE,
                        service="set_enabled")
        return SetBoolResponse(success=accepted, message=message)

    def activate(self, requested: str) -> Tuple[bool, str]:
        """Apply a request of either service: (accepted, what happened, in one line)."""
        state = parse_activation_state(requested)
        if state is None:
            message = "unknown state %r; expected one of: %s" % (requested, ", ".join(ACCEPTED_STATES))
            rospy.logwarn("%s: setActivation: %s.", NODE_NAME, message)
            return False, message
        if state == DISABLED:
            self._request(lambda done: Disable("disabled", done))
            return True, "disabled"
        try:
            config_file, config, topics = load_node_configuration()
        except ConfigurationError as error:
            rospy.logerr("%s: not enabled: %s", NODE_NAME, error)
            self._log.write(contract.CONFIGURATION_INVALID, file=config_file_parameter(), problems=list(error.problems))
            return False, "not enabled: %s" % error
        # Validated: the supervisor applies it at once, and the caller need not wait (a `disabled` does wait, so a
        # caller's next command never races the stop).
        self._post(Enable(config_file, config, topics, threading.Event()))
        return True, "enabled"

    def _request(self, make_event) -> None:
        done = threading.Event()
        self._post(make_event(done))
        if not done.wait(SERVICE_REPLY_TIMEOUT):
            rospy.logwarn("%s: the request is taking longer than %.0f ms; it will still be applied.",
                          NODE_NAME, SERVICE_REPLY_TIMEOUT * 1000)
