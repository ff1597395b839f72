#!/usr/bin/env bash
# Looks at a study's index.html the way a reader does: Debian's Chromium,
# headless, at a laptop's 1366 x 768 window and at full page height, and
# checks that the screenshots show a page (not blank, not an error page).
# Chromium is an optional dependency: `--install` installs it with apt-get;
# neither the README's commands nor CI do.
# Usage: tools/study/screenshot_report.sh [--install] STUDY_DIR [OUT_DIR]
# Writes OUT_DIR (default STUDY_DIR/screenshots)/laptop.png and full.png.
set -euo pipefail
if [[ ${1:-} == --install ]]; then
  shift
  if ! command -v chromium >/dev/null; then
    SUDO=""; [[ $(id -u) -ne 0 ]] && SUDO=sudo
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends chromium >/dev/null
  fi
fi
study=${1:?usage: screenshot_report.sh [--install] STUDY_DIR [OUT_DIR]}
out=${2:-"$study/screenshots"}
page="$study/index.html"
[[ -f "$page" ]] || { echo "screenshot_report: $page: no such page (run nuld study render or report first)" >&2; exit 2; }
command -v chromium >/dev/null || { echo "screenshot_report: chromium is not installed (rerun with --install)" >&2; exit 2; }
mkdir -p "$out"
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
url="file://$(cd "$(dirname "$page")" && pwd)/index.html"
shoot() { # shoot PNG WIDTH HEIGHT
  # The flags keep a closed network quiet (no background requests).
  timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync \
    --hide-scrollbars --user-data-dir="$profile" --window-size="$2,$3" \
    --screenshot="$1" "$url" >/dev/null 2>&1
  [[ -s "$1" ]] || { echo "screenshot_report: chromium wrote no $1" >&2; exit 1; }
}
shoot "$out/laptop.png" 1366 768
# The page's full height, from the number of figures: generous, then checked.
shoot "$out/full.png" 1366 6000
/usr/bin/python3 - "$out/laptop.png" "$out/full.png" <<'PY'
import sys
import matplotlib.image as mpimg
for path in sys.argv[1:]:
    img = mpimg.imread(path)[..., :3]
    # A page with text, tables and images: many distinct rows, some ink.
    ink = (img.mean(axis=2) < 0.5).mean()
    busy_rows = (img.std(axis=(1, 2)) > 0.02).mean()
    print(f"{path}: {img.shape[1]}x{img.shape[0]}, ink {ink:.3f}, rows with content {busy_rows:.2f}")
    if ink < 0.005 or busy_rows < 0.2:
        sys.exit(f"screenshot_report: {path} looks blank")
PY
echo "screenshots in $out"
