"""How long the virtual-finger partition search takes, and how it grows (Bell numbers).

    /tmp/gfenv/bin/python benchmarks/metric.py

Part 1: hands with 2..6 real fingers (five fingers and the palm at most), random forces,
the median over repeats of `best_partition`. Part 2: synthetic hands with up to 10 real
fingers, to show the growth with the number of set partitions, Bell(F). Part 3: the
whole pipeline from contacts (grouping, partition, poses, comparison) for a 6-finger hand.
Prints figures only; runs in well under two minutes.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable

import numpy as np

from graspframe.common.contacts import Contact
from graspframe.metrics import best_partition, compare, virtual_fingers_from_contacts

SEED = 0


def bell_number(n: int) -> int:
    """Number of set partitions of n items (Bell triangle)."""
    row = [1]
    for _ in range(n):
        next_row = [row[-1]]
        for value in row:
            next_row.append(next_row[-1] + value)
        row = next_row
    return row[0]


def median_seconds(run: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def random_forces(rng: np.random.Generator, count: int) -> dict[str, np.ndarray]:
    """Net forces [N] of `count` real fingers, random directions, 0.5..5 N."""
    directions = rng.normal(size=(count, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    magnitudes = rng.uniform(0.5, 5.0, size=count)
    forces = directions * magnitudes[:, None]
    return {f"finger{i}": force for i, force in enumerate(forces)}


def time_partition_search(counts: range, repeats: int, rng: np.random.Generator) -> None:
    print(f"{'F':>3} {'Bell(F)':>8} {'median [ms]':>12} {'per partition [us]':>19} {'N':>3}")
    for count in counts:
        forces = random_forces(rng, count)
        seconds = median_seconds(lambda forces=forces: best_partition(forces), repeats)
        partitions = bell_number(count)
        chosen = best_partition(forces).count
        print(
            f"{count:>3} {partitions:>8} {1e3 * seconds:>12.3f} "
            f"{1e6 * seconds / partitions:>19.2f} {chosen:>3}"
        )


def random_contacts(rng: np.random.Generator, names: list[str], per_finger: int) -> list:
    """Contacts on a 5 cm sphere, each pushing along the inward normal, world = object."""
    contacts = []
    for name in names:
        for _ in range(per_finger):
            n_object = rng.normal(size=3)
            n_object /= np.linalg.norm(n_object)
            p_object = 0.05 * n_object
            f_object = -rng.uniform(0.5, 5.0) * n_object
            contacts.append(Contact(f"{name}_link", name, p_object, n_object, f_object))
    return contacts


def time_pipeline(rng: np.random.Generator, repeats: int) -> None:
    names = ["palm", "thumb", "index", "middle", "ring", "pinky"]
    T_world_object = np.eye(4)
    robot = random_contacts(rng, names, per_finger=3)
    human = random_contacts(rng, names, per_finger=3)

    def run() -> None:
        robot_vfs = virtual_fingers_from_contacts(robot, T_world_object)
        human_vfs = virtual_fingers_from_contacts(human, T_world_object)
        compare(robot_vfs, human_vfs, robot_real_fingers=names, human_real_fingers=names)

    seconds = median_seconds(run, repeats)
    print(f"6 real fingers x 3 contacts, both sides + compare: {1e3 * seconds:.2f} ms (median)")


def main() -> None:
    rng = np.random.default_rng(SEED)
    start = time.perf_counter()
    print("Partition search, real hands (2..6 real fingers), median of 50 runs:")
    time_partition_search(range(2, 7), repeats=50, rng=rng)
    print()
    print("Synthetic hands (up to 10 real fingers): time grows with Bell(F), median of 3:")
    time_partition_search(range(2, 11), repeats=3, rng=rng)
    print()
    print("Whole metric from contacts, median of 50:")
    time_pipeline(rng, repeats=50)
    print(f"\nbenchmark total: {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
