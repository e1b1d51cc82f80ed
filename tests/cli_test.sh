#!/usr/bin/env bash
# Command-line behaviour of `penumbra`: help on every subcommand, hashes of a bundled trace,
# and for malformed traces a clear error naming the file and the field, a non-zero exit and
# no output file.
#   tests/cli_test.sh PENUMBRA DATA_DIR GOLDEN_FILE [EMULATOR...]
set -uo pipefail
penumbra="$1" data="$2" golden="$3"
shift 3
run=("$@" "$penumbra")
source "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"

envmap_bench=()
[[ "${PENUMBRA_HAVE_ENVMAP_BENCH:-0}" == 1 ]] && envmap_bench=(bench-envmap)
[[ "${PENUMBRA_HAVE_ENVMAP_SEQUENCE:-0}" == 1 ]] && envmap_bench+=(envmap-sequence)
for sub in "" replay isas bench-replay "${envmap_bench[@]}"; do
  "${run[@]}" $sub --help >"$tmp/help" 2>&1
  check "help: penumbra $sub --help" $?
done

# info: what the showroom bundle holds and its settings (the defaults: it predates them),
# as text and as JSON; a damaged bundle refused naming the file.
"${run[@]}" info "$data/showroom/showroom.bundle" >"$tmp/info" 2>&1
status=$?
[[ $status == 0 ]] && grep -qF "settings defaults: max_passes 64, shadow_map_sizes [256,128,64]" "$tmp/info" \
  && grep -qF "texels_per_shadow_pixel off" "$tmp/info" \
  && grep -qF "product 2 teapot:" "$tmp/info" && grep -qF "fine proxy 1000 in 8 of 50 passes" "$tmp/info"
check "info: the showroom's products and default settings ($(head -c 300 "$tmp/info"))" $status
"${run[@]}" info "$data/showroom/showroom.bundle" --json >"$tmp/info.json" 2>&1
python3 -c "
import json, sys
j = json.load(open(sys.argv[1]))
s = j['settings']
assert s == {'tuned': False, 'max_passes': 64, 'shadow_map_sizes': [256, 128, 64],
             'fine_proxy_passes': 16, 'product_fine_proxy_passes': [16, 32, 8],
             'area_penumbrae': True, 'prune_fraction': 0.02, 'receivers_per_leaf': 8,
             'texels_per_shadow_pixel': 0}, s
assert [p['name'] for p in j['products']] == ['chair', 'bunny', 'teapot'], j['products']
# The scene file's fine_proxy_passes: the bunny's fine proxy in 32 of 50 passes, the teapot's in 8
# of 50; the chair has none.
assert [p['fine_proxy_passes'] for p in j['products']] == [0, 32, 8], j['products']
" "$tmp/info.json"
check "info --json: settings and products" $?
head -c 1000 "$data/showroom/showroom.bundle" >"$tmp/cut.bundle"
"${run[@]}" info "$tmp/cut.bundle" >/dev/null 2>"$tmp/stderr"
status=$?
[[ $status == 1 ]] && grep -qF "cut.bundle" "$tmp/stderr"
status=$?
check "info: a truncated bundle is refused naming it ($(head -c 200 "$tmp/stderr"))" $status

# profile: the map size the passes drew (the bundle's 256 without --shadow-map-size; the
# board's cost model prices passes x size^2 from it) and the occluder triangles they drew.
"${run[@]}" profile "$data/showroom/showroom.bundle" --product 1 --passes 8 --frames 1 \
  --csv "$tmp/profile.csv" >/dev/null 2>&1
python3 -c "
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 1, rows
r = rows[0]
assert r['shadow_map_size'] == '256', r
assert r['passes'] == '8' and 0 < int(r['shadow_map_triangles']) <= 8 * 2500, r
" "$tmp/profile.csv"
check "profile: the map size and the occluder triangles drawn" $?
# --fine-proxy-passes: the bunny's fine proxy (2,500 triangles) in none or every pass; the
# board's cost-model counts (bench/board_instruction_counts.sh) price a triangle from these.
for fine in 0 50; do
  "${run[@]}" profile "$data/showroom/showroom.bundle" --product 1 --passes 8 --frames 1 \
    --fine-proxy-passes "$fine" --csv "$tmp/profile-fine$fine.csv" >/dev/null 2>&1
