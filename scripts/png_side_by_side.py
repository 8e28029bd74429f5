#!/usr/bin/env python3
"""Puts PNG pictures side by side in one PNG, left to right, with a thin gap.

usage: png_side_by_side.py OUT.png IN.png [IN.png ...] [--crop X,Y,W,H]

Reads the 8-bit RGB or RGBA, non-interlaced PNGs the game's --screenshot
writes (Python's standard library only: the docs' pictures are made where no
image tool is installed). --crop takes the same rectangle of every picture
first. Pictures of different heights are aligned at the top on white.
"""
import struct
import sys
import zlib


def read_png(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"{path}: not a PNG")
    pos, idat, width, height, channels = 8, b"", 0, 0, 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos : pos + 8])
        body = data[pos + 8 : pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            width, height, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or color not in (2, 6) or interlace:
                sys.exit(f"{path}: only 8-bit RGB or RGBA, non-interlaced PNGs")
            channels = 3 if color == 2 else 4
        elif kind == b"IDAT":
            idat += body
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1 : start + 1 + stride])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = previous[i]
            c = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + ((a + b) >> 1)) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        previous = line
    if channels == 4:  # drop alpha: the screenshots are opaque
        rows = [bytearray(v for i, v in enumerate(r) if i % 4 != 3) for r in rows]
    return width, height, rows


def write_png(path, width, height, rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def main(argv):
    crop = None
    if "--crop" in argv:
        i = argv.index("--crop")
        crop = [int(v) for v in argv[i + 1].split(",")]
        del argv[i : i + 2]
    if len(argv) < 3:
        sys.exit(__doc__)
    pictures = []
    for path in argv[2:]:
        width, height, rows = read_png(path)
        if crop:
            x, y, w, h = crop
            rows = [r[3 * x : 3 * (x + w)] for r in rows[y : y + h]]
            width, height = w, h
        pictures.append((width, height, rows))
    gap = 6
    total = sum(p[0] for p in pictures) + gap * (len(pictures) - 1)
    tallest = max(p[1] for p in pictures)
    out = []
    for y in range(tallest):
        line = bytearray()
        for k, (width, height, rows) in enumerate(pictures):
            if k:
                line += b"\xff" * (3 * gap)
            line += rows[y] if y < height else b"\xff" * (3 * width)
        out.append(line)
    write_png(argv[1], total, tallest, out)


if __name__ == "__main__":
    main(sys.argv)
