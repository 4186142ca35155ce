#!/usr/bin/env bash
# Issue "Your own character" measurements: heads made from the ICT identity
# modes (seeds), each built twice by `facesr character build` at the same
# budget, from scratch and transferred from the shipped ICT model
# (--init-from; its zero-shot error is in the summary). Resumable: rerun the
# same command. Summaries: out/characters/<head>_{scratch,transfer}.json.
#   bash scripts/character-heads.sh [BUDGET=3h] [SEEDS="1 2 3"] [MODES="transfer scratch"]
set -euo pipefail
cd "$(dirname "$0")/.."
BUDGET=${1:-3h}
SEEDS=${2:-1 2 3}
MODES=${3:-transfer scratch}
SHARED=${FACESR_SHARED_DIR:-../shared}
F=build/bin/facesr
[[ -x $F ]] || bash scripts/build.sh
OUT=out/characters
mkdir -p $OUT
for s in $SEEDS; do
  head=$OUT/head$(printf %02d "$s")
  [[ -f $head/generic_neutral_mesh.obj ]] || $F head identity --ict "$SHARED/data/ict-facekit" \
    --identities "$SHARED/data/ict-facekit-identities" --seed "$s" --max-sigma 3 -o "$head" --json > "$head.json"
  for mode in $MODES; do
    extra=()
    [[ $mode == transfer ]] && extra=(--init-from samples/assets/ict.fsm)
    # Both builds of a head share one test split: simulated once, then copied
    # (a finished .fsd of the same rig is kept by `facesr dataset`).
    pkg=${head}_$mode
    if [[ ! -d $pkg/dataset && -d ${head}_transfer/dataset && $mode == scratch ]]; then
      mkdir -p "$pkg/dataset"
      for f in ${head}_transfer/dataset/anger.fsd ${head}_transfer/dataset/fear.fsd; do cp "$f" "$pkg/dataset/"; done
    fi
    echo "[character-heads] $(basename "$head") $mode, budget $BUDGET" >&2
    $F character build --source "$head" -o "$pkg" --budget "$BUDGET" "${extra[@]}" --json > "$pkg.json"
  done
done
python3 - $OUT <<'PY'
import json, os, sys, glob
rows = []
for p in sorted(glob.glob(os.path.join(sys.argv[1], "head*_*.json"))):
    if p.endswith(".json") and "_" in os.path.basename(p):
        j = json.load(open(p)); z = j.get("zero_shot", {})
        rows.append(f"| {os.path.basename(p)[:-5]} | {j['ours_mean_cm']:.4f} | {j['embedded_mean_cm']:.4f} | "
                    f"{j['ours_over_embedded']:.3f} | {j['frames_ours_beats_embedded']} / {j['test_frames']} | "
                    f"{z.get('test_cm', float('nan')):.4f} | {j['stages_s']/3600:.2f} |")
print("| build | ours (cm) | embedded (cm) | ours/embedded | frames better | zero-shot (cm) | hours |")
print("|---|---|---|---|---|---|---|")
print("\n".join(rows))
PY
