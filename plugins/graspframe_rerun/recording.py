"""One run's rerun recording, kept in memory during the run and written to the run folder
at its end, atomically (graspframe.common.files): a recording file is always whole, and one that
cannot be written (no space left, ...) is an OutputError naming the file and the cause,
which fails the run. (rerun's own file sink writes from a thread of its own: a failure
shows only in rerun's log lines on stderr, a flush may then wait for ever, and half a
file is left.)

Entity layout (all in the world frame, z up, metres):
    world/table, world/object                the table top and the object (true pose): its
                                             display mesh (a mesh object: the visual mesh,
                                             coloured from its texture when it has one)
    world/object/collision                   a mesh object's convex pieces (what the
                                             simulator and the planner use), see-through
    world/robot/<link>                       each link's pose (forward kinematics), per cycle
    world/robot/<link>/visual/<i>            the link's visual meshes (the model's
                                             <visual> elements, decimated), opaque
    world/robot/<link>/collision/<i>         the link's collision shapes (the simulated
                                             geometry): opaque for a link without visual
                                             meshes, else a see-through overlay
    world/plan/{pre,goal,approach}           the planned palm path
    world/palm_path                          the executed palm path (one point per cycle)
    world/contacts/<real finger>             contact forces at the hold, as arrows
    world/corrections                        goal corrections of the volar strategy
    vf/robot, vf/human                       virtual fingers, object frame, side by side
    plots/joints/<joint>, plots/palm_sensor, plots/distance_to_goal   scalars
    vision/input, vision/<picture>           classification image and the classifier's
                                             pictures of its work (hog_knn: mask, crop)
    log                                      the run's events as text
Timeline "sim_time" [s]: simulation time of each sample. The static geometry (each
link's meshes in the link frame, the table, the object) is logged once; the per-cycle
samples (link transforms, joint values, scalars) are buffered and sent in columns
(cycles.py) before each further event and at the end of the run. Hand links are coloured
by real finger (a visual mesh keeps a tint of its material colour), arm links orange.
The hand and the object come from the run's RunInfo; the events are those declared in
graspframe/plugin_system/events.py; the score (vf/, the virtual-finger errors) from the run's typed
result at its end, logged at the time of its score.done event.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import rerun as rr
import trimesh

from graspframe.common.defaults import TABLE_HALF_SIZE
from graspframe.common.errors import GraspframeError
from graspframe.common.files import atomic_write
from graspframe.common.transforms import quat_xyzw_from_R
from graspframe.pictures import style
from graspframe.pictures.meshes import Surface, robot_meshes, vertex_normals
from graspframe.pictures.style import tinted
from graspframe.plugin_system import events
from graspframe.plugin_system.events import RunInfo
from graspframe.robot_models.model import CollisionModel
from graspframe.robot_models.shapes import (
    object_collision_meshes,
    object_mesh,
    textured_object_mesh,
)
from graspframe_rerun import RECORDING_FILE
from graspframe_rerun.cycles import MotionCycles, RobotPoser

if TYPE_CHECKING:  # the run's types import the whole pipeline
    from graspframe.run.result import Score

COLLISION_OVERLAY_ALPHA = 70  # [0, 255] collision shapes over a link's visual meshes
HUMAN_VF_OFFSET = np.array([0.0, 0.25, 0.0])  # [m] human virtual fingers beside the robot's
FORCE_ARROW_SCALE = 0.005  # [m/N]


def _mesh_archetype(mesh, colour, vertex_colours=None) -> rr.Mesh3D:
    return rr.Mesh3D(
        vertex_positions=mesh.vertices,
        triangle_indices=mesh.faces,
        vertex_normals=mesh.vertex_normals,
        vertex_colors=vertex_colours,
        albedo_factor=None if vertex_colours is not None else colour,
    )


def _surface_archetype(surface: Surface, colour, alpha: int = 255) -> rr.Mesh3D:
    """A link's mesh in the link frame, `colour` (0..255 RGB) tinted by the mesh's own
    material colour; alpha < 255: see-through."""
    base = tuple(c / 255.0 for c in colour)
    rgb = tinted(base, surface.rgb)
    return rr.Mesh3D(
        vertex_positions=surface.vertices,
        triangle_indices=surface.faces,
        vertex_normals=vertex_normals(surface.vertices, surface.faces),
        albedo_factor=(*(round(255 * c) for c in rgb), alpha),
    )


OBJECT_COLOUR = (200, 170, 60)
PIECE_COLOUR = (60, 170, 200, 90)  # translucent: the pieces inside the visual mesh


def _object_archetype(obj):
    """The object's display mesh (graspframe.robot_models.shapes.object_mesh), with the colours of a
    mesh object's texture at its vertices when it has one."""
    if not obj.is_mesh:
        return _mesh_archetype(object_mesh(obj), OBJECT_COLOUR)
    mesh, vertex_colours = textured_object_mesh(obj)
    return _mesh_archetype(mesh, OBJECT_COLOUR, vertex_colours)


