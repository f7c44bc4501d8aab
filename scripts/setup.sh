#!/usr/bin/env bash
# One command from a fresh Debian 12 checkout to out/cornell.png:
# install missing packages, build, render the default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
make run