done
python3 -c "
import csv, sys
none, every = (list(csv.DictReader(open(f)))[0] for f in sys.argv[1:3])
assert int(none['shadow_map_triangles']) <= 8 * 300 < int(every['shadow_map_triangles']), (none, every)
assert none['shadowed_pixels'] == every['shadowed_pixels'], (none, every)
" "$tmp/profile-fine0.csv" "$tmp/profile-fine50.csv"
check "profile --fine-proxy-passes: none or every pass draws the fine proxy" $?

want="$(awk '$1 == "tiny.json" {print $2}' "$golden")"
got="$("${run[@]}" replay "$data/traces/tiny.json" --hash --threads 3 --tile 16)"
[[ "$got" == "sha256 $want" ]]
check "replay --hash matches tests/golden_hashes.txt" $?

if [[ ${#envmap_bench[@]} -ge 1 ]]; then
  # bench-envmap: one "key value" line per stage (values are timings: only their presence is
  # checked), and a bad flag refused.
  "${run[@]}" bench-envmap --lights 50 --frames 3 >"$tmp/envmap" 2>&1
  status=$?
  [[ $status == 0 && -n "$(value cdf_ms "$tmp/envmap")" && -n "$(value samples_per_ms "$tmp/envmap")" \
     && -n "$(value filter_cluster_ms "$tmp/envmap")" ]]
  check "bench-envmap prints cdf_ms, samples_per_ms, filter_cluster_ms" $?
  "${run[@]}" bench-envmap --lights 0 >/dev/null 2>&1
  [[ $? != 0 ]]
  check "bench-envmap --lights 0 refused" $?
else
  # Built without OpenCV's fisheye model: the command is not offered, and asking for it fails.
  "${run[@]}" --help >"$tmp/help" 2>&1
  ! grep -q bench-envmap "$tmp/help"
  check "without the fisheye library, --help does not list bench-envmap" $?
  "${run[@]}" bench-envmap >/dev/null 2>&1
  [[ $? != 0 ]]
  check "without the fisheye library, bench-envmap is refused" $?
fi

if [[ "${PENUMBRA_HAVE_ENVMAP_SEQUENCE:-0}" == 1 ]]; then
  # envmap-sequence on small generated lat-long probes (uncompressed float EXR written here):
  # frames named in order, half float with ZIP, and clear refusals leaving nothing behind.
  python3 - "$tmp" <<'PY'
import os, struct, sys
def write_exr(path, w, h, value):
    def attr(name, kind, data):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(data)) + data
    chlist = b"".join(c + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in (b"B", b"G", b"R")) + b"\0"
    header = (attr("channels", "chlist", chlist) + attr("compression", "compression", b"\0")
              + attr("dataWindow", "box2i", struct.pack("<4i", 0, 0, w - 1, h - 1))
              + attr("displayWindow", "box2i", struct.pack("<4i", 0, 0, w - 1, h - 1))
              + attr("lineOrder", "lineOrder", b"\0") + attr("pixelAspectRatio", "float", struct.pack("<f", 1))
              + attr("screenWindowCenter", "v2f", struct.pack("<2f", 0, 0))
              + attr("screenWindowWidth", "float", struct.pack("<f", 1)) + b"\0")
    start = 8 + len(header) + 8 * h
    line = 8 + 3 * 4 * w
    out = bytearray(b"\x76\x2f\x31\x01" + struct.pack("<i", 2) + header)
    out += b"".join(struct.pack("<Q", start + y * line) for y in range(h))
    for y in range(h):
        out += struct.pack("<ii", y, 3 * 4 * w)
        for c in range(3):  # B, G, R
            out += b"".join(struct.pack("<f", value(x, y, c)) for x in range(w))
    open(path, "wb").write(out)
d = sys.argv[1]
# A dim sky and a warm window above the horizon (rows 6-9 of 32 are 34-56° from the zenith).
window = lambda x, y, c: (40.0, 30.0, 20.0)[c] if 10 <= x < 16 and 6 <= y < 10 else 0.5
write_exr(os.path.join(d, "probe.exr"), 64, 32, window)
write_exr(os.path.join(d, "square.exr"), 32, 32, window)
write_exr(os.path.join(d, "blinding.exr"), 64, 32, lambda x, y, c: 1e6 if (x, y) == (12, 8) else 0.5)
PY
  "${run[@]}" envmap-sequence "$tmp/probe.exr" -o "$tmp/seq" --frames 6 --size 48 \
    --animate lamp-off noise >"$tmp/seq.out" 2>&1
  status=$?
  [[ $status == 0 && "$(ls "$tmp/seq" | tr '\n' ' ')" == "env_0000.exr env_0001.exr env_0002.exr env_0003.exr env_0004.exr env_0005.exr " ]] \
    && ! ls -a "$tmp" | grep -q partial
  status=$?
  check "envmap-sequence writes env_0000.exr ... env_0005.exr and no partial folder: $(tail -1 "$tmp/seq.out")" $status
  python3 - "$tmp/seq/env_0003.exr" <<'PY'
import struct, sys
b = open(sys.argv[1], "rb").read()
assert b[:4] == b"\x76\x2f\x31\x01", "not an EXR"
def attr(name):
    at = b.index(name.encode() + b"\0") + len(name) + 1
    at = b.index(b"\0", at) + 1
    size, = struct.unpack_from("<i", b, at)
    return b[at + 4:at + 4 + size]
chl = attr("channels")
types = [struct.unpack_from("<i", chl, chl.index(c + b"\0") + 2)[0] for c in (b"B", b"G", b"R")]
assert types == [1, 1, 1], f"pixel types {types}, expected half (1)"
assert attr("compression") == b"\x03", f"compression {attr('compression')}, expected ZIP (3)"
assert struct.unpack("<4i", attr("dataWindow")) == (0, 0, 47, 47)
PY
  check "envmap-sequence frames are 48x48 half float, ZIP" $?

  "${run[@]}" envmap-sequence "$tmp/probe.exr" -o "$tmp/slash/" --frames 1 --size 16 >/dev/null 2>&1
  status=$?
  [[ $status == 0 && -f "$tmp/slash/env_0000.exr" ]] && ! ls -a "$tmp" "$tmp/slash" | grep -q partial
  check "envmap-sequence -o DIR/ (a trailing slash) writes into DIR" $?

  # expect_sequence_error NAME EXIT TEXT ARGS...: the exit code, TEXT in the message, no output.
  expect_sequence_error() {
    local name="$1" rc_want="$2" text="$3"
    shift 3
    "${run[@]}" envmap-sequence "$@" >"$tmp/stdout" 2>"$tmp/stderr"
    local rc=$?
    [[ $rc == "$rc_want" ]] && grep -qF -- "$text" "$tmp/stderr" && [[ ! -e "$tmp/none" ]] \
      && ! ls -a "$tmp" | grep -q partial
    status=$?
    check "envmap-sequence $name: exit $rc, $(head -c 200 "$tmp/stderr")" $status
  }
  expect_sequence_error "missing probe" 1 "absent.exr" "$tmp/absent.exr" -o "$tmp/none"
  expect_sequence_error "unreadable probe" 1 "tiny.json" "$data/traces/tiny.json" -o "$tmp/none"
  expect_sequence_error "not lat-long" 1 "square.exr: 32x32 is not a lat-long probe" \
    "$tmp/square.exr" -o "$tmp/none"
  expect_sequence_error "bad size" 2 "--size" "$tmp/probe.exr" -o "$tmp/none" --size 4
  expect_sequence_error "unknown animation" 2 "unknown animation 'sparkle'" "$tmp/probe.exr" \
    -o "$tmp/none" --animate cloud sparkle
  expect_sequence_error "output not empty" 1 "seq: exists and is not an empty folder" \
    "$tmp/probe.exr" -o "$tmp/seq"
  [[ "$(ls "$tmp/seq" | wc -l)" == 6 ]]
  check "envmap-sequence leaves a non-empty output folder as it was" $?
  expect_sequence_error "beyond half float" 1 "env_0000.exr: value" "$tmp/blinding.exr" \
    -o "$tmp/none" --size 32
fi

# expect_error NAME TRACE FIELD: exit 1, message names the file and the field, no PNG.
expect_error() {
  local name="$1" trace="$2" field="$3"
  "${run[@]}" replay "$trace" --out "$tmp/out.png" >"$tmp/stdout" 2>"$tmp/stderr"
  local rc=$?
  [[ $rc == 1 ]] && grep -q "$(basename "$trace")" "$tmp/stderr" && grep -q -- "$field" "$tmp/stderr" \
    && [[ ! -e "$tmp/out.png" ]]
  status=$?
  check "malformed ($name): exit $rc, $(head -c 200 "$tmp/stderr")" $status
}

cp "$data/traces/tiny.bin" "$tmp/tiny.bin"
sed 's/"width"/"wide"/' "$data/traces/tiny.json" >"$tmp/missing-width.json"
sed 's/"buffer": "tiny.bin"/"buffer": "tiny.bin", "unused": 0/' "$data/traces/tiny.json" >"$tmp/tiny.json"
python3 - "$tmp" <<'PY'
import json, sys, os
d = sys.argv[1]
doc = json.load(open(os.path.join(d, "tiny.json")))
def write(name, mutate):
    x = json.loads(json.dumps(doc)); mutate(x)
    json.dump(x, open(os.path.join(d, name), "w"))
write("bad-index.json", lambda x: x["passes"][0].__setitem__("occluder", 7))
write("bad-size.json", lambda x: x["passes"][0].__setitem__("shadow_map_size", 100))
write("bad-view.json", lambda x: x["static_mesh"]["indices"].__setitem__("count", 10**7))
write("not-finite.json", lambda x: x["camera_view_proj"].__setitem__(0, "nan"))
write("bad-accumulation.json", lambda x: x.__setitem__("accumulation", "u16"))
PY
expect_error "missing width" "$tmp/missing-width.json" "width"
expect_error "occluder out of range" "$tmp/bad-index.json" "passes\[0\].occluder"
expect_error "shadow map size" "$tmp/bad-size.json" "shadow_map_size"
expect_error "view past the end" "$tmp/bad-view.json" "static_mesh.indices"
expect_error "matrix not a number" "$tmp/not-finite.json" "camera_view_proj"
expect_error "unknown accumulation" "$tmp/bad-accumulation.json" "accumulation"
head -c 1000 "$data/traces/tiny.bin" >"$tmp/tiny.bin"
expect_error "truncated buffer" "$tmp/tiny.json" "runs past the end"
printf '{ not json' >"$tmp/garbage.json"
expect_error "not JSON" "$tmp/garbage.json" "line 1"

# --accumulation overrides the trace's field (spec §8): a real choice, and checked.
"${run[@]}" replay "$data/traces/tiny.json" --accumulation fixed8_8 --hash >"$tmp/fixed" 2>&1
status=$?
check "replay --accumulation fixed8_8: $(head -c 200 "$tmp/fixed")" $status
"${run[@]}" replay "$data/traces/tiny.json" --accumulation wide >/dev/null 2>"$tmp/stderr"
[[ $? != 0 ]] && grep -q "accumulation" "$tmp/stderr"
check "unknown --accumulation is refused" $?

"${run[@]}" replay "$data/traces/tiny.json" --isa no-such-isa >/dev/null 2>"$tmp/stderr"
[[ $? != 0 ]] && grep -q "no-such-isa" "$tmp/stderr"
check "unknown --isa is refused" $?

# The showroom commands, where this build has them (precompute needs Embree + meshoptimizer).
if grep -q "^  precompute" <<<"$("${run[@]}" --help 2>/dev/null)"; then
  "${run[@]}" precompute "$data/showroom/showroom.json" -o "$tmp/showroom.bundle" >"$tmp/stdout" 2>&1
  check "precompute the showroom" $?
  "${run[@]}" render "$tmp/showroom.bundle" --passes 20 --threads 2 --out "$tmp/frame.png" --hash \
    >"$tmp/stdout" 2>&1 && grep -q "^sha256 " "$tmp/stdout" && [[ -s "$tmp/frame.png" ]]
  check "render 20 passes, PNG and hash" $?
  "${run[@]}" render "$tmp/showroom.bundle" --pose 1,0,nope --passes 5 >/dev/null 2>"$tmp/stderr"
  [[ $? == 2 ]] && grep -q "nope" "$tmp/stderr"
  check "render: a bad --pose is named (a usage error)" $?
  "${run[@]}" render "$tmp/showroom.bundle" >/dev/null 2>"$tmp/stderr"
  [[ $? == 2 ]] && grep -q -- "--passes" "$tmp/stderr"
  check "render: --passes or --fps is required (a usage error)" $?
  head -c 5000 "$tmp/showroom.bundle" >"$tmp/cut.bundle"
  "${run[@]}" render "$tmp/cut.bundle" --passes 5 --out "$tmp/cut.png" >/dev/null 2>"$tmp/stderr"
  [[ $? == 1 ]] && grep -q "cut.bundle" "$tmp/stderr" && [[ ! -e "$tmp/cut.png" ]]
  status=$?
  check "render: a truncated bundle is refused, no PNG ($(head -c 150 "$tmp/stderr"))" $status
  "${run[@]}" precompute "$tmp/absent.json" -o "$tmp/x.bundle" >/dev/null 2>"$tmp/stderr"
  [[ $? == 1 ]] && grep -q "absent.json" "$tmp/stderr" && [[ ! -e "$tmp/x.bundle" ]]
  check "precompute: a missing scene file is named" $?
  # --proxy-scale: every product's shadow proxies simplified to half the file's triangles
  # (what tune --proxy-scales searches); the showroom's bunny 300 -> 150, 2,500 -> 1,250.
  "${run[@]}" precompute "$data/showroom/showroom.json" --proxy-scale 0.5 \
    -o "$tmp/half-proxies.bundle" >/dev/null 2>&1 &&
    "${run[@]}" info "$tmp/half-proxies.bundle" --json >"$tmp/half-proxies.json" &&
    python3 -c "
import json, sys
bunny = json.load(open(sys.argv[1]))['products'][1]
assert bunny['name'] == 'bunny' and bunny['proxy_triangles'] <= 150 and 1000 < bunny['fine_proxy_triangles'] <= 1250, bunny
" "$tmp/half-proxies.json"
  check "precompute --proxy-scale: the proxies at half the file's triangles" $?
  "${run[@]}" precompute "$data/showroom/showroom.json" --proxy-scale 0 \
    -o "$tmp/x.bundle" >/dev/null 2>"$tmp/stderr"
  [[ $? == 2 ]] && grep -q -- "--proxy-scale" "$tmp/stderr" && [[ ! -e "$tmp/x.bundle" ]]
  check "precompute: --proxy-scale 0 is refused" $?

  # Issue 18: precompute refuses what render would refuse, naming the file and the field,
  # with exit 1 and no bundle left behind.
  python3 - "$data" "$tmp" <<'PY'
import json, os, sys
data, tmp = sys.argv[1], sys.argv[2]
doc = json.load(open(os.path.join(data, "showroom", "showroom.json")))
for p in doc["products"]:
    p["model"] = os.path.join(data, "models", os.path.basename(p["model"]))
def write(name, mutate):
    x = json.loads(json.dumps(doc)); mutate(x)
    json.dump(x, open(os.path.join(tmp, name), "w"))
write("away.json", lambda x: x["camera"].update(eye=[-5, 1.6, 2], target=[-10, 1.6, 2]))
write("huge-room.json", lambda x: x["room"]["shell"].__setitem__("max", [3e20, 3, 5]))
open(os.path.join(tmp, "far.obj"), "w").write("v 0 0 0\nv 1 0 0\nv 1e308 1 0\nf 1 2 3\n")
write("far-vertex.json", lambda x: x["products"][0].__setitem__("model", os.path.join(tmp, "far.obj")))
PY
  # expect_scene_error NAME SCENE TEXT: exit 1, TEXT in the message, no bundle.
  expect_scene_error() {
    "${run[@]}" precompute "$2" -o "$tmp/refused.bundle" >/dev/null 2>"$tmp/stderr"
    local rc=$?
    [[ $rc == 1 ]] && grep -qF -- "$3" "$tmp/stderr" && [[ ! -e "$tmp/refused.bundle" ]]
    local ok=$?
    check "precompute: $1 is refused (exit $rc: $(head -c 200 "$tmp/stderr"))" $ok
  }
  expect_scene_error "a camera seeing no receiver" "$tmp/away.json" \
    "away.json: camera: sees no surface of the room (0 receivers)"
  expect_scene_error "a room of 3e20 m" "$tmp/huge-room.json" \
    "huge-room.json: room.shell.max: 3e+20 m is not a room"
  expect_scene_error "an OBJ vertex of 1e308" "$tmp/far-vertex.json" \
    "far.obj: line 3: coordinate 1e+308 is outside [-1e6, 1e6]"
fi
finish
