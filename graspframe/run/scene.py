"""The scene file: where the camera is and which object the human grasps, and where.

    {
      "format": "graspframe.scene/1",
      "object": "large_cylinder",          # a registered object name
      "T_world_camera": [[...4x4...]],     # camera pose in the robot's world (OpenCV axes:
                                           # x right, y down, z forward) [m]
      "T_camera_object": [[...4x4...]]     # object centroid frame in the camera frame [m]
    }

Other keys (e.g. "truth" with the ground truth of a rendered scene) are allowed and
ignored by the run. The object must stand upright on the table (table top at z = 0).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from graspframe.common.defaults import SCENE_FORMAT
from graspframe.common.errors import GraspframeError, InputError
from graspframe.common.json_files import read_json_file
from graspframe.common.transforms import as_pose

FORMAT = SCENE_FORMAT
UPRIGHT_TOL_DEG = 5.0  # the object's z axis this close to the world's
ON_TABLE_TOL = 0.02  # [m] its bottom this close to the table top


@dataclass(frozen=True)
class Scene:
    object_name: str
    T_world_camera: NDArray[np.float64]
    T_camera_object: NDArray[np.float64]
    path: str

    @property
    def T_world_object(self) -> NDArray[np.float64]:
        return self.T_world_camera @ self.T_camera_object


def load_scene(path: Path | str) -> Scene:
    """Read and validate a scene file; one-line InputError naming what is wrong."""
    path = Path(path)
    data = read_json_file(path, "scene file")
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise InputError(f'scene file {path}: expected a JSON object with "format": "{FORMAT}"')
    missing = [k for k in ("object", "T_world_camera", "T_camera_object") if k not in data]
    if missing:
        raise InputError(f"scene file {path}: missing {', '.join(missing)}")
    poses = {}
    for key in ("T_world_camera", "T_camera_object"):
        try:
            poses[key] = as_pose(np.asarray(data[key], dtype=float), key)
        except (ValueError, TypeError) as exc:
            raise InputError(f"scene file {path}: {key} must be a 4x4 matrix of numbers") from exc
        except GraspframeError as exc:
            raise InputError(f"scene file {path}: {exc}") from None
    return Scene(str(data["object"]), poses["T_world_camera"], poses["T_camera_object"], str(path))


def check_on_table(scene: Scene, half_height: float, table_height: float) -> None:
    """The object must stand upright on the table."""
    T = scene.T_world_object
    tilt_deg = np.degrees(np.arccos(np.clip(T[2, 2], -1.0, 1.0)))
    bottom = T[2, 3] - half_height
    if tilt_deg > UPRIGHT_TOL_DEG or abs(bottom - table_height) > ON_TABLE_TOL:
        raise InputError(
            f"scene file {scene.path}: the object must stand upright on the table (z up, "
            f"bottom at z = {table_height} m); it is tilted {tilt_deg:.0f} deg with its "
            f"bottom at z = {bottom:.3f} m"
        )
