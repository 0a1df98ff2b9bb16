"""What the activation services do with a request (README: "The service"), for either front-end's `setActivation`
and `set_enabled`: they run on the ROS library's threads and only request transitions. An `enabled` is validated
here, so a reply never says "1" for a configuration that cannot be applied; the supervisor applies it."""
import threading
import time
from typing import Callable, Tuple

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import ConfigurationError
from cssr_system.animate_behaviour.console import console
from cssr_system.animate_behaviour.contract import ACCEPTED_STATES, DISABLED, NODE_NAME, parse_activation_state
from cssr_system.core.events import Disable, Enable

# A `disabled` replies once the supervisor has sent the stop, so that a caller's next goal reaches the controllers
# after it. The supervisor never waits for I/O, so only a busy machine delays it: the console names a stop slower
# than SLOW_STOP, and a supervisor that has not sent it within STOP_REPLY_LIMIT (a hung one) no longer holds the reply.
SLOW_STOP = 0.08  # s
STOP_REPLY_LIMIT = 0.5  # s


class Activation:
    """`post`: the supervisor's queue; `log`: the event log; `configure()`: (configuration file, configuration,
    topics) as the node's parameters say now, or raises ConfigurationError; `config_file()`: the file they name."""

    def __init__(self, post: Callable[[object], None], log, configure: Callable[[], tuple],
                 config_file: Callable[[], str], stop_reply_limit: float = STOP_REPLY_LIMIT) -> None:
        self._post = post
        self._stop_reply_limit = stop_reply_limit
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

    def stop(self, reason: str, by: str) -> None:
        """Stops as a `disabled` does, for `by` (another service: the successor's stop), giving `reason`."""
        self._request(lambda done: Disable(reason, done, by))

    def _request(self, make_event) -> None:
        done = threading.Event()
        started = time.monotonic()
        self._post(make_event(done))
        if not done.wait(self._stop_reply_limit):
            console.warning("%s: the stop has not been sent within %.0f ms; replying now, it will still be applied.",
                            NODE_NAME, self._stop_reply_limit * 1000)
            return
        waited = time.monotonic() - started
        if waited > SLOW_STOP:
            console.warning("%s: the stop took %.0f ms to be sent (more than %.0f ms: a busy machine).", NODE_NAME,
                            waited * 1000, SLOW_STOP * 1000)
