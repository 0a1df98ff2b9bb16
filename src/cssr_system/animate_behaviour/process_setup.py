"""How the node's process is set up before its first thread starts (doc/performance.md).

- **One malloc arena.** glibc's malloc gives threads arenas of their own, up to eight per core. The node's threads
  come and go (a rospy connection each, a service call each, a controller that restarts), and each new arena keeps
  the pages it has freed: over hours of use resident memory creeps up. The Python threads take turns under the
  interpreter's lock anyway, so one arena costs them nothing.
- **A short switch interval.** A thread that computes keeps the interpreter's lock for up to the switch interval
  (5 ms by default) while another waits for it: a service's reply, ready once the supervisor has sent the stop, would
  wait for the supervisor's next lines. At 1 ms the reply leaves within about a millisecond."""
import ctypes
import sys

M_ARENA_MAX = -8  # glibc's malloc.h
SWITCH_INTERVAL = 0.001  # s


def use_one_malloc_arena() -> bool:
    """Whether malloc now keeps to one arena (False where the C library has no mallopt, or refuses)."""
    try:
        return bool(ctypes.CDLL(None).mallopt(M_ARENA_MAX, 1))
    except (OSError, AttributeError):
        return False


def set_up_process() -> None:
    use_one_malloc_arena()
    sys.setswitchinterval(SWITCH_INTERVAL)
