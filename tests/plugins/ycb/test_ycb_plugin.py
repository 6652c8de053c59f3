"""The YCB object source (plugins/graspframe_ycb) on folders made here: what it registers,
what it says when GRASPFRAME_YCB_DIR is unset, missing, empty or incomplete, and the
`evaluate --objects` options."""

from __future__ import annotations

from pathlib import Path

import pytest
import trimesh
from graspframe_ycb.catalogue import UNWEIGHED, YCB_OBJECTS
from graspframe_ycb.plugin import YCB_DIR_ENV, ycb_objects

import graspframe.plugin_system.registry
from graspframe.cli.commands import main
from graspframe.common.errors import InputError, PluginError, UnknownNameError
from graspframe.common.grasps import HumanGrasp
from graspframe.experiments.sweep import SweepConfig, object_grasps, plan_trials
from graspframe.hal import ObjectDescription
from graspframe.plugin_system import hookimpl
from graspframe.plugin_system.registry import Registry


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("GRASPFRAME_CACHE_DIR", str(tmp_path / "cache"))


def _ycb_folder(root: Path, name: str, pieces: bool = True) -> Path:
    """A YCB-layout object folder holding a 5 x 7 x 5 cm box as its scan."""
    folder = root / name / "google_16k"
    folder.mkdir(parents=True)
    box = trimesh.creation.box(extents=(0.05, 0.075, 0.05))
    box.apply_translation((-0.02, 0.02, 0.025))
    box.export(folder / "textured.obj")
    if pieces:
        box.export(folder / "textured_vhacd.stl")
    return folder


def _plugin(registry: Registry):
    return next(p for p in registry.plugins if p.name == "ycb")


def test_unset_registers_nothing(monkeypatch):
    monkeypatch.delenv(YCB_DIR_ENV, raising=False)
    registry = Registry.from_entry_points()
    info = _plugin(registry)
    assert info.status == "loaded" and info.provides == []
    assert not [n for n in registry.names("object") if n.startswith("ycb_")]


def test_a_ycb_layout_folder_is_registered_by_folder_name(tmp_path, monkeypatch):
    _ycb_folder(tmp_path, "061_foam_brick")
    _ycb_folder(tmp_path, "025_mug", pieces=False)
    _ycb_folder(tmp_path, "065-c_cups")  # a lettered id of the set
    _ycb_folder(tmp_path, "999_unknown_thing")
    _ycb_folder(tmp_path, "063-b_marbles")  # in the set, but weighed by nobody
    (tmp_path / "README.txt").write_text("not an object")
    monkeypatch.setenv(YCB_DIR_ENV, str(tmp_path))
    registry = Registry.from_entry_points()
    info = _plugin(registry)
    assert info.status == "loaded"
    assert [n for n in registry.names("object") if n.startswith("ycb_")] == [
        "ycb_025_mug",
        "ycb_061_foam_brick",
        "ycb_065-c_cups",
    ]
    skipped = {name: reason for _kind, name, reason in info.not_registered}
    assert set(skipped) == {"ycb_999_unknown_thing", "ycb_063-b_marbles"}
    marbles = tmp_path / "063-b_marbles/google_16k/textured.toml"
    assert f"set mass = <kg> in {marbles}" in skipped["ycb_063-b_marbles"]
    assert "give no mass for this part of the set" in skipped["ycb_063-b_marbles"]
    with pytest.raises(UnknownNameError, match="object 'ycb_999_unknown_thing' is not registered"):
        registry.get_object("ycb_999_unknown_thing")
    brick = registry.get_object("ycb_061_foam_brick")
    assert brick.shape == "mesh" and brick.mass == YCB_OBJECTS["061_foam_brick"].mass
    assert brick.collision_path == tmp_path / "061_foam_brick/google_16k/textured_vhacd.stl"
    assert brick.documented_grasps() == (HumanGrasp.PINCH,)
    assert brick.half_height == pytest.approx(0.025, abs=1e-6)  # recentred from the scan
    mug = registry.get_object("ycb_025_mug")
    assert mug.collision_path is None and mug.mesh_geometry().convex.method == "hull"
    assert registry.get_object("ycb_065-c_cups").mass == pytest.approx(0.017)


def test_a_sidecar_gives_a_ycb_object_its_mass_or_replaces_the_tables(tmp_path, monkeypatch):
    marbles = _ycb_folder(tmp_path, "063-b_marbles")
    (marbles / "textured.toml").write_text('mass = 0.031\ngrasps = ["pinch"]\n')
    brick = _ycb_folder(tmp_path, "061_foam_brick")
    (brick / "textured.toml").write_text("mass = 0.05\n")  # weighed by the user
    monkeypatch.setenv(YCB_DIR_ENV, str(tmp_path))
    registry = Registry.from_entry_points()
    assert registry.get_object("ycb_063-b_marbles").mass == pytest.approx(0.031)
    assert registry.get_object("ycb_063-b_marbles").collision_path == marbles / "textured_vhacd.stl"
    assert registry.get_object("ycb_061_foam_brick").mass == pytest.approx(0.05)
    assert _plugin(registry).not_registered == []


