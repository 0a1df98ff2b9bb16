"""animate_behaviour/malloc_arenas.py: after use_one_malloc_arena, threads that allocate share malloc's one arena
(glibc's malloc_stats counts them); without it, they get arenas of their own."""
import subprocess
import sys
from pathlib import Path

import pytest

SOURCE = Path(__file__).resolve().parents[2] / "src"
# Four threads that each hold blocks too big for Python's own allocator, then malloc_stats (to stderr).
PROGRAM = """
import ctypes, sys, threading
sys.path.insert(0, %r)
from cssr_system.animate_behaviour.malloc_arenas import use_one_malloc_arena
if sys.argv[1] == "one":
    assert use_one_malloc_arena()
barrier = threading.Barrier(4)
def allocate():
    blocks = [bytearray(4096) for _ in range(200)]
    barrier.wait()  # all four threads allocate at once, each holding its blocks
threads = [threading.Thread(target=allocate) for _ in range(4)]
[thread.start() for thread in threads]
[thread.join() for thread in threads]
ctypes.CDLL(None).malloc_stats()
""" % str(SOURCE)


def arenas(mode: str) -> int:
    finished = subprocess.run([sys.executable, "-c", PROGRAM, mode], stderr=subprocess.PIPE,
                              universal_newlines=True, timeout=30, check=True)
    return sum(1 for line in finished.stderr.splitlines() if line.startswith("Arena "))


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc's malloc")
def test_threads_share_one_arena_once_asked():
    assert arenas("many") > 1  # the check can tell
    assert arenas("one") == 1
