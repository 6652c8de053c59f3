"""The synthesis's grasps in worker processes, one grasp per process at a time.

Each grasp's synthesis (mapping/synthesis.py's `synthesize_grasp`: its human reference,
the kinematic search and the held trials) depends on no other, so on a machine with
more than one core they run side by side. A worker builds the default registry and the
named backend once, then synthesises the grasps it is given; its progress lines reach
the caller through a queue as they are written. Ctrl-C reaches the caller alone (the
workers ignore it), which ends the workers; a worker that dies (a crash of the physics
engine) ends the synthesis with an error rather than leaving its grasp waiting.
"""

from __future__ import annotations

import queue
import signal
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from multiprocessing import get_context
from typing import Any

from graspframe.common.errors import GraspframeError
from graspframe.common.grasps import HumanGrasp
from graspframe.hal.descriptions import HandDescription
from graspframe.specs.draft import HandDraft
from graspframe.strategy.held_check import HeldTest

POLL = 0.2  # [s] between looks at the workers' progress and results

_worker: dict[str, Any] = {}  # in a worker: its registry, backend and progress queue


def synthesize_in_workers(
    hand: HandDescription,
    roles: tuple[HandDraft, dict[str, str]],
    backend_name: str,
    grasps: Sequence[HumanGrasp],
    held: HeldTest,
    test_held: bool,
    workers: int,
    progress: Callable[[str], None],
) -> list:
    """Each grasp's `synthesize_grasp` result (a GraspSynthesis, or why the hand cannot
    make it), in the order of `grasps`, from up to `workers` processes; roles: the
    hand's `roles_of`."""
    context = get_context("spawn")
    messages = context.Queue()
    pool = ProcessPoolExecutor(
        min(workers, len(grasps)),
        mp_context=context,
        initializer=_start,
        initargs=(backend_name, messages),
    )
    finished = False
    try:
        pending = [
            pool.submit(_synthesize, hand, roles, grasp, held, test_held) for grasp in grasps
        ]
        while not all(p.done() for p in pending):
            _relay(messages, progress, POLL)
        _relay(messages, progress, 0.0)
        results = [p.result() for p in pending]  # a worker's exception is raised here
        finished = True
        return results
    except BrokenProcessPool:
        raise GraspframeError(
            "a synthesis worker process stopped before its grasp was done (a crash of the "
            "simulator?); --workers 1 runs the synthesis in one process and shows where"
        ) from None
    finally:
        if not finished:  # an error or Ctrl-C: the grasps still running are not waited for
            for process in list(pool._processes.values()):
                process.terminate()
        pool.shutdown(wait=finished, cancel_futures=not finished)


def _relay(messages, progress: Callable[[str], None], timeout: float) -> None:
    """Hand on the progress lines that arrived (waiting up to `timeout` for the first)."""
    try:
        progress(messages.get(timeout=timeout) if timeout else messages.get_nowait())
        while True:
            progress(messages.get_nowait())
    except queue.Empty:
        return


def _start(backend_name: str, messages) -> None:
    """A worker's set-up: Ctrl-C left to the caller, the registry and backend built."""
    from graspframe.plugin_system.registry import default_registry

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    registry = default_registry()
    _worker.update(
        registry=registry, backend=registry.get_backend(backend_name)(), messages=messages
    )


def _synthesize(
    hand: HandDescription,
    roles: tuple[HandDraft, dict[str, str]],
    grasp: HumanGrasp,
    held: HeldTest,
    test_held: bool,
):
    from graspframe.mapping.synthesis import synthesize_grasp

    return synthesize_grasp(
        hand,
        roles,
        _worker["registry"],
        _worker["backend"],
        grasp,
        held,
        test_held,
        progress=_worker["messages"].put,
    )
