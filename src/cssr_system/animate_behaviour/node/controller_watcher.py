"""The watcher thread: finds controllers that are not connected yet, without blocking anyone.

A missing or slow controller never blocks the service, the other parts or shutdown: the watcher polls
each missing action server briefly, posts `ControllerConnected` when one appears, and reports a
controller still missing every WAIT_REPORT_PERIOD seconds (README: "What moves, and how")."""
import threading
import time
from typing import Callable, Dict, List

import rospy

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.contract import NODE_NAME
from cssr_system.animate_behaviour.node.events import ControllerConnected

WATCH_PERIOD = 0.5  # s between checks of controllers that are not connected yet
WAIT_REPORT_PERIOD = 10.0  # s between log lines about a controller that is still missing
SERVER_PROBE_TIME = 0.05  # s one check waits for a server


class ControllerWatcher:
    def __init__(self, streams: Callable[[], List], post: Callable[[object], None], log,
                 stopped: threading.Event) -> None:
        self._streams = streams  # a snapshot of the part streams, from any thread
        self._post = post
        self._log = log
        self._stopped = stopped
        self.thread = threading.Thread(target=self.run, name="watcher", daemon=True)

    def run(self) -> None:
        started: Dict[str, float] = {}  # when each missing controller was first looked for
        last_report: Dict[str, float] = {}
        while not self._stopped.is_set() and not rospy.is_shutdown():
            for stream in self._streams():
                if stream.connected:
                    continue
                action = stream.action
                started.setdefault(action, time.monotonic())
                if stream.client.wait_for_server(rospy.Duration(SERVER_PROBE_TIME)):
                    self._post(ControllerConnected(stream.part, action))
                    continue
                waited = time.monotonic() - started[action]
                if (waited >= WAIT_REPORT_PERIOD
                        and time.monotonic() - last_report.get(action, 0.0) >= WAIT_REPORT_PERIOD):
                    last_report[action] = time.monotonic()
                    rospy.logwarn("%s: still waiting for controller %s (%.0f s); %s is skipped "
                                  "until it appears.", NODE_NAME, action, waited, stream.part)
                    self._log.write(contract.CONTROLLER_WAITING, part=stream.part, action=action,
                                    seconds=round(waited, 1))
            self._stopped.wait(WATCH_PERIOD)
