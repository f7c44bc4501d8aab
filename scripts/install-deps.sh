#!/usr/bin/env bash
# Installs the Debian 12 packages rtgi needs, only those that are missing.
# Runs apt-get as root, or through sudo when not root.
set -euo pipefail
PKGS=(build-essential cmake pkg-config
      libimgui-dev  # Dear ImGui + its GLFW/OpenGL3 back-ends: the panel of 'rtgi view'
      libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
      libcglm-dev libstb-dev libassimp-dev libglfw3-dev libembree-dev
      libcjson-dev libcmocka-dev libopenexr-dev
      xvfb xauth   # the window tests start Xvfb; xauth for the README's xvfb-run example
      chromium)    # test_bench opens the report of rtgi bench in headless Chromium
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PKGS[@]} packages present"
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
