"""The soak's memory tracing (doc/soak.md, `make soak TRACEMALLOC=1`): with this folder on PYTHONPATH and
CSSR_TRACEMALLOC_DIR set, the process traces its allocations from its start (10 frames each) and writes a
tracemalloc snapshot to that folder every CSSR_TRACEMALLOC_PERIOD s (default 300), so that two of them minutes apart
name the lines whose memory grows (tools/soak_snapshots.py compares them). Nothing happens without the variable."""
import os
import threading
import time
import tracemalloc


def _write_snapshots(folder: str, period: float) -> None:
    started = time.monotonic()
    while True:
        time.sleep(period)
        name = "snapshot-%06d.tracemalloc" % int(time.monotonic() - started)
        tracemalloc.take_snapshot().dump(os.path.join(folder, name))


if os.environ.get("CSSR_TRACEMALLOC_DIR"):
    tracemalloc.start(10)
    threading.Thread(target=_write_snapshots, name="tracemalloc", daemon=True,
                     args=(os.environ["CSSR_TRACEMALLOC_DIR"],
                           float(os.environ.get("CSSR_TRACEMALLOC_PERIOD", "300")))).start()
