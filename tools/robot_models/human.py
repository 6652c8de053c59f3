"""Generate robots/human/human.urdf: the human RIGHT hand, the reference hand for scoring.

    cd /work/main && python -m tools.robot_models.human [--hand-length 0.17] [--out PATH]

20 joints: per finger (index, middle, ring, little) ab/adduction and flexion at the knuckle
(MCP), flexion at the middle joint (PIP) and at the end joint (DIP, a URDF <mimic> of the PIP
at 2/3); the thumb has 2 joints at its base (CMC abduction and flexion), one at the MCP and
one at the IP. Segment lengths are Buchholz et al. (1992) ratios times the hand length (wrist
crease to the tip of the extended middle finger); every other dimension is given at the
reference size (190 mm) and scales with the hand length, so the whole hand scales uniformly.

Frames. Working coordinates of the hand (u, v, w): u along the hand towards the fingertips,
w out of the palm on the palmar side, v = w x u (for a right hand the thumb is at -v). The
root link hh_wrist has its origin at the wrist crease in the mid-plane of the palm, its
+z = u (towards the fingers, like a robot hand's root pointing away from the arm),
+x = -w (out of the back of the hand) and +y = v. The palm frame hh_palm_frame has
x = u, y = v, z = w: rotated by -90 deg about the root's y axis. All finger link frames are
parallel to the root frame at the zero pose (z along the finger), so every finger flexes
about its local -y axis and ab/adducts about its local -x axis (the palm normal).

Collision geometry only (boxes, cylinders, spheres). Mass: a total hand mass shared by
volume (one uniform density), so inertias follow the shapes.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from graspframe.common.transforms import R_from_axis_angle, inv_T, make_T, rpy_from_R
from tools.robot_models.urdf_builder import Box, Cylinder, Sphere, UrdfBuilder

PREFIX = "hh_"
OUT_PATH = Path(__file__).resolve().parents[2] / "robots" / "human" / "human.urdf"

# ---- size -------------------------------------------------------------------------------
# A typical adult hand is about 190 mm long. Our chosen size: 190 mm.
HAND_LENGTH_M = 0.19
REFERENCE_HAND_LENGTH_M = 0.19  # the size at which the *_MM dimensions below are given

# Buchholz et al. 1992 (docs/robots/human.md): segment length / hand length.
# Fingers: metacarpal, proximal, middle, distal; thumb: metacarpal, proximal, distal.
SEGMENT_RATIOS = {
    "thumb": (0.251, 0.196, 0.158),
    "index": (0.374, 0.265, 0.143, 0.097),
    "middle": (0.373, 0.277, 0.170, 0.108),
    "ring": (0.336, 0.259, 0.165, 0.107),
    "little": (0.295, 0.206, 0.117, 0.093),
}
FINGERS = ("index", "middle", "ring", "little")  # radial (thumb side) to ulnar

# ---- palm -------------------------------------------------------------------------------
PALM_WIDTH_MM = 85.0  # a typical adult palm: about 85 wide
PALM_THICKNESS_MM = 28.0  # assumption: adult palm thickness at the metacarpals is ~25-30 mm
PAD_THICKNESS_MM = 2.0  # assumption: the palm sensor pad is the palmar 2 mm skin layer
# Assumption: the metacarpal bases (CMC joints of the fingers) sit closer together than the
# knuckles: their lateral offsets are this fraction of the knuckles' (metacarpals converge).
METACARPAL_BASE_SPREAD = 0.6
# Assumption: gap between a palm box's distal face and the proximal phalanx's rounded
# knuckle, so a finger can flex 90 deg without entering the palm.
KNUCKLE_CLEARANCE_MM = 1.0
# A typical adult palm is about 100 long: our palm body reaches from the wrist crease to
# just before each knuckle (74 mm on the middle ray at 190 mm); the rest of the 100 mm, the
# skin web up to the finger crease, is covered by the proximal phalanges (see docs).

# ---- digit radii (assumption: human-like phalanx half-widths, ~8-10 mm) ------------------
# proximal, middle, distal phalanx radius [mm]
FINGER_RADII_MM = {
    "index": (9.5, 8.5, 7.5),
    "middle": (10.0, 9.0, 8.0),
    "ring": (9.0, 8.5, 7.5),
    "little": (8.0, 7.5, 7.0),
}
# thumb metacarpal, proximal, distal phalanx radius [mm]
THUMB_RADII_MM = (11.0, 10.0, 9.0)

# ---- thumb base (assumption: typical adult anatomy, no published number used) ---
# CMC joint position (u, v, w) [mm]: near the wrist, just outside the radial face of the
# palm box (the 85 mm palm width is measured across the metacarpals; the thumb base and
# thenar widen the hand beyond it near the wrist), a little in front of the mid-plane.
THUMB_CMC_MM = (16.0, -44.5, 4.0)
# Zero pose of the thumb: lying in the palm plane beside the index, its metacarpal turned
# this far from the hand axis towards the radial side, its pad turned this far about the
# thumb axis from facing palmar (+w) towards the fingers (the thumb's natural pronation).
THUMB_REST_RADIAL_DEG = 40.0
THUMB_REST_PRONATION_DEG = 70.0
# The CMC abduction axis runs along the hand axis, turned this far towards the ulnar side
# (+v) and lifted this far out of the palm plane (+w). Turning about it carries the thumb
# out of the palm plane in front of the palm and turns its pad towards the fingertips
# (opposition); the CMC flexion axis is perpendicular to the thumb and bends it towards
# its pad, as do the MCP and IP.
THUMB_ABD_AXIS_ULNAR_DEG = 12.0
THUMB_ABD_AXIS_PALMAR_DEG = 16.0
# The first THUMB_METACARPAL_HIDDEN_MM of the thumb metacarpal lie inside the wrist
# (carpus): its collision cylinder starts there, clear of the palm body.
THUMB_METACARPAL_HIDDEN_MM = 17.0
# Assumption: the thenar corner of the palm, radial to THENAR_V_MM and up to
# THENAR_FREE_U_MM along the hand, belongs to the thumb: the palm body and pad leave it out
# and the thenar eminence fills it, a cylinder (rounded ends) on the thumb's CMC link lying
# along the CMC abduction axis, so abduction turns it in place and it never sweeps into the
# palm; the thumb metacarpal can flex into the corner before it meets the palm.
THENAR_V_MM = -31.0
THENAR_FREE_U_MM = 38.0
THENAR_RADIUS_MM = 13.0
THENAR_SPAN_MM = (-6.0, 14.0)  # along the abduction axis from the CMC

# ---- joint limits [deg] -----------------------------------------------------------------
# The usual 20-DOF hand model (docs/robots/human.md): ab/adduction +-20 index, +-10
# middle, +-20 ring, +-30 little; MCP, PIP and DIP -10..90 each. Positive ab/adduction
# turns a finger towards the little finger (+v); positive flexion bends it towards the
# palm (+w).
ABD_LIMIT_DEG = {"index": 20.0, "middle": 10.0, "ring": 20.0, "little": 30.0}
FLEX_LIMITS_DEG = (-10.0, 90.0)  # MCP, PIP, and the DIP's own limits (the usual range)
DIP_PIP_RATIO = 2.0 / 3.0  # end joint coupled to the middle at 2/3 (Rijpkema & Girard 1991)
# Thumb (assumption: typical goniometric ranges; the CMC flexion range is wider than the
# clinical 15 deg because this model has no CMC rotation joint and reaches opposition by
# abduction plus flexion of a pre-pronated thumb).
THUMB_LIMITS_DEG = {
    "cmc_abd": (-10.0, 100.0),
    "cmc_flex": (-20.0, 50.0),
    "mcp": (-10.0, 60.0),
    "ip": (-20.0, 80.0),
}

# ---- motion, effort and mass (assumption) -----------------------------------------------
VELOCITY_LIMIT = 5.0  # [rad/s] fast voluntary finger motion
EFFORT_LIMITS = {  # [N m] roughly tendon force x moment arm
    "abd": 1.0,
    "mcp": 3.0,
    "pip": 1.5,
    "dip": 0.8,
    "thumb_cmc_abd": 3.0,
    "thumb_cmc_flex": 3.0,
    "thumb_mcp": 2.0,
    "thumb_ip": 1.0,
}
HAND_MASS_KG = 0.45  # assumption: ~0.6 % of a 75 kg adult's body mass, at 190 mm


def _sum_in_order(values) -> float:
    """The floats added left to right. Python 3.12 made the built-in `sum` of floats a
    compensated sum: its last bits differ from 3.11's, and the generated inertias (noise
    of order 1e-38 in the products of inertia) with them; the generator must write the
    same file on every Python."""
    total = 0.0
    for value in values:
        total += value
    return total


def _fmt_round(values, ndigits: int = 9) -> tuple[float, ...]:
    """Round away float noise so the output is the same on every machine."""
    return tuple(round(float(v), ndigits) + 0.0 for v in values)


class _Frames:
    """Zero-pose link frames as 4x4 poses in the root frame, and URDF origins from them."""

    def __init__(self):
        self.T: dict[str, np.ndarray] = {}

    def set(self, link: str, R: np.ndarray, p: np.ndarray) -> None:
        self.T[link] = make_T(R, p)

    def origin(self, parent: str, child: str) -> tuple[tuple, tuple]:
        T = inv_T(self.T[parent]) @ self.T[child]
        return _fmt_round(T[:3, 3]), _fmt_round(rpy_from_R(T[:3, :3]))


def _hand_to_root(u: float, v: float, w: float) -> np.ndarray:
    """Hand coordinates (u, v, w) -> root frame (x, y, z) = (-w, v, u)."""
    return np.array([-w, v, u])


def _unit(x: np.ndarray) -> np.ndarray:
    return x / np.linalg.norm(x)


def build(hand_length: float = HAND_LENGTH_M) -> UrdfBuilder:
    """The hand model for a given hand length [m]."""
    s = hand_length / REFERENCE_HAND_LENGTH_M  # scale of the *_MM dimensions
    mm = 1e-3 * s
    width, thickness, pad = PALM_WIDTH_MM * mm, PALM_THICKNESS_MM * mm, PAD_THICKNESS_MM * mm
    length = {d: tuple(r * hand_length for r in ratios) for d, ratios in SEGMENT_RATIOS.items()}

    # Knuckles: spread evenly across the palm width, in the mid-plane; each knuckle lies one
    # metacarpal length from its metacarpal base. The bases sit on one line across the hand,
    # placed so the extended middle finger ends exactly one hand length from the wrist.
    ray_width = width / 4
    knuckle_v = {f: (i - 1.5) * ray_width for i, f in enumerate(FINGERS)}
    base_v = {f: METACARPAL_BASE_SPREAD * knuckle_v[f] for f in FINGERS}
    along = {  # u-distance from metacarpal base to knuckle
        f: math.sqrt(length[f][0] ** 2 - (knuckle_v[f] - base_v[f]) ** 2) for f in FINGERS
    }
    base_u = hand_length - along["middle"] - sum(length["middle"][1:])
    knuckle_u = {f: base_u + along[f] for f in FINGERS}

    radii = {f: tuple(r * mm for r in FINGER_RADII_MM[f]) for f in FINGERS}
    thumb_radii = tuple(r * mm for r in THUMB_RADII_MM)
    palm_end_u = {f: knuckle_u[f] - radii[f][0] - KNUCKLE_CLEARANCE_MM * mm for f in FINGERS}

    # Collision shapes by link (name without the prefix); one density shares the mass.
    shapes_by_link: dict[str, list] = {}

    # ---- palm body and pad: one box per metacarpal ray, up to just before its knuckle.
    thenar_v, thenar_u = THENAR_V_MM * mm, THENAR_FREE_U_MM * mm
    palm_shapes, pad_shapes = [], []

    def ray_boxes(u0, u1, v0, v1):
        """A palm box and the pad box on its palmar face, for the band v0..v1, u0..u1."""
        w_body = thickness - pad
        centre_body = _hand_to_root((u0 + u1) / 2, (v0 + v1) / 2, -thickness / 2 + w_body / 2)
        centre_pad = _hand_to_root((u0 + u1) / 2, (v0 + v1) / 2, thickness / 2 - pad / 2)
        palm_shapes.append(Box((w_body, v1 - v0, u1 - u0), _fmt_round(centre_body)))
        pad_shapes.append(Box((pad, v1 - v0, u1 - u0), _fmt_round(centre_pad)))

    for f in FINGERS:
        v0, v1 = knuckle_v[f] - ray_width / 2, knuckle_v[f] + ray_width / 2
        if v0 < thenar_v < v1:  # the thenar corner belongs to the thumb
            ray_boxes(thenar_u, palm_end_u[f], v0, thenar_v)
            ray_boxes(0.0, palm_end_u[f], thenar_v, v1)
        else:
            ray_boxes(0.0, palm_end_u[f], v0, v1)
    shapes_by_link["wrist"] = palm_shapes
    shapes_by_link["palm_pad"] = pad_shapes

    # ---- digits: shapes in the link's own frame (z along the phalanx from its joint).
    def phalanx(seg_length, radius, last, start=0.0):
        shapes = [
            Cylinder(
                radius,
                seg_length - start - (radius if last else 0.0),
                _fmt_round((0, 0, (start + seg_length - (radius if last else 0.0)) / 2)),
            )
        ]
        if start == 0.0:  # rounded proximal end: the knuckle / joint
            shapes.append(Sphere(radius))
        if last:  # rounded fingertip, its surface at the segment end
            shapes.append(Sphere(radius, _fmt_round((0, 0, seg_length - radius))))
        return shapes

    for f in FINGERS:
        _, prox, mid, dist = length[f]
        for name, seg, r, last in (
            ("proximal", prox, radii[f][0], False),
            ("intermediate", mid, radii[f][1], False),
            ("distal", dist, radii[f][2], True),
        ):
            shapes_by_link[f"{f}_{name}"] = phalanx(seg, r, last)
    t_meta, t_prox, t_dist = length["thumb"]
    shapes_by_link["thumb_metacarpal"] = phalanx(
        t_meta, thumb_radii[0], False, start=THUMB_METACARPAL_HIDDEN_MM * mm
    )
    shapes_by_link["thumb_proximal"] = phalanx(t_prox, thumb_radii[1], False)
    shapes_by_link["thumb_distal"] = phalanx(t_dist, thumb_radii[2], True)

    # Thumb frame at its zero pose: z along the metacarpal, -x towards the thumb pad.
    radial = math.radians(THUMB_REST_RADIAL_DEG)
    z_t = _hand_to_root(math.cos(radial), -math.sin(radial), 0.0)
    w_root = _hand_to_root(0.0, 0.0, 1.0)
    pad_dir = R_from_axis_angle(z_t, -math.radians(THUMB_REST_PRONATION_DEG)) @ w_root
    x_t = -pad_dir
    R_thumb = np.column_stack([x_t, np.cross(z_t, x_t), z_t])
    # Abduction axis (root frame), signed so that a positive angle lifts the thumb to +w.
    ulnar, palmar = math.radians(THUMB_ABD_AXIS_ULNAR_DEG), math.radians(THUMB_ABD_AXIS_PALMAR_DEG)
    abd_axis_root = _hand_to_root(
        math.cos(palmar) * math.cos(ulnar), math.cos(palmar) * math.sin(ulnar), math.sin(palmar)
    )
    if R_from_axis_angle(abd_axis_root, 0.1) @ z_t @ w_root < 0:
        abd_axis_root = -abd_axis_root
    thumb_abd_axis = R_thumb.T @ abd_axis_root
    cmc = _hand_to_root(*(c * mm for c in THUMB_CMC_MM))
    # Thenar eminence on the CMC link, along the abduction axis (see THENAR_SPAN_MM).
    thenar_r = THENAR_RADIUS_MM * mm
    s0, s1 = (x * mm for x in THENAR_SPAN_MM)
    a = thumb_abd_axis
    helper = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = _unit(np.cross(helper, a))
    R_thenar = np.column_stack([e1, np.cross(a, e1), a])  # local z along the axis
    shapes_by_link["thumb_cmc"] = [
        Cylinder(
            thenar_r, s1 - s0, _fmt_round(a * (s0 + s1) / 2), _fmt_round(rpy_from_R(R_thenar))
        ),
        Sphere(thenar_r, _fmt_round(a * s0)),
        Sphere(thenar_r, _fmt_round(a * s1)),
    ]

    total_volume = _sum_in_order(sh.volume for shapes in shapes_by_link.values() for sh in shapes)
    density = HAND_MASS_KG * s**3 / total_volume

    def mass(link):
        return density * _sum_in_order(sh.volume for sh in shapes_by_link[link])

    # ---- zero-pose frames -----------------------------------------------------------
    frames = _Frames()
    I3 = np.eye(3)
    frames.set("wrist", I3, np.zeros(3))
    frames.set("palm_pad", I3, np.zeros(3))
    # Palm frame: at the area centroid of the palmar surface (outer face of the pad).
    areas = np.array([b.size[1] * b.size[2] for b in pad_shapes])
    centroid = (areas[:, None] * np.array([b.xyz for b in pad_shapes])).sum(0) / areas.sum()
    palm_origin = _hand_to_root(centroid[2], centroid[1], thickness / 2)
    R_root_palm = np.column_stack(
        [_hand_to_root(1, 0, 0), _hand_to_root(0, 1, 0), _hand_to_root(0, 0, 1)]
    )
    frames.set("palm_frame", R_root_palm, palm_origin)
    for f in FINGERS:
        _, prox, mid, dist = length[f]
        frames.set(f"{f}_metacarpal", I3, _hand_to_root(base_u, base_v[f], 0.0))
        knuckle = _hand_to_root(knuckle_u[f], knuckle_v[f], 0.0)
        frames.set(f"{f}_knuckle", I3, knuckle)
        frames.set(f"{f}_proximal", I3, knuckle)
        frames.set(f"{f}_intermediate", I3, knuckle + np.array([0, 0, prox]))
        frames.set(f"{f}_distal", I3, knuckle + np.array([0, 0, prox + mid]))
        frames.set(f"{f}_tip", I3, knuckle + np.array([0, 0, prox + mid + dist]))

    frames.set("thumb_cmc", R_thumb, cmc)
    frames.set("thumb_metacarpal", R_thumb, cmc)
    frames.set("thumb_proximal", R_thumb, cmc + R_thumb @ [0, 0, t_meta])
    frames.set("thumb_distal", R_thumb, cmc + R_thumb @ [0, 0, t_meta + t_prox])
    frames.set("thumb_tip", R_thumb, cmc + R_thumb @ [0, 0, t_meta + t_prox + t_dist])

    # ---- write ----------------------------------------------------------------------
    b = UrdfBuilder(
        "human",
        comment=(
            "Human right hand, generated by tools/robot_models/human.py "
            f"(hand length {hand_length * 1000:.1f} mm); do not edit by hand."
        ),
    )

    def add_link(name):
        if name in shapes_by_link:
            b.link(PREFIX + name, mass(name), shapes_by_link[name])
        else:  # a frame marker
            b.link(PREFIX + name)

    def add_joint(
        name, kind, parent, child, axis=(0, 0, 1), limits_deg=(0, 0), effort=0.0, mimic=None
    ):
        xyz, rpy = frames.origin(parent, child)
        b.joint(
            PREFIX + name,
            kind,
            PREFIX + parent,
            PREFIX + child,
            xyz,
            rpy,
            axis,
            math.radians(limits_deg[0]),
            math.radians(limits_deg[1]),
            effort,
            VELOCITY_LIMIT if kind != "fixed" else 0.0,
            mimic,
        )

    flex_axis = (0.0, -1.0, 0.0)  # local -y: a positive angle bends towards the palm
    abd_axis = (-1.0, 0.0, 0.0)  # local -x = palm normal: positive turns towards +v

    add_link("wrist")
    add_link("palm_pad")
    add_joint("palm_pad_joint", "fixed", "wrist", "palm_pad")
    add_link("palm_frame")
    add_joint("palm_frame_joint", "fixed", "wrist", "palm_frame")
    for f in FINGERS:
        lim = ABD_LIMIT_DEG[f]
        add_link(f"{f}_metacarpal")
        add_joint(f"{f}_cmc", "fixed", "wrist", f"{f}_metacarpal")
        add_link(f"{f}_knuckle")
        add_joint(
            f"{f}_abd",
            "revolute",
            f"{f}_metacarpal",
            f"{f}_knuckle",
            abd_axis,
            (-lim, lim),
            EFFORT_LIMITS["abd"],
        )
        add_link(f"{f}_proximal")
        add_joint(
            f"{f}_mcp",
            "revolute",
            f"{f}_knuckle",
            f"{f}_proximal",
            flex_axis,
            FLEX_LIMITS_DEG,
            EFFORT_LIMITS["mcp"],
        )
        add_link(f"{f}_intermediate")
        add_joint(
            f"{f}_pip",
            "revolute",
            f"{f}_proximal",
            f"{f}_intermediate",
            flex_axis,
            FLEX_LIMITS_DEG,
            EFFORT_LIMITS["pip"],
        )
        add_link(f"{f}_distal")
        add_joint(
            f"{f}_dip",
            "revolute",
            f"{f}_intermediate",
            f"{f}_distal",
            flex_axis,
            FLEX_LIMITS_DEG,
            EFFORT_LIMITS["dip"],
            mimic=(f"{PREFIX}{f}_pip", DIP_PIP_RATIO, 0.0),
        )
        add_link(f"{f}_tip")
        add_joint(f"{f}_tip_joint", "fixed", f"{f}_distal", f"{f}_tip")
    lim = THUMB_LIMITS_DEG
    add_link("thumb_cmc")
    add_joint(
        "thumb_cmc_abd",
        "revolute",
        "wrist",
        "thumb_cmc",
        _fmt_round(thumb_abd_axis),
        lim["cmc_abd"],
        EFFORT_LIMITS["thumb_cmc_abd"],
    )
    add_link("thumb_metacarpal")
    add_joint(
        "thumb_cmc_flex",
        "revolute",
        "thumb_cmc",
        "thumb_metacarpal",
        flex_axis,
        lim["cmc_flex"],
        EFFORT_LIMITS["thumb_cmc_flex"],
    )
    add_link("thumb_proximal")
    add_joint(
        "thumb_mcp",
        "revolute",
        "thumb_metacarpal",
        "thumb_proximal",
        flex_axis,
        lim["mcp"],
        EFFORT_LIMITS["thumb_mcp"],
    )
    add_link("thumb_distal")
    add_joint(
        "thumb_ip",
        "revolute",
        "thumb_proximal",
        "thumb_distal",
        flex_axis,
        lim["ip"],
        EFFORT_LIMITS["thumb_ip"],
    )
    add_link("thumb_tip")
    add_joint("thumb_tip_joint", "fixed", "thumb_distal", "thumb_tip")
    return b


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--hand-length",
        type=float,
        default=HAND_LENGTH_M,
        help="wrist crease to middle fingertip [m] (default 0.19)",
    )
    parser.add_argument("--out", type=Path, default=OUT_PATH, help="URDF file to write")
    args = parser.parse_args(argv)
    path = build(args.hand_length).write(args.out)
    sys.stdout.write(f"wrote {path}\n")


if __name__ == "__main__":
    main()
