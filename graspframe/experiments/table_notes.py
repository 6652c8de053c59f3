"""The note below a sweep's tables (summary.md and the terminal): what its columns mean,
and which held test judged its trials."""

from __future__ import annotations

# Below the table, in summary.md and on the terminal.
TABLE_NOTE = (
    "held: lifted 5 cm and kept in the hand while pushed along +-x, +-y, +-z with half "
    "the object's weight; 'lift only': lifted, then slipped when pushed. "
    "B held (lift): held in n of the directions (held after the lift in m). "
    "epsilon, volume: Ferrari-Canny L1 grasp quality and grasp wrench space volume "
    "(docs/method.md); A human held: the simulated human reference grasp passes the "
    "same held test."
)
BENCHMARK_HELD = (
    "held: the benchmark held test (DexGraspBench, Dexonomy): gravity off, lifted 5 cm clear "
    "of the table, pushed along +-x, +-y, +-z with the object's weight for 2 s each, failing "
    "past 5 cm or 15 deg of motion in the hand"
)


def table_note(held_test: str) -> str:
    """The note below the tables of a sweep judged by the held test `held_test`."""
    if held_test != "benchmark":
        return TABLE_NOTE
    return BENCHMARK_HELD + TABLE_NOTE[TABLE_NOTE.index(";") :]
