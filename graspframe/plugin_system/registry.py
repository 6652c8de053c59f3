"""The registry: what the plugins provide, looked up by name.

Plugins are found through the `graspframe` entry-point group, built-in ones exactly like
third-party ones. Each entry point is loaded on its own and each plugin's register hooks
are called on their own, so one broken plugin is recorded as failed (shown by
`graspframe plugins`) instead of taking the program down. Setting
GRASPFRAME_STRICT_PLUGINS=1 re-raises the first failure instead; GRASPFRAME_DISABLE_PLUGINS
takes a comma-separated list of plugin names not to load.

Core code asks the registry (`get_hand("karlsruhe")`), never `pm.hook` directly. Where
a hand or an arm is asked for, a spec file path (`my_hand.toml`, graspframe/specs/)
may stand in for a registered name; where an object is, a mesh file with its sidecar
(`mug.obj` beside `mug.toml`, graspframe/specs/objects.py). What a plugin found and
could not register (`NotRegistered`) is kept with the plugin and named when looked up.
"""

from __future__ import annotations

import functools
import logging
import os
import traceback
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from importlib.metadata import EntryPoint, entry_points
from pathlib import Path
from types import ModuleType
from typing import Any

import pluggy

from graspframe.common.errors import OutputError, PluginError, UnknownNameError
from graspframe.common.grasps import HumanGrasp
from graspframe.hal.classifier import Classifier
from graspframe.hal.depth_camera import DepthCamera
from graspframe.hal.descriptions import ArmDescription, HandDescription
from graspframe.hal.drivers import Backend
from graspframe.hal.objects import ObjectDescription
from graspframe.plugin_system import NotRegistered, hookspecs
from graspframe.plugin_system.events import RunEvent, RunInfo
from graspframe.plugin_system.kinds import KINDS, Kind
from graspframe.specs import is_spec_path, load_spec
from graspframe.specs.objects import is_object_path, load_object_file

log = logging.getLogger(__name__)

ENTRY_POINT_GROUP = "graspframe"
STRICT_ENV = "GRASPFRAME_STRICT_PLUGINS"
DISABLE_ENV = "GRASPFRAME_DISABLE_PLUGINS"
# Comma-separated names a plugin may take over from another package (e.g. "hand:barrett").
ALLOW_OVERRIDE_ENV = "GRASPFRAME_ALLOW_OVERRIDE"


@dataclass(frozen=True)
class Entry:
    """One registered thing and where it came from."""

    kind: str
    name: str
    item: Any
    plugin: str
    package: str


@dataclass
class PluginInfo:
    """One plugin (an entry point) and what became of it.

    status: "loaded", "failed" or "disabled"; error: one line; details: the traceback.
    """

    name: str
    module: str
    package: str
    version: str
    status: str = "loaded"
    error: str | None = None
    details: str | None = None
    provides: list[tuple[str, str]] = field(default_factory=list)  # (kind, name)
    # what its register hooks found and could not register: (kind, name, reason)
    not_registered: list[tuple[str, str, str]] = field(default_factory=list)


def _strict_from_env() -> bool:
    return os.environ.get(STRICT_ENV, "").strip().lower() in {"1", "true", "yes", "on"}


def _disabled_from_env() -> set[str]:
    return {n.strip() for n in os.environ.get(DISABLE_ENV, "").split(",") if n.strip()}


def _call(impl: Any, **kwargs: Any) -> Any:
    """Call one hook implementation with the arguments it declares (pluggy allows a subset)."""
    return impl.function(*(kwargs[name] for name in impl.argnames))


def _one_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0] if text else ''}".rstrip(": ")


