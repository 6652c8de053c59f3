"""Robot models read with Pinocchio and coal (`model`: joints, limits, links, collision
shapes; `shapes`: primitives and collision geometry as meshes), a hand mounted on an arm's
flange (`mounting`), and the free-floating mount (`floating_base`)."""
