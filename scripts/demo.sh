#!/usr/bin/env bash
# The main job: install dependencies, build, build the face rigs, simulate a
# performance on the LR lattice (OpenCL) and render a few frames of it, then
# make a small paired LR/HR dataset and picture its embedded-vs-HR error, run
# the head-to-model pipeline on a tiny budget, and end with the real-time demo: a performance played through the runtime (LR
# simulation + OpenCL super-resolution) with the shipped models, written as
# glTF, with the frame rate printed.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p out
F=./build/bin/facesr
$F rig build --source procedural -o out/procedural.rig --preview out/procedural.png
$F perf write --rig out/procedural.rig --builtin talk -o out/talk.json
$F simulate --rig out/procedural.rig --res low --performance out/talk.json --out out/procedural_talk.fsq --json
$F render --rig out/procedural.rig --seq out/procedural_talk.fsq --count 6 --heat -o out/procedural_talk.png
# Paired LR/HR data: the four themed performances, first 30 frames each.
$F dataset --rig out/procedural.rig --out out/procedural_dataset --frames 30 --json
$F render --rig out/procedural.rig --dataset out/procedural_dataset/pain.fsd --count 6 -o out/procedural_pain_error.png
ICT_DIR="${FACESR_ICT_DIR:-../shared/data/ict-facekit}"
if [[ -f "$ICT_DIR/generic_neutral_mesh.obj" ]]; then
  $F rig build --source "$ICT_DIR" -o out/ict.rig --preview out/ict.png
  $F simulate --rig out/ict.rig --res low --builtin talk --out out/ict_talk.fsq --json
  $F render --rig out/ict.rig --seq out/ict_talk.fsq --count 6 --heat -o out/ict_talk.png --gltf out/ict_talk.gltf
  # The full ICT dataset takes about an hour on 2 cores; opt in with FACESR_DEMO_ICT_DATASET=1.
  if [[ "${FACESR_DEMO_ICT_DATASET:-0}" == 1 ]]; then
    $F dataset --rig out/ict.rig --out out/ict_dataset --json
  fi
else
  echo "demo: ICT FaceKit data not found at $ICT_DIR; skipping the ICT rig" >&2
fi
# Your own character: the whole pipeline (rig, data, training, post-fit,
# evaluation, package) on the coarse procedural head with a minutes-long
# budget; a real head takes hours (README, "Your own character").
$F character build --source procedural --preset coarse -o out/procedural_character --budget 3m --max-frames 20 --json
# Real-time demo. The rig build is deterministic (on any x86-64 CPU), so the shipped models
# (scripts/make-procedural-model.sh, docs/network.md) fit the rigs built here;
# a model made for another rig is refused by its checksum.
$F rig build --source procedural --preset coarse -o out/procedural_coarse.rig
$F play --rig out/procedural_coarse.rig --model samples/assets/procedural_coarse.fsm \
  --builtin anger --async -o out/procedural_play.gltf
if [[ -f out/ict.rig && -f samples/assets/ict.fsm ]]; then
  $F play --rig out/ict.rig --model samples/assets/ict.fsm --builtin anger --async -o out/ict_play.gltf
fi
