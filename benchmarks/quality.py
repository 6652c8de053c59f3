"""How long one grasp's quality takes (graspframe.metrics.quality).

    python benchmarks/quality.py

Random grasps of 2..6 contacts on a 4 cm ball (normals into it, off-centre so every
contact has a lever arm), friction 0.5, torques over the ball's radius: the median time
of the L1 quality (epsilon and volume, 8-edge pyramids) over repeats, and once the
L-infinity quality (4-edge pyramids), whose Minkowski sum is the expensive part. Prints
figures only.
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from graspframe.metrics.quality import grasp_quality

SEED = 0
RADIUS = 0.04  # [m]
REPEATS = 50


def random_grasp(rng: np.random.Generator, n_contacts: int):
    directions = rng.normal(size=(n_contacts, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return RADIUS * directions + rng.normal(scale=0.005, size=3), -directions


def main() -> None:
    rng = np.random.default_rng(SEED)
    print("contacts | L1 epsilon+volume, median [ms] | L-infinity (4 edges) [ms] | epsilon L1")
    for n_contacts in range(2, 7):
        points, normals = random_grasp(rng, n_contacts)
        times = []
        for _ in range(REPEATS):
            start = time.perf_counter()
            quality = grasp_quality(points, normals, 0.5, torque_length=RADIUS)
            times.append(time.perf_counter() - start)
        start = time.perf_counter()
        if n_contacts <= 4:
            grasp_quality(points, normals, 0.5, torque_length=RADIUS, edges=4, linf=True)
            linf = f"{1000 * (time.perf_counter() - start):.0f}"
        else:
            linf = "skipped"
        print(
            f"{n_contacts} | {1000 * statistics.median(times):.2f} | {linf} "
            f"| {quality.epsilon_l1:.3f}"
        )


if __name__ == "__main__":
    main()
