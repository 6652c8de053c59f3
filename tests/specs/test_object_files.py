"""Objects from mesh files and their sidecars, with no Python (graspframe/specs/objects.py,
plugins/graspframe_scans): what a sidecar says, what is refused in one line, the
grasp that follows from a shape when none is given, a folder of scans registered with
what could not be, `graspframe objects`, and `run --object PATH` grasping a scan."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
import trimesh
from conftest import folder_state
from graspframe_scans.plugin import OBJECTS_ENV

import graspframe.plugin_system.registry
from graspframe.cli.commands import main
from graspframe.common.errors import DescriptionError, UnknownNameError
from graspframe.common.grasps import HumanGrasp
from graspframe.hal import ObjectDescription
from graspframe.hal.shape_grasps import grasp_from_shape
from graspframe.plugin_system.registry import Registry
from graspframe.specs.objects import load_object_file


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("GRASPFRAME_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv(OBJECTS_ENV, raising=False)


def _mesh(path: Path, mesh: trimesh.Trimesh) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    mesh.export(path)
    return path


def _can(path: Path) -> Path:
    """A 66 mm can, 102 mm tall, standing on z = 0 (a scan's frame: not centred)."""
    can = trimesh.creation.cylinder(radius=0.033, height=0.102, sections=32)
    can.apply_translation((0.01, -0.02, 0.051))
    return _mesh(path, can)


def test_a_sidecar_describes_its_mesh(tmp_path):
    mesh = _can(tmp_path / "tin.obj")
    (tmp_path / "tin.toml").write_text(
        'name = "my_tin"\nmass = 0.3\nstatic_friction = 0.7\ndynamic_friction = 0.5\n'
        'grasps = ["large_diameter", "abducted_thumb"]\nsummary = "a tin"\n'
    )
    for path in (mesh, tmp_path / "tin.toml"):  # the mesh or its sidecar
        tin = load_object_file(path)
        assert (tin.name, tin.mass, tin.static_friction, tin.dynamic_friction) == (
            "my_tin", 0.3, 0.7, 0.5,
        )  # fmt: skip
        assert tin.documented_grasps() == (HumanGrasp.LARGE_DIAMETER, HumanGrasp.ABDUCTED_THUMB)
        assert tin.half_height == pytest.approx(0.051, abs=1e-4)  # recentred


def test_a_density_and_a_scale_stand_in_for_a_mass_and_metres(tmp_path):
    can = trimesh.creation.cylinder(radius=33.0, height=102.0, sections=32)  # millimetres
    can.apply_translation((0, 0, 51.0))
    _mesh(tmp_path / "mm_can.stl", can)
    (tmp_path / "mm_can.toml").write_text("density = 1000.0\nscale = 0.001\n")
    obj = load_object_file(tmp_path / "mm_can.stl")
    assert obj.mass == pytest.approx(1000.0 * can.volume * 1e-9, rel=0.03)
    assert obj.half_height == pytest.approx(0.051, abs=1e-4)


@pytest.mark.parametrize(
    ("sidecar", "message"),
    [
        (None, "mesh tin.obj has no sidecar tin.toml beside it: write one with its mass = <kg>"),
        ('grasps = ["pinch"]\n', "sidecar tin.toml: no mass: set mass = <kg> (or density"),
        ("mass = 0.3\nfriction = 1.0\n", "unknown key 'friction' in the sidecar; accepted: name,"),
        ('mass = 0.3\ngrasps = ["hook"]\n', "unknown grasp 'hook'; known grasps: "),
        ("mass = -1.0\n", "mass [kg] and density [kg/m^3] must be > 0"),
        ("mass = 0.3\nmass", "sidecar tin.toml is not valid TOML"),
        ('mass = 0.3\nmesh = "gone.obj"\n', "gone.obj does not exist; give the path of a mesh"),
    ],
)
def test_a_bad_sidecar_is_refused_in_one_line(tmp_path, sidecar, message):
    _can(tmp_path / "tin.obj")
    if sidecar is not None:
        (tmp_path / "tin.toml").write_text(sidecar)
    with pytest.raises(DescriptionError) as error:
        load_object_file(tmp_path / "tin.obj")
    assert message in str(error.value) and "\n" not in str(error.value)


def _cylinder(name: str, radius: float, length: float) -> ObjectDescription:
    return ObjectDescription(name, "cylinder", {"radius": radius, "length": length}, mass=0.1)


def _box(name: str, x: float, y: float, z: float) -> ObjectDescription:
    return ObjectDescription(name, "box", {"size_x": x, "size_y": y, "size_z": z}, mass=0.1)


@pytest.mark.parametrize(
    ("obj", "grasp"),
    [
        (ObjectDescription("ball", "sphere", {"radius": 0.045}, mass=0.2), HumanGrasp.POWER_SPHERE),
        (ObjectDescription("marble", "sphere", {"radius": 0.01}, mass=0.01), HumanGrasp.PINCH),
        (_cylinder("lid", 0.045, 0.02), HumanGrasp.PRECISION_DISC),
        (_cylinder("can", 0.04, 0.11), HumanGrasp.LARGE_DIAMETER),
        (_cylinder("bar", 0.0125, 0.12), HumanGrasp.SMALL_DIAMETER),
        (_box("block", 0.025, 0.025, 0.05), HumanGrasp.PINCH),
        (_box("cube", 0.06, 0.06, 0.06), HumanGrasp.PINCH),
        (_box("carton", 0.06, 0.16, 0.21), HumanGrasp.LARGE_DIAMETER),
        (_box("pen", 0.015, 0.14, 0.015), HumanGrasp.PINCH),
        (_box("brick lying flat", 0.09, 0.2, 0.065), HumanGrasp.LARGE_DIAMETER),
    ],
)
def test_the_grasp_follows_from_the_shape(obj, grasp):
    chosen, why = grasp_from_shape(obj)
    assert chosen == grasp, why
    assert obj.documented_grasps() == (grasp,)  # nothing given: the rule decides


def test_the_rule_gives_five_default_objects_their_own_grasp():
    registry = Registry.from_entry_points()
    defaults = {grasp: registry.default_object_for(grasp) for grasp in HumanGrasp}
    by_shape = {grasp: grasp_from_shape(obj)[0] for grasp, obj in defaults.items()}
    assert [g for g, chosen in by_shape.items() if chosen != g] == [HumanGrasp.ABDUCTED_THUMB]
    assert by_shape[HumanGrasp.ABDUCTED_THUMB] == HumanGrasp.LARGE_DIAMETER


def _folder_of_scans(root: Path) -> Path:
    _can(root / "kitchen" / "tin.obj")
    (root / "kitchen" / "tin.toml").write_text("mass = 0.3\n")
    ball = trimesh.creation.icosphere(subdivisions=3, radius=0.04)
    ball.apply_translation((0, 0, 0.04))
    _mesh(root / "toys" / "ball.obj", ball)
    _mesh(root / "toys" / "ball_pieces.stl", ball)
    (root / "toys" / "ball.toml").write_text(
        'name = "toy_ball"\nmass = 0.06\ncollision = "ball_pieces.stl"\n'
    )
    _can(root / "toys" / "spare.obj")  # no sidecar
    _can(root / "toys" / "heavy.obj")
    (root / "toys" / "heavy.toml").write_text('grasps = ["large_diameter"]\n')  # no mass
    _can(root / "more" / "tin.obj")
    (root / "more" / "tin.toml").write_text("mass = 0.4\n")  # a second "tin"
    _can(root / "more" / "handle.obj")
    (root / "more" / "handle.toml").write_text("mass = 0.1\n")  # a built-in object's name
    return root


def test_a_folder_of_scans_registers_each_sidecar_and_says_what_it_could_not(
    tmp_path, monkeypatch, capsys
):
    folder = _folder_of_scans(tmp_path / "scans")
    before = folder_state(folder)
    monkeypatch.setenv(OBJECTS_ENV, str(folder))
    registry = Registry.from_entry_points()
    monkeypatch.setattr(graspframe.plugin_system.registry, "default_registry", lambda: registry)
    info = next(p for p in registry.plugins if p.name == "scans")
    assert info.status == "loaded"
    assert sorted(name for _kind, name in info.provides) == ["tin", "toy_ball"]
    assert registry.get_object("tin").mass == 0.3  # the first found, kitchen/tin.obj
    ball = registry.get_object("toy_ball")
    assert ball.documented_grasps() == (HumanGrasp.POWER_SPHERE,)  # from its shape
    skipped = {name: reason for _kind, name, reason in info.not_registered}
    assert set(skipped) == {"spare", "heavy", "tin", "handle"}
    assert "the name is taken by plugin 'objects'" in skipped["handle"]
    assert registry.get_object("handle").shape == "cylinder"  # the catalogue's stays
    assert "has no sidecar spare.toml beside it" in skipped["spare"]
    assert "no mass: set mass = <kg>" in skipped["heavy"]
    assert "are both named 'tin'" in skipped["tin"]
    with pytest.raises(UnknownNameError, match=r"object 'heavy' is not registered: .*no mass"):
        registry.get_object("heavy")

    assert main(["objects", "--json"]) == 0
    listing = json.loads(capsys.readouterr().out)
    rows = {row["name"]: row for row in listing["objects"]}
    assert rows["toy_ball"]["plugin"] == "scans" and rows["toy_ball"]["mass_g"] == 60.0
    assert rows["toy_ball"]["size_mm"] == pytest.approx([80, 80, 80], abs=2.0)
    assert rows["toy_ball"]["grasps"] == ["power_sphere"]
    assert rows["toy_ball"]["grasps_from"].startswith("from its shape: sphere-like")
    assert rows["large_cylinder"]["grasps_from"] == "given"
    unregistered = {row["name"] for row in listing["not_registered"]}
    assert unregistered == {"spare", "heavy", "tin", "handle"}
    assert main(["objects"]) == 0
    table = " ".join(capsys.readouterr().out.split())
    assert "4 object(s) found but not registered" in table and "heavy (scans)" in table
    assert folder_state(folder) == before  # read in place: nothing written beside the scans


def test_a_missing_folder_fails_the_source_in_one_line(tmp_path, monkeypatch):
    monkeypatch.setenv(OBJECTS_ENV, os.pathsep.join([str(tmp_path), str(tmp_path / "gone")]))
    registry = Registry.from_entry_points()
    info = next(p for p in registry.plugins if p.name == "scans")
    assert info.status == "failed" and f"{tmp_path / 'gone'} does not exist" in info.error
    assert registry.get_hand("barrett")  # the other plugins work


def test_run_refuses_a_mesh_without_its_mass_in_one_line(tmp_path, capsys):
    _can(tmp_path / "tin.obj")
    (tmp_path / "tin.toml").write_text('grasps = ["large_diameter"]\n')
    argv = ["run", "--hand", "barrett", "--object", str(tmp_path / "tin.obj"), "--no-record"]
    assert main([*argv, "--grasp", "large_diameter", "--out", str(tmp_path)]) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert err.startswith("error: sidecar tin.toml: no mass: set mass = <kg>")


@pytest.mark.slow
@pytest.mark.parametrize("hand", ["barrett", "karlsruhe"])
def test_a_scan_with_a_sidecar_is_grasped_by_name_of_its_file(ycb_scans, tmp_path, capsys, hand):
    # A scan of the set under a name of our own, described by a sidecar only.
    scan = ycb_scans / "005_tomato_soup_can" / "google_16k"
    (tmp_path / "soup.obj").symlink_to(scan / "textured.obj")
    (tmp_path / "soup.toml").write_text(
        f'mass = 0.349\ncollision = "{scan / "textured_vhacd.stl"}"\nsummary = "a soup can"\n'
    )
    argv = ["run", "--hand", hand, "--object", str(tmp_path / "soup.obj"), "--no-record"]
    argv += ["--mount", "floating"]  # the hand alone: the object is what is tested here
    code = main([*argv, "--grasp", "large_diameter", "--out", str(tmp_path / "runs")])
    printed = capsys.readouterr().out
    assert code == 0, printed
    (result_file,) = (tmp_path / "runs").glob("*/result.json")
    result = json.loads(result_file.read_text())
    assert result["request"]["object"] == str(tmp_path / "soup.obj")
    assert result["outcome"]["held_after_lift"] and result["outcome"]["held_under_disturbance"]
