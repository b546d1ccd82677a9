#!/usr/bin/env bash
# Builds the libFuzzer targets (the `asan` preset: clang, ASan + UBSan) and runs each
# for a bounded time on its corpus, after replaying the regression inputs. Fails on
# any crash, leak, sanitizer report, timeout or out-of-memory.
#   tests/fuzz/run.sh [SECONDS_PER_TARGET=60] [TARGET...]   # long runs, corpora kept
#   tests/fuzz/run.sh --runs N [TARGET...]                   # long runs of N executions each
#   tests/fuzz/run.sh --ci [TARGET...]                       # CI: regressions, seeds, then
#                                                            # FUZZ_CI_SECONDS (30) each
# The corpora grow in build/asan/corpus/<target> (kept between runs); findings land in
# build/asan/artifacts/. Seeds: examples/*.json, data/bathymetry, tests/fuzz/seeds.
# --ci starts from the seeds alone (a fresh corpus, -seed=1), executes every regression
# input and every seed once, then explores each target for FUZZ_CI_SECONDS. The
# exploration is bounded in time, so what it reaches depends on the machine's speed: a
# finding there is a real fault all the same — its input is printed (hex) in the log, to
# be kept under tests/fuzz/regressions/<target>/ with the fix.
set -euo pipefail
cd "$(dirname "$0")/../.."
ci=0
runs=0
if [[ ${1:-} == --ci ]]; then ci=1; seconds=${FUZZ_CI_SECONDS:-30}; shift
elif [[ ${1:-} == --runs ]]; then runs=${2:?--runs needs a count}; seconds=0; shift 2
else seconds=${1:-60}; shift || true; fi
targets=("$@")
((${#targets[@]})) || targets=(fuzz_scene fuzz_swan_bot fuzz_contours fuzz_raster fuzz_mesh fuzz_mesh_off fuzz_gltf fuzz_index)

scripts/install-deps.sh --tests >&2
cmake --preset asan >/dev/null
cmake --build --preset asan

build=build/asan
mkdir -p "$build/artifacts"
corpus_root="$build/corpus"
if ((ci)); then corpus_root="$build/ci-corpus"; rm -rf "$corpus_root"; fi
# Seeds per target (copied into the corpus once; the corpus then keeps what libFuzzer found).
seed() {  # target, files...
  local dir="$corpus_root/$1"
  shift
  mkdir -p "$dir"
  for f in "$@"; do [[ -f $f ]] && cp -n "$f" "$dir/" || true; done
}
seed fuzz_scene examples/*.json
seed fuzz_swan_bot tests/fuzz/seeds/swan/*
if [[ ! -f $corpus_root/fuzz_swan_bot/haringvliet.bot ]]; then  # the real SWAN file with its grid line
  { echo "88 117"; cat data/bathymetry/haringvliet_swan_f31hari_250m.bot; } >"$corpus_root/fuzz_swan_bot/haringvliet.bot"
fi
seed fuzz_contours tests/fuzz/seeds/contours/*
seed fuzz_raster tests/fuzz/seeds/raster/*
seed fuzz_mesh tests/fuzz/seeds/mesh/*
seed fuzz_mesh_off tests/fuzz/seeds/mesh/*.off
seed fuzz_gltf tests/fuzz/seeds/gltf/*
seed fuzz_index tests/fuzz/seeds/index/*

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:allocator_may_return_null=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# One target: its regression inputs, (CI) its seeds, then the bounded run. Prints its
# summary line last; exits non-zero on any finding.
fuzz_target() {
  local t=$1
  local bin="$build/tests/fuzz/$t"
  # Inputs that once failed stay fixed (tests/fuzz/regressions/<target>/).
  if compgen -G "tests/fuzz/regressions/$t/*" >/dev/null; then
    echo "== $t: regression inputs" >&2
    if ! "$bin" -runs=0 tests/fuzz/regressions/$t/* >"$build/$t.regressions.log" 2>&1; then
      tail -n 40 "$build/$t.regressions.log" >&2
      echo "fuzz: $t FAILED on a regression input (tests/fuzz/regressions/$t)" >&2
      exit 1
    fi
  fi
  local budget=(-max_total_time="$seconds") log executed cov secs
  ((runs)) && budget=(-runs="$runs")
  log="$build/$t.log"
  if ((ci)); then  # each seed once, then the bounded exploration
    echo "== $t: seeds" >&2
    if ! "$bin" -runs=0 "$corpus_root/$t" >"$log" 2>&1; then
      tail -n 60 "$log" >&2
      echo "fuzz: $t FAILED on a seed (tests/fuzz/seeds, examples/)" >&2
      exit 1
    fi
    budget+=(-seed=1)
  fi
  # Dictionaries: deep nesting and extreme numbers for the JSON readers, bad cells for the grids.
  case $t in
    fuzz_scene | fuzz_contours | fuzz_gltf | fuzz_index) budget+=(-dict=tests/fuzz/dicts/json.dict) ;;
    fuzz_raster | fuzz_swan_bot) budget+=(-dict=tests/fuzz/dicts/grid.dict) ;;
  esac
  echo "== $t: ${budget[*]}" >&2
  if ! "$bin" "${budget[@]}" -timeout=20 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
      -artifact_prefix="$build/artifacts/$t-" "$corpus_root/$t" >"$log" 2>&1; then
    tail -n 60 "$log" >&2
    for a in $(grep -o "Test unit written to [^ ]*" "$log" | sed 's/Test unit written to //'); do
      echo "fuzz: the input ($a), $(stat -c %s "$a") bytes:" >&2
      od -A d -t x1 -v "$a" | head -n 256 >&2
    done
    echo "fuzz: $t FAILED; the input is in $build/artifacts/" >&2
    exit 1
  fi
  executed=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | grep -o '[0-9]*$' || echo '?')
  secs=$(grep -o 'Done [0-9]* runs in [0-9]* second' "$log" | grep -o 'in [0-9]*' | grep -o '[0-9]*' || echo '?')
  echo "fuzz: $t: $executed executions in $secs s, coverage $cov edges, corpus $(ls "$corpus_root/$t" | wc -l) inputs"
}

# The targets run side by side, one per core (each for its own time budget), their
# logs kept apart and printed in order.
jobs=$(nproc)
failed=0
for ((i = 0; i < ${#targets[@]}; i += jobs)); do
  pids=()
  for t in "${targets[@]:i:jobs}"; do
    fuzz_target "$t" >"$build/$t.summary" 2>"$build/$t.stderr" &
    pids+=($!)
  done
  for k in "${!pids[@]}"; do
    t=${targets[i + k]}
    wait "${pids[$k]}" || failed=1
    cat "$build/$t.stderr" >&2
  done
done
for t in "${targets[@]}"; do cat "$build/$t.summary"; done
exit "$failed"
