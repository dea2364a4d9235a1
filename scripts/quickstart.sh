#!/usr/bin/env bash
# A new user's first command: installs what clpt needs (Debian 12, apt-get), builds it,
# and renders the bundled Cornell box on the PoCL CPU device to cornell_box.png.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake --preset release  # CMakePresets.json: build/, Release, Ninja, unity mode
cmake --build --preset release --target clpt
./build/clpt --device=pocl scenes/cornell_box.gltf --resolution 512x512 --spp 256 -o cornell_box.png
echo "quickstart: wrote $(pwd)/cornell_box.png"
