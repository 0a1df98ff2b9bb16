"""One malloc arena for the node's process (README: "Performance").

glibc's malloc gives threads arenas of their own, up to eight per core. The node's threads come and go (a rospy
connection each, a service call each, a controller that restarts), and each new arena keeps the pages it has freed:
over hours of use the node's resident memory creeps up. Its Python threads take turns under the interpreter's lock
anyway, so one arena costs them nothing. Asked for before the first thread starts."""
import ctypes

M_ARENA_MAX = -8  # glibc's malloc.h


def use_one_malloc_arena() -> bool:
    """Whether malloc now keeps to one arena (False where the C library has no mallopt, or refuses)."""
    try:
        return bool(ctypes.CDLL(None).mallopt(M_ARENA_MAX, 1))
    except (OSError, AttributeError):
        return False
