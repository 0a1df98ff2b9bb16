"""What the node's main thread sleeps on between signals.

Python runs signal handlers in the main thread, but the kernel may hand a process's signal to any of rospy's
threads; a main thread waiting on a lock or an event then sees it only when its wait ends, which is why it used to
wake ten times a second. A pipe registered with `signal.set_wakeup_fd` gets a byte from the C-level handler in
whichever thread the signal lands, and a main thread in `select` on the pipe wakes at once and runs the handler.
Anything else that must wake it (a stop request, the supervisor thread's end) writes to the same pipe.
"""
import os
import select
import signal


class Wakeup:
    def __init__(self) -> None:
        self._read, self._write = os.pipe()
        os.set_blocking(self._read, False)
        os.set_blocking(self._write, False)  # set_wakeup_fd asks for it; a full pipe already wakes the reader

    def receive_signals(self) -> None:
        """From the main thread: signals, wherever they land, wake `wait`."""
        signal.set_wakeup_fd(self._write, warn_on_full_buffer=False)

    def wake(self) -> None:
        """From any thread: `wait` returns now (or at once, if it is not waiting yet)."""
        try:
            os.write(self._write, b"\0")
        except BlockingIOError:  # the pipe is full: the reader wakes anyway
            pass

    def wait(self, timeout: float) -> bool:
        """Sleeps until a signal or `wake`, or for `timeout` s; True when woken. What woke it is drained."""
        readable, _, _ = select.select([self._read], [], [], timeout)
        if not readable:
            return False
        try:
            while os.read(self._read, 512):
                pass
        except BlockingIOError:
            pass
        return True
