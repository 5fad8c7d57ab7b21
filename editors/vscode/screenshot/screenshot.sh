#!/usr/bin/env bash
# Regenerates screenshot/highlighting.png: the grammar's tokens as HTML (render.js), photographed
# by headless Chromium. Needs node with the dev dependencies installed (npm ci) and chromium.
set -euo pipefail
cd "$(dirname "$0")"
node render.js
chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1000,950 \
    --screenshot="$PWD/highlighting.png" "file://$PWD/render.html"
