"""A robot model's display meshes, per link, in the link's frame.

Two kinds per link:

- visual: the model's `<visual>` elements (`UrdfModel.visuals`): mesh files (OBJ, STL,
  COLLADA .dae through pycollada, anything trimesh reads) with the colours of their
  materials, and primitives with the URDF's colour. A mesh file is decoded once per
  process and decimated by vertex clustering to at most `MAX_TRIANGLES` triangles per
  file (the LEAP palm's 87k triangles become 2.5k, in 6 mm clusters: its flat faces and
  edges stay, its screw holes go; a finger segment of 30k becomes 3k);
- collision: the collision shapes as Pinocchio and coal hold them
  (`graspframe.robot_models.shapes.geometry_mesh`: primitives, and the convex pieces of collision
  meshes), i.e. the geometry the simulator and the collision checks use.

`robot_meshes(model)` computes both once per model and process. Pictures draw a link's
visual meshes when it has any, else its collision shapes (`LinkMeshes.shown`); the
recording logs both.
"""

from __future__ import annotations

import functools
import os
from collections import OrderedDict
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import DescriptionError
from graspframe.common.transforms import inv_T, transform_points
from graspframe.model_files.urdf_elements import Visual
from graspframe.model_files.urdf_model import UrdfModel
from graspframe.robot_models.shapes import geometry_mesh, primitive_mesh

MAX_TRIANGLES = 3000  # per mesh file, after decimation
MIN_PART_TRIANGLES = 64  # a small part of a file keeps at least this many
FILL = 0.7  # decimation aims at between FILL and 1 times its triangle budget
DECIMATION_TRIES = 12
CACHED_MODELS = 16  # robot models whose meshes stay in memory

RGB = tuple[float, float, float]


@dataclass(frozen=True)
class Surface:
    """A triangle mesh to draw: vertices (n, 3) [m] in its frame, faces (m, 3) indices,
    rgb: its material colour in [0, 1], None when it has none of its own."""

    vertices: NDArray[np.float64]
    faces: NDArray[np.int64]
    rgb: RGB | None = None

    def moved(self, T_a_b: NDArray[np.float64]) -> Surface:
        """This surface (given in frame b) expressed in frame a."""
        vertices = transform_points(T_a_b, self.vertices).reshape(-1, 3)
        return Surface(vertices, self.faces, self.rgb)


@dataclass(frozen=True)
class LinkMeshes:
    """The display meshes of one link, in the link frame."""

    link: str
    visual: tuple[Surface, ...]
    collision: tuple[Surface, ...]

    @property
    def shown(self) -> tuple[Surface, ...]:
        """What pictures draw: the visual meshes, or the collision shapes without them."""
        return self.visual or self.collision


def decimate(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], max_triangles: int
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """(vertices, faces) with at most `max_triangles` faces: vertices merged per cubic
    cell (vertex clustering, each cluster at its mean), the cell sized so that between
    FILL and 1 times `max_triangles` triangles remain (a few tries); degenerate and
    repeated triangles dropped. Unchanged when already small enough."""
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    if len(faces) <= max_triangles:
        return vertices, faces
    corners = vertices[faces]
    area = (
        0.5
        * np.linalg.norm(
            np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1
        ).sum()
    )
    # A surface of area A in cells of size c keeps about 2 A / c^2 triangles.
    cell = max(float(np.sqrt(2.0 * area / max_triangles)), 1e-6)
    best = None
    for _ in range(DECIMATION_TRIES):
        merged_vertices, merged_faces = _cluster(vertices, faces, cell)
        if len(merged_faces) <= max_triangles:
            best = merged_vertices, merged_faces
            if len(merged_faces) >= FILL * max_triangles:
                break
            cell *= 0.85
        elif best is not None:
            break
        else:
            cell *= 1.25
    if best is None:
        best = _cluster(vertices, faces, 4.0 * cell)
    return best


def vertex_normals(vertices, faces) -> NDArray[np.float64]:
    """(n, 3) unit normals per vertex: the mean of its faces' normals, weighted by area."""
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    corners = vertices[faces]
    face_normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals = np.zeros_like(vertices)
    for k in range(3):
        np.add.at(normals, faces[:, k], face_normals)
    return normals / np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)


def _cluster(vertices, faces, cell: float):
    keys = np.floor((vertices - vertices.min(axis=0)) / cell).astype(np.int64)
    _, cluster = np.unique(keys, axis=0, return_inverse=True)
    cluster = cluster.reshape(-1)
    counts = np.bincount(cluster).astype(float)
    means = np.stack(
        [np.bincount(cluster, weights=vertices[:, k]) / counts for k in range(3)], axis=1
    )
    merged = cluster[faces]
    a, b, c = merged[:, 0], merged[:, 1], merged[:, 2]
    merged = merged[(a != b) & (b != c) & (a != c)]
    _, first = np.unique(np.sort(merged, axis=1), axis=0, return_index=True)
    merged = merged[np.sort(first)]
    used, compact = np.unique(merged, return_inverse=True)
    return means[used], compact.reshape(-1, 3)


