#!/usr/bin/env bash
# Installs what the browser build and its test need, where missing: the wasm32 target,
# wasm-bindgen-cli at the version of the wasm-bindgen crate in Cargo.lock, Debian's Chromium,
# and the test's node packages (playwright-core drives the system Chromium; nothing is
# downloaded from outside the package registries).
set -euo pipefail
cd "$(dirname "$0")/.."

rustup target list --installed | grep -qx wasm32-unknown-unknown \
  || rustup target add wasm32-unknown-unknown

wanted="$(grep -A1 '^name = "wasm-bindgen"$' Cargo.lock | sed -n 's/^version = "\(.*\)"$/\1/p')"
if [ "$(wasm-bindgen --version 2>/dev/null | cut -d' ' -f2)" != "$wanted" ]; then
  cargo install wasm-bindgen-cli --version "$wanted"
fi

if [ ! -x /usr/bin/chromium ] || ! command -v node >/dev/null; then
  apt-get update -q
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends chromium nodejs npm
fi

(cd tests/web && npm ci --no-audit --no-fund)
