#!/usr/bin/env bash
# Reproduces the shipped model samples/assets/procedural_coarse.fsm: the
# coarse procedural head's rig, its paired dataset (the four themed
# performances, first 60 frames each: onset and apex; LR and HR with
# collisions), and a small network trained on it by `facesr train` (15 epochs,
# with the embedded skip connection, see docs/network.md). About 10 minutes
# on 2 cores (2 min dataset, ~25 s per epoch). The rig build is deterministic,
# so the model fits the rig that scripts/demo.sh rebuilds.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
F=./build/bin/facesr
mkdir -p out samples/assets
$F rig build --source procedural --preset coarse -o out/procedural_coarse.rig
$F dataset --rig out/procedural_coarse.rig --out out/procedural_coarse_dataset --frames 60 --json
$F train --rig out/procedural_coarse.rig --dataset out/procedural_coarse_dataset \
  -o samples/assets/procedural_coarse.fsm --embedded-skip --recon-hidden 64,64 --lr 1e-3 --epochs 15 --restart --json
$F eval --rig out/procedural_coarse.rig --dataset out/procedural_coarse_dataset \
  --model samples/assets/procedural_coarse.fsm --methods ours,embedded,rbf,mls -o out/procedural_coarse_eval --json
