#!/usr/bin/env bash
# Renders a libwave animation on a Slurm cluster: an array job of frame slices, then
# the merge step once every slice succeeded. OUT must be on a filesystem all nodes see.
#   scripts/slurm/submit.sh [--slices N] [--wait] [--logs DIR] [--sbatch "OPTIONS"] \
#       SCENE|default OUT [-- wave run options…]
# Prints the array and merge job ids. --wait blocks until the merge job ends and exits
# with its status (non-zero when a slice failed: the merge is then cancelled).
# $WAVE names the wave executable (default: wave on PATH); it is resolved here and
# passed to the jobs.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
slices=4 wait=() logs="" sbatch_opts=""
usage() { sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while (($# > 0)); do
  case $1 in
    --slices) slices=${2:?}; shift 2 ;;
    --wait) wait=(--wait); shift ;;
    --logs) logs=${2:?}; shift 2 ;;
    --sbatch) sbatch_opts=${2:?}; shift 2 ;;
    -h|--help) usage ;;
    --) break ;;
    -*) echo "submit.sh: unknown option $1" >&2; usage ;;
    *) break ;;
  esac
done
(($# >= 2)) || usage
scene=$1 out=$2
shift 2
[[ ${1:-} == -- ]] && shift
if ! [[ $slices =~ ^[1-9][0-9]*$ ]]; then echo "submit.sh: --slices must be a whole number >= 1, got '$slices'" >&2; exit 2; fi
wave=$(command -v "${WAVE:-wave}") || { echo "submit.sh: no wave executable (${WAVE:-wave}); set WAVE" >&2; exit 2; }
if [[ $scene != default ]]; then
  [[ -f $scene ]] || { echo "submit.sh: scene $scene: no such file" >&2; exit 2; }
  scene=$(realpath "$scene")
  "$wave" validate "$scene" >/dev/null  # fail here, not in every task
fi
out=$(realpath -m "$out")
logs=$(realpath -m "${logs:-$out.slurm-logs}")
mkdir -p "$out" "$logs"  # before the tasks: none of them owns the folder
read -r -a extra_sbatch <<<"$sbatch_opts"
array=$(sbatch --parsable --export="ALL,WAVE=$wave" --array="0-$((slices - 1))" \
  --output="$logs/slice-%a.out" "${extra_sbatch[@]}" "$here/wave-slice.sbatch" "$scene" "$out" "$@")
array=${array%%;*}
echo "array job $array: $slices slices of $scene into $out"
set +e
merge=$(sbatch --parsable "${wait[@]}" --export="ALL,WAVE=$wave" --dependency="afterok:$array" \
  --kill-on-invalid-dep=yes --output="$logs/merge.out" "${extra_sbatch[@]}" "$here/wave-merge.sbatch" "$out")
status=$?
set -e
merge=${merge%%;*}
echo "merge job $merge: index.json and report.json in $out (logs in $logs)"
if ((${#wait[@]} > 0 && status == 0)); then
  # sbatch --wait returns 0 for a job cancelled before it ran (a slice failed).
  state=$(scontrol show job -o "$merge" 2>/dev/null | grep -o 'JobState=[A-Z_]*' || true)
  if [[ -n $state && $state != JobState=COMPLETED ]]; then
    echo "submit.sh: merge job $merge ended ${state#JobState=} (a slice failed? see $logs)" >&2
    status=1
  fi
fi
exit "$status"
