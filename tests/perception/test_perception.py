"""The depth camera and the object localisation, on the real CPU rasteriser: the
sensor noise model's statistics, the depth of a rendered scene, the object fitted from a
displaced belief, and a fit that must be refused."""

from __future__ import annotations

import numpy as np
import pytest
from graspframe_depth_sim.camera import ideal_depth

from graspframe.common.camera import Camera
from graspframe.hal.depth_camera import DepthImage
from graspframe.hal.objects import ObjectDescription
from graspframe.perception.depth_noise import BASELINE, DISPARITY_STEP_PX, FOCAL_PX, DepthNoise
from graspframe.perception.localise import (
    INLIER_DISTANCE,
    MIN_POINTS,
    ObjectModel,
    fit_object,
)
from graspframe.pictures.render3d import Placed, look_at
from graspframe.pictures.robot_scene import object_soup, table_soup

CAMERA = Camera(320, 240, 290.0, 290.0, 160.0, 120.0)
CAN = ObjectDescription("can", "cylinder", {"radius": 0.033, "length": 0.12}, mass=0.3)
EYE = np.array([0.15, -0.45, 0.8])  # [m] a head camera beside the arm's base


def _pose(x: float, y: float, z: float) -> np.ndarray:
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def test_a_rendered_plane_has_its_distance_at_every_pixel():
    T_world_camera = look_at((0.0, 0.0, 1.0), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0))
    table = Placed(table_soup((0.0, 0.0), 2.0, 0.0), np.eye(4))
    depth = ideal_depth([table], CAMERA, T_world_camera)
    assert depth.shape == (240, 320)
    assert np.allclose(depth, 1.0, atol=1e-4)


def test_the_noise_grows_with_distance_and_follows_its_model():
    rng = np.random.default_rng(0)
    noise = DepthNoise()
    for z in (0.8, 1.6):
        ideal = np.full((200, 200), z, dtype=np.float32)
        measured = noise.apply(ideal, 290.0, 290.0, rng)
        sigma = noise.axial_sigma(np.array(z), np.array(0.0))
        step = z**2 * DISPARITY_STEP_PX / (FOCAL_PX * BASELINE)
        # Quantisation adds step^2 / 12 to the variance of the Gaussian.
        expected = np.sqrt(sigma**2 + step**2 / 12)
        assert np.nanstd(measured) == pytest.approx(expected, rel=0.1)
        levels = np.unique(np.round(measured[np.isfinite(measured)] / step, 6))
        assert np.allclose(levels, np.round(levels)), "depth is quantised in disparity steps"
    doubled = DepthNoise(2.0).apply(np.full((200, 200), 1.0, np.float32), 290, 290, rng)
    single = noise.apply(np.full((200, 200), 1.0, np.float32), 290, 290, rng)
    assert np.nanstd(doubled) > 1.7 * np.nanstd(single)


def test_grazing_surfaces_edges_and_empty_pixels_return_nothing():
    rng = np.random.default_rng(0)
    ideal = np.full((100, 100), np.inf, dtype=np.float32)
    ideal[:, :50] = 1.0  # a plane seen head-on beside nothing
    measured = DepthNoise().apply(ideal, 290.0, 290.0, rng)
    assert np.isnan(measured[:, 60:]).all()
    assert np.isfinite(measured[:, :40]).all()
    assert np.isnan(measured[:, 49]).mean() > 0.2  # the edge drops pixels
    # A surface seen at 80 deg from head-on (each row tan(80 deg) / f deeper, relative
    # to its depth, than the one above): no return.
    rows = np.arange(100, dtype=np.float64)[:, None]
    growth = 1.0 + np.tan(np.radians(80)) / 290.0
    steep = np.broadcast_to(0.6 * growth**rows, (100, 100)).astype(np.float32)
    assert np.isnan(DepthNoise().apply(steep.copy(), 290.0, 290.0, rng)[5:95, 5:95]).all()


