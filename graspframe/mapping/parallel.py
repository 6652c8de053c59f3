"""The synthesis's grasps in worker processes, one grasp per process at a time.

Each grasp's synthesis (mapping/synthesis.py's `synthesize_grasp`: its human reference,
the kinematic search and the held trials) depends on no other, so on a machine with
more than one core they run side by side. A worker builds the default registry and the
named backend once, then synthesises the grasps it is given; its progress lines reach
the caller through a queue as they are written. Ctrl-C reaches the caller alone (the
workers ignore it), which ends the workers.
"""

from __future__ import annotations

import queue
import signal
from collections.abc import Callable, Sequence
from multiprocessing import get_context
from typing import Any

from graspframe.common.grasps import HumanGrasp
from graspframe.hal.descriptions import HandDescription
from graspframe.strategy.held_check import HeldTest

POLL = 0.2  # [s] between looks at the workers' progress and results

_worker: dict[str, Any] = {}  # in a worker: its registry, backend and progress queue


def synthesize_in_workers(
    hand: HandDescription,
    backend_name: str,
    grasps: Sequence[HumanGrasp],
    held: HeldTest,
    test_held: bool,
    workers: int,
    progress: Callable[[str], None],
) -> list:
    """Each grasp's `synthesize_grasp` result (a GraspSynthesis, or why the hand cannot
    make it), in the order of `grasps`, from up to `workers` processes."""
    context = get_context("spawn")
    messages = context.Queue()
    pool = context.Pool(
        min(workers, len(grasps)), initializer=_start, initargs=(backend_name, messages)
    )
    finished = False
    try:
        pending = [
            pool.apply_async(_synthesize, (hand, grasp, held, test_held)) for grasp in grasps
        ]
        while not all(p.ready() for p in pending):
            _relay(messages, progress, POLL)
        _relay(messages, progress, 0.0)
        results = [p.get() for p in pending]  # a worker's exception is raised here
        finished = True
        return results
    finally:
        if finished:
            pool.close()
        else:  # an error or Ctrl-C: the grasps still running are not waited for
            pool.terminate()
        pool.join()


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


def _synthesize(hand: HandDescription, grasp: HumanGrasp, held: HeldTest, test_held: bool):
    from graspframe.mapping.synthesis import synthesize_grasp

    return synthesize_grasp(
        hand,
        _worker["registry"],
        _worker["backend"],
        grasp,
        held,
        test_held,
        progress=_worker["messages"].put,
    )
