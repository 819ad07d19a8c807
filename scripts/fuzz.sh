#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (ASan + UBSan) and runs each for
# SECONDS_PER_TARGET seconds (default 60) on its committed corpus; exits non-zero on any finding
# (crash, sanitizer report, leak, timeout, out-of-memory) or if clang with libFuzzer is missing.
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]      targets: see TARGETS below
# Environment:
#   FUZZ_BUILD_DIR  build folder (default build-fuzzers, beside the main build)
#   FUZZ_WORK_DIR   where new corpus entries and findings go (default $FUZZ_BUILD_DIR/work)
#   FUZZ_JOBS       targets run at the same time (default 1)
#   FUZZ_MERGE=1    afterwards, minimise each target's corpus into fuzz/corpus/<target>, keeping
#                   the smallest inputs within FUZZ_CORPUS_KB (default 64) KiB
# Findings are written to $FUZZ_WORK_DIR/<target>/findings/ and listed at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
TARGETS=(scene_json obj ply pbrt gltf gzip scene2d pfm png exr jpeg)
targets=("$@")
[[ ${#targets[@]} -eq 0 ]] && targets=("${TARGETS[@]}")
build=${FUZZ_BUILD_DIR:-build-fuzzers}
work=${FUZZ_WORK_DIR:-$build/work}
jobs=${FUZZ_JOBS:-1}

# Longest input per target: a few times the largest seed, small enough to keep runs fast.
declare -A max_len=([scene_json]=8192 [obj]=4096 [ply]=4096 [pbrt]=8192 [gltf]=8192 [gzip]=4096
  [scene2d]=4096 [pfm]=4096 [png]=8192 [exr]=8192 [jpeg]=8192)

if ! command -v clang++ >/dev/null ||
  ! echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, long) { return 0; }' |
  clang++ -fsanitize=fuzzer -x c++ - -o /dev/null 2>/dev/null; then
  echo "fuzz.sh: clang++ with libFuzzer is not installed" >&2
  exit 2
fi
CXX=clang++ cmake -S fuzz -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j"${FUZZ_BUILD_JOBS:-$(nproc)}" -- -k 0 >/dev/null || {
  cmake --build "$build" -j1 # show the error
  exit 1
}

# Runs one target; its log is $work/<target>/log.
run_one() {
  local t=$1 dir=$work/$1
  mkdir -p "$dir/corpus" "$dir/findings"
  local rc=0
  "$build/fuzz_$t" "$dir/corpus" "fuzz/corpus/$t" -max_total_time="$seconds" \
    -dict="fuzz/dict/$t.dict" -max_len="${max_len[$t]}" -rss_limit_mb=2048 \
    -malloc_limit_mb=1024 -timeout=10 -print_final_stats=1 -detect_leaks=1 \
    -artifact_prefix="$dir/findings/" >"$dir/log" 2>&1 || rc=$?
  local execs
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log" | tail -1)
  printf '%-11s %4s s %10s executions  %s\n' "$t" "$seconds" "${execs:-?}" \
    "$([[ $rc -eq 0 ]] && echo ok || echo "FINDING (rc $rc, see $dir/log)")"
  return $rc
}

failed=0
pids=()
for t in "${targets[@]}"; do
  [[ -n ${max_len[$t]:-} ]] || { echo "fuzz.sh: unknown target '$t' (valid: ${TARGETS[*]})" >&2; exit 2; }
  run_one "$t" &
  pids+=($!)
  if ((${#pids[@]} >= jobs)); then
    wait "${pids[0]}" || failed=1
    pids=("${pids[@]:1}")
  fi
done
for p in "${pids[@]}"; do wait "$p" || failed=1; done

if [[ ${FUZZ_MERGE:-0} == 1 ]]; then
  for t in "${targets[@]}"; do
    mkdir -p "$work/$t/merged"
    "$build/fuzz_$t" -merge=1 -max_len="${max_len[$t]}" -rss_limit_mb=2048 \
      -malloc_limit_mb=1024 -timeout=10 "$work/$t/merged" "fuzz/corpus/$t" "$work/$t/corpus" \
      >"$work/$t/merge.log" 2>&1 || failed=1
    # Keep the smallest inputs of the merged set within the budget.
    rm -rf "fuzz/corpus/$t" && mkdir -p "fuzz/corpus/$t"
    budget=$((${FUZZ_CORPUS_KB:-64} * 1024)) total=0
    while read -r f; do
      size=$(stat -c %s "$f")
      ((total + size > budget)) && break
      cp "$f" "fuzz/corpus/$t/" && total=$((total + size))
    done < <(ls -1Sr "$work/$t/merged"/*)
    echo "$t: corpus of $(ls "fuzz/corpus/$t" | wc -l) files, $total bytes"
  done
fi

if ((failed)); then
  echo "fuzz.sh: findings:" >&2
  find "$work" -path '*/findings/*' -type f >&2
  exit 1
fi
