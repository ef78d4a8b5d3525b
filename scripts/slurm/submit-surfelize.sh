#!/usr/bin/env bash
# On a login node: surfelize SCENE as a job array of N shards, then the merge into OUT.surfels once every
# shard succeeded. Prints the two job ids. Extra options go to pbs surfelize (and to sbatch through
# SBATCH_* variables, e.g. SBATCH_PARTITION).
#   scripts/slurm/submit-surfelize.sh N SCENE OUT.surfels [pbs surfelize options…]
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 N SCENE OUT.surfels [pbs surfelize options]" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
shards=$1 scene=$2 out=$3
shift 3
parts="$out.parts"
array=$(sbatch --parsable --array=0-$((shards - 1)) "$here/surfelize.sbatch" "$shards" "$scene" "$parts" "$@")
merge=$(sbatch --parsable --dependency="afterok:$array" --kill-on-invalid-dep=yes "$here/merge.sbatch" "$parts" "$out")
echo "surfelize array $array ($shards shards into $parts/), merge $merge into $out"
