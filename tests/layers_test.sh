#!/usr/bin/env bash
# layers.includes: the project's #include lines obey docs/architecture.md's layer table
# (.ci/check_layers.py), and the check itself fails where it must: an upward include, a
# folder missing from the table, a table row for a folder that does not exist.
#   bash tests/layers_test.sh REPO_ROOT
set -euo pipefail
root="$1"
check="$root/.ci/check_layers.py"
python3 "$check" "$root"

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/docs" "$tmp/core" "$tmp/raster"
cat > "$tmp/docs/architecture.md" <<'DOC'
<!-- layers: begin -->
| folder | may include |
|---|---|
| `core` | |
| `raster` | `core` |
<!-- layers: end -->
DOC
echo '#include "core/a.h"' > "$tmp/raster/r.cpp"
echo '#pragma once' > "$tmp/core/a.h"
python3 "$check" "$tmp" >/dev/null || { echo "a downward include was refused"; exit 1; }

expect_failure() {  # expect_failure WHAT NEEDLE
  local out
  if out="$(python3 "$check" "$tmp" 2>&1)"; then
    echo "check_layers passed with $1"; exit 1
  fi
  grep -q -- "$2" <<<"$out" || { echo "check_layers did not say '$2' for $1:"; echo "$out"; exit 1; }
}
echo '#include "raster/r.h"' > "$tmp/core/up.cpp"
expect_failure "an upward include" "core/up.cpp:1: core/ may not include raster/"
rm "$tmp/core/up.cpp"
mkdir -p "$tmp/extra" && echo 'int x;' > "$tmp/extra/x.cpp"
expect_failure "a folder missing from the table" "extra/: holds C++ code"
rm -r "$tmp/extra"
rm -r "$tmp/raster"
expect_failure "a table row without its folder" "lists \`raster\`"
echo "layers_test: ok"
