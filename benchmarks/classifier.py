"""Benchmark of the hog_knn classifier on held-out renders.

    python benchmarks/classifier.py [--db PATH] [--test-views N] [--k K] [--seed S]
    python benchmarks/classifier.py --real DIR [--classifier NAME] [--k K]

With --real, benchmarks real photographs instead (see benchmarks/classifier_real.py:
top-1 per class, confusion matrix, refusal rate, latency).

Held-out renders come from the "held_out" view distribution (other hand sizes, lighting
ranges, striped/checked backgrounds, more sensor noise) with a seed the database did not
use. Prints: top-1 accuracy and the confusion matrix; orientation error [deg] (median
and 90th percentile, over all test views and over the correctly classified ones);
median query latency split into segmentation / features / search; search speed-up of
the approximate index (HNSW) over exact brute force and its recall@k; the database's
build rate [views/s] (from its metadata, or measured with --build-views).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from graspframe_hog_knn.classifier import DEFAULT_K, HogKnnClassifier, UncertainGraspError
from graspframe_hog_knn.database import (
    build_database,
    iter_views,
    load_database,
    shipped_database_path,
)
from graspframe_hog_knn.rotations import angle_deg
from graspframe_hog_knn.views import GRASPS, HELD_OUT

from graspframe.common.defaults import DEFAULT_CLASSIFIER
from graspframe.vision.common import NoHandFoundError

TEST_SEED = 9_000_001  # never used for a database build


def evaluate(db, views, k: int, index_kind: str = "hnsw") -> dict:
    """Classify every rendered view; accuracy, confusion, orientation error, latency."""
    classifier = HogKnnClassifier.from_database(db, k=k, index_kind=index_kind)
    _ = classifier.index
    truth, predicted, errors, correct_errors, timings = [], [], [], [], []
    no_hand = uncertain = 0
    for view in views:
        try:
            estimate, t = classifier.classify_timed(view.image)
        except NoHandFoundError:
            no_hand += 1
            continue
        except UncertainGraspError:
            uncertain += 1
            continue
        truth.append(GRASPS.index(view.grasp))
        predicted.append(GRASPS.index(estimate.grasp))
        error = angle_deg(estimate.R_camera_palm, view.T_camera_palm[:3, :3])
        errors.append(error)
        if estimate.grasp == view.grasp:
            correct_errors.append(error)
        timings.append((t.segmentation, t.features, t.search))
    truth, predicted = np.array(truth), np.array(predicted)
    confusion = np.zeros((len(GRASPS), len(GRASPS)), int)
    np.add.at(confusion, (truth, predicted), 1)
    return {
        "n": len(truth),
        "no_hand": no_hand,
        "uncertain": uncertain,
        # refused as uncertain counts wrong; views without a segmentable hand are left out
        "accuracy": float(np.sum(truth == predicted) / (len(truth) + uncertain)),
        "confusion": confusion,
        "errors": np.array(errors),
        "correct_errors": np.array(correct_errors),
        "timings_ms": np.median(np.array(timings), axis=0) * 1e3,
    }


def search_comparison(db, queries: np.ndarray, k: int) -> dict:
    """HNSW against exact search over the same database vectors: time and recall@k."""
    from graspframe_hog_knn.index import NeighbourIndex

    out = {}
    for kind in ("flat", "hnsw"):
        start = time.perf_counter()
        index = NeighbourIndex(db.descriptors, kind)
        built = time.perf_counter() - start
        index.search(queries[:5], k)  # warm up
        start = time.perf_counter()
        for q in queries:  # one query at a time, as the classifier searches
            index.search(q, k)
        per_query = (time.perf_counter() - start) / len(queries)
        out[kind] = (index.search(queries, k)[1], per_query, built)
    exact, approx = out["flat"][0], out["hnsw"][0]
    recall = np.mean([len(set(a) & set(e)) / k for a, e in zip(approx, exact, strict=True)])
    return {
        "flat_ms": out["flat"][1] * 1e3,
        "hnsw_ms": out["hnsw"][1] * 1e3,
        "speedup": out["flat"][1] / out["hnsw"][1],
        "recall": float(recall),
        "hnsw_build_s": out["hnsw"][2],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--db", type=Path, default=None, help="database .npz (default: shipped)")
    parser.add_argument("--test-views", type=int, default=600)
    parser.add_argument("--k", type=int, default=DEFAULT_K)
    parser.add_argument("--seed", type=int, default=TEST_SEED)
    parser.add_argument("--build-views", type=int, default=0, help="also time a build of N/grasp")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--real", type=Path, default=None, help="folder of real photos")
    parser.add_argument(
        "--classifier", default=DEFAULT_CLASSIFIER, help="with --real: classifier name"
    )
    args = parser.parse_args()
    if args.real is not None:
        from classifier_real import benchmark_folder  # the sibling script in benchmarks/

        benchmark_folder(args.real, args.classifier, args.k)
        return

    db = load_database(args.db)
    size = db.metadata["build"]["size_px"]
    print(f"database: {args.db or shipped_database_path()}  views={len(db)}  size={size}px")
    start = time.perf_counter()
    views = list(iter_views(range(args.test_views), args.seed, size, HELD_OUT.name))
    print(f"rendered {len(views)} held-out views in {time.perf_counter() - start:.1f} s")

    result = evaluate(db, views, args.k)
    print(
        f"\ntop-1 accuracy: {result['accuracy']:.3f} on {result['n'] + result['uncertain']} "
        f"views, {result['uncertain']} refused as uncertain counted wrong "
        f"(chance {1 / len(GRASPS):.3f}; {result['no_hand']} views without a segmentable hand)"
    )
    print("confusion (rows: truth, columns: estimate):")
    short = [g.value[:10] for g in GRASPS]
    print(" " * 16 + " ".join(f"{s:>10}" for s in short))
    for g, row in zip(GRASPS, result["confusion"], strict=True):
        print(f"{g.value:>15} " + " ".join(f"{v:>10d}" for v in row))
    for label, errors in (
        ("all views", result["errors"]),
        ("correct class", result["correct_errors"]),
    ):
        print(
            f"orientation error [deg], {label}: median {np.median(errors):.1f}, "
            f"p90 {np.percentile(errors, 90):.1f}"
        )
    seg, feat, search = result["timings_ms"]
    print(
        f"median query latency [ms]: segmentation {seg:.2f}, features {feat:.2f}, "
        f"search {search:.3f}, total {seg + feat + search:.2f}"
    )

    from graspframe_hog_knn.features import hog_descriptor
    from graspframe_hog_knn.segmentation import segment_hand

    queries = []
    for view in views:
        try:
            queries.append(db.pca.project(hog_descriptor(segment_hand(view.image).patch)))
        except NoHandFoundError:
            continue
    s = search_comparison(db, np.array(queries), args.k)
    print(
        f"search per query [ms]: exact {s['flat_ms']:.3f}, HNSW {s['hnsw_ms']:.3f}; "
        f"speed-up {s['speedup']:.1f}x, recall@{args.k} {s['recall']:.3f} "
        f"(HNSW build {s['hnsw_build_s']:.2f} s)"
    )
    meta = db.metadata
    print(
        f"database build rate: {meta['views_per_second']} views/s "
        f"({meta['views_rendered']} views in {meta['build_seconds']} s, "
        f"{meta['build']['workers']} workers)"
    )
    if args.build_views:
        start = time.perf_counter()
        small = build_database(args.build_views, size, args.workers, seed=12345)
        seconds = time.perf_counter() - start
        print(
            f"measured build: {len(small)} views in {seconds:.1f} s = "
            f"{args.build_views * len(GRASPS) / seconds:.1f} views/s, {args.workers} workers"
        )


if __name__ == "__main__":
    main()
