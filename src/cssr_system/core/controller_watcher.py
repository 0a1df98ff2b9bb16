"""The watcher thread: follows which controllers are there, without blocking anyone.

A missing or slow controller never blocks the service, the other parts or shutdown: twice a second, and at
once when a status message comes from a controller not yet connected (so a node enabled as soon as it starts
sends its first goals within a status period of the controllers appearing), the watcher checks each
controller's action server once (no waiting), posts `ControllerConnected` when one appears and
`ControllerLost` when one goes away (a controller spawner restarting it), and reports a controller still missing
every WAIT_REPORT_PERIOD seconds (README: "What moves, and how")."""
import threading
import time
from typing import Callable, Dict, List, Set

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.console import console
from cssr_system.animate_behaviour.contract import NODE_NAME
from cssr_system.core.events import ControllerConnected, ControllerLost

WATCH_PERIOD = 0.5  # s between checks of the controllers
WAIT_REPORT_PERIOD = 10.0  # s between log lines about a controller that is still missing


class ControllerWatcher:
    def __init__(self, streams: Callable[[], List], post: Callable[[object], None], log,
                 stopped: threading.Event, report_error: Callable[[str, Exception], None]) -> None:
        self._streams = streams  # a snapshot of the part streams, from any thread
        self._post = post
        self._log = log
        self._stopped = stopped
        self._report_error = report_error
        self._missing_since: Dict[str, float] = {}  # when each missing controller was first looked for
        self._last_report: Dict[str, float] = {}
        self._ready: Set[str] = set()  # the controllers found ready at the last check
        self._wake = threading.Event()
        self.thread = threading.Thread(target=self.run, name="watcher", daemon=True)

    def status_seen(self, action: str) -> None:
        """A status message came from `action`'s server (any thread): check now if it was not ready."""
        if action not in self._ready:
            self._wake.set()

    def run(self) -> None:
        while not self._stopped.is_set():
            try:
                self.check()
            except Exception as error:  # the watcher goes on: a missed check is made again in WATCH_PERIOD
                self._report_error("watcher", error)
            self._wake.wait(WATCH_PERIOD)
            self._wake.clear()

    def check(self) -> None:
        for stream in self._streams():
            action = stream.action
            ready = stream.controller_ready()
            (self._ready.add if ready else self._ready.discard)(action)
            if ready and not stream.connected:
                self._post(ControllerConnected(stream.part, action))
            elif not ready and stream.connected:
                self._post(ControllerLost(stream.part, action))
            if ready:
                self._missing_since.pop(action, None)
                continue
            waited = time.monotonic() - self._missing_since.setdefault(action, time.monotonic())
            if (waited >= WAIT_REPORT_PERIOD
                    and time.monotonic() - self._last_report.get(action, 0.0) >= WAIT_REPORT_PERIOD):
                self._last_report[action] = time.monotonic()
                controller = getattr(stream, "controller", action)  # a joint-angle stream's topic
                console.warning("%s: still waiting for controller %s (%.0f s); %s is skipped "
                                "until it appears.", NODE_NAME, controller, waited, stream.part)
                self._log.write(contract.CONTROLLER_WAITING, part=stream.part, action=controller,
                                seconds=round(waited, 1))
