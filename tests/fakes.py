"""A fake two-finger hand, only for testing the plugin and contract machinery itself."""

from __future__ import annotations

import math
from pathlib import Path

from graspframe.common.grasps import PALM, HumanGrasp
from graspframe.hal import DriveGains, HandDescription, HandPreshape, JointSpec

FAKE_HAND_URDF = """<?xml version="1.0"?>
<robot name="fake_hand">
  <link name="fk_base">
    <inertial><mass value="0.3"/><inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/></inertial>
    <collision><origin xyz="0 0 0.02"/><geometry><box size="0.08 0.06 0.04"/></geometry></collision>
  </link>
  <link name="fk_palm_frame">
    <inertial><mass value="0.001"/><inertia ixx="1e-8" ixy="0" ixz="0" iyy="1e-8" iyz="0" izz="1e-8"/></inertial>
  </link>
  <link name="fk_finger">
    <inertial><mass value="0.05"/><inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-6"/></inertial>
    <collision><origin xyz="0 0 0.03"/><geometry><cylinder radius="0.008" length="0.06"/></geometry></collision>
  </link>
  <link name="fk_thumb">
    <inertial><mass value="0.05"/><inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-6"/></inertial>
    <collision><origin xyz="0 0 0.03"/><geometry><cylinder radius="0.008" length="0.06"/></geometry></collision>
  </link>
  <joint name="fk_palm_frame_joint" type="fixed">
    <parent link="fk_base"/><child link="fk_palm_frame"/><origin xyz="0 0 0.04" rpy="0 0 0"/>
  </joint>
  <joint name="fk_finger_joint" type="revolute">
    <parent link="fk_base"/><child link="fk_finger"/><origin xyz="0 0.03 0.04"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="1.5" effort="2" velocity="2"/>
  </joint>
  <joint name="fk_thumb_joint" type="revolute">
    <parent link="fk_base"/><child link="fk_thumb"/><origin xyz="0 -0.03 0.04"/>
    <axis xyz="-1 0 0"/><limit lower="0" upper="1.5" effort="2" velocity="2"/>
  </joint>
</robot>
"""


def make_fake_hand(model_path: Path, name: str = "fake_hand", **overrides) -> HandDescription:
    """A valid two-finger hand description over FAKE_HAND_URDF; overrides break it."""
    joints = (
        JointSpec("fk_finger_joint", 0.0, 1.5, max_velocity=2.0, max_effort=2.0),
        JointSpec("fk_thumb_joint", 0.0, 1.5, max_velocity=2.0, max_effort=2.0),
    )
    pinch = HandPreshape(
        "pinch",
        open_q={"fk_finger_joint": 0.1, "fk_thumb_joint": 0.1},
        closed_q={"fk_finger_joint": 1.2, "fk_thumb_joint": 1.2},
        delta=0.06,
    )
    fields = dict(
        name=name,
        model_path=model_path,
        root_link="fk_base",
        joints=joints,
        palm_frame="fk_palm_frame",
        palm_sensor_link="fk_base",
        real_fingers={PALM: ("fk_base",), "finger": ("fk_finger",), "thumb": ("fk_thumb",)},
        preshapes={"pinch": pinch},
        grasp_map={g: "pinch" for g in HumanGrasp},
        drive=DriveGains(stiffness=5.0, damping=0.5, force_limit=math.inf),
    )
    fields.update(overrides)
    return HandDescription(**fields)
