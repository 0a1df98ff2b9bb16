"""How the node reports what goes wrong while it runs (README: "Faults"), on either ROS: one console line and one
`error` line in the event log, and the thread that met it goes on."""
from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.console import console
from cssr_system.animate_behaviour.contract import NODE_NAME


class Problems:
    def __init__(self, log) -> None:
        self._log = log

    def error(self, where: str, error: Exception) -> None:
        """An unexpected error in a thread of the node."""
        console.error("%s: %s: %s: %s", NODE_NAME, where, type(error).__name__, error)
        self._log.write(contract.ERROR, where=where, message="{}: {}".format(type(error).__name__, error))

    def bad_input(self, where: str, text: str) -> None:
        """Bad input from outside."""
        console.warning("%s: %s", NODE_NAME, text)
        self._log.write(contract.ERROR, where=where, message=text)
