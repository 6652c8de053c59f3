"""Human reference grasps: the contacts of the human hand performing a grasp on an object.

By default they are simulated: the free-floating human hand is placed at the reference
palm pose for the grasp (reference_poses.py), takes the grasp's open posture and closes
towards its closed posture until its fingers stop on the object. Results are cached per
(grasp, object, model) in the cache folder. Measured human contacts can replace them: a
JSON file in the format below (docs/method.md shows an example).

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
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from graspframe.contacts import Contact
from graspframe.errors import InputError
from graspframe.grasps import HumanGrasp
from graspframe.hal.descriptions import HandDescription
from graspframe.hal.drivers import Backend, WorldConfig
from graspframe.hal.objects import ObjectDescription
from graspframe.mounting import cache_dir
from graspframe.results import read_json_file
from graspframe.strategy.reference_poses import reference_placement
from graspframe.transforms import make_T

FORMAT = "graspframe.human_contacts/1"
# Part of the cache key: bump it when the way references are simulated changes.
PROCEDURE_VERSION = 2
SETTLE_TIME = 1.0  # [s] after the slowest joint could have reached its closed target
# The hand takes its open posture this far back along its palm normal, then approaches
# in small kinematic steps (it floats: its pose is set, not driven).
APPROACH_DISTANCE = 0.08  # [m]
APPROACH_STEP = 0.0005  # [m] per physics step
# Where the object stands in the reference world (the hand floats, so any place works).
T_WORLD_OBJECT_XY = (0.0, 0.0)


@dataclass(frozen=True)
class HumanReference:
    """Human contacts for one grasp on one object, in the object frame.

    source: "simulated", "cache" or the path of a measured-contacts file.
    """

    grasp: HumanGrasp
    object_name: str
    contacts: tuple[Contact, ...]
    source: str

    @property
    def touching_fingers(self) -> list[str]:
        return sorted({c.real_finger for c in self.contacts})

    def to_json(self) -> dict:
        return {
            "format": FORMAT,
            "grasp": self.grasp.value,
            "object": self.object_name,
            "frame": "object",
            "contacts": [c.to_dict() for c in self.contacts],
        }


def load_reference_file(path: Path | str) -> HumanReference:
    """Read measured human contacts (format in the module docstring); clear errors."""
    path = Path(path)
    data = read_json_file(path, "human contacts file")
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise InputError(f'{path}: expected a JSON object with "format": "{FORMAT}"')
    if data.get("frame") != "object":
        raise InputError(f'{path}: "frame" must be "object" (contacts in the object frame)')
    grasp = HumanGrasp.parse(str(data.get("grasp", "")))
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
        contacts.append(Contact(str(item.get("link", finger)), finger, p, n, f))
    if not contacts:
        raise InputError(f"{path}: no contacts")
    return HumanReference(grasp, str(data.get("object", "")), tuple(contacts), str(path))


def simulate_human_grasp(
    grasp: HumanGrasp, obj: ObjectDescription, human: HandDescription, backend: Backend
) -> HumanReference:
    """Perform the grasp with the free-floating human hand and read its contacts.

    The hand approaches its reference palm pose along the palm normal from
    APPROACH_DISTANCE back, then closes."""
    posture = human.preshape_for(grasp)
    T_world_object = make_T(p=[*T_WORLD_OBJECT_XY, obj.half_height])
    world = backend.create_world(
        WorldConfig(hand=human, arm=None, object=obj, T_world_object=T_world_object)
    )
    with world:
        T_world_palm = T_world_object @ reference_placement(obj, posture).T_object_palm
        # Shape the open posture away from the object, then approach along the palm
        # normal to the reference pose: the posture leaves the object room to come in.
        z_palm = T_world_palm[:3, 2]
        T_start = T_world_palm.copy()
        T_start[:3, 3] -= APPROACH_DISTANCE * z_palm
        world.hand.set_free_pose(T_start)
        world.hand.set_joint_targets(posture.open_q)
        world.step(round((_travel_time(human, {}, posture.open_q) + 0.2) / world.timestep))
        steps = round(APPROACH_DISTANCE / APPROACH_STEP)
        for k in range(1, steps + 1):
            T = T_start.copy()
            T[:3, 3] += k * APPROACH_STEP * z_palm
            world.hand.set_free_pose(T)
            world.step(1)
        world.hand.set_joint_targets(posture.closed_q)
        travel_time = _travel_time(human, posture.open_q, posture.closed_q)
        world.step(round((travel_time + SETTLE_TIME) / world.timestep))
        T_world_object_now = world.object.T_world_object()
        contacts = tuple(c.in_frame(T_world_object_now) for c in world.hand.contacts())
    return HumanReference(grasp, obj.name, contacts, "simulated")


def _travel_time(hand: HandDescription, q_from: dict, q_to: dict) -> float:
    """[s] for the slowest joint to go from q_from to q_to at its velocity limit."""
    return max(
        (
            abs(q_to[j.name] - q_from.get(j.name, 0.0)) / j.max_velocity
            for j in hand.joints
            if j.name in q_to
        ),
        default=0.0,
    )


def _cache_key(grasp: HumanGrasp, obj: ObjectDescription, human: HandDescription) -> str:
    digest = hashlib.sha256(f"procedure {PROCEDURE_VERSION}".encode())
    digest.update(Path(human.model_path).read_bytes())
    digest.update(reference_placement(obj, human.preshape_for(grasp)).T_object_palm.tobytes())
    digest.update(repr(sorted(human.preshape_for(grasp).closed_q.items())).encode())
    digest.update(repr(sorted(human.preshape_for(grasp).open_q.items())).encode())
    digest.update(repr((obj.shape, sorted(obj.dimensions.items()), obj.mass)).encode())
    return f"{grasp.value}_{obj.name}_{digest.hexdigest()[:12]}"


def human_reference(
    grasp: HumanGrasp,
    obj: ObjectDescription,
    human: HandDescription,
    backend: Backend,
    use_cache: bool = True,
) -> HumanReference:
    """The simulated human reference, from the cache when it holds it."""
    path = cache_dir().parent / "human_references" / f"{_cache_key(grasp, obj, human)}.json"
    if use_cache and path.is_file():
        cached = load_reference_file(path)
        return HumanReference(cached.grasp, obj.name, cached.contacts, "cache")
    reference = simulate_human_grasp(grasp, obj, human, backend)
    if reference.contacts:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(".tmp")
        tmp.write_text(json.dumps(reference.to_json(), indent=1))
        tmp.replace(path)
    return reference
