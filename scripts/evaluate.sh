#!/usr/bin/env bash
# Re-measures the baseline of docs/evaluation.md: the embedded default scene, a generated city of the
# four largest shared meshes (about 500 M instanced triangles) and the same city with every instance
# baked into its own mesh (--unique), each surfelized with the defaults and evaluated on the orbit,
# approach and flythrough paths against Embree at 64 samples per pixel. Usage:
#   scripts/evaluate.sh [OUT] [SIZE] [FRAMES]   (defaults: /tmp/pbs-evaluate 960x540 12)
# PBS_EVAL_PEERS=embree=1,4,16 measures only those peers (the default adds exact=1, the rasterizer, which
# is never the faster exact renderer on these scenes and takes seconds a frame on the cities at 1920x1080).
# PBS_EVAL_SWEEP=rays=keep measures that setting beside the defaults in the same runs (default: none).
# Scenes and .surfels files already in OUT are reused. Run it on a quiet machine: it reports times.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-/tmp/pbs-evaluate}
size=${2:-960x540}
frames=${3:-12}
scenes=${PBS_SCENES:-../shared/scenes}
pbs=./build/bin/pbs
meshes=()
for mesh in bunny horse rocker-arm fandisk; do meshes+=(--mesh "$scenes/$mesh.glb"); done
mkdir -p "$out"
peers=()
[ -z "${PBS_EVAL_PEERS:-}" ] || peers=(--peers "$PBS_EVAL_PEERS")

# One generated city, instanced and unique; `time -v` gives the peak memory of each step.
timed() { local log=$1; shift; /usr/bin/time -v "$@" > "$log" 2>&1 || { cat "$log"; exit 1; }; }
[ -f "$out/city.glb" ] || timed "$out/generate-city.log" $pbs generate city "${meshes[@]}" --levels 4 --fanout 10 -o "$out/city.glb"
[ -f "$out/unique.glb" ] ||
  timed "$out/generate-unique.log" $pbs generate city "${meshes[@]}" --levels 4 --fanout 7 --unique -o "$out/unique.glb"

for scene in default city unique; do
  file=$scene
  [ "$scene" = default ] || file="$out/$scene.glb"
  [ -f "$out/$scene.surfels" ] || timed "$out/surfelize-$scene.log" $pbs surfelize "$file" -o "$out/$scene.surfels" --quiet
  # What each renderer needs before its first frame, and its peak memory: one frame each.
  timed "$out/first-frame-embree-$scene.log" $pbs render "$file" --mode embree --size "$size" --json
  timed "$out/first-frame-surfels-$scene.log" $pbs render "$file" --surfels "$out/$scene.surfels" --size "$size" --json
  for path in orbit approach flythrough; do
    $pbs eval "$file" --surfels "$out/$scene.surfels" -o "$out/$scene-$path" --size "$size" --frames "$frames" \
      --path "$path" "${peers[@]}" --sweep "${PBS_EVAL_SWEEP:-surfels}" --quiet | tee "$out/$scene-$path.txt"
  done
done
