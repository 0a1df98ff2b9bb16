"""What the activation services do with a request (README: "The service"), for either front-end's `setActivation`
and `set_enabled`: they run on the ROS library's threads and only request transitions. An `enabled` is validated
here, so a reply never says "1" for a configuration that cannot be applied; the supervisor applies it."""
import threading
from typing import Callable, Tuple

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import ConfigurationError
from cssr_system.animate_behaviour.console import console
from cssr_system.animate_behaviour.contract import ACCEPTED_STATES, DISABLED, NODE_NAME, parse_activation_state
from cssr_system.core.events import Disable, Enable

SERVICE_REPLY_TIMEOUT = 0.08  # s a service waits for the supervisor to apply a request


class Activation:
    """`post`: the supervisor's queue; `log`: the event log; `configure()`: (configuration file, configuration,
    topics) as the node's parameters say now, or raises ConfigurationError; `config_file()`: the file they name."""

    def __init__(self, post: Callable[[object], None], log, configure: Callable[[], tuple],
                 config_file: Callable[[], str]) -> None:
        self._post = post
        self._log = log
        self._configure = configure
        self._config_file = config_file

    def activate(self, requested: str) -> Tuple[bool, str]:
        """Apply a request of either service: (accepted, what happened, in one line)."""
        state = parse_activation_state(requested)
        if state is None:
            message = "unknown state %r; expected one of: %s" % (requested, ", ".join(ACCEPTED_STATES))
            console.warning("%s: setActivation: %s.", NODE_NAME, message)
            return False, message
        if state == DISABLED:
            self._request(lambda done: Disable("disabled", done))
            return True, "disabled"
        try:
            config_file, config, topics = self._configure()
        except ConfigurationError as error:
            console.error("%s: not enabled: %s", NODE_NAME, error)
            self._log.write(contract.CONFIGURATION_INVALID, file=self._config_file(), problems=list(error.problems))
            return False, "not enabled: %s" % error
        # Validated: the supervisor applies it at once, and the caller need not wait (a `disabled` does wait, so a
        # caller's next command never races the stop).
        self._post(Enable(config_file, config, topics, threading.Event()))
        return True, "enabled"

    def _request(self, make_event) -> None:
        done = threading.Event()
        self._post(make_event(done))
        if not done.wait(SERVICE_REPLY_TIMEOUT):
            console.warning("%s: the request is taking longer than %.0f ms; it will still be applied.",
                            NODE_NAME, SERVICE_REPLY_TIMEOUT * 1000)
