"""Nearest-neighbour search over PCA-reduced HOG descriptors (faiss).

`Pca` projects descriptors onto their leading principal components (fitted on the
database). `NeighbourIndex` wraps a faiss index: "hnsw" (approximate, graph search;
the default, chosen by benchmarks/classifier.py against exact search) or "flat" (exact
brute-force L2). Distances returned are Euclidean (not squared) in PCA space.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

HNSW_M = 32  # graph degree
HNSW_EF_CONSTRUCTION = 80
HNSW_EF_SEARCH = 64
INDEX_KINDS = ("hnsw", "flat")


@dataclass(frozen=True)
class Pca:
    """mean (F,) and components (D, F), rows orthonormal."""

    mean: NDArray[np.float32]
    components: NDArray[np.float32]

    @classmethod
    def fit(cls, X: NDArray[np.float32], dims: int, seed: int = 0) -> Pca:
        """The `dims` leading principal directions of the rows of X, by randomised SVD
        (Halko et al. 2011: 10 extra directions, 3 power iterations; seeded, so a build
        is reproducible). A full eigendecomposition of the 1764^2 covariance takes
        seconds; this takes a fraction of one."""
        X = np.asarray(X, dtype=np.float64)
        mean = X.mean(axis=0)
        centred = X - mean
        rng = np.random.default_rng(seed)
        omega = rng.standard_normal((X.shape[1], min(dims + 10, X.shape[1])))
        Q, _ = np.linalg.qr(centred @ omega)
        for _ in range(3):
            Q, _ = np.linalg.qr(centred.T @ Q)
            Q, _ = np.linalg.qr(centred @ Q)
        _, _, Vt = np.linalg.svd(Q.T @ centred, full_matrices=False)
        components = Vt[:dims]
        # Fix each component's sign (largest entry positive) so builds are reproducible.
        signs = np.sign(components[np.arange(dims), np.abs(components).argmax(axis=1)])
        return cls(mean.astype(np.float32), (components * signs[:, None]).astype(np.float32))

    def project(self, X: NDArray[np.float32]) -> NDArray[np.float32]:
        """Rows of X (N, F) or one (F,) -> (N, D) or (D,)."""
        return ((np.asarray(X, np.float32) - self.mean) @ self.components.T).astype(np.float32)


class NeighbourIndex:
    """k-nearest-neighbour search over database vectors (N, D) float32."""

    def __init__(self, vectors: NDArray[np.float32], kind: str = "hnsw"):
        import faiss

        if kind not in INDEX_KINDS:
            raise ValueError(f"unknown index kind {kind!r}; kinds: {', '.join(INDEX_KINDS)}")
        faiss.omp_set_num_threads(1)
        vectors = np.ascontiguousarray(vectors, dtype=np.float32)
        dims = vectors.shape[1]
        index: faiss.Index
        if kind == "hnsw":
            hnsw = faiss.IndexHNSWFlat(dims, HNSW_M)
            hnsw.hnsw.efConstruction = HNSW_EF_CONSTRUCTION
            hnsw.hnsw.efSearch = HNSW_EF_SEARCH
            index = hnsw
        else:
            index = faiss.IndexFlatL2(dims)
        index.add(vectors)
        self.kind = kind
        self.index = index

    def search(self, queries: NDArray[np.float32], k: int) -> tuple[NDArray, NDArray]:
        """(distances (Q, k) Euclidean, ids (Q, k)) of the k nearest vectors per query."""
        queries = np.ascontiguousarray(np.atleast_2d(queries), dtype=np.float32)
        squared, ids = self.index.search(queries, k)
        return np.sqrt(np.maximum(squared, 0.0)), ids
