#!/usr/bin/env bash
# Run a `proofs` certificate as N shards on one machine, J at a time, then merge and
# re-check: the same shard and merge commands as the Slurm job array (scripts/slurm/).
# Uses GNU parallel when it is installed, xargs -P otherwise.
#
#   scripts/parallel.sh N DIR PROOF ARGS...
#   JOBS=2 scripts/parallel.sh 8 certs/mdd stuffing --row max-dihedral-double
#
# Environment: PROOFS (default `proofs`), JOBS (default: the number of cores),
# DRY_RUN=1 (print the commands; run nothing).
set -euo pipefail
if (( $# < 3 )); then
  sed -n '2,10p' "$0" >&2
  exit 2
fi
n=$1 dir=$2; shift 2
if ! [[ $n =~ ^[0-9]+$ ]] || (( n < 2 )); then
  echo "parallel.sh: N must be a whole number >= 2 (got '$n')" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
export SHARDS=$n DIR=$dir PROOFS=${PROOFS:-proofs}
jobs=${JOBS:-$(nproc 2>/dev/null || echo 1)}
if [[ ${DRY_RUN:-0} == 1 ]]; then
  for ((i = 0; i < n; i++)); do SLURM_ARRAY_TASK_ID=$i bash "$here/slurm/shard.sbatch" "$@"; done
  bash "$here/slurm/merge.sbatch"
  exit 0
fi
mkdir -p "$dir"
task='SLURM_ARRAY_TASK_ID=$0 exec bash "$1"/slurm/shard.sbatch "${@:2}"'
if command -v parallel >/dev/null 2>&1; then
  seq 0 $((n - 1)) | parallel --halt now,fail=1 -j "$jobs" bash -c "$task" {} "$here" "$@"
else
  seq 0 $((n - 1)) | xargs -P "$jobs" -I{} bash -c "$task" {} "$here" "$@"
fi
bash "$here/slurm/merge.sbatch"
