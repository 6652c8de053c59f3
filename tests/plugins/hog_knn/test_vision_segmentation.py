"""Hand segmentation: refusal of hand-free images, renders unchanged, real photos."""

from __future__ import annotations

import csv
from pathlib import Path

import cv2
import numpy as np
import pytest
from graspframe_hog_knn.classifier import HogKnnClassifier
from graspframe_hog_knn.database import iter_views
from graspframe_hog_knn.segmentation import crop_hand, hand_mask, segment_hand
from graspframe_hog_knn.views import HELD_OUT

from graspframe.vision.common import MIRROR_X, NoHandFoundError, unmirror
from graspframe.vision.images import read_image

REAL_PHOTOS = Path("/work/shared/real_photos")
DEMO = Path(__file__).parents[3] / "graspframe" / "run" / "demo" / "demo.png"


def _noisy(image: np.ndarray, sigma: float, seed: int = 0) -> np.ndarray:
    noise = np.random.default_rng(seed).normal(0, sigma, image.shape)
    return np.clip(image + noise, 0, 255).astype(np.uint8)


def wood_texture(h: int = 240, w: int = 320, seed: int = 0) -> np.ndarray:
    """A procedural wood grain: warm brown with wavy darker rings and noise (BGR)."""
    rng = np.random.default_rng(seed)
    v, u = np.mgrid[0:h, 0:w].astype(np.float64)
    warp = 6 * np.sin(u / 37 + rng.uniform(0, 6)) + 3 * np.sin(u / 11)
    rings = 0.5 + 0.5 * np.sin((v + warp) / 4.5)
    base = np.array([70, 120, 175], np.float64)  # BGR of a light oak
    dark = np.array([40, 80, 130], np.float64)
    image = base * (1 - rings[..., None]) + dark * rings[..., None]
    return _noisy(image, 4, seed)


@pytest.fixture(scope="module")
def classifier():
    # A database that does not exist: every refusal must happen before it is needed.
    return HogKnnClassifier(database_path="/nonexistent/views.npz")


@pytest.mark.parametrize(
    ("name", "image", "words"),
    [
        ("uniform skin", np.full((240, 320, 3), (120, 160, 210), np.uint8), "uniform"),
        ("noisy skin wall", _noisy(np.full((240, 320, 3), (120, 160, 210), float), 3), "uniform"),
        ("blank white", _noisy(np.full((240, 320, 3), 248, float), 2), "uniform"),
        ("warm white", _noisy(np.full((240, 320, 3), (225, 235, 250), float), 2), "uniform"),
        ("wood", wood_texture(), "skin-coloured surface"),
        ("wood 2", wood_texture(480, 640, seed=3), "skin-coloured surface"),
    ],
)
def test_hand_free_images_are_refused(classifier, name, image, words):
    assert skin_share(image) > 0.9 or name.startswith(("blank", "warm"))
    with pytest.raises(NoHandFoundError) as info:
        classifier.classify(image)
    message = str(info.value)
    assert words in message and "\n" not in message, name


def skin_share(image: np.ndarray) -> float:
    from graspframe_hog_knn.segmentation import skin_pixels

    return float(np.count_nonzero(skin_pixels(image)) / skin_pixels(image)[..., None].size)


def test_classify_command_exits_non_zero_on_wood(tmp_path):
    import subprocess
    import sys

    path = tmp_path / "table.png"
    cv2.imwrite(str(path), wood_texture())
    done = subprocess.run(
        [sys.executable, "-m", "graspframe.cli.commands", "classify", str(path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode != 0
    lines = [line for line in done.stderr.splitlines() + done.stdout.splitlines() if line]
    assert any("skin-coloured surface" in line for line in lines), lines


def test_renders_segment_as_before():
    """A rendered view (hand clear of the border, non-skin background) keeps the plain
    skin-box segmentation: the database built with it stays valid."""
    checked = 0
    for view in iter_views(range(40), 9_000_001, 128, HELD_OUT.name):
        try:
            old = crop_hand(view.image, hand_mask(view.image))
        except NoHandFoundError:
            continue
        new = segment_hand(view.image)
        assert not new.mirrored
        assert np.array_equal(new.patch, old.patch) and new.box == old.box
        checked += 1
    assert checked >= 35


def test_demo_and_renders_are_still_classified():
    classifier = HogKnnClassifier()
    estimate = classifier.classify(read_image(DEMO))
    assert estimate.grasp.value == "large_diameter"
    answered = 0
    for view in iter_views(range(30), 9_000_001, 128, HELD_OUT.name):
        try:
            classifier.classify(view.image)
        except NoHandFoundError:
            continue
        answered += 1
    assert answered >= 28


def test_a_left_hand_estimate_is_reflected_back_to_a_proper_rotation():
    R_mirrored = cv2.Rodrigues(np.array([0.3, -0.7, 1.1]))[0]
    R = unmirror(R_mirrored)
    assert np.allclose(R @ R.T, np.eye(3)) and np.isclose(np.linalg.det(R), 1.0)
    # The fingertip direction (x) and the palm normal (z) are the mirrored estimate's,
    # reflected back through the image's vertical axis.
    assert np.allclose(R[:, 0], MIRROR_X @ R_mirrored[:, 0])
    assert np.allclose(R[:, 2], MIRROR_X @ R_mirrored[:, 2])


def _real_rows():
    if not (REAL_PHOTOS / "labels.csv").is_file():
        pytest.skip(f"{REAL_PHOTOS} is absent: the real photographs are not part of the project")
    with (REAL_PHOTOS / "labels.csv").open(newline="") as stream:
        return [(REAL_PHOTOS / row["file"], row["grasp_type"]) for row in csv.DictReader(stream)]


def test_real_hands_are_segmented_not_refused():
    """Every real photograph of a grasp gives a hand crop (none is refused), and the
    crop is not the whole image."""
    rows = _real_rows()
    for path, _ in rows:
        image = read_image(path)
        crop = segment_hand(image)
        assert crop.area < 0.9 * image.shape[0] * image.shape[1], path.name


def test_a_left_hand_mask_is_shown_in_the_image_pixels():
    """The crop of a left hand is taken from the mirrored image; the mask the classifier
    shows is flipped back onto the image it was given."""
    from graspframe_hog_knn.classifier import pictures
    from graspframe_hog_knn.segmentation import crop_hand_mirrored

    image = read_image(DEMO)
    mask = hand_mask(image)
    crop = crop_hand_mirrored(image, mask)
    assert crop.mirrored and not np.array_equal(crop.mask, mask)
    shown = {picture.name: picture.pixels for picture in pictures(crop)}
    assert np.array_equal(shown["mask"], mask)
    assert np.array_equal(shown["crop"], crop.patch)
