"""Images the classifier cannot use give a clear one-line error, never a guess."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from graspframe_hog_knn.classifier import HogKnnClassifier

from graspframe.cli.vision import classify_command
from graspframe.common.errors import GraspframeError, InputError
from graspframe.testing import assert_classifier_contract
from graspframe.vision.common import NoHandFoundError
from graspframe.vision.images import MAX_SIDE, read_image


@pytest.fixture(scope="module")
def classifier():
    # A database that does not exist: every refusal must happen before it is needed.
    return HogKnnClassifier(database_path="/nonexistent/views.npz")


@pytest.mark.parametrize(
    ("image", "words"),
    [
        (np.zeros((0, 0, 3), np.uint8), "empty"),
        (np.zeros(10, np.uint8), "colour"),
        (np.zeros((64, 64, 3), np.float32), "uint8"),
        (np.zeros((64, 64, 4), np.uint8), "H x W x 3"),
        (np.full((64, 64), 90, np.uint8), "grey-level"),
        (np.dstack([np.arange(64 * 64, dtype=np.uint8).reshape(64, 64)] * 3), "grey-level"),
        (np.zeros((MAX_SIDE + 1, 40, 3), np.uint8), f"maximum is {MAX_SIDE}"),
        (np.zeros((8, 8, 3), np.uint8), "minimum"),
        ("not an array", "image array"),
    ],
)
def test_unusable_images_are_refused(classifier, image, words):
    with pytest.raises(InputError) as info:
        classifier.classify(image)
    message = str(info.value)
    assert words in message and "\n" not in message


@pytest.mark.parametrize("colour", [(128, 128, 128), (200, 60, 20), (20, 160, 40), (255, 255, 255)])
def test_hand_free_images_are_refused(classifier, colour):
    image = np.zeros((120, 160, 3), np.uint8)
    image[:] = colour
    image[30:60, 40:90] = (220, 90, 10)  # a blue patch: colour, but not skin
    with pytest.raises(NoHandFoundError, match="no hand found"):
        classifier.classify(image)


def test_files_that_are_not_images(tmp_path):
    corrupt = tmp_path / "corrupt.png"
    _, png = cv2.imencode(".png", np.full((40, 40, 3), 100, np.uint8))
    corrupt.write_bytes(png.tobytes()[:60])  # truncated
    text = tmp_path / "notes.jpg"
    text.write_text("this is not a picture")
    empty = tmp_path / "empty.png"
    empty.write_bytes(b"")
    for path, words in [
        (corrupt, "not a readable image"),
        (text, "not a readable image"),
        (empty, "is empty"),
        (tmp_path / "missing.png", "not found"),
    ]:
        with pytest.raises(InputError, match=words):
            read_image(path)
        with pytest.raises(GraspframeError):
            classify_command(path, k=8, as_json=True)


def test_a_grey_level_file_is_refused(tmp_path):
    path = tmp_path / "grey.png"
    cv2.imwrite(str(path), np.full((64, 64), 77, np.uint8))
    with pytest.raises(InputError, match="grey-level"):
        classify_command(path, k=8, as_json=False)


def test_public_classifier_contract():
    assert_classifier_contract(HogKnnClassifier)


def test_the_users_k_reaches_the_classifier():
    from graspframe.hal import ClassifierOptions

    assert HogKnnClassifier.with_options(ClassifierOptions(k=3)).k == 3
    assert HogKnnClassifier.with_options(ClassifierOptions()).k == HogKnnClassifier().k
    with pytest.raises(InputError, match="k must be >= 1"):
        HogKnnClassifier.with_options(ClassifierOptions(k=0))