def _pieces_archetype(obj) -> rr.Mesh3D:
    """A mesh object's convex pieces as one mesh
    (graspframe.robot_models.shapes.object_collision_meshes)."""
    return _mesh_archetype(trimesh.util.concatenate(object_collision_meshes(obj)), PIECE_COLOUR)


def _transform(T) -> rr.Transform3D:
    """A pose as translation and quaternion, as the per-cycle columns log it."""
    T = np.asarray(T, dtype=float)
    return rr.Transform3D(
        translation=T[:3, 3], quaternion=rr.Quaternion(xyzw=quat_xyzw_from_R(T[:3, :3]))
    )


class RunRecording:
    """Receives the run's events and logs them to recording.rrd in the run folder."""

    def __init__(self, run: RunInfo):
        if run.hand is None or run.object is None:
            raise GraspframeError(f"run {run.run_id}: recording needs its hand and object")
        self._hand = run.hand
        # real finger -> "#rrggbb", the pictures' colours (graspframe/pictures/style.py)
        self._finger_colours = style.finger_colours(run.hand.finger_of_link())
        self._object = run.object
        self.path = Path(run.out_dir) / RECORDING_FILE
        self.stream = rr.RecordingStream("graspframe", recording_id=run.run_id)
        self._memory = self.stream.memory_recording()
        self._cycles: MotionCycles | None = None  # from world.built on
        self._sim_time_s = 0.0
        self._score_time_s: float | None = None  # [s] of the score.done event
        self._handlers = {
            events.WORLD_BUILT.name: self._on_world_built,
            events.PLAN_DONE.name: self._on_plan_done,
            events.EXECUTE_FIRST_CONTACT.name: self._on_execute_first_contact,
            events.EXECUTE_CORRECTION.name: self._on_execute_correction,
            events.EXECUTE_DEPTH_IMAGE.name: self._on_execute_depth_image,
            events.EXECUTE_HOLD.name: self._on_execute_hold,
            events.SCORE_DONE.name: self._on_score_done,
            events.CLASSIFY_IMAGES.name: self._on_classify_images,
        }

    # -- helpers -----------------------------------------------------------------------------

    def _log(self, entity: str, archetype, static: bool = False) -> None:
        self.stream.log(entity, archetype, static=static)

    def _at(self, sim_time: float | None) -> None:
        if sim_time is not None:
            self._sim_time_s = float(sim_time)
            self.stream.set_time("sim_time", duration=self._sim_time_s)

    def text(self, message: str) -> None:
        self._log("log", rr.TextLog(message))

    # -- events ------------------------------------------------------------------------------

    def handle(self, kind: str, sim_time: float | None, data: dict) -> None:
        """Log one run event (`kind` the name of its EventKind) at `sim_time` [s]."""
        self._at(sim_time)
        if kind == events.MOTION_CYCLE.name:  # buffered; no log line, it would drown the log
            if self._cycles is not None:
                self._cycles.add(self._sim_time_s, data)
            return
        self._flush_cycles()
        handler = self._handlers.get(kind)
        if handler is not None:
            handler(data)
        self.text(kind + " " + ", ".join(f"{k}={_short(v)}" for k, v in data.items()))

    def _flush_cycles(self) -> None:
        if self._cycles is not None:
            self._cycles.flush()

    def _on_world_built(self, data: dict) -> None:
        T_world_object = np.asarray(data["T_world_object"])
        table_centre = [*T_world_object[:2, 3], data["table_height"] - TABLE_HALF_SIZE[2]]
        self._log(
            "world/table",
            rr.Boxes3D(
                centers=[table_centre], half_sizes=[TABLE_HALF_SIZE], colors=[(120, 90, 60)]
            ),
            static=True,
        )
        self._log("world/object", _object_archetype(self._object), static=True)
        if self._object.is_mesh:
            self._log("world/object/collision", _pieces_archetype(self._object), static=True)
        self._log("world/object", _transform(T_world_object))
        self._log(
            "world/object_believed",
            rr.Points3D(
                [np.asarray(data["T_world_object_est"])[:3, 3]],
                radii=0.006,
                colors=[(255, 0, 0)],
                labels=["believed object"],
            ),
            static=True,
        )
        model = data["model"]
        finger_of_link = self._hand.finger_of_link()
        links = []
        for meshes in robot_meshes(model):
            finger = finger_of_link.get(meshes.link)
            colour = style.rgb255(
                style.ARM_COLOUR if finger is None else self._finger_colour(finger)
            )
            entity = f"world/robot/{meshes.link}"
            for i, surface in enumerate(meshes.visual):
                self._log(f"{entity}/visual/{i}", _surface_archetype(surface, colour), static=True)
            alpha = COLLISION_OVERLAY_ALPHA if meshes.visual else 255
            for i, surface in enumerate(meshes.collision):
                archetype = _surface_archetype(surface, colour, alpha)
                self._log(f"{entity}/collision/{i}", archetype, static=True)
            links.append(meshes.link)
        poser = RobotPoser(
            CollisionModel(model),
            np.asarray(data["T_world_arm_base"], dtype=float),
            tuple(data["arm_joint_names"]),
            self._hand,
        )
        self._cycles = MotionCycles(self.stream, poser, links)

    def _on_plan_done(self, data: dict) -> None:
        pre = np.asarray(data["T_world_palm_pre"])[:3, 3]
        goal = np.asarray(data["T_world_palm_goal"])[:3, 3]
        via = np.asarray(data["T_world_palm_via"])[:3, 3]
        self._log(
            "world/plan/path",
            rr.LineStrips3D([[via, pre, goal]], colors=[(0, 120, 255)]),
            static=True,
        )
        self._log(
            "world/plan/goal",
            rr.Points3D([goal], radii=0.006, colors=[(0, 120, 255)], labels=["goal"]),
            static=True,
        )
        self._log(
            "world/plan/approach",
            rr.Arrows3D(origins=[pre], vectors=[goal - pre], colors=[(0, 120, 255)]),
            static=True,
        )

    def _finger_colour(self, finger: str) -> str:
        return style.colour_of_finger(finger, self._finger_colours)

    def _on_execute_first_contact(self, data: dict) -> None:
        colour = style.rgb255(self._finger_colour(data["real_finger"]))
        self._log(
            "world/first_contacts",
            rr.Points3D(
                [data["p_world"]], radii=0.005, colors=[colour], labels=[data["real_finger"]]
            ),
        )

    def _on_execute_correction(self, data: dict) -> None:
        before, after = np.asarray(data["goal_before"]), np.asarray(data["goal_after"])
        self._log(
            f"world/corrections/{data['index']}",
            rr.Arrows3D(
                origins=[before],
                vectors=[after - before],
                colors=[(255, 60, 60)],
                labels=[f"correction {data['index']}: {data.get('reason', '')}"],
            ),
            static=True,
        )

    def _on_execute_depth_image(self, data: dict) -> None:
        """The servo's depth camera: its pose and pinhole in the world, the image (shown
        as a point cloud in 3D, 0 where no return), and the fitted object position."""
        c = data["intrinsics"]
        T = np.asarray(data["T_world_camera"])
        self._log("world/depth_camera", rr.Transform3D(translation=T[:3, 3], mat3x3=T[:3, :3]))
        self._log(
            "world/depth_camera/image",
            rr.Pinhole(
                focal_length=[c["fx"], c["fy"]],
                principal_point=[c["cx"], c["cy"]],
                width=c["width"],
                height=c["height"],
                camera_xyz=rr.ViewCoordinates.RDF,
            ),
        )
        depth = np.nan_to_num(np.asarray(data["depth_m"], dtype=np.float32), nan=0.0)
        self._log("world/depth_camera/image", rr.DepthImage(depth, meter=1.0))
        self._log(
            "world/object_fitted",
            rr.Points3D(
                [np.asarray(data["p_world_fitted"])],
                radii=0.006,
                colors=[(40, 200, 80)],
                labels=[f"fitted object ({data['stage']}, step {data['step']})"],
            ),
        )

    def _on_execute_hold(self, data: dict) -> None:
        self._log_contacts("world/contacts", data.get("contacts", []), offset=np.zeros(3))

    def _log_contacts(self, root: str, contacts, offset) -> None:
        by_finger: dict[str, list] = {}
        for c in contacts:
            by_finger.setdefault(c.real_finger, []).append(c)
        for finger, items in by_finger.items():
            colour = style.rgb255(self._finger_colour(finger))
            origins = [c.p + offset for c in items]
            vectors = [FORCE_ARROW_SCALE * c.f for c in items]
            self._log(
                f"{root}/{finger}",
                rr.Arrows3D(origins=origins, vectors=vectors, colors=[colour] * len(items)),
                static=True,
            )

    def _on_score_done(self, _data: dict) -> None:
        # The score is drawn from the run's typed result when it finishes, at this time.
        self._score_time_s = self._sim_time_s

    def _log_score(self, score: Score) -> None:
        """The contacts and virtual fingers of both sides (object frame, the human's
        beside the robot's) and the virtual-finger errors."""
        self._log_contacts("vf/robot/contacts", score.robot_contacts, np.zeros(3))
        self._log_contacts("vf/human/contacts", score.human_contacts, HUMAN_VF_OFFSET)
        for side, grasp, offset in (
            ("robot", score.robot, np.zeros(3)),
            ("human", score.human, HUMAN_VF_OFFSET),
        ):
            vfs = [] if grasp is None else grasp.virtual_fingers
            if vfs:
                positions = [np.asarray(vf.position) + offset for vf in vfs]
                normals = [0.03 * np.asarray(vf.normal) for vf in vfs]
                labels = ["+".join(vf.members) for vf in vfs]
                self._log(
                    f"vf/{side}/virtual_fingers",
                    rr.Arrows3D(origins=positions, vectors=normals, labels=labels),
                    static=True,
                )
        comparison = score.comparison
        if comparison is not None:
            self._log("plots/vf_position_err_mm", rr.Scalars(float(comparison.position_err_mm)))
            self._log(
                "plots/vf_orientation_err_deg", rr.Scalars(float(comparison.orientation_err_deg))
            )

    def _on_classify_images(self, data: dict) -> None:
        self._log("vision/input", rr.Image(np.asarray(data["image_bgr"])[..., ::-1]), static=True)
        for picture in data["pictures"]:
            self._log(f"vision/{picture.name}", _picture_archetype(picture), static=True)

    def finish(self, status: str, error: str | None = None, score: Score | None = None) -> None:
        """Send the cycles still buffered, log how the run ended (its status and error)
        and its score (at the time of its score.done event), and write the recording
        file (OutputError: the path and the cause)."""
        self._flush_cycles()
        self.text(f"run {status}: {error or ''}")
        if score is not None:
            self._at(self._score_time_s)
            self._log_score(score)
        recording = self._memory.drain_as_bytes()  # before disconnecting: it ends the data
        self.stream.disconnect()
        atomic_write(self.path, recording)


def _picture_archetype(picture) -> rr.SegmentationImage | rr.Image:
    """A classifier's picture (graspframe.hal.ClassifierPicture): a mask as a
    segmentation image, a grey image as it is, a BGR image as RGB."""
    pixels = np.asarray(picture.pixels)
    if picture.kind == "mask":
        return rr.SegmentationImage(pixels.astype(np.uint8))
    return rr.Image(pixels[..., ::-1] if pixels.ndim == 3 else pixels)


def _short(value) -> str:
    if isinstance(value, np.ndarray):
        return f"array{value.shape}"
    if isinstance(value, list | tuple) and len(value) > 6:
        return f"[{len(value)} items]"
    text = str(value)
    return text if len(text) <= 80 else text[:77] + "..."
