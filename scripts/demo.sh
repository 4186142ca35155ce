#!/usr/bin/env bash
# The main job: install dependencies, build, build the procedural head's rig
# and print its summary (and the ICT head's rig when the data is beside us).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p out
./build/bin/facesr rig build --source procedural -o out/procedural.rig --preview out/procedural.png
ICT_DIR="${FACESR_ICT_DIR:-../shared/data/ict-facekit}"
if [[ -f "$ICT_DIR/generic_neutral_mesh.obj" ]]; then
  ./build/bin/facesr rig build --source "$ICT_DIR" -o out/ict.rig --preview out/ict.png
else
  echo "demo: ICT FaceKit data not found at $ICT_DIR; skipping the ICT rig" >&2
fi
