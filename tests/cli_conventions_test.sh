#!/usr/bin/env bash
# The command-line conventions of every program (core/cli.h, README "Command-line
# conventions"): `--version` names the program and the build, --help exits 0 and speaks to
# users (no issue numbers), a usage error exits 2 and a runtime error exits 1, both as
# `<program>: error: <message>` on stderr.
#   tests/cli_conventions_test.sh DATA_DIR PROGRAM...
set -uo pipefail
data="$1"
shift
source "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"

# expect NAME CODE STDERR-REGEX CMD...: the exit code and the first line of stderr.
expect() {
  local name="$1" code="$2" regex="$3"
  shift 3
  "$@" >"$tmp/stdout" 2>"$tmp/stderr"
  local rc=$?
  [[ $rc == "$code" ]] && head -n1 "$tmp/stderr" | grep -qE -- "$regex"
  status=$?
  check "$name: exit $rc (want $code): $(head -n1 "$tmp/stderr" | head -c 150)" $status
}

# help_is_for_users NAME CMD...: --help exits 0 and mentions no issue number.
help_is_for_users() {
  local name="$1"
  shift
  "$@" --help >"$tmp/help" 2>&1
  local rc=$?
  [[ $rc == 0 ]] && ! grep -qiE 'issue *[0-9#]' "$tmp/help"
  check "$name --help: exit $rc, no issue numbers" $?
}

: >"$tmp/empty.json"
for program in "$@"; do
  name="$(basename "$program")"
  "$program" --version >"$tmp/version" 2>&1
  rc=$?
  [[ $rc == 0 ]] && grep -qE "^$name [0-9]+\.[0-9]+( \(git [^)]+\))?$" "$tmp/version"
  status=$?
  check "$name --version: exit $rc, $(head -c 80 "$tmp/version")" $status
  help_is_for_users "$name" "$program"
  # (A program with a required option reports that one first.)
  expect "$name: unknown flag" 2 "^$name: error: " "$program" --no-such-flag x y
  grep -qF "Run '$name --help' for usage." "$tmp/stderr"
  check "$name: a usage error points to --help" $?

  # A runtime error: an input that exists but is not what the program reads, or an output
  # below a file.
  case "$name" in
    penumbra) runtime=("$program" replay "$tmp/empty.json") ;;
    penumbra-sim | penumbra-kiosk | penumbra-gl-replay) runtime=("$program" "$tmp/empty.json") ;;
    penumbra-capture-synth) runtime=("$program" "$tmp/empty.json" "$tmp/synth-out") ;;
    penumbra-fig3 | penumbra-accuracy-sweep) runtime=("$program" "$tmp/empty.json" --csv "$tmp/x.csv") ;;
    penumbra-drift) runtime=("$program" --csv "$tmp/empty.json/x.csv") ;;
    penumbra-synth-trace) runtime=("$program" --out "$tmp/empty.json/traces") ;;
    # Google Benchmark programs: no input file of their own (the kernels' traces are the
    # repository's), so no unreadable input to give them.
    penumbra_bench | penumbra_shadow_bench | penumbra_shading_bench | \
      penumbra_environment_camera_bench) continue ;;
    *) echo "no runtime-error case for $name"; runtime=(false) ;;
  esac
  expect "$name: unreadable input" 1 "^$name: error: .*empty.json" "${runtime[@]}"
done

# penumbra-sim's video is H.264 where OpenCV can encode it (Debian 12's FFmpeg has libx264):
# the MP4's sample description is 'avc1', not MPEG-4 Part 2's 'mp4v'.
for program in "$@"; do
  [[ "$(basename "$program")" == penumbra-sim ]] || continue
  grep -q 'write an MP4 video' <<<"$("$program" --help)" || continue
  "$program" "$data/sessions/demo.json" --frames 3 --video "$tmp/v.mp4" >/dev/null 2>"$tmp/stderr"
  rc=$?
  if command -v ffprobe >/dev/null; then
    codec="$(ffprobe -v error -select_streams v:0 -show_entries stream=codec_name \
      -of default=noprint_wrappers=1:nokey=1 "$tmp/v.mp4")"
  else
    codec="$(grep -aoE 'avc1|mp4v' "$tmp/v.mp4" | head -n1)"
  fi
  [[ $rc == 0 && ( "$codec" == h264 || "$codec" == avc1 ) ]]
  status=$?
  check "penumbra-sim --video: H.264 (exit $rc, codec '$codec'; $(head -c 120 "$tmp/stderr"))" $status
done

for program in "$@"; do
  [[ "$(basename "$program")" == penumbra ]] || continue
  for sub in "" replay isas bench-replay precompute info render profile calibrate compare \
    accuracy tune capture reference synth-showroom; do
    if [[ -z "$sub" ]] || "$program" $sub --help >/dev/null 2>&1; then
      help_is_for_users "penumbra $sub" "$program" $sub
    fi
  done
  if "$program" tune --help >/dev/null 2>&1; then
    expect "tune without a target" 2 "^penumbra: error: --max-error is required" \
      "$program" tune "$data/showroom/showroom.bundle" -o "$tmp/t.bundle"
    expect "tune with a target of four numbers" 2 "^penumbra: error: --max-error" \
      "$program" tune "$data/showroom/showroom.bundle" --max-error 1,2,3,4 -o "$tmp/t.bundle"
  fi
  expect "penumbra without a command" 2 "^penumbra: error: a command is required" "$program"
  expect "render --passes with a list" 2 \
    "^penumbra: error: --passes: expects a single whole number from 1 to 257 \(not a list\)" \
    "$program" render "$data/showroom/showroom.bundle" --passes 1,10,50
  expect "render without --passes or --fps" 2 "^penumbra: error: render needs --passes" \
    "$program" render "$data/showroom/showroom.bundle"
  expect "profile --passes out of range" 2 \
    "^penumbra: error: --passes: expects a comma-separated list of whole numbers from 1 to 257, got '300'" \
    "$program" profile "$data/showroom/showroom.bundle" --passes 1,300 --csv "$tmp/p.csv"
  expect "replay of a missing trace" 1 "^penumbra: error: .*nope.json" \
    "$program" replay "$tmp/nope.json"
done
finish
