"""The motion cycles of a run, buffered and sent to rerun in columns.

A control cycle only stores its samples (joint values, object pose, palm position,
scalars); `flush` places the robot's links for all buffered cycles at once and sends
each entity's samples in one `send_columns` call, on the "sim_time" timeline with the
cycles' own times. (One `rr.log` per entity and cycle cost about as much as the rest of
the run.) A link's pose goes to `world/robot/<link>`; its meshes, logged once below that
entity in the link frame, move with it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import rerun as rr

from graspframe.common.transforms import quat_xyzw_from_R
from graspframe.hal.descriptions import HandDescription, joints_by_name
from graspframe.robot_models.model import CollisionModel

PALM_PATH_COLOUR = (255, 255, 255)


def sim_time_column(sim_time_s) -> rr.TimeColumn:
    """The "sim_time" index of samples at `sim_time_s` [s], in whole nanoseconds rounded
    as `set_time(duration=...)` rounds them (the column API would truncate floats)."""
    sim_time_ns = np.round(1e9 * np.asarray(sim_time_s, dtype=float)).astype(np.int64)
    return rr.TimeColumn("sim_time", duration=sim_time_ns.astype("timedelta64[ns]"))


def transform_columns(T_world_x: np.ndarray) -> rr.ComponentColumnList:
    """Transform3D columns from N 4x4 poses (N, 4, 4), one row per pose."""
    return rr.Transform3D.columns(
        translation=T_world_x[:, :3, 3], quaternion=quat_xyzw_from_R(T_world_x[:, :3, :3])
    )


@dataclass
class RobotPoser:
    """Places a run's robot: the world poses of its links for joint values."""

    model: CollisionModel
    T_world_base: np.ndarray
    arm_joint_names: tuple[str, ...]
    hand: HandDescription

    def q_by_joint(self, q_arm, q_hand: dict[str, float]) -> dict[str, float]:
        """Every model joint's value [rad] (arm, hand and the hand's mimic followers)."""
        return joints_by_name(self.arm_joint_names, q_arm, self.hand.with_model_followers(q_hand))

    def T_world_links(self, q_by_joint: dict[str, float], links: Sequence[str]) -> np.ndarray:
        """(n_links, 4, 4) world poses of `links`, in that order."""
        self.model.place(q_by_joint)
        T_base_links = np.stack([self.model.T_root_frame(link) for link in links])
        return self.T_world_base @ T_base_links


class MotionCycles:
    """Buffers motion.cycle samples and sends them to `stream` in columns on `flush`.

    links: the links whose poses are sent, each to the entity `world/robot/<link>`.
    The executed palm path grows over the whole run: each cycle's row is the path so far.
    """

    def __init__(self, stream: rr.RecordingStream, poser: RobotPoser, links: Sequence[str]):
        self.stream = stream
        self.poser = poser
        self.links = tuple(links)
        self.sim_time_s: list[float] = []
        self.q_by_joint: list[dict[str, float]] = []
        self.T_world_object: list[np.ndarray] = []
        self.palm_touched: list[float] = []
        self.distance_to_goal_m: list[float] = []
        self.p_world_palm_path: list[np.ndarray] = []  # every cycle's, sent or not
        self._sent_path_points = 0

    def add(self, sim_time_s: float, data: dict) -> None:
        """Buffer one motion.cycle payload (see graspframe/plugin_system/events.py) at
        `sim_time_s`."""
        self.sim_time_s.append(float(sim_time_s))
        self.q_by_joint.append(self.poser.q_by_joint(data["q_arm"], data["q_hand"]))
        self.T_world_object.append(np.asarray(data["T_world_object"], dtype=float))
        self.palm_touched.append(float(bool(data["palm_touched"])))
        self.distance_to_goal_m.append(float(data["distance_to_goal"]))
        self.p_world_palm_path.append(np.asarray(data["T_world_palm"], dtype=float)[:3, 3])

    def flush(self) -> None:
        """Send the buffered cycles, then forget them (the palm path is kept)."""
        if not self.sim_time_s:
            return
        times = sim_time_column(self.sim_time_s)
        T_world_links = np.stack([self.poser.T_world_links(q, self.links) for q in self.q_by_joint])
        for index, link in enumerate(self.links):
            self._send(f"world/robot/{link}", times, transform_columns(T_world_links[:, index]))
        self._send("world/object", times, transform_columns(np.stack(self.T_world_object)))
        self._send("world/palm_path", times, self._palm_path_columns())
        for name in dict.fromkeys(name for q in self.q_by_joint for name in q):
            self._send_scalars(f"plots/joints/{name}", [q.get(name) for q in self.q_by_joint])
        self._send_scalars("plots/palm_sensor", self.palm_touched)
        self._send_scalars("plots/distance_to_goal", self.distance_to_goal_m)
        self._sent_path_points = len(self.p_world_palm_path)
        for samples in (
            self.sim_time_s,
            self.q_by_joint,
            self.T_world_object,
            self.palm_touched,
            self.distance_to_goal_m,
        ):
            samples.clear()

    def _palm_path_columns(self) -> rr.ComponentColumnList:
        path = np.asarray(self.p_world_palm_path)
        ends = range(self._sent_path_points + 1, len(path) + 1)
        strips = [path[:end] for end in ends]
        return rr.LineStrips3D.columns(strips=strips, colors=[PALM_PATH_COLOUR] * len(strips))

    def _send_scalars(self, entity: str, values: Sequence[float | None]) -> None:
        """Scalars at the buffered times; a None (joint absent from that cycle) is skipped."""
        rows = [i for i, value in enumerate(values) if value is not None]
        times = sim_time_column(np.asarray(self.sim_time_s)[rows])
        scalars = np.asarray([values[i] for i in rows], dtype=float)
        self._send(entity, times, rr.Scalars.columns(scalars=scalars))

    def _send(self, entity: str, times: rr.TimeColumn, columns) -> None:
        self.stream.send_columns(entity, indexes=[times], columns=columns)
