"""The node's two services on ROS 1 (README: "The service"): `setActivation` (cssr_system/setActivation) and
`set_enabled` (std_srvs/SetBool), over core/activation.py."""
from typing import Callable

import rospy
from std_srvs.srv import SetBool, SetBoolResponse

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.contract import (ACCEPTED_STATES, DISABLED, ENABLED, NODE_NAME, REPLY_FAILURE,
                                                    REPLY_SUCCESS, SET_ACTIVATION, SET_ENABLED)
from cssr_system.core.activation import Activation
from cssr_system.ros1.parameters import config_file_parameter, load_node_configuration
from cssr_system.srv import setActivation, setActivationResponse


class ActivationServices:
    def __init__(self, post: Callable[[object], None], log) -> None:
        self._log = log
        self._activation = Activation(post, log, load_node_configuration, config_file_parameter)
        self._services = []

    def withdraw(self) -> None:
        """Unregisters both services from the master at once, so callers see the node gone."""
        for service in self._services:
            service.shutdown("the node stops")

    def advertise(self) -> None:
        # Private names: under the node's name, in its namespace (README: "Several robots").
        self._services = [rospy.Service("~" + SET_ACTIVATION, setActivation, self.handle_set_activation),
                          rospy.Service("~" + SET_ENABLED, SetBool, self.handle_set_enabled)]
        rospy.loginfo("%s: service %s ready (requests: %s); %s ready.", NODE_NAME,
                      rospy.resolve_name("~" + SET_ACTIVATION), ", ".join(ACCEPTED_STATES),
                      rospy.resolve_name("~" + SET_ENABLED))

    def handle_set_activation(self, request) -> setActivationResponse:
        accepted, _ = self._activation.activate(request.state)
        reply = REPLY_SUCCESS if accepted else REPLY_FAILURE
        self._log.write(contract.ACTIVATION_REQUEST, state=request.state, reply=reply)
        return setActivationResponse(reply)

    def handle_set_enabled(self, request) -> SetBoolResponse:
        state = ENABLED if request.data else DISABLED
        accepted, message = self._activation.activate(state)
        self._log.write(contract.ACTIVATION_REQUEST, state=state, reply=REPLY_SUCCESS if accepted else REPLY_FAILURE,
                        service="set_enabled")
        return SetBoolResponse(success=accepted, message=message)
