"""Human reference grasps: the contacts of the human hand performing a grasp on an object.

By default they are simulated: the human hand, on the floating base (floating_base.py),
takes the grasp's open posture back from its reference palm pose (reference_poses.py),
approaches that pose along the palm normal and closes towards its closed posture until its
fingers stop on the object. Its contacts at the hold are the reference. The grasp then
goes through the robots' held test (held_check.py): a reference that does not hold says
so (`HumanReference.held`), and the run reports it. Results are cached per (grasp,
object, model, backend, held test) in the cache folder (graspframe/common/cache.py: checked when
read, rebuilt when damaged), the contacts, the verdict and the picture of the grasp in one
entry. Measured human contacts can replace them: a JSON file
in the format below (docs/method.md shows an example); they are taken as given (no held
test).

    {
      "format": "graspframe.human_contacts/1",
      "grasp": "pinch",                # a HumanGrasp name
      "object": "pinch_block",         # an object name
      "frame": "object",               # contacts are in the object frame (centroid)
      "contacts": [
        {"real_finger": "thumb", "p": [x, y, z], "n": [nx, ny, nz], "f": [fx, fy, fz]}
      ]
    }

p: position [m]; n: unit normal from the object into the hand; f: force of the hand on
the object [N].
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from graspframe.common.cache import ENTRY_FORMAT, CacheEntry, cache_dir, read_entry, write_entry
from graspframe.common.contacts import OBJECT, Contact
from graspframe.common.errors import InputError
from graspframe.common.files import temporary_path
from graspframe.common.grasps import HumanGrasp
from graspframe.common.json_files import jsonable, read_json_file
from graspframe.hal.descriptions import HandDescription, HandPreshape
from graspframe.hal.drivers import Backend, World, WorldConfig
from graspframe.hal.objects import ObjectDescription
from graspframe.motion.arm_motion import ArmMotion
from graspframe.motion.joint_limits import LimitExcess
from graspframe.pictures.snapshots import PICTURE_STYLE, draw_grasp
from graspframe.robot_models.floating_base import mount_floating
from graspframe.strategy.execution import ExecutionLog, Grip, execute
from graspframe.strategy.held_check import HeldTest, HeldVerdict
from graspframe.strategy.method import ExecutorParams
from graspframe.strategy.reference_poses import reference_placement

FORMAT = "graspframe.human_contacts/1"
CACHE_KIND = "human_references"
PICTURE = "picture.png"  # the picture of the simulated grasp, in its cache entry
# Part of the cache key: bump it when the way references are simulated changes.
PROCEDURE_VERSION = 5
# Part of the cache key: bump it when what an entry stores changes (2: every field of
# the held verdict and of the joint-limit excesses).
STORED_VALUES_VERSION = 2
CLOSING_SETTLE_TIME = 1.0  # [s] after the slowest joint could have reached its closed target
OPENING_SETTLE_TIME = 0.2  # [s] after the slowest joint could have reached its open target
# The hand takes its open posture this far back along its palm normal, then approaches.
APPROACH_DISTANCE = 0.08  # [m]
APPROACH_SPEED = ExecutorParams().approach_speed  # [m/s] the robots' non-volar approach
# Where the object stands in the reference world (the hand floats, so any place works).
T_WORLD_OBJECT_XY = (0.0, 0.0)


@dataclass(frozen=True)
class HumanReference:
    """Human contacts for one grasp on one object, in the object frame.

    source: "simulated", "cache" or the path of a measured-contacts file.
    held: the held test of the simulated grasp; None for measured contacts (not tested).
    picture: a PNG of the simulated grasp at the hold and after the lift (None: not drawn).
    joint_limit_violations: the joints the simulator moved past their model limit by more
        than the tolerance, as in result.json's joint_limits (simulated references only).
    """

    grasp: HumanGrasp
    object_name: str
    contacts: tuple[Contact, ...]
    source: str
    held: HeldVerdict | None = None
    picture: Path | None = None
    joint_limit_violations: tuple[LimitExcess, ...] = ()

    @property
    def touching_fingers(self) -> list[str]:
        return sorted({c.real_finger for c in self.contacts})

    def to_json(self) -> dict[str, object]:
        """The file format; a simulated reference adds its held verdict and the joints
        past their limits, every field of each (its cache entry reads them back)."""
        data: dict[str, object] = {
            "format": FORMAT,
            "grasp": self.grasp.value,
            "object": self.object_name,
            "frame": "object",
            "contacts": [c.to_dict() for c in self.contacts],
        }
        if self.held is not None:
            data["held_test"] = jsonable(self.held)
        if self.joint_limit_violations:
            data["joint_limit_violations"] = jsonable(self.joint_limit_violations)
        return data


def load_reference_file(path: Path | str) -> HumanReference:
    """Read measured human contacts (format in the module docstring); clear errors."""
    path = Path(path)
    return _reference_from_json(read_json_file(path, "human contacts file"), path)


def _reference_from_json(data: object, path: Path) -> HumanReference:
    """The measured reference in `data` (the file format), read from `path` (named in
    errors); it must have contacts."""
    data = _of_the_format(data, path)
    grasp = HumanGrasp.parse(str(data.get("grasp", "")))
    contacts = _contacts_from_json(data, path)
    if not contacts:
        raise InputError(f"{path}: no contacts")
    return HumanReference(grasp, str(data.get("object", "")), contacts, str(path))


def _of_the_format(data: object, path: Path) -> dict:
    """`data` when it is a JSON object of the file format with contacts in the object
    frame; an InputError naming `path` otherwise."""
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise InputError(f'{path}: expected a JSON object with "format": "{FORMAT}"')
    if data.get("frame") != "object":
        raise InputError(f'{path}: "frame" must be "object" (contacts in the object frame)')
    return data


def _contacts_from_json(data: dict, path: Path) -> tuple[Contact, ...]:
    """The contacts of `data` (of the file format; none is fine here), read from `path`."""
    contacts = []
    for index, item in enumerate(data.get("contacts") or []):
        try:
            p, n, f = (np.asarray(item[key], dtype=float) for key in ("p", "n", "f"))
            finger = str(item["real_finger"])
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(
                f"{path}: contact {index} needs real_finger and 3-vectors p, n, f ({exc})"
            ) from None
        if (
            p.shape != (3,)
            or n.shape != (3,)
            or f.shape != (3,)
            or not np.all(np.isfinite([*p, *n, *f]))
        ):
            raise InputError(f"{path}: contact {index}: p, n, f must be 3 finite numbers each")
        if abs(np.linalg.norm(n) - 1.0) > 1e-3:
            raise InputError(f"{path}: contact {index}: n must be a unit vector")
        contacts.append(Contact(str(item.get("link", finger)), finger, p, n, f, frame=OBJECT))
    return tuple(contacts)


def _cached_reference(entry: CacheEntry, obj: ObjectDescription) -> HumanReference:
    """A reference this module wrote to the cache (graspframe/common/cache.py checked the entry),
    its held test and picture included."""
    values = _of_the_format(entry.values, entry.folder)
    return HumanReference(
        HumanGrasp.parse(str(values["grasp"])),
        obj.name,
        _contacts_from_json(values, entry.folder),
        "cache",
        HeldVerdict.from_json(values["held_test"]),
        entry.files.get(PICTURE),
        tuple(LimitExcess.from_json(e) for e in values.get("joint_limit_violations", ())),
    )


@dataclass(frozen=True)
class HumanClosing:
    """The human hand's grasp policy (execution.py): take the open posture, approach the
    reference palm pose along the palm normal, close towards the closed posture open-loop
    (for the slowest joint's travel time, then CLOSING_SETTLE_TIME) until the fingers stop on
    the object."""

    human: HandDescription
    posture: HandPreshape
    approach_direction_world: NDArray[np.float64]

    def grasp(self, world: World, motion: ArmMotion, log: ExecutionLog) -> Grip:
        world.hand.set_joint_targets(self.posture.open_q)
        opening_time = _travel_time(self.human, {}, self.posture.open_q) + OPENING_SETTLE_TIME
        motion.idle(round(opening_time / world.timestep))
        motion.move_palm_linear(
            self.approach_direction_world, APPROACH_DISTANCE, APPROACH_SPEED, stop_on_contact=False
        )
        world.hand.set_joint_targets(self.posture.closed_q)
        travel_time = _travel_time(self.human, self.posture.open_q, self.posture.closed_q)
        motion.idle(round((travel_time + CLOSING_SETTLE_TIME) / world.timestep))
        return Grip()


def simulate_human_grasp(
    grasp: HumanGrasp,
    obj: ObjectDescription,
    human: HandDescription,
    backend: Backend,
    held: HeldTest | None = None,
    picture: Path | None = None,
) -> HumanReference:
    """Perform the grasp with the human hand on the floating base (`HumanClosing`),
    read its contacts at the hold, and judge it with the robots' held test `held`.

    The hand shapes its open posture APPROACH_DISTANCE back along the palm normal from its
    reference palm pose, approaches that pose, closes until its fingers stop on the
    object, holds, and is lifted and pushed. picture: also draw the hand at the hold and
    after the lift (snapshots.py) to this PNG."""
    posture = human.preshape_for(grasp)
    T_world_object = obj.T_world_standing(T_WORLD_OBJECT_XY)
    T_world_palm = T_world_object @ reference_placement(obj, posture).T_object_palm
    z_palm = T_world_palm[:3, 2]
    T_world_palm_start = T_world_palm.copy()
    T_world_palm_start[:3, 3] -= APPROACH_DISTANCE * z_palm
    robot, T_world_base = mount_floating(human, T_world_palm_start)
    config = WorldConfig(
        hand=human,
        object=obj,
        robot=robot,
        T_world_arm_base=T_world_base,
        T_world_object=T_world_object,
    )
    execution = execute(backend, config, HumanClosing(human, posture, z_palm), held or HeldTest())
    outcome = execution.outcome
    # The robot's rule: held, and touched by MIN_FINGERS real fingers (the palm counts).
    verdict = replace(outcome.verdict, failure=outcome.failure_reason)
    contacts = tuple(c.in_object_frame(outcome.T_world_object_at_hold) for c in outcome.contacts)
    violations = execution.joint_limits.violations
    reference = HumanReference(grasp, obj.name, contacts, "simulated", verdict, picture, violations)
    if picture is not None:
        what = f"human {grasp.value}, {obj.name}"
        draw_grasp(
            picture, robot, config.T_world_arm_base, obj, config.table_height,
            execution.moments, what, verdict.held, verdict.failure,
        )  # fmt: skip
    return reference


def _travel_time(
    hand: HandDescription, q_from: Mapping[str, float], q_to: Mapping[str, float]
) -> float:
    """[s] for the slowest joint to go from q_from to q_to at its velocity limit."""
    return max(
        (
            abs(q_to[j.name] - q_from.get(j.name, 0.0)) / j.max_velocity
            for j in hand.joints
            if j.name in q_to
        ),
        default=0.0,
    )


def _cache_key(
    grasp: HumanGrasp,
    obj: ObjectDescription,
    human: HandDescription,
    backend: Backend,
    held: HeldTest,
) -> str:
    versions = f"procedure {PROCEDURE_VERSION} {ENTRY_FORMAT} values {STORED_VALUES_VERSION}"
    digest = hashlib.sha256(versions.encode())
    digest.update(f"backend {backend.name}".encode())
    # The cached entry keeps its picture: a new picture style makes a new entry.
    digest.update(f"pictures {PICTURE_STYLE}".encode())
    digest.update(Path(human.model_path).read_bytes())
    digest.update(reference_placement(obj, human.preshape_for(grasp)).T_object_palm.tobytes())
    digest.update(repr(sorted(human.preshape_for(grasp).closed_q.items())).encode())
    digest.update(repr(sorted(human.preshape_for(grasp).open_q.items())).encode())
    digest.update(repr((obj.shape, sorted(obj.dimensions.items()), obj.mass)).encode())
    if obj.is_mesh:  # its files' content and the geometry made of them, not their names
        digest.update(obj.mesh_geometry().fingerprint.encode())
    digest.update(repr((obj.static_friction, obj.dynamic_friction, human.drive)).encode())
    # The stored held verdict depends on how the grasp is made and judged.
    procedure = (
        APPROACH_DISTANCE,
        APPROACH_SPEED,
        CLOSING_SETTLE_TIME,
        OPENING_SETTLE_TIME,
        held.key(),
    )
    digest.update(repr(procedure).encode())
    return f"{grasp.value}_{obj.name}_{digest.hexdigest()[:12]}"


def human_reference(
    grasp: HumanGrasp,
    obj: ObjectDescription,
    human: HandDescription,
    backend: Backend,
    held: HeldTest | None = None,
    use_cache: bool = True,
) -> HumanReference:
    """The simulated human reference with its picture, from the cache when it holds it
    (the cache key names the backend and the held test's criteria; default: the held
    test's defaults, as a run uses). A reference without contacts is cached too: the same
    inputs give it again."""
    held = held or HeldTest()
    folder = cache_dir(CACHE_KIND) / _cache_key(grasp, obj, human, backend, held)
    if use_cache:
        entry = read_entry(folder)
        if entry is not None:
            return _cached_reference(entry, obj)
    drawn = temporary_path(folder.with_suffix(".png"))  # then kept in the entry
    try:
        reference = simulate_human_grasp(grasp, obj, human, backend, held, picture=drawn)
        files = {PICTURE: drawn.read_bytes()} if drawn.is_file() else {}
    finally:
        drawn.unlink(missing_ok=True)
    entry = write_entry(folder, jsonable(reference.to_json()), files)
    return replace(reference, picture=entry.files.get(PICTURE))
