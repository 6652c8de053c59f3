"""The default objects, one per human grasp, sized from the method's grasp table
(docs/method.md, section 1).

Sizes follow the "typical object" column (large diameter: a can, diameter 7-9 cm; small
diameter: a handle, 2-3 cm; power sphere: a ball, 8-10 cm), with every object about 10 cm
in its largest dimension as in experiment B. Masses are those of everyday objects of that
size, and the friction (static 0.8, dynamic 0.6) that of a rubber-coated or
matt-plastic surface against the hands' pads: our choices, listed in docs/objects.md.
Cylinders stand upright (axis along the object's z); the object frame is the centroid.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from graspframe.common.grasps import HumanGrasp
from graspframe.hal.objects import ObjectDescription
from graspframe.plugin_system import hookimpl
from graspframe.plugin_system.hookspecs import Register

STATIC_FRICTION = 0.8
DYNAMIC_FRICTION = 0.6


def _object(**fields: Any) -> ObjectDescription:
    return ObjectDescription(
        static_friction=STATIC_FRICTION, dynamic_friction=DYNAMIC_FRICTION, **fields
    )


OBJECTS = (
    _object(
        name="large_cylinder",
        shape="cylinder",
        dimensions={"radius": 0.04, "length": 0.11},
        mass=0.30,
        default_for=frozenset({HumanGrasp.LARGE_DIAMETER}),
        summary="a can: diameter 8 cm, 11 cm tall, 300 g",
    ),
    _object(
        name="handle",
        shape="cylinder",
        dimensions={"radius": 0.0125, "length": 0.12},
        mass=0.08,
        default_for=frozenset({HumanGrasp.SMALL_DIAMETER}),
        summary="an upright bar or handle: diameter 2.5 cm, 12 cm tall, 80 g",
    ),
    _object(
        name="thumb_cylinder",
        shape="cylinder",
        dimensions={"radius": 0.03, "length": 0.10},
        mass=0.15,
        default_for=frozenset({HumanGrasp.ABDUCTED_THUMB}),
        summary="a cylinder held with the thumb abducted: diameter 6 cm, 10 cm tall, 150 g",
    ),
    _object(
        name="pinch_block",
        shape="box",
        dimensions={"size_x": 0.025, "size_y": 0.025, "size_z": 0.05},
        mass=0.03,
        default_for=frozenset({HumanGrasp.PINCH}),
        summary="a small block held between thumb and fingertips: 2.5 x 2.5 x 5 cm, 30 g",
    ),
    _object(
        name="ball",
        shape="sphere",
        dimensions={"radius": 0.045},
        mass=0.20,
        default_for=frozenset({HumanGrasp.POWER_SPHERE}),
        summary="a ball: diameter 9 cm, 200 g",
    ),
    _object(
        name="disc",
        shape="cylinder",
        dimensions={"radius": 0.045, "length": 0.025},
        mass=0.10,
        default_for=frozenset({HumanGrasp.PRECISION_DISC}),
        summary="a lid or disc lying flat: diameter 9 cm, 2.5 cm thick, 100 g",
    ),
)


# Every default object also comes about 25% smaller and 25% larger in every dimension
# (mass scaled with the volume), named <name>_075 and <name>_125: each grasp is tested
# on all three sizes.
SIZE_VARIANTS = (0.75, 1.25)


def scaled(obj: ObjectDescription, scale: float) -> ObjectDescription:
    """`obj` with every dimension times `scale` and its mass times scale^3; the variant
    is nobody's default object, but a person grasps it the same way."""
    return replace(
        obj,
        name=f"{obj.name}_{round(100 * scale):03d}",
        dimensions={k: scale * v for k, v in obj.dimensions.items()},
        mass=obj.mass * scale**3,
        default_for=frozenset(),
        grasps=obj.documented_grasps(),
        summary=f"{obj.summary.split(':')[0]}, {round(100 * scale)}% size",
    )


SIZED_OBJECTS = tuple(scaled(obj, scale) for obj in OBJECTS for scale in SIZE_VARIANTS)


@hookimpl
def graspframe_register_objects(register: Register) -> None:
    for obj in (*OBJECTS, *SIZED_OBJECTS):
        register(obj)
