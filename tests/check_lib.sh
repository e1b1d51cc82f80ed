# Shared by the end-to-end CLI test scripts (sourced, not run): a private scratch directory
# removed on exit, named checks that count failures instead of stopping at the first, and
# readers for the commands' "key value" output lines.
#   source "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"
#   check NAME $?        after a command or a [[ ]] condition
#   finish               prints the tally; exit status 1 when any check failed
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
failures=0
checks=0
check() {  # check NAME EXIT-CODE-OF-CONDITION
  checks=$((checks + 1))
  if [[ "$2" == 0 ]]; then echo "ok   $1"; else echo "FAIL $1"; failures=$((failures + 1)); fi
}
# value KEY FILE: the second word of the line whose first word is KEY ("key value" output).
value() { awk -v k="$1" '$1 == k {print $2}' "$2"; }
# field KEY FILE: the word after KEY anywhere on a line ("a 1 b 2" output).
field() { awk -v k="$1" '{for (i = 1; i < NF; ++i) if ($i == k) print $(i + 1)}' "$2"; }
finish() {
  echo "$((checks - failures)) of $checks checks passed, $failures failed"
  exit $((failures > 0))
}
