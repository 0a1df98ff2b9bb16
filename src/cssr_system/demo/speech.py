"""The demo's conversation (`make demo CONVERSATION=1`): a stand-in speech node listens, then speaks, then falls silent.

`Conversation.play` runs the script once: ``true`` on the listening topic for `LISTEN_FOR` s, then a goal of its own
speaking action for `SPEAK_FOR` s (``false`` on the topic just after the goal starts: `HANDOVER`), then nothing. The
animateBehaviour node of the demo watches that topic (``listeningTopic``) and that action's status
(``speakingAction``) in mode ``auto`` (README: "Modes"), so it listens and speaks with no call to it. A subclass
gives what needs a ROS (``cssr_system.ros1.speech_player``, ``cssr_system.ros2.speech_player``): publishing on the
topic and running a goal. Pure Python: no ROS import.
"""
import functools
import threading
import time
from typing import Callable

from cssr_system.animate_behaviour import console

NODE_NAME = "animateBehaviourDemoSpeech"
PLAY_TOPIC = NODE_NAME + "/play"  # std_msgs/Empty: play the conversation now (relative: in the demo's namespace)
LISTENING_TOPIC = "listening"  # std_msgs/Bool, relative: the node of the same namespace resolves it alike
SPEAKING_ACTION = "tts"  # the speaking action, named as the successor's text to speech (README: "Modes")
LISTEN_FOR = 6.0  # s
SPEAK_FOR = 8.0  # s
SPEAK_MARGIN = 10.0  # s more than the goal's duration before the script stops waiting for its end
# s of listening left after the speaking goal is sent: speaking wins over listening, and the goal's status reaches the
# node only with the action's next status message (5 Hz on ROS 1), so the robot goes from listening to speaking with
# no idle moment between them, in which the base could start a turn.
HANDOVER = 0.5

say = functools.partial(console.say, NODE_NAME)


class Conversation:
    """The script; `stop` ends a wait early (the program is stopping). One play at a time: a play asked while one
    runs is ignored."""

    def __init__(self, stop: threading.Event) -> None:
        self.stop = stop
        self._playing = threading.Lock()

    # -- what a subclass gives ------------------------------------------------------------------
    def set_listening(self, listening: bool) -> None:
        """Publish `listening` on the listening topic."""
        raise NotImplementedError

    def speak(self, seconds: float, done: Callable[[str], None]) -> None:
        """Send a goal of `seconds` to the speaking action; `done` gets its final state's name when it ends (from
        any thread), or why there was none."""
        raise NotImplementedError

    # -- the script -----------------------------------------------------------------------------
    def play(self) -> None:
        if not self._playing.acquire(blocking=False):
            return
        try:
            self._play()
        finally:
            self._playing.release()

    def _play(self) -> None:
        say("listening for %g s (true on %s)" % (LISTEN_FOR, LISTENING_TOPIC))
        self.set_listening(True)
        if self.stop.wait(LISTEN_FOR):
            self.set_listening(False)  # the robot never stays listening
            return
        ended = threading.Event()
        outcome = []

        def done(state: str) -> None:
            outcome.append(state)
            ended.set()

        say("speaking for %g s (a goal of the action %s)" % (SPEAK_FOR, SPEAKING_ACTION))
        self.speak(SPEAK_FOR, done)
        self.stop.wait(HANDOVER)
        self.set_listening(False)
        deadline = time.monotonic() + SPEAK_FOR + SPEAK_MARGIN
        while not ended.wait(0.1) and not self.stop.is_set() and time.monotonic() < deadline:
            pass
        if outcome:
            say("silent: the speaking goal ended (%s)" % outcome[0])
        elif not self.stop.is_set():
            say("error: the speaking goal did not end within %g s" % (SPEAK_FOR + SPEAK_MARGIN))
