"""The node's services on ROS 2 (README: "ROS 2"): `setActivation` (cssr_system_interfaces/srv/SetActivation,
the same fields and replies as on ROS 1) and `set_enabled` (std_srvs/srv/SetBool), over core/activation.py; and the
successor system's `animate_behavior/stop` (std_srvs/srv/Trigger, README: "With the successor's behaviour tree"),
which stops as a `disabled` does and answers success.

A `disabled` replies once the stop's goals have left, as on ROS 1, so that a caller's next command never races
them: the services run on the executor's thread, the one the goals leave from, so once the supervisor has handed the
stop over, the service sends what was handed over, then answers (no coroutine, no extra turn of the executor)."""
from typing import Callable

from cssr_system_interfaces.srv import SetActivation
from std_srvs.srv import SetBool, Trigger

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.contract import DISABLED, ENABLED, REPLY_FAILURE, REPLY_SUCCESS
from cssr_system.core.activation import Activation
from cssr_system.core.session import STOPPED

STOP_SERVICE = "animate_behavior/stop"  # the successor's: relative, in the node's namespace


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
                                callback_group=callback_group),
            node.create_service(Trigger, STOP_SERVICE, self.handle_stop, callback_group=callback_group)]
        self._node = node
        self.stop_service = node.resolve_service_name(STOP_SERVICE)

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

    def handle_stop(self, request, response):
        self._activation.stop(STOPPED, self.stop_service)
        self._run_pending()
        response.success, response.message = True, "stopped"
        self._log.write(contract.ACTIVATION_REQUEST, state=DISABLED, reply=REPLY_SUCCESS, service=self.stop_service)
        return response
