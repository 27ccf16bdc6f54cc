#!/usr/bin/env bash
# A local stand-in for the scheduler: runs shard.sh for every index of an n-task array, as SLURM
# would (SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT), a few at a time, then merges the shards.
# Given a reference log (an unsharded run of the same configuration), checks that the merged log has
# the same header and rows (wall-clock timings, the machine and the commit aside).
#
#   experiments/scheduler/local-array.sh experiments/paper.toml 20 [reference.jsonl]
#
# Environment: PUSHMOG (default target/release/pushmog), PARALLEL tasks at once (default 2), LOG_DIR
# (default: a new temporary folder).
set -euo pipefail
config="${1:?usage: local-array.sh CONFIG.toml SHARDS [REFERENCE.jsonl]}"
count="${2:?usage: local-array.sh CONFIG.toml SHARDS [REFERENCE.jsonl]}"
reference="${3:-}"
export PUSHMOG="${PUSHMOG:-target/release/pushmog}"
export LOG_DIR="${LOG_DIR:-$(mktemp -d)}"
export JOBS=1
name="$(basename "$config" .toml)"
here="$(dirname "$0")"
seq 0 $((count - 1)) | xargs -P "${PARALLEL:-2}" -I{} \
  env SLURM_ARRAY_TASK_ID={} SLURM_ARRAY_TASK_COUNT="$count" "$here/shard.sh" "$config"
shards=()
for ((i = 0; i < count; i++)); do shards+=("$LOG_DIR/$name.shard-$i-of-$count.jsonl"); done
"$PUSHMOG" merge "${shards[@]}" -o "$LOG_DIR/$name.jsonl"
if [[ -n "$reference" ]]; then
  python3 - "$LOG_DIR/$name.jsonl" "$reference" <<'PY'
import json, sys
def load(path):
    lines = [json.loads(l) for l in open(path, encoding="utf-8")]
    for row in lines[1:]:
        row.pop("timing", None)
    return lines
merged, reference = load(sys.argv[1]), load(sys.argv[2])
same_rows = merged[1:] == reference[1:]
header = {k: v for k, v in merged[0].items() if k not in ("machine", "git_commit")} == {k: v for k, v in reference[0].items() if k not in ("machine", "git_commit")}
print(f"{len(merged) - 1} rows merged, {len(reference) - 1} in the reference: rows {'identical' if same_rows else 'DIFFERENT'}, header {'identical' if header else 'DIFFERENT'} (timings, machine and commit aside)")
sys.exit(0 if same_rows and header else 1)
PY
fi
echo "merged log: $LOG_DIR/$name.jsonl"
