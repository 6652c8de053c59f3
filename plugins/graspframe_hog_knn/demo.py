"""The bundled demo: one rendered image of a human Large Diameter grasp on the
large_cylinder, as the robot's camera sees it, with its ground truth (scene.json).

Rendered with this classifier's hand model and backgrounds; `write_demo` writes it into
the core's package folder graspframe/run/demo/, where `graspframe run` finds it by default.

World: z up, table top at z = 0, the object upright at x = 0.55, y = 0.2 with its
centroid at half its height; the human palm placed by `reference_placement`; the camera
above the table looking down at the hand, OpenCV axes (x right, y down, z forward).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from graspframe.common.defaults import SCENE_FORMAT, SCENE_OBJECT_XY
from graspframe.common.files import atomic_write
from graspframe.common.grasps import HumanGrasp
from graspframe.common.transforms import inv_T, make_T
from graspframe.pictures.rasteriser import Camera, Lighting, Renderer, composite
from graspframe_hog_knn.hand_scene import HandModel, T_palm_object, object_mesh, primitive
from graspframe_hog_knn.views import SKIN_TONES, R_world_camera_looking, background

GRASP = HumanGrasp.LARGE_DIAMETER
OBJECT_YAW = 0.0  # [rad] the human grasps from the robot's side (palm facing world +x)
CAMERA_DISTANCE = 0.6  # [m] from the point between palm and object
CAMERA_ELEVATION = np.radians(30.0)  # [rad] looking down
CAMERA_AZIMUTH = np.radians(-140.0)  # [rad] camera direction from the object, in world
WIDTH, HEIGHT, FOV_X_DEG = 640, 480, 60.0
CLOSURE = 0.6
TABLE_COLOUR = (0.42, 0.45, 0.50)
OBJECT_COLOUR = (0.15, 0.30, 0.80)


def demo_scene() -> dict:
    """The poses of the demo (4x4 arrays): T_world_object, T_world_palm, T_world_camera."""
    obj, T_palm_obj = T_palm_object(GRASP)
    R_yaw = make_T(
        [
            [np.cos(OBJECT_YAW), -np.sin(OBJECT_YAW), 0],
            [np.sin(OBJECT_YAW), np.cos(OBJECT_YAW), 0],
            [0, 0, 1],
        ]
    )[:3, :3]
    T_world_object = make_T(R_yaw, [*SCENE_OBJECT_XY, obj.half_height])
    T_world_palm = T_world_object @ inv_T(T_palm_obj)
    target = (T_world_object[:3, 3] + T_world_palm[:3, 3]) / 2
    e, a = CAMERA_ELEVATION, CAMERA_AZIMUTH
    position = target + CAMERA_DISTANCE * np.array(
        [np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)]
    )
    T_world_camera = make_T(R_world_camera_looking(e, a), position)
    return {
        "object": obj,
        "T_world_object": T_world_object,
        "T_world_palm": T_world_palm,
        "T_world_camera": T_world_camera,
    }


def render_demo(seed: int = 7, renderer: Renderer | None = None):
    """(image BGR uint8 HEIGHT x WIDTH, scene dict in the graspframe.scene/1 format)."""
    rng = np.random.default_rng(seed)
    scene = demo_scene()
    obj = scene["object"]
    T_camera_world = inv_T(scene["T_world_camera"])
    hand = HandModel()
    hand_mesh = hand.mesh(hand.posture_q(GRASP, CLOSURE))
    table = primitive("box", (1.2, 1.0, 0.02)).transformed(make_T(p=[0.5, 0.1, -0.01]))
    parts = [
        (hand_mesh.transformed(T_camera_world @ scene["T_world_palm"]), SKIN_TONES[2]),
        (object_mesh(obj).transformed(T_camera_world @ scene["T_world_object"]), OBJECT_COLOUR),
        (table.transformed(T_camera_world), TABLE_COLOUR),
    ]
    positions = np.concatenate([m.positions for m, _ in parts])
    normals = np.concatenate([m.normals for m, _ in parts])
    albedo = np.concatenate([np.tile(c, (len(m.positions), 1)) for m, c in parts])
    light_world = np.array([0.3, -0.4, 1.0])
    lighting = Lighting(
        light_dir=tuple(T_camera_world[:3, :3] @ (light_world / np.linalg.norm(light_world))),
        ambient=0.5,
        specular=0.06,
    )
    camera = Camera.from_fov(WIDTH, HEIGHT, FOV_X_DEG)
    renderer = renderer or Renderer()
    fg, alpha = renderer.render(
        camera, positions.astype(np.float32), normals, albedo.astype(np.float32), lighting
    )
    image = composite(fg, alpha, background(rng, "blobs", WIDTH, HEIGHT))
    noisy = image.astype(np.float32) + rng.normal(0, 2.0, image.shape)
    image = np.clip(noisy + 0.5, 0, 255).astype(np.uint8)
    T_camera_object = T_camera_world @ scene["T_world_object"]
    T_camera_palm = T_camera_world @ scene["T_world_palm"]
    record = {
        "format": SCENE_FORMAT,
        "object": obj.name,
        "T_world_camera": np.round(scene["T_world_camera"], 9).tolist(),
        "T_camera_object": np.round(T_camera_object, 9).tolist(),
        "truth": {"grasp": GRASP.value, "T_camera_palm": np.round(T_camera_palm, 9).tolist()},
        "camera": {
            "width": WIDTH,
            "height": HEIGHT,
            "fx": camera.fx,
            "fy": camera.fy,
            "cx": camera.cx,
            "cy": camera.cy,
            "fov_x_deg": FOV_X_DEG,
        },
        "seed": seed,
    }
    return image, record


def demo_dir() -> Path:
    """The core's package folder holding demo.png and scene.json (graspframe/run/demo/)."""
    from importlib.resources import files

    return Path(str(files("graspframe.run.demo")))


def write_demo(out_dir: Path | None = None, seed: int = 7) -> tuple[Path, Path]:
    """Render the demo and write demo.png and scene.json."""
    import cv2

    out_dir = Path(out_dir or demo_dir())
    image, record = render_demo(seed)
    png, js = out_dir / "demo.png", out_dir / "scene.json"
    atomic_write(png, cv2.imencode(".png", image)[1].tobytes())
    atomic_write(js, json.dumps(record, indent=2) + "\n")
    return png, js
