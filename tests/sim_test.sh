#!/usr/bin/env bash
# penumbra-sim end to end (issue 6): every displayed frame of a kiosk session is a pure
# function of the session file, so its per-frame hashes are fixed.
#   golden  SIM SESSION GOLDEN [EMULATOR...]: the first N frames (N = lines of GOLDEN) at 1
#           and 2 threads equal the golden hashes (run natively and under qemu-aarch64 NEON).
#   invariance SIM SESSION [FRAMES]: the whole session (or its first FRAMES) at threads 1/2/4 (best ISA) and at every x86 ISA
#           (2 threads) gives one and the same hash list; the summary is printed.
#   bundle  PENUMBRA SHOWROOM_JSON BUNDLE: the committed bundle equals a fresh precompute.
set -euo pipefail
mode=$1; shift
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

case "$mode" in
  golden)
    sim=$1 session=$2 golden=$3; shift 3
    n=$(wc -l <"$golden")
    [ "$n" -ge 30 ] || fail "$golden: only $n hashes"
    # PENUMBRA_SIM_GOLDEN_FRAMES (the sanitizer builds) checks only the first frames.
    n=${PENUMBRA_SIM_GOLDEN_FRAMES:-$n}
    head -n "$n" "$golden" >"$tmp/golden.txt"
    for t in 1 2; do
      "$@" "$sim" "$session" --frames "$n" --threads "$t" --hashes "$tmp/h$t.txt" >"$tmp/out$t.txt"
      cat "$tmp/out$t.txt"
      grep -q '^fps ' "$tmp/out$t.txt" || fail "no fps line"
      grep -q '^passes median ' "$tmp/out$t.txt" || fail "no passes line"
      cmp "$tmp/golden.txt" "$tmp/h$t.txt" || fail "threads $t: hashes differ from $golden (first: $(diff "$tmp/golden.txt" "$tmp/h$t.txt" | head -2 | tr '\n' ' '))"
    done
    # The session really changes what is shown (a test that cannot pass on a frozen screen).
    [ "$(sort -u "$tmp/h1.txt" | wc -l)" -ge $((n * 3 / 4)) ] || fail "too few distinct frames"
    # Bad input: a clear error naming the file, non-zero exit, no hash file.
    echo '{"format": "penumbra-session", "version": 1, "frames": "many"}' >"$tmp/bad.json"
    if "$@" "$sim" "$tmp/bad.json" --hashes "$tmp/bad.txt" 2>"$tmp/err.txt"; then fail "bad session accepted"; fi
    grep -q "bad.json" "$tmp/err.txt" || fail "error does not name the file: $(cat "$tmp/err.txt")"
    [ ! -e "$tmp/bad.txt" ] || fail "hash file written for a bad session"
    ;;
  invariance)
    sim=$1 session=$2 frames=${3:-}
    if [ -n "$frames" ]; then f=(--frames "$frames"); else f=(); fi
    "$sim" "$session" "${f[@]}" --threads 1 --hashes "$tmp/ref.txt"
    n=$(wc -l <"$tmp/ref.txt")
    for t in 2 4; do
      "$sim" "$session" "${f[@]}" --threads "$t" --hashes "$tmp/t$t.txt" >/dev/null
      cmp "$tmp/ref.txt" "$tmp/t$t.txt" || fail "threads $t differ from threads 1"
    done
    for isa in scalar sse4 avx2 avx512; do
      if ! "$sim" "$session" --frames 1 --isa "$isa" --hashes /dev/null >/dev/null 2>&1; then
        echo "isa $isa: not on this CPU, skipped"; continue
      fi
      "$sim" "$session" "${f[@]}" --threads 2 --isa "$isa" --hashes "$tmp/$isa.txt" >/dev/null
      cmp "$tmp/ref.txt" "$tmp/$isa.txt" || fail "isa $isa differs"
      echo "isa $isa: $n frames identical"
    done
    ;;
  bundle)
    penumbra=$1 json=$2 bundle=$3
    "$penumbra" precompute "$json" -o "$tmp/fresh.bundle" >/dev/null
    cmp "$bundle" "$tmp/fresh.bundle" || fail "$bundle is stale: run penumbra precompute $json -o $bundle"
    ;;
  *) fail "unknown mode $mode" ;;
esac
echo PASS
