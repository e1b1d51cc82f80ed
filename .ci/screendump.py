#!/usr/bin/env python3
"""QEMU `screendump`s for .ci/board-vm and .ci/board-vm-quick (standard library only).

  screendump.py dump QMP.sock SHOT          the VM's screen through its QMP socket, as
                                            SHOT.ppm and SHOT.png

  screendump.py stats SHOT.ppm              size, mean, share of non-black pixels
  screendump.py screen SHOT.ppm WxH PCT     stats; exit 1 unless the size is WxH and at least
                                            PCT % of the pixels are not (nearly) black
  screendump.py differ A.ppm B.ppm MIN      exit 1 unless at least MIN pixels differ
  screendump.py shadow WITH.ppm WITHOUT.ppm MIN
      the same frame with and without the shadow passes: counts the pixels darker in WITH
      (every channel lower, the largest drop >= 8 levels) and brighter in WITH; exit 1 unless
      at least MIN are darker and at most 1 % as many are brighter
"""
import json
import socket
import sys


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


def stats(path):
    w, h, p = read_ppm(path)
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
    elif cmd == "differ" and len(sys.argv) == 5:
        wa, ha, a = read_ppm(sys.argv[2])
        wb, hb, b = read_ppm(sys.argv[3])
        if (wa, ha) != (wb, hb):
            sys.exit(f"screendump.py: sizes differ: {wa}x{ha} and {wb}x{hb}")
        n = sum(1 for i in range(0, len(a), 3) if a[i:i + 3] != b[i:i + 3])
        print(f"differ: {n} of {wa * ha} pixels differ")
        sys.exit(0 if n >= int(sys.argv[4]) else 1)
    elif cmd == "shadow" and len(sys.argv) == 5:
        wa, ha, a = read_ppm(sys.argv[2])
        wb, hb, b = read_ppm(sys.argv[3])
        if (wa, ha) != (wb, hb):
            sys.exit(f"screendump.py: sizes differ: {wa}x{ha} and {wb}x{hb}")
        darker = brighter = 0
        box = [wa, ha, -1, -1]
        for i in range(0, len(a), 3):
            d = [b[i + c] - a[i + c] for c in range(3)]
            if min(d) > 0 and max(d) >= 8:
                darker += 1
                x, y = (i // 3) % wa, (i // 3) // wa
                box = [min(box[0], x), min(box[1], y), max(box[2], x), max(box[3], y)]
            elif max(d) < 0 and min(d) <= -8:
                brighter += 1
        where = f"in x {box[0]}-{box[2]}, y {box[1]}-{box[3]}" if darker else "nowhere"
        print(f"shadow: {darker} pixels darker with the shadow passes ({where}), "
              f"{brighter} brighter")
        ok = darker >= int(sys.argv[4]) and brighter <= darker // 100
        sys.exit(0 if ok else 1)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
