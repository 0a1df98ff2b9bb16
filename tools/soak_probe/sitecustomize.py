"""The soak's probe of the node's process (doc/soak.md): `make soak` starts the node with this folder on PYTHONPATH.

- With CSSR_SOAK_HEAP_FILE set, every CSSR_SOAK_HEAP_PERIOD s (default 10) the process writes to that file (replaced
  whole, so a reader never sees half of it) what its allocators hold: malloc's bytes in use and its free bytes kept
  (glibc's mallinfo2, mallinfo before glibc 2.33) and Python's allocated blocks. Resident memory that grows while
  these stay flat is memory the allocators keep, not memory the node holds.
- With CSSR_TRACEMALLOC_DIR set, it traces its allocations from its start (10 frames each) and writes a tracemalloc
  snapshot to that folder every CSSR_TRACEMALLOC_PERIOD s (default 300), so that two of them minutes apart name the
  lines whose memory grows (tools/soak_snapshots.py compares them).

Nothing happens without the variables."""
import ctypes
import ctypes.util
import json
import os
import sys
import threading
import time
import tracemalloc


def malloc_info():
    """glibc's mallinfo2 (size_t fields), or mallinfo (int fields) before 2.33; None without glibc."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
    except OSError:
        return None
    field = ctypes.c_size_t if hasattr(libc, "mallinfo2") else ctypes.c_int

    class MallInfo(ctypes.Structure):
        _fields_ = [(name, field) for name in ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks",
                                               "uordblks", "fordblks", "keepcost")]
    function = libc.mallinfo2 if hasattr(libc, "mallinfo2") else getattr(libc, "mallinfo", None)
    if function is None:
        return None
    function.restype = MallInfo
    return function


def malloc_bytes(mallinfo):
    """Bytes in use and free bytes kept, from `mallinfo` (malloc_info()'s): in use, the arenas' allocated chunks and
    the chunks malloc mapped on their own; free, what the arenas keep without handing it back to the system."""
    info = mallinfo()
    return info.uordblks + info.hblkhd, info.fordblks


def _write_heap(path: str, period: float) -> None:
    mallinfo = malloc_info()
    while True:
        figures = {"python blocks": sys.getallocatedblocks()}
        if mallinfo is not None:
            in_use, free = malloc_bytes(mallinfo)
            figures.update({"malloc in use": in_use / 1e6, "malloc free": free / 1e6})
        with open(path + ".new", "w") as stream:
            json.dump(figures, stream)
        os.replace(path + ".new", path)
        time.sleep(period)


def _write_snapshots(folder: str, period: float) -> None:
    started = time.monotonic()
    while True:
        time.sleep(period)
        name = "snapshot-%06d.tracemalloc" % int(time.monotonic() - started)
        tracemalloc.take_snapshot().dump(os.path.join(folder, name))


if os.environ.get("CSSR_SOAK_HEAP_FILE"):
    threading.Thread(target=_write_heap, name="soak-heap", daemon=True,
                     args=(os.environ["CSSR_SOAK_HEAP_FILE"],
                           float(os.environ.get("CSSR_SOAK_HEAP_PERIOD", "10")))).start()
if os.environ.get("CSSR_TRACEMALLOC_DIR"):
    tracemalloc.start(10)
    threading.Thread(target=_write_snapshots, name="tracemalloc", daemon=True,
                     args=(os.environ["CSSR_TRACEMALLOC_DIR"],
                           float(os.environ.get("CSSR_TRACEMALLOC_PERIOD", "300")))).start()
