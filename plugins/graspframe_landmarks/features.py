"""Joint-angle features and the palm frame from 21 hand landmarks (MediaPipe's layout).

Landmarks: 0 wrist; thumb 1 CMC, 2 MCP, 3 IP, 4 tip; then per finger (index, middle,
ring, little) MCP, PIP, DIP, tip at 5-8, 9-12, 13-16, 17-20. Points are (21, 3) in any
frame and unit (the features are angles [rad], invariant to rotation, translation,
scale and mirroring).

Features (19 angles [rad]), each the angle between two bone vectors:
- per finger: flexion at MCP (wrist->MCP vs MCP->PIP), PIP, DIP (consecutive bones);
- thumb: flexion at MCP (CMC->MCP vs MCP->IP) and IP. Not at the CMC: MediaPipe's CMC
  landmark sits near the wrist->thumb-MCP line, the model's CMC joint well off it, so that
  angle differed by 20 to 50 deg per grasp between the model and the real photographs
  (docs/vision.md), and dropping it raised the real-photo top-1;
- thumb abduction: thumb metacarpal (CMC->MCP) vs index metacarpal (wrist->index MCP);
- finger spread: proximal phalanges (MCP->PIP) of adjacent fingers, and thumb
  (MCP->tip) vs index (MCP->PIP).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from graspframe.vision.common import MIRROR_X, unmirror

WRIST = 0
THUMB = (1, 2, 3, 4)  # CMC, MCP, IP, tip
FINGERS = {
    "index": (5, 6, 7, 8),  # MCP, PIP, DIP, tip
    "middle": (9, 10, 11, 12),
    "ring": (13, 14, 15, 16),
    "little": (17, 18, 19, 20),
}
INDEX_MCP, MIDDLE_MCP, LITTLE_MCP = 5, 9, 17
FEATURE_NAMES = (
    *(f"{f}_{j}" for f in FINGERS for j in ("mcp", "pip", "dip")),
    "thumb_mcp",
    "thumb_ip",
    "thumb_abduction",
    "spread_index_middle",
    "spread_middle_ring",
    "spread_ring_little",
    "spread_thumb_index",
)


def _angle(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """Angle between two vectors [rad], in [0, pi]."""
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), np.dot(a, b)))


def angle_features(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """The 19 joint angles [rad] of one hand, in the order of FEATURE_NAMES."""
    p = np.asarray(points, np.float64)
    if p.shape != (21, 3):
        raise ValueError(f"expected (21, 3) landmarks, got shape {p.shape}")
    angles = []
    for mcp, pip, dip, tip in FINGERS.values():
        chain = (p[mcp] - p[WRIST], p[pip] - p[mcp], p[dip] - p[pip], p[tip] - p[dip])
        angles += [_angle(chain[i], chain[i + 1]) for i in range(3)]
    cmc, mcp, ip, tip = THUMB
    thumb = (p[mcp] - p[cmc], p[ip] - p[mcp], p[tip] - p[ip])
    angles += [_angle(thumb[i], thumb[i + 1]) for i in range(2)]
    angles.append(_angle(p[mcp] - p[cmc], p[INDEX_MCP] - p[WRIST]))
    proximal = [p[f[1]] - p[f[0]] for f in FINGERS.values()]
    angles += [_angle(proximal[i], proximal[i + 1]) for i in range(3)]
    angles.append(_angle(p[tip] - p[mcp], proximal[0]))
    return np.array(angles)


def palm_frame(points: NDArray[np.float64], left: bool = False) -> NDArray[np.float64]:
    """R_frame_palm: the palm frame of the landmarks in their own frame (3x3).

    +x wrist -> middle MCP, +y index MCP -> little MCP made orthogonal to x (the palm
    plane is spanned by x and y), +z = x X y, out of the palm on the palmar side for a
    right hand (the thumb is on -y), as the human model's hh_palm_frame. A left hand is
    mirrored (x -> -x) into a right hand and its frame mapped back (`unmirror`: the
    fingertip axis and the palm normal reflected back, y = z x x).
    """
    p = np.asarray(points, np.float64)
    if left:
        p = p @ MIRROR_X
    x = p[MIDDLE_MCP] - p[WRIST]
    x /= np.linalg.norm(x)
    y = p[LITTLE_MCP] - p[INDEX_MCP]
    y -= (y @ x) * x
    y /= np.linalg.norm(y)
    R = np.column_stack([x, y, np.cross(x, y)])
    return unmirror(R) if left else R
