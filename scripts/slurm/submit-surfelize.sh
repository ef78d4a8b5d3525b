#!/usr/bin/env bash
# On a login node: surfelize SCENE as a job array of N shards, then the merge into OUT.surfels once every
# shard succeeded. Prints the two job ids. Extra arguments go to pbs surfelize; $PBS_SHARD_SBATCH to the
# array's sbatch (e.g. PBS_SHARD_SBATCH="--cpus-per-task=32 --time=2:00:00"), SBATCH_* variables to both.
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
# shellcheck disable=SC2086
array=$(sbatch --parsable ${PBS_SHARD_SBATCH:-} --array=0-$((shards - 1)) "$here/surfelize.sbatch" "$shards" "$scene" "$parts" "$@")
merge=$(sbatch --parsable --dependency="afterok:$array" --kill-on-invalid-dep=yes "$here/merge.sbatch" "$parts" "$out")
echo "surfelize array $array ($shards shards into $parts/), merge $merge into $out"
