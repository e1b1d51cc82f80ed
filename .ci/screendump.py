#!/usr/bin/env python3
"""QEMU `screendump`s for .ci/board-vm and .ci/board-vm-quick (standard library only).

  screendump.py dump QMP.sock SHOT          the VM's screen through its QMP socket, as
                                            SHOT.ppm and SHOT.png

  screendump.py stats SHOT.ppm              size, mean, share of non-black pixels
  screendump.py match SHOT.ppm FRAME.png PCT
                                            exit 1 unless at least PCT % of the pixels are
                                            within 2 levels in every channel (the screen shows
                                            the frame `penumbra render` draws); images are PPM
                                            or 8-bit RGB/RGBA PNG everywhere
  screendump.py screen SHOT.ppm WxH PCT     stats; exit 1 unless the size is WxH and at least
                                            PCT % of the pixels are not (nearly) black
  screendump.py differ A.ppm B.ppm MIN      exit 1 unless at least MIN pixels differ
"""
import json
import socket
import struct
import sys
import zlib


def qmp_screendump(sock_path, shot):
    """One QMP session: capabilities, then a screendump per format; QEMU's error exits."""
    s = socket.socket(socket.AF_UNIX)
    s.settimeout(50)
    s.connect(sock_path)
    f = s.makefile("rw")

    def reply():
        while True:
            m = json.loads(f.readline())
            if "event" not in m:
                return m

    reply()  # the greeting
    commands = [{"execute": "qmp_capabilities"}]
    for fmt in ("ppm", "png"):
        commands.append({"execute": "screendump",
                         "arguments": {"filename": f"{shot}.{fmt}", "format": fmt}})
    for cmd in commands:
        f.write(json.dumps(cmd) + "\n")
        f.flush()
        r = reply()
        if "error" in r:
            sys.exit(f"screendump.py: qmp {cmd['execute']}: {r['error']['desc']}")


def read_ppm(path):
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos)
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    if fields[0] != b"P6" or fields[3] != b"255":
        sys.exit(f"screendump.py: {path}: not a binary 8-bit PPM")
    w, h = int(fields[1]), int(fields[2])
    pixels = data[pos + 1:pos + 1 + w * h * 3]
    if len(pixels) != w * h * 3:
        sys.exit(f"screendump.py: {path}: truncated ({len(pixels)} of {w * h * 3} bytes)")
    return w, h, pixels


def read_png(path):
    """8-bit RGB or RGBA, not interlaced (what Penumbra and QEMU write) -> RGB bytes."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"screendump.py: {path}: not a PNG")
    pos, idat, header = 8, [], None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        pos += 12 + length
    w, h, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace:
        sys.exit(f"screendump.py: {path}: only 8-bit RGB/RGBA PNG without interlace")
    bpp = 3 if colour == 2 else 4
    raw, stride = zlib.decompress(b"".join(idat)), w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):  # the five PNG filters, undone in place
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line if bpp == 3 else bytearray(v for i, v in enumerate(line) if i % 4 != 3))
        prev = line
    return w, h, bytes(b"".join(rows))


def read_image(path):
    return read_png(path) if path.endswith(".png") else read_ppm(path)


def stats(path):
    w, h, p = read_image(path)
    n = w * h
    lit = sum(1 for i in range(0, len(p), 3) if p[i] + p[i + 1] + p[i + 2] > 24)
    print(f"{path}: {w}x{h}, mean {sum(p) / len(p):.1f}, non-black {100.0 * lit / n:.1f} %")
    return w, h, lit / n


def main():
    cmd = sys.argv[1] if len(sys.argv) > 1 else ""
    if cmd == "dump" and len(sys.argv) == 4:
        qmp_screendump(sys.argv[2], sys.argv[3])
        stats(sys.argv[3] + ".ppm")
    elif cmd == "stats" and len(sys.argv) == 3:
        stats(sys.argv[2])
    elif cmd == "screen" and len(sys.argv) == 5:
        w, h, lit = stats(sys.argv[2])
        ok = f"{w}x{h}" == sys.argv[3] and 100.0 * lit >= float(sys.argv[4])
        if not ok:
            print(f"screen: expected {sys.argv[3]} with >= {sys.argv[4]} % not black")
        sys.exit(0 if ok else 1)
    elif cmd == "match" and len(sys.argv) == 5:
        wa, ha, a = read_image(sys.argv[2])
        wb, hb, b = read_image(sys.argv[3])
        if (wa, ha) != (wb, hb):
            sys.exit(f"screendump.py: sizes differ: {wa}x{ha} and {wb}x{hb}")
        close = sum(1 for i in range(0, len(a), 3)
                    if max(abs(a[i + c] - b[i + c]) for c in range(3)) <= 2)
        share = 100.0 * close / (wa * ha)
        print(f"match: {share:.2f} % of the pixels within 2 levels")
        sys.exit(0 if share >= float(sys.argv[4]) else 1)
    elif cmd == "differ" and len(sys.argv) == 5:
        wa, ha, a = read_image(sys.argv[2])
        wb, hb, b = read_image(sys.argv[3])
        if (wa, ha) != (wb, hb):
            sys.exit(f"screendump.py: sizes differ: {wa}x{ha} and {wb}x{hb}")
        n = sum(1 for i in range(0, len(a), 3) if a[i:i + 3] != b[i:i + 3])
        print(f"differ: {n} of {wa * ha} pixels differ")
        sys.exit(0 if n >= int(sys.argv[4]) else 1)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