class Registry:
    """Registered hands, arms, backends, classifiers, objects, cameras, viewers and commands,
    with their origin."""

    def __init__(self, strict: bool | None = None) -> None:
        self.strict = _strict_from_env() if strict is None else strict
        self._pm = pluggy.PluginManager("graspframe")
        self._pm.add_hookspecs(hookspecs)
        self._entries: dict[str, dict[str, Entry]] = {kind: {} for kind in KINDS}
        self.plugins: list[PluginInfo] = []

    # -- loading ---------------------------------------------------------------------------

    @classmethod
    def from_entry_points(cls, strict: bool | None = None) -> Registry:
        """Load every plugin of the `graspframe` entry-point group, one at a time."""
        registry = cls(strict=strict)
        disabled = _disabled_from_env()
        for ep in sorted(entry_points(group=ENTRY_POINT_GROUP), key=lambda e: e.name):
            registry._load_entry_point(ep, disabled)
        return registry

    def _load_entry_point(self, ep: EntryPoint, disabled: set[str]) -> None:
        dist = ep.dist
        info = PluginInfo(
            name=ep.name,
            module=ep.value,
            package=dist.name if dist is not None else "?",
            version=dist.version if dist is not None else "?",
        )
        self.plugins.append(info)
        if ep.name in disabled:
            info.status = "disabled"
            info.error = f"disabled by {DISABLE_ENV}"
            return
        try:
            module = ep.load()
        except Exception as exc:
            self._fail(info, exc, "import failed")
            return
        self._register_module(info, module)

    def add_plugin(
        self, name: str, module: ModuleType | object, package: str = "", version: str = ""
    ) -> PluginInfo:
        """Register a plugin object directly (tests, notebooks); same checks as entry points."""
        info = PluginInfo(
            name=name,
            module=getattr(module, "__name__", type(module).__name__),
            package=package or "(added directly)",
            version=version,
        )
        self.plugins.append(info)
        self._register_module(info, module)
        return info

    def _register_module(self, info: PluginInfo, module: object) -> None:
        try:
            self._pm.register(module, name=info.name)
            # A hook implementation whose name matches no hookspec (a typo) fails loudly.
            self._pm.check_pending()
        except Exception as exc:
            if self._pm.is_registered(module):
                self._pm.unregister(module)
            self._fail(info, exc, "invalid hook implementation")
            return
        try:
            self._collect(info, module)
        except Exception as exc:
            self._pm.unregister(module)
            self._fail(info, exc, "registration failed")

    def _collect(self, info: PluginInfo, module: object) -> None:
        """Call this plugin's register hooks; add its entries only if all of them succeed."""
        staged: list[Entry] = []
        skipped: list[tuple[str, str, str]] = []
        for kind in KINDS.values():
            for impl in getattr(self._pm.hook, kind.hook).get_hookimpls():
                if impl.plugin is not module:
                    continue
                _call(impl, register=self._stager(kind, info, staged, skipped))
        # An object whose name another plugin took is left out, not the whole source: a
        # folder of scans loses one scan, and a catalogue loaded after it loses nothing.
        for entry in [
            e for e in staged if e.kind == "object" and e.name in self._entries["object"]
        ]:
            taken = self._entries["object"][entry.name]
            reason = (
                f"the name is taken by plugin {taken.plugin!r} (package {taken.package}); "
                "give it another name"
            )
            staged.remove(entry)
            skipped.append((entry.kind, entry.name, reason))
        for entry in staged:
            self._check_unique(entry)
        for entry in staged:
            self._entries[entry.kind][entry.name] = entry
            info.provides.append((entry.kind, entry.name))
        info.not_registered.extend(skipped)

    def _stager(
        self,
        kind: Kind,
        info: PluginInfo,
        staged: list[Entry],
        skipped: list[tuple[str, str, str]],
    ) -> Callable:
        def register(item: Any) -> None:
            if isinstance(item, NotRegistered):
                skipped.append((kind.name, item.name, item.reason))
                return
            if not kind.accepts(item):
                raise PluginError(
                    f"plugin {info.name!r} registered {item!r} as a {kind.name}; "
                    f"expected {kind.expected}"
                )
            name = getattr(item, "name", None)
            if not isinstance(name, str) or not name:
                raise PluginError(f"plugin {info.name!r} registered a {kind.name} with no name")
            if any(e.kind == kind.name and e.name == name for e in staged):
                raise PluginError(f"plugin {info.name!r} registers {kind.name} {name!r} twice")
            staged.append(Entry(kind.name, name, item, info.name, info.package))

        return register

    def _check_unique(self, entry: Entry) -> None:
        existing = self._entries[entry.kind].get(entry.name)
        if existing is None:
            return
        allowed = {n.strip() for n in os.environ.get(ALLOW_OVERRIDE_ENV, "").split(",")}
        if f"{entry.kind}:{entry.name}" in allowed:
            log.warning(
                "%s %r from package %s replaces the one from package %s (%s)",
                entry.kind, entry.name, entry.package, existing.package, ALLOW_OVERRIDE_ENV,
            )  # fmt: skip
            return
        raise PluginError(
            f"{entry.kind} {entry.name!r} from plugin {entry.plugin!r} "
            f"(package {entry.package}) is already provided by plugin "
            f"{existing.plugin!r} (package {existing.package}); refusing to replace it "
            f"(allow it with {ALLOW_OVERRIDE_ENV}={entry.kind}:{entry.name})"
        )

    def _fail(self, info: PluginInfo, exc: Exception, what: str) -> None:
        info.status = "failed"
        info.error = f"{what}: {_one_line(exc)}"
        info.details = "".join(traceback.format_exception(exc))
        log.warning("plugin %r (%s) %s", info.name, info.package, info.error)
        if self.strict:
            raise PluginError(f"plugin {info.name!r} ({info.package}): {info.error}") from exc

    # -- lookup ----------------------------------------------------------------------------

    def names(self, kind: str) -> list[str]:
        return sorted(self._entries[kind])

    def entries(self, kind: str) -> list[Entry]:
        return [self._entries[kind][n] for n in self.names(kind)]

    def entry(self, kind: str, name: str) -> Entry:
        try:
            return self._entries[kind][name]
        except KeyError:
            for plugin, reason in self.not_registered(kind).get(name, []):
                raise UnknownNameError(
                    kind, name, self._entries[kind], f"plugin {plugin!r} found it: {reason}"
                ) from None
            raise UnknownNameError(kind, name, self._entries[kind]) from None

    def not_registered(self, kind: str) -> dict[str, list[tuple[str, str]]]:
        """name -> [(plugin, reason)] of what the plugins found of a kind and could not
        register."""
        found: dict[str, list[tuple[str, str]]] = {}
        for info in self.plugins:
            for item_kind, name, reason in info.not_registered:
                if item_kind == kind:
                    found.setdefault(name, []).append((info.name, reason))
        return found

    def get_hand(self, name: str) -> HandDescription:
        """The registered hand `name`, or the hand of the spec file `name` (*.toml)."""
        if is_spec_path(name):
            return _spec_of_kind(name, HandDescription, "hand")
        return self.entry("hand", name).item

    def get_arm(self, name: str) -> ArmDescription:
        """The registered arm `name`, or the arm of the spec file `name` (*.toml)."""
        if is_spec_path(name):
            return _spec_of_kind(name, ArmDescription, "arm")
        return self.entry("arm", name).item

    def get_backend(self, name: str) -> type[Backend]:
        return self.entry("backend", name).item

    def get_classifier(self, name: str) -> type[Classifier]:
        return self.entry("classifier", name).item

    def get_object(self, name: str) -> ObjectDescription:
        """The registered object `name`, or the object of a mesh file with its sidecar
        (or of the sidecar file itself, graspframe/specs/objects.py)."""
        if is_object_path(name):
            # absolute, not resolved: a symlinked mesh keeps the sidecar beside the link
            return _load_object_file(str(Path(name).expanduser().absolute()))
        return self.entry("object", name).item

    def get_camera(self, name: str) -> type[DepthCamera]:
        return self.entry("camera", name).item

    def default_object_for(self, grasp: HumanGrasp) -> ObjectDescription:
        """The registered object that is the default for a human grasp."""
        for entry in self.entries("object"):
            if grasp in entry.item.default_for:
                return entry.item
        raise UnknownNameError(
            f"default object for {grasp.value}", grasp.value, self.names("object")
        )

    @property
    def failures(self) -> list[PluginInfo]:
        return [p for p in self.plugins if p.status == "failed"]

    # -- observers -------------------------------------------------------------------------

    def notify_run_started(self, run: RunInfo) -> None:
        self._notify("graspframe_run_started", run=run)

    def notify_run_event(self, run: RunInfo, event: RunEvent) -> None:
        self._notify("graspframe_run_event", run=run, event=event)

    def notify_run_finished(self, run: RunInfo, result: Any) -> dict[str, str]:
        """Tell the observers the run ended; the files they wrote for it, by name."""
        artifacts: dict[str, str] = {}
        for written in self._notify("graspframe_run_finished", run=run, result=result):
            if isinstance(written, dict):
                artifacts.update({str(k): str(v) for k, v in written.items()})
        return artifacts

    def _notify(self, hook: str, **kwargs: Any) -> list[Any]:
        """Call each implementation on its own (a failing observer is logged and the
        others still run); what they returned. An observer that cannot write its files
        (OutputError) fails the run: the first such error is raised once every observer
        has been called."""
        returned = []
        output_errors: list[OutputError] = []
        for impl in getattr(self._pm.hook, hook).get_hookimpls():
            try:
                returned.append(_call(impl, **kwargs))
            except OutputError as exc:
                output_errors.append(exc)
            except Exception:
                if self.strict:
                    raise
                log.exception("observer %r failed in %s", impl.plugin_name, hook)
        if output_errors:
            raise output_errors[0]
        return returned


