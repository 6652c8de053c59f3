"""Shape conversions (graspframe.robot_models.shapes): meshes and coal shapes of the right size."""

from __future__ import annotations

import coal
import numpy as np
import pytest

from graspframe.robot_models.shapes import (
    coal_geometry,
    geometry_mesh,
    geometry_primitive,
    primitive_mesh,
)

PRIMITIVES = [
    ("box", {"size_x": 0.1, "size_y": 0.2, "size_z": 0.3}, [0.05, 0.1, 0.15]),
    ("cylinder", {"radius": 0.03, "length": 0.12}, [0.03, 0.03, 0.06]),
    ("sphere", {"radius": 0.04}, [0.04, 0.04, 0.04]),
]


@pytest.mark.parametrize(("shape", "dimensions", "half_extents"), PRIMITIVES)
def test_primitive_mesh_is_centred_and_of_its_size(shape, dimensions, half_extents):
    mesh = primitive_mesh(shape, dimensions)
    np.testing.assert_allclose(mesh.bounds, [np.negative(half_extents), half_extents], atol=1e-12)
    assert mesh.is_watertight


@pytest.mark.parametrize(("shape", "dimensions", "half_extents"), PRIMITIVES)
def test_coal_shape_and_back(shape, dimensions, half_extents):
    geometry = coal_geometry(shape, dimensions)
    back_shape, back_dimensions = geometry_primitive(geometry)
    assert back_shape == shape
    assert back_dimensions == pytest.approx(dimensions)
    np.testing.assert_allclose(
        geometry_mesh(geometry).bounds, [np.negative(half_extents), half_extents], atol=1e-12
    )


def test_capsule_and_cone_are_centred_on_their_frame():
    capsule = geometry_mesh(coal.Capsule(0.02, 0.1))  # radius, length between the centres
    np.testing.assert_allclose(capsule.bounds, [[-0.02, -0.02, -0.07], [0.02, 0.02, 0.07]])
    cone = geometry_mesh(coal.Cone(0.03, 0.08))  # radius, height
    np.testing.assert_allclose(cone.bounds, [[-0.03, -0.03, -0.04], [0.03, 0.03, 0.04]])


def test_cylinder_sections_set_the_rim_samples():
    mesh = primitive_mesh("cylinder", {"radius": 1.0, "length": 2.0}, sections=12)
    rim = mesh.vertices[np.isclose(mesh.vertices[:, 2], -1.0)]
    angles = np.sort(np.degrees(np.arctan2(rim[:, 1], rim[:, 0])) % 360)
    np.testing.assert_allclose(
        angles[np.linalg.norm(rim[:, :2], axis=1) > 0.5], np.arange(0, 360, 30)
    )
