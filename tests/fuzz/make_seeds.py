#!/usr/bin/env python3
"""Gathers the seed corpus of every fuzz target (docs/fuzzing.md) into OUT/<target>/.

    python3 tests/fuzz/make_seeds.py SOURCE_DIR OUT

Seeds come from three places, so the repository holds no copy of data/:
  - data/ files as they are (models, sessions, the showroom scene) or reshaped into the
    target's input layout (a frame trace's JSON, a NUL byte, its buffer; a .glb packed
    from the glTF teapot; triangles for triangle_setup);
  - tests/fuzz/corpus/<target>/: small seeds that data/ has no file for (a bundle, a kiosk
    configuration, a capture manifest, EXR, PNG and JPEG images);
  - tests/fuzz/regressions/<target>/: reproducers of fixed crashes, so every run (and the
    ctest fuzz.<target>) replays them.
OUT/<target>/ is emptied first; libFuzzer adds what it finds there during a run.
"""
import base64
import json
import shutil
import struct
import sys
from pathlib import Path


def trace_seed(traces: Path, name: str) -> bytes:
    doc = json.loads((traces / f"{name}.json").read_text())
    buffer = (traces / doc["buffer"]).read_bytes()
    doc["buffer"] = "buffer.bin"  # where tests/fuzz/trace_fuzz.cpp writes the tail
    return json.dumps(doc).encode() + b"\0" + buffer


def glb_from_gltf(gltf: Path) -> bytes:
    """The same model as a binary glTF: the data-URI buffer moved into the BIN chunk."""
    doc = json.loads(gltf.read_text())
    uri = doc["buffers"][0].pop("uri")
    binary = base64.b64decode(uri.split(",", 1)[1])
    binary += b"\0" * (-len(binary) % 4)
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
    chunks += struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def triangle_seeds() -> dict:
    """A viewport and one triangle, in both input modes of triangle_setup_fuzz.cpp."""
    viewport = struct.pack("<HH", 63, 47)  # 64 x 48
    clip = struct.pack("<12f", -0.5, -0.5, 0.5, 1, 0.5, -0.5, 0.5, 1, 0, 0.5, 0.5, 1)
    identity = struct.pack("<16f", *[1.0 if r == c else 0.0 for r in range(4) for c in range(4)])
    world = struct.pack("<9f", -0.5, -0.5, 0.5, 0.5, -0.5, 0.5, 0, 0.5, 0.5)
    # A triangle crossing the near plane: clipping makes a fan of several.
    crossing = struct.pack("<12f", -0.5, -0.5, -2, 1, 0.5, -0.5, 0.5, 1, 0, 0.5, 0.5, 1)
    colours = bytes([10, 200, 255])
    return {
        "clip.bin": b"\0" + viewport + clip + colours,
        "near.bin": b"\0" + viewport + crossing + colours,
        "matrix.bin": b"\1" + viewport + identity + world + colours,
    }


def main() -> None:
    source, out = Path(sys.argv[1]), Path(sys.argv[2])
    data, fuzz = source / "data", source / "tests" / "fuzz"
    seeds = {
        "trace": {f"{n}.trace": trace_seed(data / "traces", n) for n in ("tiny", "edges", "pcf")},
        "triangle_setup": triangle_seeds(),
        "gltf": {"teapot.glb": glb_from_gltf(data / "models" / "teapot.gltf")},
    }
    files = {
        "obj": [data / "models" / "chair.obj", *sorted((data / "sessions" / "faulty-models").glob("*.obj"))],
        "ply": [data / "models" / "teapot.ply", data / "models" / "bunny.ply"],
        "gltf": [data / "models" / "teapot.gltf", data / "sessions" / "faulty-models" / "truncated.glb"],
        "session": sorted((data / "sessions").glob("*.json")),
        "scene_file": [data / "showroom" / "showroom.json"],
    }
    targets = set(seeds) | set(files)
    targets |= {p.name for p in (fuzz / "corpus").iterdir() if p.is_dir()}
    for target in sorted(targets):
        folder = out / target
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
        for name, content in seeds.get(target, {}).items():
            (folder / name).write_bytes(content)
        for f in files.get(target, []):
            shutil.copyfile(f, folder / f.name)
        for extra in ("corpus", "regressions"):
            for f in sorted((fuzz / extra / target).glob("*")):
                shutil.copyfile(f, folder / f"{extra}-{f.name}")
        print(f"{target}: {len(list(folder.iterdir()))} seeds")


if __name__ == "__main__":
    main()
