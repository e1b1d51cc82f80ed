#!/usr/bin/env python3
"""Side-by-side crops for docs (issue 15's closing figures): the same window of several
frames of one view, each scaled up with nearest-neighbour pixels, and under each frame but
the first its signed difference from the first (grey 128 = equal, 4 grey levels per level).

  /usr/bin/python3 bench/crops.py OUT.png X0,Y0,X1,Y1 SCALE LABEL=FRAME.png [LABEL=FRAME.png ...]

The first frame is the reference. Labels are printed above the columns. Needs numpy and PIL
(python3-numpy, python3-pil).
"""
import sys

import numpy as np
from PIL import Image, ImageDraw


def main(argv):
    if len(argv) < 5:
        sys.exit(__doc__)
    out, window, scale = argv[1], [int(v) for v in argv[2].split(",")], int(argv[3])
    x0, y0, x1, y1 = window
    frames = []
    for item in argv[4:]:
        label, _, path = item.partition("=")
        if not path:
            sys.exit(f"crops.py: {item}: expected LABEL=FRAME.png")
        image = np.asarray(Image.open(path).convert("RGB")).astype(int)
        if not (0 <= x0 < x1 <= image.shape[1] and 0 <= y0 < y1 <= image.shape[0]):
            sys.exit(f"crops.py: {path}: window {argv[2]} is outside its {image.shape[1]}x{image.shape[0]}")
        frames.append((label, image[y0:y1, x0:x1]))
    reference = frames[0][1]

    def up(a):
        return np.kron(a, np.ones((scale, scale, 1), dtype=a.dtype))

    w, h = (x1 - x0) * scale, (y1 - y0) * scale
    pad, text = 6, 16
    sheet = Image.new("RGB", (len(frames) * (w + pad) + pad, 2 * (h + pad) + text + pad), "white")
    draw = ImageDraw.Draw(sheet)
    for i, (label, crop) in enumerate(frames):
        x = pad + i * (w + pad)
        draw.text((x, 2), label, fill="black")
        sheet.paste(Image.fromarray(up(crop).astype(np.uint8)), (x, text))
        if i == 0:
            continue
        diff = (crop - reference).mean(axis=2, keepdims=True)
        grey = np.clip(128 + 4 * diff, 0, 255).repeat(3, axis=2)
        sheet.paste(Image.fromarray(up(grey).astype(np.uint8)), (x, text + h + pad))
        err = np.abs(crop - reference).mean(axis=2)
        draw.text((x, text + 2 * h + pad + 1),
                  f"mean abs {err.mean():.2f}, p99 {np.percentile(err, 99):.0f}, max {err.max():.0f}",
                  fill="black")
    sheet.save(out)


if __name__ == "__main__":
    main(sys.argv)
