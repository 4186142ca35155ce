#!/usr/bin/env bash
# Robustness run (issue "Robust on any face and any real capture"): N heads
# drawn from the ICT identity modes (seeds 1..N, every weight uniform in
# ±3σ) × every Live Link take in ../shared/data/livelink × every built-in
# performance × 1000 extreme control frames, on the LR lattice (accurate
# preset), then the HR reference with contacts on a subset. Writes the
# tables into BENCHMARKS.md. Resumable: rigs and per-rig results are kept
# under out/robustness and not made again; rerun the same command.
#   bash scripts/robustness.sh [HEADS=20] [MAX_FRAMES_PER_TAKE=0 (whole takes)] [HR_HEADS=2]
set -euo pipefail
cd "$(dirname "$0")/.."
HEADS=${1:-20}
MAX_FRAMES=${2:-0}
HR_HEADS=${3:-2}
SHARED=${FACESR_SHARED_DIR:-../shared}
ICT=${FACESR_ICT_DIR:-$SHARED/data/ict-facekit}
IDS=$SHARED/data/ict-facekit-identities
TAKES=$SHARED/data/livelink
for d in "$ICT" "$IDS" "$TAKES"; do
  [[ -d "$d" ]] || { echo "robustness: missing $d" >&2; exit 1; }
done
FACESR=build/bin/facesr
[[ -x $FACESR ]] || bash scripts/build.sh
OUT=out/robustness
mkdir -p "$OUT"
rigs=()
for s in $(seq 1 "$HEADS"); do
  rig=$OUT/head$(printf %02d "$s").rig
  if [[ ! -f $rig && ! -f $OUT/head$(printf %02d "$s").rig.failed ]]; then
    echo "[robustness] head $s/$HEADS: generating and building its rig" >&2
    rm -rf "$OUT/head_tmp"
    $FACESR head identity --ict "$ICT" --identities "$IDS" --seed "$s" --max-sigma 3 -o "$OUT/head_tmp" --json > "$OUT/head$(printf %02d "$s").json"
    # A rig build that fails or hangs is a finding too: recorded, not fatal.
    if ! timeout "${RIG_TIMEOUT:-600}" $FACESR rig build --source "$OUT/head_tmp" -o "$rig" -q > /dev/null 2> "$OUT/head$(printf %02d "$s").rig.err"; then
      echo "[robustness] head $s: rig build failed or took over ${RIG_TIMEOUT:-600} s (see $OUT/head$(printf %02d "$s").rig.err)" >&2
      rm -f "$rig"
      touch "$OUT/head$(printf %02d "$s").rig.failed"
    fi
    rm -rf "$OUT/head_tmp"  # 137 MB of OBJs; the weights are in headNN.json
  fi
  [[ -f $rig ]] && rigs+=(--rig "$rig")
done
takes=()
for t in "$TAKES"/*.csv; do takes+=(--performance "$t"); done
# LR (what a game runs): every head.
$FACESR bench robustness "${rigs[@]}" "${takes[@]}" --max-frames "$MAX_FRAMES" --results "$OUT/lr" \
  --markdown BENCHMARKS.md --json > "$OUT/lr.json"
# HR reference with contacts (seconds per frame): the first HR_HEADS heads,
# 20 frames of each take and of the extreme frames.
hr_rigs=()
for s in $(seq 1 "$HR_HEADS"); do hr_rigs+=(--rig "$OUT/head$(printf %02d "$s").rig"); done
$FACESR bench robustness "${hr_rigs[@]}" "${takes[@]}" --builtins none --res high --max-frames 20 --extreme-frames 20 \
  --results "$OUT/hr" --markdown BENCHMARKS.md --json > "$OUT/hr.json"
echo "[robustness] done: tables in BENCHMARKS.md, results in $OUT" >&2
