"""The node's two services on ROS 2 (README: "ROS 2"): `setActivation` (cssr_system_interfaces/srv/SetActivation,
the same fields and replies as on ROS 1) and `set_enabled` (std_srvs/srv/SetBool), over core/activation.py.

A `disabled` replies once the stop's goals have left, as on ROS 1, so that a caller's next command never races
them: the services run on the executor's thread, the one the goals leave from, so once the supervisor has handed the
stop over, the service sends what was handed over, then answers (no coroutine, no extra turn of the executor)."""
from typing import Callable

from cssr_system_interfaces.srv import SetActivation
from std_srvs.srv import SetBool

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.contract import DISABLED, ENABLED, REPLY_FAILURE, REPLY_SUCCESS
from cssr_system.core.activation import Activation


class ActivationServices:
    def __init__(self, node, activation: Activation, log, run_pending: Callable[[], None],
                 callback_group=None) -> None:
        self._log = log
        self._activation = activation
        self._run_pending = run_pending
        self._services = [
            # Private names: under the node's name, in its namespace (README: "Several robots").
            node.create_service(SetActivation, "~/" + contract.SET_ACTIVATION, self.handle_set_activation,
                                callback_group=callback_group),
            node.create_service(SetBool, "~/" + contract.SET_ENABLED, self.handle_set_enabled,
                                callback_group=callback_group)]
        self._node = node

    def withdraw(self) -> None:
        """Both services go, so callers see the node gone."""
        for service in self._services:
            self._node.destroy_service(service)
        self._services = []

    def handle_set_activation(self, request, response):
        accepted, _ = self._activation.activate(request.state)
        self._run_pending()
        response.success = REPLY_SUCCESS if accepted else REPLY_FAILURE
        self._log.write(contract.ACTIVATION_REQUEST, state=request.state, reply=response.success)
        return response

    def handle_set_enabled(self, request, response):
        state = ENABLED if request.data else DISABLED
        accepted, message = self._activation.activate(state)
        self._run_pending()
        self._log.write(contract.ACTIVATION_REQUEST, state=state, reply=REPLY_SUCCESS if accepted else REPLY_FAILURE,
                        service="set_enabled")
        response.success, response.message = accepted, message
        return response
