"""animate_behaviour/process_setup.py: after use_one_malloc_arena, threads that allocate share malloc's one arena
(glibc's malloc_stats counts them), where without it they get arenas of their own; and a thread waiting for the
interpreter while another computes gets it within the short switch interval; and malloc's free pages are handed
back to the system, once a minute from the main loop."""
import subprocess
import sys
from pathlib import Path

import pytest

from cssr_system.animate_behaviour.process_setup import MEMORY_RETURN_PERIOD, MemoryReturn

SOURCE = Path(__file__).resolve().parents[2] / "src"
# Four threads that each hold blocks too big for Python's own allocator, then malloc_stats (to stderr).
PROGRAM = """
import ctypes, sys, threading
sys.path.insert(0, %r)
from cssr_system.animate_behaviour.process_setup import use_one_malloc_arena
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


WAKE_PROGRAM = """
import sys, threading, time
sys.path.insert(0, %r)
from cssr_system.animate_behaviour.process_setup import set_up_process
if sys.argv[1] == "set up":
    set_up_process()
delays = []
for _ in range(40):
    ready, woke = threading.Event(), []
    waiter = threading.Thread(target=lambda: (ready.wait(), woke.append(time.perf_counter())))
    waiter.start()
    time.sleep(0.002)
    set_at = time.perf_counter()
    ready.set()
    while time.perf_counter() < set_at + 0.012:  # computes on, as the supervisor does after a reply is ready
        pass
    waiter.join()
    delays.append(woke[0] - set_at)
print(min(delays))  # the least: the interpreter's own hand-over, without the machine's scheduling
""" % str(SOURCE)


def least_wake_delay(mode: str) -> float:
    finished = subprocess.run([sys.executable, "-c", WAKE_PROGRAM, mode], stdout=subprocess.PIPE,
                              universal_newlines=True, timeout=30, check=True)
    return float(finished.stdout)


def test_a_thread_woken_while_another_computes_runs_sooner_after_the_set_up():
    """About 1 ms against 5 here; the least of 40 wakes, as a busy machine (`make test` runs its lanes side by side)
    adds its own waits to any one of them."""
    assert least_wake_delay("set up") < 0.6 * least_wake_delay("default")


RETURN_PROGRAM = """
import random, sys
sys.path.insert(0, %r)
from cssr_system.animate_behaviour.process_setup import return_free_memory
def resident():
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[1])
blocks = [bytearray(random.randint(600, 60000)) for _ in range(2000)]
del blocks[::2]  # holes in the heap's middle, which malloc keeps
before = resident()
return_free_memory()
print(before, resident())
""" % str(SOURCE)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc's malloc")
def test_free_pages_in_the_heap_go_back_to_the_system():
    finished = subprocess.run([sys.executable, "-c", RETURN_PROGRAM], stdout=subprocess.PIPE,
                              universal_newlines=True, timeout=30, check=True)
    before, after = map(int, finished.stdout.split())
    assert after < before - 1000  # pages: about 30 MB of holes, 4 MB at the very least


def test_memory_goes_back_once_a_period_from_the_main_loop():
    now, returned = [100.0], []
    memory = MemoryReturn(lambda: now[0], lambda: returned.append(now[0]))
    for _ in range(3 * int(MEMORY_RETURN_PERIOD)):
        now[0] += 1.0
        memory.tick()
    assert returned == [100.0 + MEMORY_RETURN_PERIOD * k for k in (1, 2, 3)]
