#!/usr/bin/env bash
# penumbra-sim end to end (issue 6): every displayed frame of a kiosk session is a pure
# function of the session file, so its per-frame hashes are fixed.
#   golden  SIM SESSION GOLDEN FRAMES THREADS ISA [EMULATOR...]: the first FRAMES frames (0:
#           all of GOLDEN) at each thread count of THREADS (comma-separated) with --isa ISA equal
#           the golden hashes (natively and under qemu-aarch64 NEON). Exit 77 (skipped) when
#           this CPU lacks ISA. Issue 6: the same per-frame hashes on 1, 2 and 4 threads, on
#           every x86 target and under qemu NEON.
#   regenerate SIM SESSION GOLDEN: rewrites GOLDEN from the whole session (2 threads, best
#           ISA); the `update-sim-golden` build target runs it. Only after a deliberate pixel
#           change, in its own commit saying why (docs/kiosk.md).
#   faults  SIM SESSION: data/sessions/faults.json's first 200 frames (6.6 s): the start-up
#           faults and every product file fault are refused with their reasons, the good files
#           accepted, the early camera faults logged (the disconnect comes later; gtests).
#   bundle  PENUMBRA SHOWROOM_JSON BUNDLE: the committed bundle equals a fresh precompute.
set -euo pipefail
mode=$1; shift
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

case "$mode" in
  golden)
    sim=$1 session=$2 golden=$3 frames=$4 threads=$5 isa=$6; shift 6
    n=$(wc -l <"$golden")
    [ "$n" -ge 30 ] || fail "$golden: only $n hashes"
    [ "$frames" -eq 0 ] || [ "$frames" -gt "$n" ] || n=$frames
    if ! "$@" "$sim" "$session" --frames 1 --isa "$isa" --hashes /dev/null >/dev/null 2>&1; then
      echo "SKIP: --isa $isa is not supported on this CPU"; exit 77
    fi
    head -n "$n" "$golden" >"$tmp/golden.txt"
    IFS=, read -ra counts <<<"$threads"
    for t in "${counts[@]}"; do
      start=$(date +%s%N)
      "$@" "$sim" "$session" --frames "$n" --threads "$t" --isa "$isa" --hashes "$tmp/h$t.txt" >"$tmp/out$t.txt"
      cat "$tmp/out$t.txt"
      grep -q '^fps ' "$tmp/out$t.txt" || fail "no fps line"
      grep -q '^passes median ' "$tmp/out$t.txt" || fail "no passes line"
      cmp "$tmp/golden.txt" "$tmp/h$t.txt" || fail "isa $isa threads $t: hashes differ from $golden (first: $(diff "$tmp/golden.txt" "$tmp/h$t.txt" | head -2 | tr '\n' ' '))"
      echo "isa $isa threads $t: $n frames equal $golden ($((($(date +%s%N) - start) / 1000000)) ms)"
    done
    # The session really changes what is shown (a test that cannot pass on a frozen screen).
    [ "$(sort -u "$tmp/golden.txt" | wc -l)" -ge $((n * 3 / 4)) ] || fail "too few distinct frames"
    # Bad input: a clear error naming the file, non-zero exit, no hash file.
    echo '{"format": "penumbra-session", "version": 1, "frames": "many"}' >"$tmp/bad.json"
    if "$@" "$sim" "$tmp/bad.json" --hashes "$tmp/bad.txt" 2>"$tmp/err.txt"; then fail "bad session accepted"; fi
    grep -q "bad.json" "$tmp/err.txt" || fail "error does not name the file: $(cat "$tmp/err.txt")"
    [ ! -e "$tmp/bad.txt" ] || fail "hash file written for a bad session"
    # A run that fails after it started (frame 1 cannot be written: its PNG name is taken by
    # a folder) leaves no hash file, neither a new partial one nor a temporary; an existing
    # one is left as it was (issue 18).
    mkdir -p "$tmp/frames/frame-0001.png"
    if "$@" "$sim" "$session" --frames 2 --frames-dir "$tmp/frames" --hashes "$tmp/fail.txt" 2>"$tmp/err.txt"; then fail "unwritable frame accepted"; fi
    [ ! -e "$tmp/fail.txt" ] || fail "hash file left behind by a failed run"
    echo "old hashes" >"$tmp/keep.txt"
    if "$@" "$sim" "$session" --frames 2 --frames-dir "$tmp/frames" --hashes "$tmp/keep.txt" 2>/dev/null; then fail "unwritable frame accepted"; fi
    [ "$(cat "$tmp/keep.txt")" = "old hashes" ] || fail "a failed run replaced the existing hash file"
    ! ls "$tmp" | grep -q '\.tmp-' || fail "temporary hash file left behind: $(ls "$tmp")"
    ;;
  regenerate)
    sim=$1 session=$2 golden=$3
    "$sim" "$session" --threads 2 --hashes "$tmp/new.txt"
    mv "$tmp/new.txt" "$golden"
    echo "wrote $(wc -l <"$golden") hashes to $golden; commit it on its own, saying why the pixels changed"
    exit 0
    ;;
  faults)
    sim=$1 session=$2
    "$sim" "$session" --frames 200 --threads 2 --log >"$tmp/out.txt" 2>"$tmp/log.txt" || fail "faults session failed: $(tail -3 "$tmp/log.txt")"
    for line in "bundle: refused .*checksum.*; running on the last good bundle" \
        "refused product teapot: mesh a vertex is not a finite number" \
        "product bunny: refused .*truncated.glb" \
        "product chair: refused .*nan-vertex.obj: line 4: non-finite coordinate" \
        "product chair: refused .*truncated.obj" "product bunny: model .*chair.obj" \
        "product chair: model .*chair.obj" \
        "delivered again (already shown), ignored" "refused: frame size 320x240"; do
      grep -q -- "$line" "$tmp/log.txt" ||
        fail "faults session: no log line '$line'; the log: $(cat "$tmp/log.txt")"
    done
    # Outages are reported apart from the latency (issue 18): the drop of 6 frames at
    # camera frame 40 and the 150 ms late frames are outages, so there are some.
    grep -Eq '^camera outages [1-9][0-9]*, total ' "$tmp/out.txt" || fail "no camera outages line: $(cat "$tmp/out.txt")"
    ;;
  bundle)
    penumbra=$1 json=$2 bundle=$3
    "$penumbra" precompute "$json" -o "$tmp/fresh.bundle" >/dev/null
    cmp "$bundle" "$tmp/fresh.bundle" || fail "$bundle is stale: run penumbra precompute $json -o $bundle"
    ;;
  *) fail "unknown mode $mode" ;;
esac
echo PASS