def _spec_of_kind(path: str, kind: type, what: str) -> Any:
    """The description of a spec file, which must describe a `what`."""
    description = _load_spec(str(Path(path).expanduser().resolve()))
    if not isinstance(description, kind):
        found = "hand" if isinstance(description, HandDescription) else "arm"
        raise PluginError(
            f"spec {Path(path).name} describes a {found} ({description.name}), where {what}s "
            "are expected"
        )
    return description


@functools.cache
def _load_spec(path: str) -> HandDescription | ArmDescription:
    return load_spec(path)


@functools.cache
def _load_object_file(path: str) -> ObjectDescription:
    return load_object_file(path)


@functools.cache
def default_registry() -> Registry:
    """The registry of every installed plugin, loaded once per process."""
    return Registry.from_entry_points()


def get_hand(name: str) -> HandDescription:
    return default_registry().get_hand(name)


def get_arm(name: str) -> ArmDescription:
    return default_registry().get_arm(name)


def get_backend(name: str) -> type[Backend]:
    return default_registry().get_backend(name)


def get_classifier(name: str) -> type[Classifier]:
    return default_registry().get_classifier(name)


def get_object(name: str) -> ObjectDescription:
    return default_registry().get_object(name)


def names(kind: str) -> Iterable[str]:
    return default_registry().names(kind)
