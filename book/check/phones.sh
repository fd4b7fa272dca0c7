#!/usr/bin/env bash
# Checks a built book as a phone shows it (390 px wide, in headless Chromium): every plot
# must lie within the screen (no panel in a sideways scroller) with its smallest text drawn
# at 11 px or more. Prints one line per plot and exits 1 if any fails.
#   book/check/phones.sh [BUILT_BOOK_DIR]   (default book/build; needs Debian's chromium)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
built="$(cd "${1:-$here/../build}" && pwd)"
pages="$(cd "$built" && ls -- *.html | grep -v -e '^print.html$' -e '^toc.html$' -e '^404.html$' | paste -sd, -)"
profile="$(mktemp -d)"
trap 'rm -rf "$profile"' EXIT
report="$(chromium --headless --no-sandbox --disable-gpu --disable-background-networking \
  --disable-component-update --disable-sync --no-first-run --user-data-dir="$profile" \
  --allow-file-access-from-files --virtual-time-budget=120000 --dump-dom \
  "file://$here/phones.html?book=file://$built/&pages=$pages" 2>/dev/null |
  sed -n '/<pre id="out">/,/<\/pre>/p' | sed -e 's/<[^>]*>//g')"
printf '%s\n' "$report"
grep -q '^done$' <<<"$report" || { echo "the check did not finish" >&2; exit 1; }
! grep -q '^FAIL' <<<"$report"
