#!/usr/bin/env bash
# Run a `proofs` certificate as a Slurm job array: one array task per shard, then one
# merge job that waits for all of them (afterok) and re-checks the merged certificate.
#
#   scripts/slurm/submit.sh N DIR PROOF ARGS...
#   scripts/slurm/submit.sh 64 certs/mdd stuffing --row max-dihedral-double
#   scripts/slurm/submit.sh 32 certs/ue stuffing --alpha-long 0.21509 --alpha-short 0.359 --side both
#   scripts/slurm/submit.sh 16 certs/gn gradnormal --a sommerville --rule paper
#
# Environment: PROOFS (the binary on the cluster, default `proofs`), SBATCH_ARGS (extra
# sbatch options, e.g. "--partition=short --account=geo"), DRY_RUN=1 (print the sbatch
# commands and every command the tasks would run; submit nothing).
set -euo pipefail
if (( $# < 3 )); then
  sed -n '2,12p' "$0" >&2
  exit 2
fi
n=$1 dir=$2; shift 2
if ! [[ $n =~ ^[0-9]+$ ]] || (( n < 2 )); then
  echo "submit.sh: N must be a whole number >= 2 (got '$n')" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
export SHARDS=$n DIR=$dir PROOFS=${PROOFS:-proofs}
read -r -a extra <<< "${SBATCH_ARGS:-}"
array=(sbatch --parsable "${extra[@]}" --array="0-$((n - 1))" --export=ALL "$here/shard.sbatch" "$@")
if [[ ${DRY_RUN:-0} == 1 ]]; then
  printf '%q ' "${array[@]}"; echo
  for ((i = 0; i < n; i++)); do SLURM_ARRAY_TASK_ID=$i bash "$here/shard.sbatch" "$@"; done
  printf '%q ' sbatch "${extra[@]}" --dependency=afterok:JOBID --export=ALL "$here/merge.sbatch"; echo
  bash "$here/merge.sbatch"
  exit 0
fi
mkdir -p "$dir"
jid=$("${array[@]}")
jid=${jid%%;*}
sbatch "${extra[@]}" --dependency="afterok:$jid" --export=ALL "$here/merge.sbatch"
echo "submitted array job $jid ($n shards) and its merge; certificate: $dir/merged.json"
