"""How the node's process is set up before its first thread starts (doc/performance.md).

- **One malloc arena.** glibc's malloc gives threads arenas of their own, up to eight per core. The node's threads
  come and go (a rospy connection each, a service call each, a controller that restarts), and each new arena keeps
  the pages it has freed: over hours of use resident memory creeps up. The Python threads take turns under the
  interpreter's lock anyway, so one arena costs them nothing.
- **Free pages handed back.** A heap keeps the pages freed in its middle (the messages, goals and log lines of the
  moment land in new places as the node works), so resident memory would only grow, by steps. Once a minute the
  main thread has malloc hand them back (`MemoryReturn`): a millisecond or two.
- **A short switch interval.** A thread that computes keeps the interpreter's lock for up to the switch interval
  (5 ms by default) while another waits for it: a service's reply, ready once the supervisor has sent the stop, would
  wait for the supervisor's next lines. At 1 ms the reply leaves within about a millisecond."""
import ctypes
import sys
import time
from typing import Callable

from cssr_system.animate_behaviour.periodic import Periodic

M_ARENA_MAX = -8  # glibc's malloc.h
SWITCH_INTERVAL = 0.001  # s
MEMORY_RETURN_PERIOD = 60.0  # s


def use_one_malloc_arena() -> bool:
    """Whether malloc now keeps to one arena (False where the C library has no mallopt, or refuses)."""
    try:
        return bool(ctypes.CDLL(None).mallopt(M_ARENA_MAX, 1))
    except (OSError, AttributeError):
        return False


def set_up_process() -> None:
    use_one_malloc_arena()
    sys.setswitchinterval(SWITCH_INTERVAL)


def return_free_memory() -> None:
    """malloc hands the whole pages it holds free back to the system (glibc's malloc_trim; nothing elsewhere)."""
    try:
        ctypes.CDLL(None).malloc_trim(0)
    except (OSError, AttributeError):
        pass


class MemoryReturn(Periodic):
    """`tick()` from the main loop: return_free_memory every MEMORY_RETURN_PERIOD s."""

    def __init__(self, clock: Callable[[], float] = time.monotonic,
                 return_memory: Callable[[], None] = return_free_memory) -> None:
        super().__init__(clock, MEMORY_RETURN_PERIOD, return_memory)
