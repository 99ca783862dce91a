# tests/lib.sh — sourced by the shell tests (`. "$(dirname "$0")/lib.sh"` with the test's own
# arguments in place): the program under test as $sinew (the first argument), a temporary
# folder $tmp removed on exit, and fail MESSAGE, which prints and counts a failure in $fails.
set -u
sinew=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
