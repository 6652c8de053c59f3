"""Ctrl-C (SIGINT) and SIGTERM while a command runs, and after it has ended.

While a command runs, both signals raise a KeyboardInterrupt in the main thread, so that
each stage cleans up on its way out (the world released, workers killed, the recording
closed, result.json marked "interrupted"). This holds also where SIGINT arrives ignored,
as a shell starts its background jobs. Once the command has ended and said how, both are
ignored: the interpreter's shutdown (about 0.3 s: the simulator and the plugins
released) resets the handlers to the defaults, under which a late Ctrl-C would kill the
process and lose the command's exit code.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

SIGNALS = (signal.SIGINT, signal.SIGTERM)


def _stop(signum: int, frame: object) -> None:
    raise KeyboardInterrupt(signal.Signals(signum).name)


@contextmanager
def interruptible() -> Iterator[None]:
    """Both signals raise a KeyboardInterrupt naming the signal inside the block; the
    handlers before it are restored after it. Signals need the main thread: elsewhere
    the block runs unchanged."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {number: signal.getsignal(number) for number in SIGNALS}
    for number in SIGNALS:
        signal.signal(number, _stop)
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)


def ignore_until_exit() -> None:
    """Ignore both signals from now on: for a process whose command has ended."""
    for number in SIGNALS:
        signal.signal(number, signal.SIG_IGN)
