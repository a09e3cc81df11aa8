#!/usr/bin/env bash
# Builds the browser viewer and serves it on http://127.0.0.1:${1:-8080}/ (Ctrl-C stops).
# Scenes by address: /?scene=pachinko; graphics backend: /?backend=webgl or /?backend=webgpu.
set -euo pipefail
cd "$(dirname "$0")/.."
port="${1:-8080}"
site=target/web/site
bash web/build.sh "$site"
echo "serving the viewer on http://127.0.0.1:$port/"
exec python3 -m http.server --directory "$site" --bind 127.0.0.1 "$port"
