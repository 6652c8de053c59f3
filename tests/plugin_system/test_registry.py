"""The plugin manager and registry, tested with plugins added in-process."""

from __future__ import annotations

import logging
from types import SimpleNamespace

import pytest

from graspframe.common.errors import OutputError, PluginError, UnknownNameError
from graspframe.hal import Backend, Classifier
from graspframe.plugin_system import hookimpl
from graspframe.plugin_system.events import RunEvent, RunInfo
from graspframe.plugin_system.registry import Registry


def hand_plugin(*hands):
    @hookimpl
    def graspframe_register_hands(register):
        for hand in hands:
            register(hand)

    return SimpleNamespace(graspframe_register_hands=graspframe_register_hands)


def test_registered_hand_is_found_by_name(fake_hand):
    registry = Registry(strict=False)
    info = registry.add_plugin("fake", hand_plugin(fake_hand), package="fake-pkg")
    assert info.status == "loaded"
    assert info.provides == [("hand", "fake_hand")]
    assert registry.get_hand("fake_hand") is fake_hand
    assert registry.entry("hand", "fake_hand").package == "fake-pkg"


def test_unknown_name_lists_the_known_ones(fake_hand):
    registry = Registry(strict=False)
    registry.add_plugin("fake", hand_plugin(fake_hand))
    with pytest.raises(UnknownNameError) as err:
        registry.get_hand("allegro")
    assert str(err.value) == "unknown hand 'allegro'; known hands: fake_hand"
    with pytest.raises(UnknownNameError, match="none are registered"):
        registry.get_arm("kuka")


def test_same_name_from_a_second_package_is_refused_naming_both(fake_hand):
    registry = Registry(strict=False)
    registry.add_plugin("first", hand_plugin(fake_hand), package="pkg-one")
    second = registry.add_plugin("second", hand_plugin(fake_hand), package="pkg-two")
    assert second.status == "failed"
    assert "pkg-one" in second.error and "pkg-two" in second.error
    assert registry.entry("hand", "fake_hand").package == "pkg-one"


def test_registering_the_wrong_type_fails_that_plugin_only(fake_hand):
    registry = Registry(strict=False)
    bad = registry.add_plugin("bad", hand_plugin("not a hand"))
    good = registry.add_plugin("good", hand_plugin(fake_hand))
    assert bad.status == "failed"
    assert "expected a HandDescription" in bad.error
    assert good.status == "loaded"
    assert registry.names("hand") == ["fake_hand"]


def test_a_failing_plugin_registers_nothing(fake_hand):
    @hookimpl
    def graspframe_register_hands(register):
        register(fake_hand)
        raise RuntimeError("half-way")

    registry = Registry(strict=False)
    info = registry.add_plugin(
        "flaky", SimpleNamespace(graspframe_register_hands=graspframe_register_hands)
    )
    assert info.status == "failed"
    assert "RuntimeError: half-way" in info.error
    assert registry.names("hand") == []


def test_misspelt_hook_fails_loudly():
    @hookimpl
    def graspframe_register_hand(register):  # missing the final "s"
        pass

    registry = Registry(strict=False)
    info = registry.add_plugin(
        "typo", SimpleNamespace(graspframe_register_hand=graspframe_register_hand)
    )
    assert info.status == "failed"
    assert "graspframe_register_hand" in info.error


def test_strict_mode_reraises(fake_hand, monkeypatch):
    monkeypatch.setenv("GRASPFRAME_STRICT_PLUGINS", "1")
    registry = Registry()
    assert registry.strict
    with pytest.raises(PluginError, match="expected a HandDescription"):
        registry.add_plugin("bad", hand_plugin(42))


def test_backend_and_classifier_are_registered_as_classes():
    class FakeBackend(Backend):
        name = "fake_backend"

        def create_world(self, config):
            raise NotImplementedError

    class FakeClassifier(Classifier):
        name = "fake_classifier"

        def classify(self, image_bgr):
            raise NotImplementedError

    @hookimpl
    def graspframe_register_backends(register):
        register(FakeBackend)

    @hookimpl
    def graspframe_register_classifiers(register):
        register(FakeClassifier)

    registry = Registry(strict=True)
    registry.add_plugin(
        "fakes",
        SimpleNamespace(
            graspframe_register_backends=graspframe_register_backends,
            graspframe_register_classifiers=graspframe_register_classifiers,
        ),
    )
    assert registry.get_backend("fake_backend") is FakeBackend
    assert registry.get_classifier("fake_classifier") is FakeClassifier
    with pytest.raises(PluginError, match="expected a Backend subclass"):
        registry.add_plugin(
            "inst", SimpleNamespace(graspframe_register_backends=_registers(FakeBackend()))
        )


def _registers(item):
    @hookimpl
    def graspframe_register_backends(register):
        register(item)

    return graspframe_register_backends


def test_observers_all_run_when_one_fails(caplog):
    seen = []

    @hookimpl
    def graspframe_run_event(run, event):
        raise RuntimeError("observer bug")

    class Good:
        @hookimpl
        def graspframe_run_event(self, event):  # declares a subset of the arguments
            seen.append(event.kind)

    registry = Registry(strict=False)
    registry.add_plugin("bad_observer", SimpleNamespace(graspframe_run_event=graspframe_run_event))
    registry.add_plugin("good_observer", Good())
    run = RunInfo("r1", "/tmp/r1")
    with caplog.at_level(logging.ERROR):
        registry.notify_run_event(run, RunEvent("execute.contact", 0.1))
    assert seen == ["execute.contact"]
    assert "observer bug" in caplog.text


def test_an_observer_that_cannot_write_its_file_fails_the_run_after_the_others_ran(caplog):
    seen = []

    @hookimpl
    def graspframe_run_finished(run, result):
        raise OutputError(f"cannot write {run.out_dir}/recording.rrd: No space left on device")

    class Good:
        @hookimpl
        def graspframe_run_finished(self, run, result):
            seen.append(run.run_id)
            return {"summary": f"{run.out_dir}/summary.txt"}

    registry = Registry(strict=False)
    registry.add_plugin(
        "full_disk", SimpleNamespace(graspframe_run_finished=graspframe_run_finished)
    )
    registry.add_plugin("good_observer", Good())
    run = RunInfo("r1", "/tmp/r1")
    with pytest.raises(OutputError, match=r"recording\.rrd: No space left on device"):
        registry.notify_run_finished(run, result=None)
    assert seen == ["r1"]
    assert not caplog.text  # no traceback logged: the error is the run's own


def test_disabled_plugins_are_not_loaded(monkeypatch):
    monkeypatch.setenv("GRASPFRAME_DISABLE_PLUGINS", "barrett, kuka")
    registry = Registry.from_entry_points(strict=False)
    statuses = {p.name: p.status for p in registry.plugins}
    assert statuses["barrett"] == "disabled"
    assert statuses["kuka"] == "disabled"


def test_replacing_a_name_can_be_allowed_explicitly(fake_hand, monkeypatch):
    from dataclasses import replace

    monkeypatch.setenv("GRASPFRAME_ALLOW_OVERRIDE", "hand:fake_hand")
    registry = Registry(strict=False)
    registry.add_plugin("builtin", hand_plugin(fake_hand), package="graspframe")
    mine = replace(fake_hand, summary="my own")
    info = registry.add_plugin("mine", hand_plugin(mine), package="my-hands")
    assert info.status == "loaded"
    assert registry.get_hand("fake_hand").summary == "my own"
