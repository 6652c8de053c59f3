"""Long-lived, supervised trial workers: the local executor of sweeps.

`run_in_workers` spawns N worker processes; each imports the simulator once, then runs
trials one at a time, a trial per message over its pipe, so a sweep pays the start-up of
a process per worker instead of per trial. The supervisor (the sweep's process) waits on
the pipes and on the processes' sentinels together. A row is yielded the moment it
arrives (its worker already on its next trial). A worker that dies (a crash, a kill) or
whose trial runs past the time limit is killed if needed, that trial yields a failed row
with the errors of `run_trial_isolated`, and a fresh worker takes the remaining trials.
A worker's start-up (imports) does not count against the trial time limit.

Workers are told to stop once no trial is left for them. When the sweep stops early (the
generator closed, or an exception such as Ctrl-C in the supervisor) the workers, each in
a trial, are killed. A worker whose supervisor dies exits by itself.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading
import time
from collections import deque
from collections.abc import Generator, Iterable
from contextlib import suppress
from multiprocessing.connection import Connection, wait
from multiprocessing.context import SpawnContext

from graspframe.experiments.trials import (
    TrialRow,
    TrialSpec,
    died_error,
    failed_row,
    run_trial,
    timed_out_error,
)

START_LIMIT = 300.0  # [s] wall time for a worker to import the simulator before it is killed
STOP_GRACE = 10.0  # [s] wait for a worker told to stop before it is killed
READY = "ready"  # a worker's first message: its imports are done, it takes trials now


def run_in_workers(
    specs: Iterable[TrialSpec], workers: int, time_limit: float
) -> Generator[TrialRow, None, None]:
    """Run every trial in up to `workers` worker processes; yields one row per trial
    in the order they finish. time_limit: [s] per trial, from when its worker starts it."""
    context = multiprocessing.get_context("spawn")
    todo = deque(specs)
    busy: list[_Worker] = []
    try:
        while todo and len(busy) < workers:
            busy.append(_Worker(context, todo.popleft()))
        while busy:
            now = time.perf_counter()
            timeout = max(0.0, min(worker.deadline(time_limit) for worker in busy) - now)
            wait([w.connection for w in busy] + [w.process.sentinel for w in busy], timeout)
            for worker in list(busy):
                row = worker.check(time_limit)
                if row is None:
                    continue
                # The next trial starts before the row is handed on (and written).
                if worker.process.is_alive() and todo:
                    worker.send(todo.popleft())
                else:
                    busy.remove(worker)
                    worker.stop()
                    if todo:  # the worker died or was killed: a fresh one goes on
                        busy.append(_Worker(context, todo.popleft()))
                yield row
    finally:
        for worker in busy:  # only when the sweep stops early: the trials are cut short
            worker.kill()


class _Worker:
    """One worker process, the trial it holds (sent, or waiting for the worker's start)
    and since when it holds it [s, perf_counter]."""

    def __init__(self, context: SpawnContext, spec: TrialSpec) -> None:
        self.connection, worker_end = context.Pipe()
        self.process = context.Process(target=_serve, args=(worker_end,), daemon=False)
        self.process.start()
        worker_end.close()
        self.spec = spec
        self.since = time.perf_counter()
        self.ready = False

    def deadline(self, time_limit: float) -> float:
        """[s, perf_counter] when the trial it holds (or its start-up) is over time."""
        return self.since + (time_limit if self.ready else START_LIMIT)

    def send(self, spec: TrialSpec) -> None:
        """Start a trial on this worker (it is between trials)."""
        self.spec, self.since = spec, time.perf_counter()
        with suppress(OSError):  # it just died: `check` reports the trial as failed
            self.connection.send(spec)

    def check(self, time_limit: float) -> TrialRow | None:
        """The row of its trial if it has one now: its own, or a failed row when the
        worker died or ran over time (then killed); None while the trial runs."""
        if self.connection.poll():
            try:
                message = self.connection.recv()
            except EOFError:  # it died, possibly while sending
                return self._failed(died_error(self._exit_code()))
            if message != READY:
                return message
            self.ready = True
            self.send(self.spec)
            return None
        if not self.process.is_alive():
            return self._failed(died_error(self._exit_code()))
        if time.perf_counter() >= self.deadline(time_limit):
            self.kill()
            if not self.ready:
                return self._failed(f"the worker did not start within {START_LIMIT:.0f} s")
            return self._failed(timed_out_error(time_limit))
        return None

    def stop(self) -> None:
        """End the process: told to stop if alive (it is between trials), killed if it
        does not within STOP_GRACE."""
        if self.process.is_alive():
            with suppress(OSError):  # it died meanwhile
                self.connection.send(None)
            self.process.join(STOP_GRACE)
        self.kill()

    def kill(self) -> None:
        """Kill the process (if alive) and release it and its pipe."""
        if self.process.is_alive():
            self.process.kill()
        self.process.join()
        self.connection.close()

    def _exit_code(self) -> int | None:
        self.process.join()
        return self.process.exitcode

    def _failed(self, error: str) -> TrialRow:
        return failed_row(self.spec, error, time.perf_counter() - self.since)


def _serve(connection: Connection) -> None:
    """A worker process: import once, then run each trial it is sent until told to stop
    (None) or its supervisor is gone."""
    # Ctrl-C reaches the whole process group: the supervisor decides what stops.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _exit_with_supervisor()
    import graspframe.run.runner  # noqa: F401  the heavy imports (simulator, kinematics), once
    from graspframe.plugin_system.registry import default_registry

    default_registry()
    connection.send(READY)
    try:
        while (spec := connection.recv()) is not None:
            connection.send(run_trial(spec))
    except (EOFError, BrokenPipeError):  # the supervisor closed the pipe or is gone
        pass


def _exit_with_supervisor() -> None:
    """Exit this process as soon as its parent dies (even by kill -9), mid-trial too."""
    parent = multiprocessing.parent_process()
    if parent is None:
        return

    def watch() -> None:
        wait([parent.sentinel])
        os._exit(1)

    threading.Thread(target=watch, name="supervisor-watch", daemon=True).start()
