"""graspframe.pictures: display meshes, views and the picture of one hand around an object
(check-hand), with the real rasteriser and the real robot models. The Panda's COLLADA
visual meshes are read from the third-party models beside the project (skipped when they
are not there)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh
from conftest import THIRD_PARTY
from test_snapshots import hue_mask, read_rgb, red_pixels

from graspframe.checks.grasps import design_object
from graspframe.common.errors import InputError
from graspframe.common.transforms import inv_T, make_T, transform_points
from graspframe.model_files.urdf_model import read_model
from graspframe.pictures import style
from graspframe.pictures.hand_grasp import PANEL_PX, draw_hand_grasp
from graspframe.pictures.meshes import MAX_TRIANGLES, decimate, robot_meshes
from graspframe.pictures.render3d import Camera, Placed, Soup, fit_view, visible
from graspframe.pictures.sheet import GAP, MARGIN, PANEL_EDGE, compose
from graspframe.plugin_system.registry import default_registry
from graspframe.strategy.reference_poses import R_object_palm_for_design

PANDA_PACKAGE = THIRD_PARTY / "arms" / "panda" / "example-robot-data"
PANDA_URDF = PANDA_PACKAGE / "robots" / "panda_description" / "urdf" / "panda.urdf"


def test_decimation_keeps_the_shape_within_the_triangle_budget():
    sphere = trimesh.creation.icosphere(subdivisions=5, radius=0.05)  # 20480 triangles
    vertices, faces = decimate(sphere.vertices, sphere.faces, 2000)
    assert 0.7 * 2000 <= len(faces) <= 2000
    radii = np.linalg.norm(vertices, axis=1)
    assert np.all(np.abs(radii - 0.05) < 0.004)  # still the sphere, within a cluster
    small = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    unchanged = decimate(small.vertices, small.faces, 2000)
    np.testing.assert_array_equal(unchanged[1], small.faces)


def test_a_fitted_view_shows_every_point_and_visibility_sees_through_nothing():
    camera = Camera.from_fov(200, 200, 30.0)
    centre = np.array([0.5, 0.2, 0.3])
    points = centre + np.random.default_rng(0).uniform(-0.1, 0.1, (50, 3))
    view = fit_view(camera, points, (1.0, -1.0, 0.5), (0.0, 0.0, 1.0))
    pixels, depth = view.project(points)
    assert np.all(depth > 0)
    assert np.all((pixels >= 0) & (pixels <= 200))
    # A 10 cm box between the camera and a point hides it; a point in front shows.
    box = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    soup = Soup.of_mesh(box.vertices, box.faces, (0.5, 0.5, 0.5))
    placed = [Placed(soup, make_T(p=centre))]
    eye = view.T_world_camera[:3, 3]
    towards_eye = (eye - centre) / np.linalg.norm(eye - centre)
    behind, in_front = centre - 0.1 * towards_eye, centre + 0.1 * towards_eye
    np.testing.assert_array_equal(visible(placed, view, [behind, in_front]), [False, True])


@pytest.mark.skipif(not PANDA_URDF.is_file(), reason="the third-party models are not here")
def test_collada_visual_meshes_are_read_decimated_with_their_colours():
    model = read_model(
        PANDA_URDF, packages={"example-robot-data": PANDA_PACKAGE}, cut_below="panda_link8"
    )
    meshes = {m.link: m for m in robot_meshes(model)}
    assert robot_meshes(model) is robot_meshes(model)  # once per model and process
    link6 = meshes["panda_link6"]
    assert len(link6.visual) > 1 and link6.collision  # COLLADA parts, and the hull pieces
    assert sum(len(s.faces) for s in link6.visual) <= MAX_TRIANGLES + 64 * len(link6.visual)
    colours = {s.rgb for s in link6.visual}
    assert len(colours) > 1  # the white shell and the dark parts keep their own colours
    extent = np.ptp(np.concatenate([s.vertices for s in link6.visual]), axis=0)
    assert 0.05 < extent.max() < 0.3  # metres, not millimetres


@pytest.fixture(scope="module")
def karlsruhe_wrap():
    """The Karlsruhe hand's wrap preshape closed, its design object where it is held."""
    hand = default_registry().get_hand("karlsruhe")
    preshape = hand.preshape("wrap")
    obj = design_object(preshape)
    R = R_object_palm_for_design(preshape.design_object)
    T_palm_object = inv_T(make_T(R, -R @ np.asarray(preshape.grasp_center_palm)))
    return hand, preshape, obj, T_palm_object


