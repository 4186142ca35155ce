#!/usr/bin/env bash
# The shipped ICT model from scratch in one command: `facesr character build`
# on the generic ICT head, then its test-split errors beside the shipped
# model's on the same dataset. Resumable: rerun the same command after a kill
# (every stage is kept in out/ict_character/character.json).
#   bash scripts/reproduce-ict-model.sh [BUDGET=12h]
set -euo pipefail
cd "$(dirname "$0")/.."
BUDGET=${1:-12h}
ICT=${FACESR_ICT_DIR:-../shared/data/ict-facekit}
[[ -f $ICT/generic_neutral_mesh.obj ]] || { echo "reproduce-ict-model: no ICT FaceKit data at $ICT" >&2; exit 1; }
F=build/bin/facesr
[[ -x $F ]] || bash scripts/build.sh
OUT=out/ict_character
$F character build --source "$ICT" -o $OUT --budget "$BUDGET" --json > $OUT.json
# The shipped model on the same test split (same rig: the build is deterministic).
$F eval --rig $OUT/rig.rig --dataset $OUT/dataset --model samples/assets/ict.fsm --methods ours,embedded \
  -o $OUT/eval_shipped --json > $OUT.shipped.json
python3 - "$OUT.json" "$OUT.shipped.json" <<'PY'
import json, sys
new, old = (json.load(open(p)) for p in sys.argv[1:3])
o, s, e = new["ours_mean_cm"], old["ours"]["mean_cm"], new["embedded_mean_cm"]
print(f"reproduced: {o:.5f} cm in {new['stages_s']/3600:.2f} h; shipped: {s:.5f} cm; embedded {e:.5f} cm; "
      f"reproduced / shipped = {o/s:.3f} (goal <= 1.10)")
PY
