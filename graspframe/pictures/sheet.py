"""Panels composed into one picture: a title, a header over each column, a label beside
each row, a legend below, written as a PNG atomically.

Markers on a panel (contacts, arrows) are drawn with OpenCV, anti-aliased, in the
panel's pixels; text with Pillow's built-in scalable font. No matplotlib: a sheet of nine
360 px panels is composed in a few tens of milliseconds and written in about 0.1 s.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

from graspframe.common.files import atomic_output
from graspframe.pictures import style

TITLE_PX, HEADER_PX, LABEL_PX, LEGEND_PX = 20, 15, 15, 14  # font sizes
GAP = 8  # [px] between panels
MARGIN = 12  # [px] around the sheet
ROW_LABEL_WIDTH = 28  # [px] the rotated row label's band
LEGEND_SWATCH = 14  # [px]
CONTACT_RADIUS = 5  # [px]
ARROW_WIDTH = 2  # [px]
PALETTE_COLOURS = 256  # of a written PNG
PALETTE_SAMPLING = 4
PANEL_EDGE = (190, 190, 190)  # RGB of the line around each panel
KEPT_COLOURS = (
    "#000000", "#ffffff", style.CONTACT_COLOUR, style.PALM_Z_COLOUR, style.PALM_X_COLOUR,
    style.BACKGROUND, *style.FINGER_COLOURS, style.PALM_COLOUR, style.ARM_COLOUR,
    style.OBJECT_COLOUR,
)  # fmt: skip


@dataclass(frozen=True)
class LegendEntry:
    """kind: "patch" (a filled square), "dot" (a contact), "ring" (a hidden contact) or
    "arrow"."""

    kind: str
    colour: str
    label: str


def draw_contacts(panel: NDArray[np.uint8], pixels, hidden: bool = False) -> None:
    """Contact markers at `pixels` (n, 2) (column, row) on the panel: red dots with a
    black edge; red rings (hidden=True) for contacts out of sight."""
    red, black = style.bgr255(style.CONTACT_COLOUR), style.bgr255(style.CONTACT_EDGE)
    r = CONTACT_RADIUS * 16  # 4 fractional bits: sub-pixel placement
    for u, v in np.asarray(pixels, dtype=float).reshape(-1, 2):
        if not (np.isfinite(u) and np.isfinite(v)):
            continue
        centre = (round(u * 16), round(v * 16))
        if hidden:
            cv2.circle(panel, centre, r + 8, black, 1, cv2.LINE_AA, 4)
            cv2.circle(panel, centre, r - 8, red, 2, cv2.LINE_AA, 4)
        else:
            cv2.circle(panel, centre, r, red, -1, cv2.LINE_AA, 4)
            cv2.circle(panel, centre, r, black, 1, cv2.LINE_AA, 4)


def draw_arrow(panel: NDArray[np.uint8], start, end, colour: str) -> None:
    """An arrow from `start` to `end` (pixels); a dot when it points at the viewer."""
    start = np.asarray(start, dtype=float)
    end = np.asarray(end, dtype=float)
    if not (np.all(np.isfinite(start)) and np.all(np.isfinite(end))):
        return
    bgr = style.bgr255(colour)
    length = float(np.linalg.norm(end - start))
    a = (round(start[0] * 16), round(start[1] * 16))
    if length < 3.0:
        cv2.circle(panel, a, 4 * 16, bgr, -1, cv2.LINE_AA, 4)
        return
    b = (round(end[0] * 16), round(end[1] * 16))
    tip = min(0.45, 9.0 / length)
    cv2.arrowedLine(panel, a, b, bgr, ARROW_WIDTH, cv2.LINE_AA, 4, tip)


def _font(size: int):
    from PIL import ImageFont

    return ImageFont.load_default(size=size)


def _wrap(draw, text: str, font, width: float) -> list[str]:
    """Lines of `text` (its own line breaks kept) no wider than `width` pixels: broken
    between words, and inside a word (an object's long name) only where it alone is
    wider."""
    lines = []
    for paragraph in text.split("\n"):
        line = ""
        for word in paragraph.split(" "):
            candidate = word if not line else f"{line} {word}"
            if draw.textlength(candidate, font=font) <= width:
                line = candidate
                continue
            if line:
                lines.append(line)
            *whole, line = _pieces(draw, word, font, width)
            lines += whole
        lines.append(line)
    return lines


def _pieces(draw, word: str, font, width: float) -> list[str]:
    """`word` cut into pieces no wider than `width` pixels (one piece when it fits)."""
    pieces = [""]
    for character in word:
        if pieces[-1] and draw.textlength(pieces[-1] + character, font=font) > width:
            pieces.append("")
        pieces[-1] += character
    return pieces


def _legend_rows(draw, entries: Sequence[LegendEntry], font, width: float):
    """Entries in rows that fit `width`: [(x offset, entry), ...] per row."""
    rows: list[list[tuple[float, LegendEntry]]] = [[]]
    x = 0.0
    for entry in entries:
        entry_width = LEGEND_SWATCH + 6 + draw.textlength(entry.label, font=font) + 18
        if rows[-1] and x + entry_width > width:
            rows.append([])
            x = 0.0
        rows[-1].append((x, entry))
        x += entry_width
    return [row for row in rows if row]  # no legend: no row


def compose(
    title: str,
    column_headers: Sequence[str],
    row_labels: Sequence[str],
    panels: Sequence[Sequence[NDArray[np.uint8]]],
    legend: Sequence[LegendEntry],
) -> NDArray[np.uint8]:
    """The sheet as a BGR image: `panels[row][column]` (BGR, all the same size), the
    title wrapped over the top, each column's header (lines) above it, each row's label
    (rotated) left of it, the legend below."""
    from PIL import Image, ImageDraw

    n_rows, n_columns = len(panels), len(panels[0])
    panel_h, panel_w = panels[0][0].shape[:2]
    grid_w = n_columns * panel_w + (n_columns - 1) * GAP
    label_w = ROW_LABEL_WIDTH if row_labels else 0
    width = MARGIN + label_w + grid_w + MARGIN
    measure = ImageDraw.Draw(Image.new("RGB", (1, 1)))
    title_font, header_font = _font(TITLE_PX), _font(HEADER_PX)
    legend_font, label_font = _font(LEGEND_PX), _font(LABEL_PX)
    title_lines = _wrap(measure, title, title_font, width - 2 * MARGIN)
    header_lines = [_wrap(measure, h, header_font, panel_w - 4) for h in column_headers]
    title_h = len(title_lines) * (TITLE_PX + 6) + 8
    header_h = max((len(lines) for lines in header_lines), default=0) * (HEADER_PX + 4) + 6
    legend_rows = _legend_rows(measure, legend, legend_font, grid_w)
    legend_h = len(legend_rows) * (LEGEND_PX + 10) + 6
    grid_top = MARGIN + title_h + header_h
    grid_h = n_rows * panel_h + (n_rows - 1) * GAP
    height = grid_top + grid_h + 8 + legend_h + MARGIN

    sheet = Image.new("RGB", (width, height), "white")
    draw = ImageDraw.Draw(sheet)
    y = MARGIN
    for line in title_lines:
        draw.text((width / 2, y), line, font=title_font, fill=(0, 0, 0), anchor="ma")
        y += TITLE_PX + 6
    grid_left = MARGIN + label_w
    for column, lines in enumerate(header_lines):
        x = grid_left + column * (panel_w + GAP) + panel_w / 2
        top = MARGIN + title_h
        for k, line in enumerate(lines):
            draw.text(
                (x, top + k * (HEADER_PX + 4)), line, font=header_font, fill=(0, 0, 0), anchor="ma"
            )
    for row in range(n_rows):
        top = grid_top + row * (panel_h + GAP)
        for column in range(n_columns):
            left = grid_left + column * (panel_w + GAP)
            sheet.paste(Image.fromarray(panels[row][column][..., ::-1]), (left, top))
            draw.rectangle((left - 1, top - 1, left + panel_w, top + panel_h), outline=PANEL_EDGE)
        if row < len(row_labels):
            label = Image.new("RGB", (panel_h, ROW_LABEL_WIDTH), "white")
            ImageDraw.Draw(label).text(
                (panel_h / 2, ROW_LABEL_WIDTH / 2), row_labels[row], font=label_font,
                fill=(0, 0, 0), anchor="mm",
            )  # fmt: skip
            sheet.paste(label.rotate(90, expand=True), (MARGIN, top))
    y = grid_top + grid_h + 8
    for legend_row in legend_rows:
        row_width = legend_row[-1][0] + LEGEND_SWATCH + 6
        row_width += draw.textlength(legend_row[-1][1].label, font=legend_font)
        x0 = grid_left + (grid_w - row_width) / 2
        for offset, entry in legend_row:
            _legend_swatch(draw, entry, x0 + offset, y + 2)
            draw.text(
                (x0 + offset + LEGEND_SWATCH + 6, y + 2 + LEGEND_SWATCH / 2), entry.label,
                font=legend_font, fill=(0, 0, 0), anchor="lm",
            )  # fmt: skip
        y += LEGEND_PX + 10
    return np.asarray(sheet)[..., ::-1].copy()


def _legend_swatch(draw, entry: LegendEntry, x: float, y: float) -> None:
    s = LEGEND_SWATCH
    fill = style.rgb(entry.colour)
    fill_255 = tuple(round(255 * c) for c in fill)
    if entry.kind == "dot":
        draw.ellipse((x + 1, y + 1, x + s - 1, y + s - 1), fill=fill_255, outline=(0, 0, 0))
    elif entry.kind == "ring":
        draw.ellipse((x + 1, y + 1, x + s - 1, y + s - 1), outline=(0, 0, 0))
        draw.ellipse((x + 2, y + 2, x + s - 2, y + s - 2), outline=fill_255, width=2)
    elif entry.kind == "arrow":
        draw.line((x, y + s / 2, x + s - 5, y + s / 2), fill=fill_255, width=ARROW_WIDTH + 1)
        draw.polygon(
            ((x + s, y + s / 2), (x + s - 6, y + 2), (x + s - 6, y + s - 2)), fill=fill_255
        )
    else:
        draw.rectangle((x, y, x + s, y + s), fill=fill_255, outline=(60, 60, 60))


def write_png(path: Path, image: NDArray[np.uint8]) -> Path:
    """Write a BGR image as a PNG of at most PALETTE_COLOURS colours, atomically; returns
    the path. The folder is created.

    The palette: the exact marker and text colours (KEPT_COLOURS: a contact stays pure
    red), the rest a median-cut palette of the image (of every PALETTE_SAMPLING-th pixel
    each way: a fifth of the time); Floyd-Steinberg dithered so that shading shows no
    bands. A third of the size of a full-colour PNG of a rendered sheet.
    """
    from PIL import Image

    path = Path(path)
    rgb = Image.fromarray(np.ascontiguousarray(image[..., ::-1]))
    kept = [round(255 * c) for colour in KEPT_COLOURS for c in style.rgb(colour)]
    sample = rgb.reduce(PALETTE_SAMPLING)
    cut = sample.quantize(PALETTE_COLOURS - len(KEPT_COLOURS), method=Image.Quantize.MEDIANCUT)
    cut_palette = cut.getpalette() or []
    palette = Image.new("P", (1, 1))
    palette.putpalette(kept + cut_palette[: 3 * (PALETTE_COLOURS - len(KEPT_COLOURS))])
    paletted = rgb.quantize(palette=palette, dither=Image.Dither.FLOYDSTEINBERG)
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_output(path) as stream:
        paletted.save(stream, format="PNG", compress_level=3)
    return path
