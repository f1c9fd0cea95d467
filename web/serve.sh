#!/usr/bin/env bash
# Builds the module and serves the repository on localhost, so that the page can also load
# the repository's scenes: web/?scene=../examples/scenes/tinyraytracer.toml. PORT=8000 unless
# set.
set -euo pipefail
cd "$(dirname "$0")"
bash build.sh
port=${PORT:-8000}
echo "microray in a browser: http://localhost:$port/web/"
cd ..
exec python3 -m http.server "$port" --bind 127.0.0.1
