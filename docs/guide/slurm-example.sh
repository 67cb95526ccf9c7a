#!/usr/bin/env bash
# pcbench on a Slurm cluster, two ways (docs/guide/cluster.md; not run by CI). Edit the
# partition, the time and the paths; the suite is the door-ajar power check (its CPU hours are in
# docs/findings/scene-power.md). Each way gives the report one process would have written, bit
# for bit.
#
# 1. One MPI job: P ranks over N nodes, one rank per node using all its cores (pcbench's
#    threads), rank 0 writing the report:
#      sbatch docs/guide/slurm-example.sh mpi
# 2. A job array without MPI: n shards, each a whole share of the suite's runs, then a merge job
#    that waits for all of them:
#      sbatch docs/guide/slurm-example.sh array
#    A shard that failed (node lost, time limit) is named by the merge (exit 2); resubmit it
#    alone (`sbatch --array=I docs/guide/slurm-example.sh shard`, or `--resume` it) and merge again.
#SBATCH --job-name=pcbench
#SBATCH --time=04:00:00
#SBATCH --cpus-per-task=32
set -euo pipefail

suite=suites/door-ajar-power.json
out=results/door-ajar-power
shards=16

case "${1:-mpi}" in
  mpi)
    # Resubmitted with --resume after a failure, it restores what rank 0's journal holds.
    resume=()
    [ -f "$out/checkpoint/session.json" ] && resume=(--resume)
    # Open MPI 4.1 starts under srun through PMIx (--mpi=pmix); where it does not, mpirun inside
    # the allocation does the same.
    srun --mpi=pmix --nodes="${SLURM_JOB_NUM_NODES:-8}" --ntasks-per-node=1 \
      --cpus-per-task="${SLURM_CPUS_PER_TASK:-32}" \
      build/release/pcbench verify "$suite" --quiet --out "$out" "${resume[@]}"
    ;;
  array)
    array=$(sbatch --parsable --array=0-$((shards - 1)) "$0" shard)
    sbatch --dependency=afterany:"$array" "$0" merge
    ;;
  shard)
    folder="$out-shards/$SLURM_ARRAY_TASK_ID"
    resume=()
    [ -f "$folder/shard.json" ] && resume=(--resume)
    build/release/pcbench verify "$suite" --quiet --shard "$SLURM_ARRAY_TASK_ID/$shards" \
      --out "$folder" "${resume[@]}"
    ;;
  merge)
    build/release/pcbench merge "$out"-shards/* --out "$out"
    ;;
esac
