"""The synthesis written as a spec's preshape table (graspframe/mapping/synthesis.py):
each preshape with a comment naming the grasps it serves, its object, its virtual-finger
errors and its held verdict."""

from __future__ import annotations

from graspframe.mapping.synthesis import GraspSynthesis, Synthesis
from graspframe.specs.draft import HandDraft
from graspframe.specs.draft_text import posture_table


def preshape_tables(synthesis: Synthesis, draft: HandDraft) -> str:
    """The [preshapes.*] tables, each with a comment: the grasp(s) it serves, its
    object, the virtual-finger errors (predicted by the kinematic closing, and measured
    in the held trial) and the held verdict."""
    lines = [
        "# Preshapes synthesised by graspframe from the human reference grasps (see",
        "# docs/synthesis.md): edit any value; `graspframe check-hand SPEC --synthesize`",
        "# rewrites them.",
    ]
    for grasp, why in synthesis.impossible.items():
        lines += ["", f"# {grasp}: no preshape, not in [grasp_map]. {why}."]
    by_preshape: dict[str, list[GraspSynthesis]] = {}
    for result in synthesis.grasps:
        by_preshape.setdefault(synthesis.grasp_map[result.grasp.value], []).append(result)
    for name, preshape in synthesis.preshapes.items():
        served = by_preshape[name]
        result = served[0]
        chosen = result.chosen
        lines.append("")
        also = [r.grasp.value for r in served[1:]]
        lines.append(
            f"# {result.grasp.value} on {result.obj.name}"
            + (f" (also serves {', '.join(also)}: the same preshape)" if also else "")
            + f": fingers {', '.join(chosen.choice.fingers)}, roll {chosen.choice.roll_deg:g} deg, "
            f"open {100 * chosen.choice.open_fraction:.0f} % closed."
        )
        lines.append(
            f"# Virtual-finger error: predicted {chosen.position_err_mm:.1f} mm, "
            f"{chosen.orientation_err_deg:.1f} deg"
            + (
                f"; measured {result.measured_position_err_mm:.1f} mm, "
                f"{result.measured_orientation_err_deg:.1f} deg"
                if result.measured_position_err_mm is not None
                and result.measured_orientation_err_deg is not None
                else ""
            )
            + "."
        )
        if result.held is None:
            lines.append("# Held: not tested.")
        elif result.held and result.design_failure:
            lines.append(
                f"# Held: yes (held trial {result.kept_trial} of {len(result.trials)}), but "
                f"not {result.design_failure}"
            )
        elif result.held:
            lines.append(f"# Held: yes (held trial {result.kept_trial} of {len(result.trials)}).")
        else:
            lines.append(f"# Held: NO after {len(result.trials)} candidates: {result.failure}")
        lines.append(f"[preshapes.{name}]")
        centre = ", ".join(f"{round(v, 4):g}" for v in preshape.grasp_center_palm)
        lines.append(f"grasp_center = [{centre}]")
        lines.append(f"roll_deg = {chosen.choice.roll_deg:g}")
        # the open fingertips' height over the palm (the standoff), as synthesised: 0 for
        # fingertips open level with or below the palm surface
        lines.append(f"delta = {round(max(preshape.delta, 0.0), 4):g}")
        design = preshape.design_object
        assert design is not None
        vector = lambda v: "[" + ", ".join(f"{round(float(x), 4):g}" for x in v) + "]"  # noqa: E731
        if design.shape == "sphere":
            lines.append(
                f'design_object = {{ shape = "sphere", centre = {vector(design.centre)}, '
                f"radius = {round(design.radius, 4):g} }}"
            )
        else:
            assert design.axis is not None and design.length is not None
            lines.append(
                f'design_object = {{ shape = "cylinder", centre = {vector(design.centre)}, '
                f"radius = {round(design.radius, 4):g}, axis = {vector(design.axis)}, "
                f"length = {round(design.length, 4):g} }}"
            )
        lines += posture_table(name, "open", preshape.open_q, draft.joints)
        lines += posture_table(name, "closed", preshape.closed_q, draft.joints)
    return "\n".join(lines)
