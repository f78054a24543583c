#!/usr/bin/env bash
# Checks that C and C++ files match .clang-format, changing nothing (Debian's clang-format 14: other
# versions format differently, so another major version is refused).
#   bash scripts/check_format.sh --all            # every tracked *.cpp, *.hpp, *.h, *.c
#   bash scripts/check_format.sh --changed REF    # those changed since git REF (and still present)
#   bash scripts/check_format.sh FILE...          # just these
# Exit 0 when every file matches; 1 listing the files that do not (clang-format's first
# differences above the list); 2 on bad usage. `clang-format -i FILE` reformats one.
set -euo pipefail
cd "$(dirname "$0")/.."
CLANG_FORMAT=${CLANG_FORMAT:-clang-format}
PATTERNS=('*.cpp' '*.hpp' '*.h' '*.c')

usage() { sed -n '4,6p' "$0" | sed 's/^# *//' >&2; exit 2; }
[ $# -gt 0 ] || usage
files=()
case "$1" in
  --all) [ $# -eq 1 ] || usage; mapfile -t files < <(git ls-files -- "${PATTERNS[@]}") ;;
  --changed)
    [ $# -eq 2 ] || usage
    mapfile -t files < <(git diff --name-only --diff-filter=ACMR "$2" -- "${PATTERNS[@]}") ;;
  -*) usage ;;
  *) files=("$@") ;;
esac

command -v "$CLANG_FORMAT" >/dev/null || { echo "check_format: $CLANG_FORMAT not found (Debian package clang-format)" >&2; exit 2; }
version=$("$CLANG_FORMAT" --version | sed -n 's/.*version \([0-9]*\)\..*/\1/p')
[ "$version" = 14 ] || { echo "check_format: clang-format 14 expected, found '$version' ($CLANG_FORMAT)" >&2; exit 2; }

bad=()
for f in "${files[@]}"; do
  [ -f "$f" ] || { echo "check_format: $f: no such file" >&2; exit 2; }
  "$CLANG_FORMAT" --dry-run --Werror --ferror-limit=3 "$f" || bad+=("$f")
done
if [ ${#bad[@]} -gt 0 ]; then
  echo "check_format: ${#bad[@]} of ${#files[@]} files do not match .clang-format:" >&2
  printf '  %s\n' "${bad[@]}" >&2
  exit 1
fi
echo "check_format: ${#files[@]} files match .clang-format"
