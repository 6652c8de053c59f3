"""Convex pieces of a mesh file (graspframe/model_files/convex.py): the three rules, the
vertex limit, the cache and its recovery from a damaged entry, bad input."""

from __future__ import annotations

import logging
import time
from pathlib import Path

import numpy as np
import pytest
import trimesh

from graspframe.common.cache import ENTRY_FILE, read_entry
from graspframe.common.errors import DescriptionError
from graspframe.model_files import convex
from graspframe.model_files.convex import (
    MAX_PIECE_VERTICES,
    METHOD_COACD,
    METHOD_GIVEN,
    METHOD_HULL,
    convex_pieces,
    farthest_points,
    without_flat_vertices,
)


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch) -> Path:
    """Every test with a cache of its own."""
    folder = tmp_path / "cache"
    monkeypatch.setenv("GRASPFRAME_CACHE_DIR", str(folder))
    return folder


def _write(mesh: trimesh.Trimesh, path: Path) -> Path:
    mesh.export(path)
    return path


def _outside(points, piece: trimesh.Trimesh) -> float:
    """[m] how far the points reach outside the convex piece (<= 0: all inside)."""
    normals = piece.face_normals
    offsets = -np.einsum("ij,ij->i", normals, piece.triangles[:, 0])
    return float((np.asarray(points) @ normals.T + offsets).max())


def _entry(cache: Path) -> Path:
    (entry,) = (cache / "decompositions").iterdir()
    return entry


def test_a_convex_mesh_is_its_hull_with_at_most_the_vertex_limit(tmp_path):
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.05)  # 642 vertices
    result = convex_pieces(_write(sphere, tmp_path / "ball.stl"))
    assert result.method == METHOD_HULL
    (piece,) = result.pieces
    assert piece.is_watertight and piece.is_convex
    assert 4 <= len(piece.vertices) <= MAX_PIECE_VERTICES
    # An inner approximation: its vertices are vertices of the sphere (to the 8 digits
    # of the cached OBJ file); 64 of them hold 90 % of its volume (the best spread of 64
    # points on a sphere holds about 92 %).
    assert _outside(piece.vertices, sphere) < 1e-7
    assert 0.88 < piece.volume / sphere.volume <= 1.0
    (piece_file,) = result.files
    assert piece_file.name.startswith("piece_000-") and piece_file.suffix == ".obj"


def test_a_box_is_kept_exactly(tmp_path):
    box = trimesh.creation.box(extents=(0.04, 0.06, 0.1))
    (piece,) = convex_pieces(_write(box, tmp_path / "box.obj")).pieces
    assert len(piece.vertices) == 8
    assert piece.volume == pytest.approx(0.04 * 0.06 * 0.1, rel=1e-9)


def test_scale_takes_the_file_to_metres(tmp_path):
    box_mm = trimesh.creation.box(extents=(40.0, 60.0, 100.0))
    (piece,) = convex_pieces(_write(box_mm, tmp_path / "box_mm.stl"), scale=(1e-3,) * 3).pieces
    assert piece.extents == pytest.approx((0.04, 0.06, 0.1))


def test_given_pieces_are_split_hulled_and_slivers_dropped(tmp_path):
    a = trimesh.creation.box(extents=(0.04, 0.04, 0.04))
    b = trimesh.creation.box(extents=(0.02, 0.02, 0.08))
    b.apply_translation((0.02, 0.0, 0.0))  # overlaps a
    speck = trimesh.creation.box(extents=(0.001, 0.001, 0.001))  # 1e-9 m^3: a sliver
    speck.apply_translation((0.1, 0.0, 0.0))
    flat = trimesh.Trimesh([[0.2, 0, 0], [0.21, 0, 0], [0.2, 0.01, 0]], [[0, 1, 2]])  # no volume
    merged = trimesh.util.concatenate([a, b, speck, flat])
    pieces_file = _write(merged, tmp_path / "pieces.stl")
    visual = _write(trimesh.util.concatenate([a, b]), tmp_path / "visual.obj")
    result = convex_pieces(visual, given_pieces=pieces_file)
    assert result.method == METHOD_GIVEN
    assert sorted(round(p.volume * 1e9) for p in result.pieces) == [32000, 64000]  # [mm^3]
    assert all(p.is_convex for p in result.pieces)


