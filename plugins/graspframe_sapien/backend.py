"""The SAPIEN backend as registered: a light class whose worlds import SAPIEN when the
first one is built, so that listing the plugins does not load the simulator."""

from __future__ import annotations

from typing import TYPE_CHECKING

from graspframe.hal.drivers import Backend, WorldConfig

if TYPE_CHECKING:
    from graspframe_sapien.world import SapienWorld


class SapienBackend(Backend):
    name = "sapien"
    summary = "SAPIEN 3 physics (PhysX on the CPU, no renderer)"

    def create_world(self, config: WorldConfig) -> SapienWorld:
        from graspframe_sapien.world import SapienWorld

        return SapienWorld(config)
