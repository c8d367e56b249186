#!/usr/bin/env python3
"""Compares two folders of frames (facerig-player --headless --frames) pixel by pixel.

usage: scripts/compare-frames.py DIR_A DIR_B [--picture FILE.png]

Prints, per frame and over all, the largest difference in a colour channel (0-255), the mean
difference and how many channels differ. --picture writes the frame of DIR_B that differs most (by
the mean) beside its difference from DIR_A times 64. Reads 8-bit RGB / RGBA PNGs without interlacing (what
the player writes) with the standard library only. Exit code 1 when the folders hold different
frame names or sizes, 2 on a bad command line.
"""
import os
import struct
import sys
import zlib


def read_png(path):
    """The raw 8-bit channels of a PNG, its channel count and its width."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, header = 8, [], None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    channels = {2: 3, 6: 4}.get(colour)
    if depth != 8 or channels is None or interlace:
        raise ValueError(f"{path}: only 8-bit RGB / RGBA PNGs without interlacing are read")
    raw = zlib.decompress(b"".join(idat))
    stride = width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            left = line[i - channels] if i >= channels else 0
            up, up_left = previous[i], previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 255
            elif kind == 2:
                line[i] = (line[i] + up) & 255
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - up_left
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - up_left)
                line[i] = (line[i] + (left if pa <= pb and pa <= pc else up if pb <= pc else up_left)) & 255
        rows.append(line)
        previous = line
    return b"".join(rows), channels, width


def write_png(path, rgb, width, height):
    """8-bit RGB rows, no filtering."""
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    rows = b"".join(b"\0" + rgb[y * width * 3:(y + 1) * width * 3] for y in range(height))
    with open(path + ".tmp", "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))
    os.replace(path + ".tmp", path)


def write_picture(path, a, b, channels, width):
    """Frame b beside |a - b| * 64 (alpha left out)."""
    height = len(a) // (width * channels)
    out = bytearray()
    for y in range(height):
        row = range(y * width * channels, (y + 1) * width * channels)
        out += bytes(b[i] for i in row if i % channels < 3)
        out += bytes(min(255, 64 * abs(a[i] - b[i])) for i in row if i % channels < 3)
    write_png(path, bytes(out), 2 * width, height)


def main(argv):
    picture = None
    if len(argv) == 5 and argv[3] == "--picture":
        picture, argv = argv[4], argv[:3]
    if len(argv) != 3:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    names = sorted(n for n in os.listdir(argv[1]) if n.endswith(".png"))
    if names != sorted(n for n in os.listdir(argv[2]) if n.endswith(".png")):
        print("the folders hold different frames", file=sys.stderr)
        return 1
    worst, total, count, differing_frames, most = 0, 0, 0, 0, (-1.0, None)
    for name in names:
        (a, channels, width), (b, other_channels, other_width) = (read_png(os.path.join(d, name)) for d in argv[1:])
        if len(a) != len(b) or channels != other_channels or width != other_width:
            print(f"{name}: the frames differ in size", file=sys.stderr)
            return 1
        colour = [i for i in range(len(a)) if i % channels < 3]  # alpha is left out
        diffs = [abs(a[i] - b[i]) for i in colour]
        largest, changed = max(diffs), sum(1 for d in diffs if d)
        print(f"{name}: max {largest}, mean {sum(diffs) / len(diffs):.5f}, {changed} channels differ")
        worst, total, count = max(worst, largest), total + sum(diffs), count + len(diffs)
        differing_frames += largest > 0
        most = max(most, (sum(diffs) / len(diffs), name), key=lambda m: m[0])
    print(f"{len(names)} frames, {differing_frames} differ: max {worst} / 255 in a channel, mean {total / count:.5f}")
    if picture and most[1]:
        (a, channels, width), (b, _, _) = (read_png(os.path.join(d, most[1])) for d in argv[1:])
        write_picture(picture, a, b, channels, width)
        print(f"wrote {picture}: {most[1]} of {argv[2]} beside its difference from {argv[1]} times 64")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
