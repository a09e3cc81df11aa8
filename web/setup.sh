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

# Only what is missing: a machine whose node comes from elsewhere (NodeSource's bundles npm)
# cannot also take Debian's npm, which conflicts with it.
missing=()
[ -x /usr/bin/chromium ] || missing+=(chromium)
command -v node >/dev/null || missing+=(nodejs)
command -v npm >/dev/null || missing+=(npm)
if [ ${#missing[@]} -gt 0 ]; then
  apt-get update -q
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

(cd tests/web && npm ci --no-audit --no-fund)
