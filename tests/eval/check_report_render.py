#!/usr/bin/env python3
"""Checks a headless-Chromium rendering of a slamkit HTML report (standard library only).

usage: check_report_render.py SCREENSHOT.png DOM.html MIN_SVG MIN_POLYLINE

The screenshot must not be blank: enough non-background pixels, many distinct colours, the
run colours of the plots (palette blue/orange) and the viridis colours of the colour-coded
paths must be present. The DOM Chromium built must hold the expected <svg>/<polyline>
elements with non-empty point lists, and no <script> element.
"""
import re
import struct
import sys
import zlib


def read_png(path):
    """Returns (width, height, channels, rows) for 8-bit RGB/RGBA non-interlaced PNGs."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit(f"{path}: not a PNG file")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace:
        raise SystemExit(f"{path}: unsupported PNG (depth {depth}, colour type {colour}, interlace {interlace})")
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, prev, k = [], bytearray(stride), 0
    for _ in range(height):
        kind, line = raw[k], bytearray(raw[k + 1:k + 1 + stride])
        k += 1 + stride
        if kind == 1:
            for x in range(channels, stride):
                line[x] = (line[x] + line[x - channels]) & 255
        elif kind == 2:
            line = bytearray((a + b) & 255 for a, b in zip(line, prev))
        elif kind == 3:
            for x in range(stride):
                left = line[x - channels] if x >= channels else 0
                line[x] = (line[x] + ((left + prev[x]) >> 1)) & 255
        elif kind == 4:
            for x in range(stride):
                a = line[x - channels] if x >= channels else 0
                b, c = prev[x], (prev[x - channels] if x >= channels else 0)
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return width, height, channels, rows


def near(c, ref, tol=40):
    return abs(c[0] - ref[0]) + abs(c[1] - ref[1]) + abs(c[2] - ref[2]) <= tol


def main():
    png, dom_path, min_svg, min_polyline = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
    failures = []

    width, height, channels, rows = read_png(png)
    colours, counts = {}, {"ink": 0, "blue": 0, "orange": 0, "viridis_dark": 0, "viridis_mid": 0}
    background = {(255, 255, 255), (244, 245, 247)}  # page and figure backgrounds
    for row in rows[::2]:  # every other row and pixel is plenty
        for x in range(0, width * channels, 2 * channels):
            c = (row[x], row[x + 1], row[x + 2])
            colours[c] = colours.get(c, 0) + 1
            if c in background:
                continue
            counts["ink"] += 1
            if near(c, (31, 119, 180)):
                counts["blue"] += 1
            if near(c, (255, 127, 14)):
                counts["orange"] += 1
            if near(c, (68, 1, 84), 60) or near(c, (59, 81, 139), 40):
                counts["viridis_dark"] += 1
            if near(c, (33, 144, 141), 40) or near(c, (92, 200, 99), 40):
                counts["viridis_mid"] += 1
    sampled = len(rows[::2]) * len(range(0, width * channels, 2 * channels))
    ink = counts["ink"] / sampled
    print(f"screenshot {width}x{height}: {len(colours)} distinct colours, {100 * ink:.1f} % ink, "
          f"blue {counts['blue']}, orange {counts['orange']}, viridis {counts['viridis_dark']}+{counts['viridis_mid']}")
    if ink < 0.05:
        failures.append(f"screenshot nearly blank ({100 * ink:.2f} % non-background pixels)")
    if len(colours) < 100:
        failures.append(f"only {len(colours)} distinct colours")
    for key, minimum in (("blue", 500), ("orange", 200), ("viridis_dark", 200), ("viridis_mid", 100)):
        if counts[key] < minimum:
            failures.append(f"too few {key} pixels: {counts[key]} < {minimum} (plot not drawn?)")

    dom = open(dom_path, encoding="utf-8", errors="replace").read()
    n_svg = len(re.findall(r"<svg\b", dom))
    polylines = re.findall(r"<polyline\b[^>]*\bpoints=\"([^\"]*)\"", dom)
    drawn = [p for p in polylines if len(p.split()) >= 2]
    print(f"DOM: {n_svg} <svg>, {len(polylines)} <polyline> ({len(drawn)} with 2+ points), "
          f"{len(re.findall(r'<table', dom))} <table>")
    if n_svg < min_svg:
        failures.append(f"{n_svg} <svg> elements < {min_svg}")
    if len(drawn) < min_polyline:
        failures.append(f"{len(drawn)} drawn <polyline> elements < {min_polyline}")
    if re.search(r"<script\b", dom):
        failures.append("the report contains a <script> element")
    if "Absolute pose error" not in dom or "Optimization" not in dom:
        failures.append("section headings missing from the DOM")

    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
