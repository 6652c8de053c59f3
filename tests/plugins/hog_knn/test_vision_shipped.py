"""The database shipped in the package loads, says how it was built, and classifies the
bundled demo image correctly."""

from __future__ import annotations

import json
from importlib.resources import files

import numpy as np
import pytest
from graspframe_hog_knn.classifier import HogKnnClassifier
from graspframe_hog_knn.database import FORMAT, load_database, read_metadata, shipped_database_path
from graspframe_hog_knn.rotations import angle_deg

from graspframe.cli.vision import classify_command
from graspframe.common.grasps import HumanGrasp
from graspframe.plugin_system.registry import default_registry
from graspframe.testing import estimate_problems
from graspframe.vision.images import read_image

MAX_SHIPPED_MB = 5.0
DEMO_MAX_ERROR_DEG = 20.0  # measured 2.5 deg


def test_shipped_database_is_package_data_and_compact():
    path = shipped_database_path()
    assert path.is_file() and path.with_suffix(".json").is_file()
    assert path.parent == __import__("pathlib").Path(str(files("graspframe_hog_knn") / "data"))
    assert path.stat().st_size < MAX_SHIPPED_MB * 1e6


def test_shipped_database_loads_with_readable_metadata():
    meta = read_metadata()
    assert meta["format"] == FORMAT
    assert meta["graspframe_version"]
    build = meta["build"]
    for key in ("views_per_grasp", "size_px", "seed", "pca_dims", "hog"):
        assert key in build
    db = load_database()
    assert len(db) == meta["views_stored"] > 1000
    assert set(np.unique(db.labels)) == set(range(len(HumanGrasp)))
    norms = np.linalg.norm(db.quat_xyzw, axis=1)
    np.testing.assert_allclose(norms, 1.0, atol=1e-3)


def test_registered_classifier_builds_fast_and_lazily():
    cls = default_registry().get_classifier("hog_knn")
    assert cls is HogKnnClassifier
    classifier = cls()
    assert classifier._database is None  # nothing loaded until the first image


@pytest.fixture(scope="module")
def demo():
    root = files("graspframe.run.demo")
    scene = json.loads((root / "scene.json").read_text())
    return read_image(root / "demo.png"), scene


def test_demo_scene_format(demo):
    image, scene = demo
    assert scene["format"] == "graspframe.scene/1"
    assert scene["object"] == "large_cylinder"
    for key in ("T_world_camera", "T_camera_object"):
        assert np.asarray(scene[key]).shape == (4, 4)
    assert np.asarray(scene["truth"]["T_camera_palm"]).shape == (4, 4)
    assert image.shape[2] == 3


def test_demo_image_is_classified_correctly(demo):
    image, scene = demo
    estimate = HogKnnClassifier().classify(image)
    truth = np.asarray(scene["truth"]["T_camera_palm"])
    error = angle_deg(estimate.R_camera_palm, truth[:3, :3])
    print(f"demo: {estimate.grasp.value} ({estimate.confidence:.2f}), error {error:.1f} deg")
    assert estimate.grasp.value == scene["truth"]["grasp"]
    assert error < DEMO_MAX_ERROR_DEG
    assert np.linalg.norm(estimate.p_camera_palm - truth[:3, 3]) < 0.05  # [m]


def test_the_estimate_shows_the_mask_and_the_crop_it_used(demo):
    from graspframe_hog_knn.segmentation import CROP_SIZE, hand_mask

    image, _ = demo
    estimate = HogKnnClassifier().classify(image)
    assert not estimate_problems(estimate, image.shape)
    pictures = {picture.name: picture for picture in estimate.pictures}
    assert [(p.name, p.kind) for p in estimate.pictures] == [("mask", "mask"), ("crop", "image")]
    # The whole hand is clear of the border: the mask is the plain skin mask.
    assert np.array_equal(pictures["mask"].pixels, hand_mask(image))
    assert pictures["crop"].pixels.shape == (CROP_SIZE, CROP_SIZE)


def test_classify_command_prints_json(capsys):
    path = files("graspframe.run.demo") / "demo.png"
    assert classify_command(path, k=8, as_json=True) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["grasp"] == "large_diameter"
    assert len(result["neighbours"]) == 8
    assert "roll-pitch-yaw" in result["euler_convention"]
    assert classify_command(path, k=5, as_json=False) == 0
    assert "large_diameter" in capsys.readouterr().out