def _material_rgb(mesh) -> RGB | None:
    """The colour a mesh file gives a part (its material's or its main colour), None
    when the file gives none."""
    visual = mesh.visual
    if visual is None or visual.kind is None:
        return None
    if visual.kind == "texture":
        colour = getattr(visual.material, "main_color", None)
    else:
        colour = visual.main_color
    if colour is None:
        return None
    rgba = np.asarray(colour, dtype=float).reshape(-1)
    return (float(rgba[0]) / 255.0, float(rgba[1]) / 255.0, float(rgba[2]) / 255.0)


@functools.lru_cache(maxsize=256)
def _mesh_file(path: str, modified_ns: int, scale: tuple[float, float, float]):
    """The parts of a mesh file (its node transforms applied, scaled), decimated."""
    import trimesh

    del modified_ns  # part of the cache key only: a changed file is read again
    try:
        scene = trimesh.load_scene(path)
    except Exception as exc:
        raise DescriptionError(f"cannot read the visual mesh {path}: {exc}") from exc
    parts = [m for m in scene.dump() if isinstance(m, trimesh.Trimesh) and len(m.faces)]
    total = sum(len(m.faces) for m in parts)
    surfaces = []
    for part in parts:
        budget = max(MIN_PART_TRIANGLES, MAX_TRIANGLES * len(part.faces) // total)
        vertices, faces = decimate(
            np.asarray(part.vertices) * np.asarray(scale), part.faces, budget
        )
        if len(faces):
            surfaces.append(Surface(vertices, faces, _material_rgb(part)))
    return tuple(surfaces)


def visual_surfaces(visual: Visual) -> tuple[Surface, ...]:
    """The surfaces of one visual element, in its link's frame. A mesh part without a
    colour of its own takes the URDF's colour (None without one)."""
    urdf_rgb = None if visual.rgba is None else tuple(float(v) for v in visual.rgba[:3])
    if visual.shape == "mesh":
        if visual.mesh_path is None:
            return ()
        path = Path(visual.mesh_path)
        try:
            modified_ns = os.stat(path).st_mtime_ns
        except OSError as exc:
            raise DescriptionError(f"link {visual.link!r}: visual mesh {path}: {exc}") from exc
        scale = tuple(float(s) for s in visual.scale)
        parts = _mesh_file(str(path), modified_ns, scale)
        return tuple(
            Surface(
                transform_points(visual.T_link_visual, part.vertices).reshape(-1, 3),
                part.faces,
                part.rgb if part.rgb is not None else urdf_rgb,  # type: ignore[arg-type]
            )
            for part in parts
        )
    mesh = primitive_mesh(visual.shape, visual.dimensions)
    surface = Surface(np.asarray(mesh.vertices), np.asarray(mesh.faces), urdf_rgb)  # type: ignore[arg-type]
    return (surface.moved(visual.T_link_visual),)


def _model_key(model: UrdfModel) -> tuple:
    visuals = tuple(
        (
            v.link,
            v.shape,
            str(v.mesh_path),
            tuple(v.scale),
            v.rgba,
            tuple(sorted(v.dimensions.items())),
            np.round(v.T_link_visual, 12).tobytes(),
        )
        for v in model.visuals
    )
    return (model.digest, visuals)


_ROBOT_MESHES: OrderedDict[tuple, tuple[LinkMeshes, ...]] = OrderedDict()


def robot_meshes(model: UrdfModel) -> tuple[LinkMeshes, ...]:
    """Every link's display meshes (links with neither visuals nor collision shapes left
    out), in the model's link order; computed once per model and process."""
    key = _model_key(model)
    if key in _ROBOT_MESHES:
        _ROBOT_MESHES.move_to_end(key)
        return _ROBOT_MESHES[key]
    meshes = _link_meshes(model)
    _ROBOT_MESHES[key] = meshes
    while len(_ROBOT_MESHES) > CACHED_MODELS:
        _ROBOT_MESHES.popitem(last=False)
    return meshes


def _link_meshes(model: UrdfModel) -> tuple[LinkMeshes, ...]:
    from graspframe.robot_models.model import CollisionModel

    collision_model = CollisionModel(model)  # at its neutral configuration
    collision: dict[str, list[Surface]] = {}
    for link, geometry, T_root_shape in collision_model.shapes():
        mesh = geometry_mesh(geometry)
        if mesh is None:
            continue
        T_link_shape = inv_T(collision_model.T_root_frame(link)) @ T_root_shape
        surface = Surface(np.asarray(mesh.vertices), np.asarray(mesh.faces, dtype=np.int64))
        collision.setdefault(link, []).append(surface.moved(T_link_shape))
    visual: dict[str, list[Surface]] = {}
    for element in model.visuals:
        visual.setdefault(element.link, []).extend(visual_surfaces(element))
    order = [e.get("name", "") for e in model.root().findall("link")]
    return tuple(
        LinkMeshes(link, tuple(visual.get(link, ())), tuple(collision.get(link, ())))
        for link in order
        if link in visual or link in collision
    )
