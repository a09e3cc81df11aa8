#!/usr/bin/env bash
# Builds the viewer for the browser into a folder that any static server can serve:
#   bash web/build.sh [OUT_DIR]        (default: target/web/site)
# Needs the wasm32 target and wasm-bindgen-cli (`cargo xtask setup` installs them).
set -euo pipefail
cd "$(dirname "$0")/.."

out="${1:-target/web/site}"
# A target folder of its own: the build may run while another cargo holds target/.
export CARGO_TARGET_DIR="${WEB_TARGET_DIR:-target/web/build}"
cargo build --release --target wasm32-unknown-unknown --bin rigid
mkdir -p "$out"
wasm-bindgen --target web --no-typescript --out-dir "$out" \
  "$CARGO_TARGET_DIR/wasm32-unknown-unknown/release/rigid.wasm"
cp web/index.html "$out/index.html"
echo "web page built in $out (serve it with: python3 -m http.server -d $out -b 127.0.0.1 8080)"