def test_the_table_holds_the_whole_set_with_masses_and_grasps():
    assert len(YCB_OBJECTS) == 73
    assert all(0.0005 < facts.mass < 2.0 for facts in YCB_OBJECTS.values())
    for folder, grams in (("005_tomato_soup_can", 349), ("006_mustard_bottle", 603),
                          ("011_banana", 66), ("025_mug", 118), ("056_tennis_ball", 58),
                          ("061_foam_brick", 28), ("002_master_chef_can", 414)):  # fmt: skip
        assert YCB_OBJECTS[folder].mass == pytest.approx(grams / 1000)
    assert not set(YCB_OBJECTS) & set(UNWEIGHED) and len(UNWEIGHED) == 30


@pytest.mark.parametrize(
    ("layout", "message"),
    [
        ("missing", "GRASPFRAME_YCB_DIR={root}/missing: no such folder; it should hold "),
        ("empty", "GRASPFRAME_YCB_DIR={root}/empty holds no YCB object; it should hold "),
        ("no scan", "YCB object folder {root}/no scan/006_mustard_bottle has no "),
    ],
)
def test_an_unusable_folder_fails_the_plugin_with_one_line(tmp_path, monkeypatch, layout, message):
    (tmp_path / "empty").mkdir()
    (tmp_path / "no scan" / "006_mustard_bottle" / "google_16k").mkdir(parents=True)
    monkeypatch.setenv(YCB_DIR_ENV, str(tmp_path / layout))
    registry = Registry.from_entry_points()
    info = _plugin(registry)
    assert info.status == "failed"
    assert message.format(root=tmp_path) in info.error
    assert "google_16k/textured.obj" in info.error and "\n" not in info.error
    assert registry.get_hand("barrett")  # the other plugins work
    with pytest.raises(PluginError):
        ycb_objects(tmp_path / layout)


def test_plugins_command_shows_the_failure(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv(YCB_DIR_ENV, str(tmp_path / "missing"))
    monkeypatch.setattr(
        graspframe.plugin_system.registry, "default_registry", Registry.from_entry_points
    )
    assert main(["plugins"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "failed" in out and "no such folder" in out


class _Objects:
    """A plugin with a mesh-free object that documents no grasp."""

    @hookimpl
    def graspframe_register_objects(self, register):
        register(
            ObjectDescription(
                "bare_box", "box", {"size_x": 0.02, "size_y": 0.03, "size_z": 0.05}, 1
            )
        )


def test_a_sweep_over_objects_runs_each_objects_documented_grasps(tmp_path, monkeypatch):
    registry = Registry.from_entry_points()
    registry.add_plugin("bare", _Objects())
    monkeypatch.setattr(graspframe.plugin_system.registry, "default_registry", lambda: registry)
    assert object_grasps("large_cylinder_075") == ("large_diameter",)  # its size's grasp
    assert object_grasps("bare_box") == ("pinch",)  # none given: from its shape, a small block
    config = SweepConfig(
        hands=("barrett",),
        grasps=(),
        out_dir=tmp_path,
        directions=1,
        mounts=("arm", "floating"),
        objects=("handle", "ball"),
    )
    ids = [spec.trial_id for spec in plan_trials(config)]
    assert ids == [
        "arm/barrett/small_diameter/A/handle",
        "arm/barrett/small_diameter/B0/handle",
        "arm/barrett/power_sphere/A/ball",
        "arm/barrett/power_sphere/B0/ball",
        "floating/barrett/small_diameter/A/handle",
        "floating/barrett/small_diameter/B0/handle",
        "floating/barrett/power_sphere/A/ball",
        "floating/barrett/power_sphere/B0/ball",
    ]
    with pytest.raises(InputError, match="give --objects without --grasps and --sizes"):
        SweepConfig(hands=("barrett",), grasps=("pinch",), out_dir=tmp_path, objects=("ball",))


@pytest.mark.parametrize(
    ("command", "message"),
    [
        (["evaluate", "--objects", "teapot"], "unknown object 'teapot'; known objects: ball,"),
        (
            ["evaluate", "--objects", "ball", "--grasps", "pinch"],
            "--objects runs each object's documented grasps; leave out --grasps",
        ),
        (["evaluate", "--objects", "ball", "--sizes", "75"], "give --objects without --grasps"),
    ],
)
def test_bad_object_arguments_give_one_line_and_exit_1(command, message, capsys):
    assert main(command) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: ") and err.count("error: ") == 1  # one message (wrapped)
    assert message in " ".join(err.split())


def test_the_summary_of_a_sweep_over_objects_names_the_object(tmp_path):
    from graspframe.experiments.summary import COLUMNS, summarize, write_tables
    from graspframe.experiments.trials import TrialRow, TrialSpec

    rows = [
        TrialRow(
            TrialSpec("barrett", grasp, "A", (0.0, 0.0), 0, "runs", object=name),
            "ok",
            success=held,
            held_after_lift=held,
        )
        for name, grasp, held in (("can", "large_diameter", True), ("brick", "pinch", False))
    ]
    summary = summarize(rows)
    assert [(r.object, r.grasp, r.a.success) for r in summary] == [
        ("can", "large_diameter", True),
        ("brick", "pinch", False),
    ]
    csv_path, md_path = write_tables(summary, tmp_path)
    header = csv_path.read_text().splitlines()[0].split(",")
    assert header == [*COLUMNS[:3], "object", *COLUMNS[3:]]
    lines = md_path.read_text().splitlines()
    assert lines[0].startswith("| mount | hand | grasp | object | A held |")
    assert lines[2].startswith("| arm | barrett | large_diameter | can | yes |")
    assert lines[3].startswith("| arm | barrett | pinch | brick | no |")
    assert lines[1].count("|---") == lines[0].count("|") - 1
