#!/usr/bin/env python3
"""Writes the hostile files of this directory, which ../hostile_files.rs loads; run it from here."""
import struct
import zlib


def png_chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png(width, height, depth, colour, chunks):
    ihdr = struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", ihdr) + b"".join(chunks) + png_chunk(b"IEND", b"")


def attr(name, kind, value):
    return name + b"\0" + kind + b"\0" + struct.pack("<i", len(value)) + value


def exr(compression, x1, y1, chunk_payload):
    channels = b"".join(c + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in (b"B", b"G", b"R")) + b"\0"
    header = b"".join([
        attr(b"channels", b"chlist", channels),
        attr(b"compression", b"compression", bytes([compression])),
        attr(b"dataWindow", b"box2i", struct.pack("<iiii", 0, 0, x1, y1)),
        attr(b"displayWindow", b"box2i", struct.pack("<iiii", 0, 0, x1, y1)),
        attr(b"lineOrder", b"lineOrder", b"\0"),
        attr(b"pixelAspectRatio", b"float", struct.pack("<f", 1.0)),
        attr(b"screenWindowCenter", b"v2f", struct.pack("<ff", 0, 0)),
        attr(b"screenWindowWidth", b"float", struct.pack("<f", 1.0)),
    ]) + b"\0"
    start = 8 + len(header) + 8
    chunk = struct.pack("<ii", 0, len(chunk_payload)) + chunk_payload
    # One offset (the rest of the table, if the window needs more chunks, is missing).
    return b"\x76\x2f\x31\x01" + struct.pack("<i", 2) + header + struct.pack("<Q", start) + chunk


def write(name, data):
    with open(name, "wb") as f:
        f.write(data)


# A 4-bit palette PNG whose PLTE chunk is 4 bytes, not a multiple of 3.
write("palette-plte-not-multiple-of-3.png", png(8, 1, 4, 3, [
    png_chunk(b"PLTE", b"\xff\x00\x00\x00"),
    png_chunk(b"IDAT", zlib.compress(b"\x00\x01\x23\x01\x23")),
]))
# A 69-byte PNG that claims 30000 x 30000 16-bit RGB pixels (5.4 GB decoded).
write("png-30000x30000.png", png(30000, 30000, 16, 2, [
    png_chunk(b"IDAT", zlib.compress(b"\x00" * 64)),
]))
# OpenEXR files with garbage chunks in the compressions raylab refuses from the header, whose
# decoders in exr 1.74 can allocate from unchecked chunk sizes: DWAA (8), PIZ (4), B44 (6),
# PXR24 (5); and ZIP (3) with a window of 200000 x 200000 pixels (4·10^10).
garbage = bytes(range(256)) * 4
write("exr-dwaa.exr", exr(8, 63, 63, garbage))
write("exr-piz.exr", exr(4, 63, 63, b"\xff\xff\xff\x7f" * 64))
write("exr-b44.exr", exr(6, 63, 63, garbage))
write("exr-pxr24.exr", exr(5, 63, 63, garbage))
write("exr-zip-huge-window.exr", exr(3, 199999, 199999, garbage))
# Text files that are not text, and references to a device.
write("not-text.obj", b"v 0 0 0\nv 1 0 0\n\xff\xfe\x00binary")
write("mtllib-dev-zero.obj", b"mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
write("mesh-dev-zero.toml", b"""[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]
up = [0, 1, 0]
focal_distance = 1.0

[[meshes]]
file = "/dev/zero"
""")
