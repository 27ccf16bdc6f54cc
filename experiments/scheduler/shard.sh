#!/usr/bin/env bash
# Runs one shard of an experiment configuration, the shard given by the batch scheduler:
#   SLURM array job:         SLURM_ARRAY_TASK_ID of SLURM_ARRAY_TASK_COUNT tasks (array 0..n-1);
#   Kubernetes indexed job:  JOB_COMPLETION_INDEX of SHARDS (set SHARDS to the job's completions).
# Each shard writes its own log, LOG_DIR/<name>.shard-<i>-of-<n>.jsonl (default experiments/results),
# and resumes it if the task is restarted. PUSHMOG names the binary (default: pushmog on PATH), JOBS
# the worker threads (default: SLURM_CPUS_PER_TASK, else 1). Usage: shard.sh CONFIG.toml
set -euo pipefail
config="${1:?usage: shard.sh CONFIG.toml}"
if [[ -n "${SLURM_ARRAY_TASK_ID:-}" ]]; then
  index="$SLURM_ARRAY_TASK_ID"
  count="${SLURM_ARRAY_TASK_COUNT:?SLURM_ARRAY_TASK_COUNT is not set: submit with --array=0-<n-1>}"
elif [[ -n "${JOB_COMPLETION_INDEX:-}" ]]; then
  index="$JOB_COMPLETION_INDEX"
  count="${SHARDS:?set SHARDS to the number of completions of the indexed job}"
else
  echo "shard.sh: no array index (SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX)" >&2
  exit 2
fi
name="$(basename "$config" .toml)"
log_dir="${LOG_DIR:-experiments/results}"
mkdir -p "$log_dir"
exec "${PUSHMOG:-pushmog}" experiment "$config" --quiet \
  --shard "$index/$count" \
  --jobs "${JOBS:-${SLURM_CPUS_PER_TASK:-1}}" \
  --log "$log_dir/$name.shard-$index-of-$count.jsonl"
