#!/usr/bin/env bash
# The README's first command: installs what is missing, builds, and shows the product on a
# bundled real T-mesh.
set -euo pipefail
cd "$(dirname "$0")/.."

bash deploy/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j 2

SAMPLE=tests/data/s07c_notch.tmesh.json
build/release/client/ispq stats "$SAMPLE"
echo "quantization not yet available"
