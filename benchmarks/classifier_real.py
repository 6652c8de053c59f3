"""Benchmark of the grasp classifier on real photographs.

    python benchmarks/classifier_real.py DIR [--k K] [--classifier NAME]

DIR holds the photos and a labels.csv with at least the columns `file` and `grasp_type`
(one of the six grasp names, or `other`: a real grasp that is none of the six). Each
photo is classified as `graspframe classify --classifier NAME` would (default hog_knn;
`landmarks` needs the `hands` extra); an image the classifier refuses
(no hand found, a bad image) counts as refused. Prints, over the photos of the six
classes: top-1 accuracy with refusals counted wrong, top-1 of the answered ones, per-class
top-1 (chance is 1/6), the confusion matrix and the refusal rate; for the `other` rows,
how many were refused (the right answer for a grasp outside the six) and what was
answered for the rest; the median latency per image. When DIR does not exist, says so
and exits 0 (the photos are not part of the project).
"""

from __future__ import annotations

import argparse
import csv
import statistics
import sys
import time
from pathlib import Path

from graspframe_hog_knn.classifier import DEFAULT_K
from graspframe_hog_knn.views import GRASPS

from graspframe.common.defaults import DEFAULT_CLASSIFIER
from graspframe.common.errors import GraspframeError
from graspframe.hal import ClassifierOptions
from graspframe.plugin_system.registry import get_classifier
from graspframe.vision.images import read_image

OTHER = "other"
REFUSED = "refused"


def read_labels(folder: Path) -> list[tuple[Path, str]]:
    """(photo path, label) per row of folder/labels.csv; a clear error on a bad file."""
    path = folder / "labels.csv"
    if not path.is_file():
        raise SystemExit(f"{path} not found: the folder needs a labels.csv (file,grasp_type,...)")
    known = {g.value for g in GRASPS} | {OTHER}
    rows = []
    with path.open(newline="") as stream:
        for number, row in enumerate(csv.DictReader(stream), start=2):
            label = (row.get("grasp_type") or "").strip()
            if label not in known:
                accepted = ", ".join(sorted(known))
                raise SystemExit(f"{path}:{number}: grasp_type {label!r} is not one of {accepted}")
            rows.append((folder / row["file"].strip(), label))
    return rows


def classify_all(classifier, rows) -> list[tuple[str, str, float]]:
    """(truth, answer or REFUSED, seconds) per photo."""
    results = []
    for path, truth in rows:
        start = time.perf_counter()
        try:
            answer = classifier.classify(read_image(path)).grasp.value
        except GraspframeError:
            answer = REFUSED
        results.append((truth, answer, time.perf_counter() - start))
    return results


def report(results) -> None:
    names = [g.value for g in GRASPS]
    six = [(t, a) for t, a, _ in results if t != OTHER]
    others = [a for t, a, _ in results if t == OTHER]
    answered = [(t, a) for t, a in six if a != REFUSED]
    correct = sum(t == a for t, a in six)
    print(
        f"six classes: {len(six)} photos, top-1 {correct / max(len(six), 1):.3f} "
        f"(refusals counted wrong; chance {1 / len(names):.3f}), top-1 of the answered "
        f"{sum(t == a for t, a in answered) / max(len(answered), 1):.3f}, refused "
        f"{len(six) - len(answered)}/{len(six)}"
    )
    print("per class: " + ", ".join(_per_class(six, name) for name in names))
    columns = [*names, REFUSED]
    print("confusion (rows: truth, columns: answer):")
    print(" " * 16 + " ".join(f"{c[:10]:>10}" for c in columns))
    for name in names:
        counts = [sum(1 for t, a in six if t == name and a == c) for c in columns]
        print(f"{name:>15} " + " ".join(f"{v:>10d}" for v in counts))
    if others:
        refused = sum(a == REFUSED for a in others)
        answers = ", ".join(f"{a} {others.count(a)}" for a in sorted(set(others) - {REFUSED}))
        print(
            f"other (none of the six): {len(others)} photos, refused {refused} "
            f"(right if refusal is required); answered {len(others) - refused}: {answers or '-'}"
        )
    latencies = [s for _, _, s in results]
    print(f"latency per photo [ms]: median {1e3 * statistics.median(latencies):.1f}")


def _per_class(six, name: str) -> str:
    truths = [a for t, a in six if t == name]
    if not truths:
        return f"{name} -"
    return f"{name} {sum(a == name for a in truths)}/{len(truths)}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="photos and labels.csv")
    parser.add_argument("--k", type=int, default=DEFAULT_K)
    parser.add_argument(
        "--classifier", default=DEFAULT_CLASSIFIER, help="registered classifier name"
    )
    args = parser.parse_args()
    benchmark_folder(args.folder, args.classifier, args.k)
    return 0


def benchmark_folder(folder: Path, classifier_name: str, k: int) -> None:
    """Classify every labelled photo in `folder` and print the report."""
    if not folder.is_dir():
        print(f"{folder}: no such folder; nothing to benchmark")
        return
    rows = read_labels(folder)
    try:
        classifier = get_classifier(classifier_name).with_options(ClassifierOptions(k=k))
    except GraspframeError as exc:
        raise SystemExit(f"error: {exc}") from None
    classify_all(classifier, rows[:1])  # load databases and detectors before timing
    print(f"classifier {classifier_name}, k {k}")
    report(classify_all(classifier, rows))


if __name__ == "__main__":
    sys.exit(main())