def test_a_non_convex_mesh_is_decomposed_with_coacd_and_cached(tmp_path, cache):
    ring = trimesh.creation.annulus(r_min=0.02, r_max=0.04, height=0.03, sections=16)
    assert ring.is_watertight and ring.convex_hull.volume > 1.3 * ring.volume
    path = _write(ring, tmp_path / "ring.obj")
    started = time.perf_counter()
    first = convex_pieces(path)
    computed = time.perf_counter() - started
    assert first.method == METHOD_COACD
    assert len(first.pieces) >= 3
    for piece in first.pieces:
        assert piece.is_convex and len(piece.vertices) <= MAX_PIECE_VERTICES
    # The pieces follow the ring: its surface is within 2 mm of them, the hole is empty.
    surface = ring.sample(2000, seed=0)
    gap = [min(_outside([p], piece) for piece in first.pieces) for p in surface]
    assert max(gap) < 0.002
    assert min(_outside([[0.0, 0.0, 0.0]], piece) for piece in first.pieces) > 0.01

    started = time.perf_counter()
    again = convex_pieces(path)
    assert time.perf_counter() - started < computed / 5  # read back, not computed
    assert again.method == METHOD_COACD
    assert [f.name for f in again.files] == [f.name for f in first.files]
    for a, b in zip(first.pieces, again.pieces, strict=True):
        np.testing.assert_array_equal(a.vertices, b.vertices)
    assert all(f.parent == _entry(cache) for f in again.files)