def test_one_hand_around_its_design_object(tmp_path: Path, karlsruhe_wrap):
    hand, preshape, obj, T_palm_object = karlsruhe_wrap
    contacts_object = np.array([[0.0, obj.dimensions["radius"], 0.0]])
    contacts_palm = transform_points(T_palm_object, contacts_object).reshape(-1, 3)
    path = tmp_path / "check" / "wrap.png"
    caption = "karlsruhe wrap: closed around its design handle"
    assert (
        draw_hand_grasp(path, hand, preshape.closed_q, obj, T_palm_object, contacts_palm,
                        ["thumb"], caption)
        == path
    )  # fmt: skip
    image = read_rgb(path)
    assert PANEL_PX * 2 < image.shape[1] < PANEL_PX * 2 + 60  # two panels side by side
    assert PANEL_PX < image.shape[0] < PANEL_PX + 200
    colours = style.finger_colours(hand.finger_of_link())
    for finger in ("thumb", "index", "middle"):
        assert np.count_nonzero(hue_mask(image, colours[finger])) > 1500, finger
    assert np.count_nonzero(hue_mask(image, style.OBJECT_COLOUR, tol_deg=6)) > 1000
    assert red_pixels(image) > 2 * 20  # the contact in both views (plus the legend's)
    open_path = tmp_path / "open.png"
    draw_hand_grasp(open_path, hand, preshape.open_q, obj, T_palm_object, [], [], caption)
    thumb = colours["thumb"]
    changed = hue_mask(read_rgb(open_path), thumb) ^ hue_mask(image, thumb)
    assert np.count_nonzero(changed) > 1000  # the thumb moved


def test_bad_hand_picture_input_is_one_line(tmp_path: Path, karlsruhe_wrap):
    hand, preshape, obj, T_palm_object = karlsruhe_wrap
    path = tmp_path / "bad.png"
    cases = [
        ({"T_palm_object": np.eye(3)}, "T_palm_object must be a 4x4"),
        ({"contact_fingers": ["thumb", "index"]}, "1 contact points but 2 contact fingers"),
        ({"q_by_joint": {"no_such_joint": 0.1}}, "no_such_joint"),
        ({"obj": None}, "must be an ObjectDescription"),
    ]
    for change, message in cases:
        arguments = {
            "path": path,
            "hand": hand,
            "q_by_joint": preshape.closed_q,
            "obj": obj,
            "T_palm_object": T_palm_object,
            "contact_points_palm": np.zeros((1, 3)),
            "contact_fingers": ["thumb"],
            "caption": "bad",
        } | change
        with pytest.raises(InputError, match=message) as info:
            draw_hand_grasp(**arguments)
        assert "\n" not in str(info.value)
    assert not path.exists()


def _above_the_panels(sheet: np.ndarray) -> np.ndarray:
    """The band of a sheet above its panels (title and column headers): down to the top
    of the first panel's frame, a long vertical run of the frame's grey."""
    edge_column = sheet[:, MARGIN - 1]
    for top in range(len(sheet)):
        if np.all(edge_column[top : top + 20] == PANEL_EDGE):
            return sheet[:top]
    raise AssertionError("no panel frame found")


def _white(pixels: np.ndarray) -> bool:
    return bool(np.all(pixels == 255))


LONG_HEADERS = (
    "hold\n16 contacts: index 1, little 2, middle 3, palm 7, ring 1, thumb 2",
    "after lift (object out of view)\n"
    "ycb_005_tomato_soup_can_lying_on_its_side_after_the_lift: 1 contact, palm 1",
    "released\nno contacts",
)


def test_column_headers_stay_within_their_columns():
    """However long a column's header (contacts of every finger, an object's long name
    that no space breaks), its text stays over its own panel: the gaps between the
    panels and the margins stay white above them."""
    panel_w, columns = 220, len(LONG_HEADERS)
    panels = [[np.full((100, panel_w, 3), 255, np.uint8)] * columns]
    sheet = compose("", LONG_HEADERS, [], panels, [])
    band = _above_the_panels(sheet)
    assert not _white(band), "no header drawn"
    assert _white(band[:, :MARGIN]) and _white(band[:, -MARGIN:])
    for column in range(columns - 1):
        right_edge = MARGIN + column * (panel_w + GAP) + panel_w
        assert _white(band[:, right_edge + 1 : right_edge + GAP - 1]), f"gap after {column}"


def test_the_title_stays_within_the_margins():
    long_word = "ycb_005_tomato_soup_can_lying_on_its_side_after_the_lift_" * 2
    panels = [[np.full((100, 150, 3), 255, np.uint8)] * 2]
    sheet = compose(f"human pinch, {long_word}; held", ["", ""], [], panels, [])
    band = _above_the_panels(sheet)
    assert not _white(band), "no title drawn"
    assert _white(band[:, :MARGIN]) and _white(band[:, -MARGIN:])
