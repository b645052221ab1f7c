#!/usr/bin/env bash
# Installs what the dashboard's browser and metrics tests need into TOOLS_DIR (a folder under the
# build dir), idempotently and quietly: playwright-core from the committed package-lock.json
# (npm ci; it never downloads a browser: the tests drive Debian's /usr/bin/chromium) and a Python
# venv with prometheus_client (requirements.txt). The Debian packages (chromium, nodejs, npm,
# python3-venv) come from scripts/install-deps.sh.
# Usage: setup.sh TOOLS_DIR
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
TOOLS="${1:?usage: setup.sh TOOLS_DIR}"
mkdir -p "$TOOLS"

for tool in /usr/bin/chromium node npm python3; do
  if ! command -v "$tool" >/dev/null; then
    echo "dashboard test setup: $tool is missing: run scripts/install-deps.sh" >&2
    exit 1
  fi
done

if [ ! -d "$TOOLS/node_modules/playwright-core" ] || ! cmp -s "$HERE/package-lock.json" "$TOOLS/package-lock.json"; then
  cp "$HERE/package.json" "$HERE/package-lock.json" "$TOOLS/"
  (cd "$TOOLS" && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund --loglevel=error)
fi

if [ ! -x "$TOOLS/venv/bin/python" ] || ! cmp -s "$HERE/requirements.txt" "$TOOLS/venv/requirements.txt"; then
  rm -rf "$TOOLS/venv"
  python3 -m venv "$TOOLS/venv"
  "$TOOLS/venv/bin/pip" install --quiet --disable-pip-version-check -r "$HERE/requirements.txt"
  cp "$HERE/requirements.txt" "$TOOLS/venv/requirements.txt"
fi
echo "dashboard test tools ready in $TOOLS"