@pytest.mark.parametrize(
    "damage", ["entry.json missing", "entry.json cut short", "a piece changed", "a piece missing"]
)
def test_a_damaged_cache_entry_is_rebuilt_with_a_warning(tmp_path, cache, damage, caplog):
    box = _write(trimesh.creation.box(extents=(0.03, 0.03, 0.03)), tmp_path / "box.stl")
    original = convex_pieces(box)
    entry = _entry(cache)
    (piece_file,) = original.files
    if damage == "entry.json missing":
        (entry / ENTRY_FILE).unlink()
    elif damage == "entry.json cut short":  # as a full disk leaves it
        text = (entry / ENTRY_FILE).read_bytes()
        (entry / ENTRY_FILE).write_bytes(text[: len(text) // 2])
    elif damage == "a piece changed":
        piece_file.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n")
    else:
        piece_file.unlink()
    with caplog.at_level(logging.WARNING, logger="graspframe.common.cache"):
        rebuilt = convex_pieces(box)
    (warning,) = caplog.messages
    assert warning.startswith(f"cache entry {entry} is damaged (") and "rebuilding it" in warning
    assert rebuilt.files == original.files and rebuilt.method == original.method
    np.testing.assert_array_equal(rebuilt.pieces[0].vertices, original.pieces[0].vertices)
    caplog.clear()
    assert read_entry(entry) is not None and not caplog.messages  # whole again


def test_a_different_file_or_scale_is_a_different_entry(tmp_path, cache):
    box = _write(trimesh.creation.box(extents=(0.03, 0.03, 0.03)), tmp_path / "box.stl")
    convex_pieces(box)
    convex_pieces(box, scale=(2.0, 2.0, 2.0))
    _write(trimesh.creation.box(extents=(0.03, 0.03, 0.04)), box)
    convex_pieces(box)
    assert len(list((cache / "decompositions").iterdir())) == 3


def test_bad_files_are_refused_in_one_line(tmp_path):
    image = tmp_path / "texture.jpg"
    image.write_bytes(b"\xff\xd8")
    with pytest.raises(DescriptionError, match=r"unknown format '\.jpg'; mesh files are \.obj"):
        convex_pieces(image)
    with pytest.raises(DescriptionError, match="does not exist"):
        convex_pieces(tmp_path / "missing.obj")
    box = _write(trimesh.creation.box(), tmp_path / "box.stl")
    with pytest.raises(DescriptionError, match="scale must be three finite numbers > 0"):
        convex_pieces(box, scale=(1.0, 0.0, 1.0))
    empty = tmp_path / "empty.obj"
    empty.write_text("# nothing\n")
    with pytest.raises(DescriptionError, match=r"empty\.obj") as raised:
        convex_pieces(empty)
    assert "\n" not in str(raised.value)


def test_farthest_points_keep_the_extremes_and_spread_out():
    rng = np.random.default_rng(0)
    points = rng.normal(size=(500, 3))
    chosen = farthest_points(points, 20)
    assert len(np.unique(chosen, axis=0)) == 20
    for axis in range(3):
        assert points[:, axis].max() in chosen[:, axis]
        assert points[:, axis].min() in chosen[:, axis]


def test_nearly_coplanar_vertices_are_dropped():
    cube = trimesh.creation.box(extents=(0.04, 0.04, 0.04)).vertices
    low_bump = np.vstack([cube, [0.0, 0.0, 0.02 + 0.0005]])  # 0.5 mm above the top face
    high_bump = np.vstack([cube, [0.0, 0.0, 0.02 + 0.002]])  # 2 mm above it
    assert len(without_flat_vertices(low_bump, convex.PLANE_TOLERANCE)) == 8
    assert len(without_flat_vertices(high_bump, convex.PLANE_TOLERANCE)) == 9
    # Every vertex that stays is farther than the tolerance from the hull of the others.
    hull = convex.convex_hull(np.vstack([cube, [[0.0, 0.0, 0.0205], [0.01, 0.0, 0.0203]]]))
    assert hull is not None and len(hull.vertices) == 8


# The largest gap a simplified piece leaves inside its original: the docstring's bound.
MAX_INNER_GAP = 1.5e-3  # [m]


def test_the_panda_meshes_keep_what_their_edges_need(panda_description_dir):
    """The Panda's collision STLs are convex, of up to 152 hull vertices with long flat
    faces: each keeps more than the 64 a dense scan keeps (64 leave 5.25 mm out), enough
    to reach within 1.5 mm of the vendor's surface."""
    meshes = sorted((panda_description_dir / "meshes" / "collision").glob("link*.stl"))
    assert len(meshes) == 8
    kept = []
    for path in meshes:
        pieces = convex_pieces(path)
        assert pieces.method == METHOD_HULL and len(pieces.pieces) == 1, path.name
        piece = pieces.pieces[0]
        assert convex.inner_gap(convex.load_mesh(path).vertices, piece) <= MAX_INNER_GAP
        kept.append(len(piece.vertices))
    assert max(kept) > convex.MIN_KEPT_VERTICES


def test_a_dense_hull_keeps_few_vertices_within_the_tolerance():
    """A sphere of 2562 vertices (1 cm radius): 64 of them already lie within 1.5 mm."""
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=0.01)
    kept = convex.reduced_hull_vertices(np.asarray(sphere.vertices))
    assert len(kept) == convex.MIN_KEPT_VERTICES
    gap = convex.inner_gap(sphere.vertices, trimesh.convex.convex_hull(kept))
    assert gap <= convex.HULL_TOLERANCE


def test_the_ycb_given_pieces_lie_within_the_bound():
    """Each YCB scan's V-HACD part, as a piece, reaches within 1.5 mm of the part."""
    from conftest import THIRD_PARTY

    pieces_file = THIRD_PARTY / "objects/ycb/006_mustard_bottle/google_16k/textured_vhacd.stl"
    if not pieces_file.is_file():
        pytest.skip("the YCB scans are not on this machine")
    parts = convex.load_mesh(pieces_file).split(only_watertight=False)
    assert len(parts) > 50
    for part in parts:
        piece = convex.convex_hull(part.vertices)  # what `given pieces` keeps of a part
        if piece is not None:
            assert convex.inner_gap(part.vertices, piece) <= MAX_INNER_GAP
