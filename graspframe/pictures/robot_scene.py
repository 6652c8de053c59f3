"""A robot, an object and a table as soups to render (render3d.py), placed in the world.

`RobotFigure` holds a model's display meshes (pictures/meshes.py: each link's visual
meshes, or its collision shapes without them), one soup per link coloured by real finger
(style.py), and a Pinocchio model that places the links by forward kinematics.
`object_soup` is the object's display mesh (`graspframe.robot_models.shapes.object_mesh`);
`table_soup` the table top as a checker of `TABLE_CELL` squares fixed to the world grid,
so squares stay put between pictures and give the eye a scale and a floor.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from graspframe.model_files.urdf_model import UrdfModel
from graspframe.pictures import style
from graspframe.pictures.meshes import robot_meshes
from graspframe.pictures.render3d import Placed, Soup


class RobotFigure:
    """A robot model to draw: a soup per link (in the link frame) and its kinematics.

    finger_of_link: hand link -> real finger; links missing from it are arm links
    (ARM_COLOUR). colours: real finger -> colour (style.finger_colours).
    simulated: draw every link's collision shapes (what the simulator and the collision
    checker use) instead of its visual meshes.
    DescriptionError when the model cannot be loaded.
    """

    def __init__(
        self,
        model: UrdfModel,
        finger_of_link: Mapping[str, str],
        colours: Mapping[str, str],
        simulated: bool = False,
    ):
        from graspframe.robot_models.model import CollisionModel

        self.kinematics = CollisionModel(model)
        self.finger_of_link = dict(finger_of_link)
        self.soups: dict[str, Soup] = {}
        for meshes in robot_meshes(model):
            base = style.rgb(style.link_colour(meshes.link, finger_of_link, colours))
            surfaces = meshes.collision if simulated else meshes.shown
            parts = [Soup.of_mesh(s.vertices, s.faces, style.tinted(base, s.rgb)) for s in surfaces]
            if parts:
                self.soups[meshes.link] = Soup(
                    np.concatenate([p.positions for p in parts]),
                    np.concatenate([p.normals for p in parts]),
                    np.concatenate([p.albedo for p in parts]),
                )

    def place(self, q_by_joint: Mapping[str, float]) -> None:
        """Set the joints [rad or m] by name (others at zero); DescriptionError for a
        joint the model lacks."""
        self.kinematics.place(dict(q_by_joint))

    def T_root_frame(self, frame: str) -> NDArray[np.float64]:
        """Pose of a link or frame in the root frame, as last placed."""
        return self.kinematics.T_root_frame(frame)

    def has_frame(self, frame: str) -> bool:
        return bool(self.kinematics.model.existFrame(frame))

    def placed_links(self, T_world_root) -> dict[str, Placed]:
        """Every link's soup at its pose in the world, as last placed."""
        return {
            link: Placed(soup, T_world_root @ self.T_root_frame(link))
            for link, soup in self.soups.items()
        }

    def is_hand_link(self, link: str) -> bool:
        return link in self.finger_of_link


def distance_to(placed: Placed, p_world) -> float:
    """[m] smallest distance from the soup's triangle corners to a world point."""
    T = placed.T_world_soup
    p_soup = T[:3, :3].T @ (np.asarray(p_world, dtype=float) - T[:3, 3])
    return float(np.linalg.norm(placed.soup.positions - p_soup, axis=1).min())


def object_soup(obj, simulated: bool = False) -> Soup:
    """The object in the object frame: its display mesh
    (`graspframe.robot_models.shapes.object_mesh`), or with `simulated` its collision shapes
    (`graspframe.robot_models.shapes.object_collision_meshes`: a mesh object's convex
    pieces)."""
    from graspframe.robot_models.shapes import object_collision_meshes, object_mesh

    if simulated:
        pieces = object_collision_meshes(obj)
        vertices = np.concatenate([p.vertices for p in pieces])
        offsets = np.cumsum([0] + [len(p.vertices) for p in pieces[:-1]])
        faces = np.concatenate([p.faces + o for p, o in zip(pieces, offsets, strict=True)])
        return Soup.of_mesh(vertices, faces, style.rgb(style.OBJECT_COLOUR))
    mesh = object_mesh(obj)
    return Soup.of_mesh(mesh.vertices, mesh.faces, style.rgb(style.OBJECT_COLOUR))


def table_soup(centre_xy, half_size: float, height: float) -> Soup:
    """The table top (world frame): squares of TABLE_CELL on the world grid, alternating
    between the two TABLE_COLOURS, covering at least half_size [m] around centre_xy."""
    cell = style.TABLE_CELL
    n = math.ceil(half_size / cell)
    i0 = math.floor(float(centre_xy[0]) / cell) - n
    j0 = math.floor(float(centre_xy[1]) / cell) - n
    i, j = np.meshgrid(np.arange(i0, i0 + 2 * n), np.arange(j0, j0 + 2 * n), indexing="ij")
    i, j = i.reshape(-1), j.reshape(-1)
    x0, y0 = i * cell, j * cell
    x1, y1 = x0 + cell, y0 + cell
    z = np.full_like(x0, height, dtype=float)
    square = np.stack(
        [
            np.stack([x0, y0, z], axis=1),
            np.stack([x1, y0, z], axis=1),
            np.stack([x1, y1, z], axis=1),
            np.stack([x0, y0, z], axis=1),
            np.stack([x1, y1, z], axis=1),
            np.stack([x0, y1, z], axis=1),
        ],
        axis=1,
    )  # (squares, 6 corners, 3)
    light, dark = (np.asarray(style.rgb(c), dtype=np.float32) for c in style.TABLE_COLOURS)
    colour = np.where(((i + j) % 2 == 0)[:, None], light, dark)
    albedo = np.repeat(colour[:, None, :], 6, axis=1)
    normals = np.zeros_like(square)
    normals[..., 2] = 1.0
    return Soup(
        square.reshape(-1, 3).astype(np.float32),
        normals.reshape(-1, 3).astype(np.float32),
        albedo.reshape(-1, 3).astype(np.float32),
    )