def _image(T_world_object, seed: int = 0, scale: float = 1.0) -> DepthImage:
    T_world_camera = look_at(EYE, T_world_object[:3, 3], (0.0, 0.0, 1.0))
    placed = [
        Placed(object_soup(CAN), T_world_object),
        Placed(table_soup(T_world_object[:2, 3], 1.5, 0.0), np.eye(4)),
    ]
    ideal = ideal_depth(placed, CAMERA, T_world_camera)
    measured = DepthNoise(scale).apply(ideal, CAMERA.fx, CAMERA.fy, np.random.default_rng(seed))
    return DepthImage(measured, CAMERA, T_world_camera)


@pytest.mark.parametrize("scale", [1.0, 2.0], ids=["noise", "noise-doubled"])
@pytest.mark.parametrize("direction_deg", [0, 120, 240])
def test_the_object_is_found_from_a_belief_5_cm_off(direction_deg, scale):
    T_true = _pose(0.55, 0.2, 0.06)
    a = np.radians(direction_deg)
    T_believed = _pose(0.55 + 0.05 * np.cos(a), 0.2 + 0.05 * np.sin(a), 0.06)
    fit = fit_object(_image(T_true, scale=scale), ObjectModel(CAN), T_believed, 0.0)
    assert fit.accepted, fit.reason
    assert np.linalg.norm(fit.T_world_object[:2, 3] - T_true[:2, 3]) < 0.003
    assert fit.rms_mm < 1000 * INLIER_DISTANCE
    shift = np.array(fit.shift_xy)
    assert np.allclose(shift, T_true[:2, 3] - T_believed[:2, 3], atol=0.003)


def test_a_fit_without_the_object_in_sight_is_refused_and_says_why():
    T_true = _pose(0.55, 0.2, 0.06)
    T_believed = _pose(0.95, 0.2, 0.06)  # 40 cm off: the search sees only the table
    fit = fit_object(_image(T_true), ObjectModel(CAN), T_believed, 0.0)
    assert not fit.accepted
    assert fit.reason is not None and f"fewer than {MIN_POINTS}" in fit.reason
    assert fit.to_json()["accepted"] is False


def test_a_fit_of_the_wrong_model_is_refused():
    """A box where the model says a thin cylinder: the points do not lie on it."""
    box = ObjectDescription("box", "box", {"size_x": 0.12, "size_y": 0.12, "size_z": 0.12}, mass=1)
    T_true = _pose(0.55, 0.2, 0.06)
    T_world_camera = look_at(EYE, T_true[:3, 3], (0.0, 0.0, 1.0))
    placed = [
        Placed(object_soup(box), T_true),
        Placed(table_soup((0.55, 0.2), 1.5, 0.0), np.eye(4)),
    ]
    ideal = ideal_depth(placed, CAMERA, T_world_camera)
    measured = DepthNoise().apply(ideal, CAMERA.fx, CAMERA.fy, np.random.default_rng(0))
    thin = ObjectDescription("pen", "cylinder", {"radius": 0.008, "length": 0.12}, mass=0.02)
    fit = fit_object(DepthImage(measured, CAMERA, T_world_camera), ObjectModel(thin), T_true, 0.0)
    assert not fit.accepted
    assert fit.reason is not None


def test_points_come_back_where_they_were_rendered():
    T_world_camera = look_at(EYE, (0.55, 0.2, 0.06), (0.0, 0.0, 1.0))
    T_object = _pose(0.55, 0.2, 0.06)
    ideal = ideal_depth([Placed(object_soup(CAN), T_object)], CAMERA, T_world_camera)
    image = DepthImage(np.where(np.isfinite(ideal), ideal, np.nan), CAMERA, T_world_camera)
    p_object = image.points_world() - T_object[:3, 3]
    radial = np.linalg.norm(p_object[:, :2], axis=1)
    on_side = np.abs(p_object[:, 2]) < 0.05
    assert on_side.sum() > 200
    assert np.allclose(radial[on_side], 0.033, atol=0.002)
