#!/usr/bin/env bash
# Builds the libFuzzer harnesses (fuzz/) in the clang-14 ASan + UBSan build they share with the
# sanitized test suite (scripts/lib/asan_build.sh; build-asan/ or $LIXEL_FUZZ_BUILD_DIR) and runs
# each for LIXEL_FUZZ_SECONDS (default 20) over its seed corpus fuzz/corpus/<harness>/, as many at
# once as there are cores (LIXEL_JOBS). LIXEL_FUZZ_TOTAL_SECONDS, where set, bounds the whole run:
# each harness then gets at most that over the number of batches (at least 10 s; .ci/run sets it to
# what is left of CI's time). Fails after the batch that had a crash, leak, timeout or
# out-of-memory, leaving the input in <build>/artifacts/.
# A harness with a dictionary fuzz/<harness>.dict runs with it.
# Harnesses to run can be named: scripts/fuzz.sh fuzz_solver. New inputs the fuzzer finds go to
# <build>/corpus/<harness>/, never into the committed seeds.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${LIXEL_FUZZ_BUILD_DIR:-$root/build-asan}
seconds=${LIXEL_FUZZ_SECONDS:-20}
jobs=${LIXEL_JOBS:-$(nproc)}
harnesses=("$@")
if ((${#harnesses[@]} == 0)); then
    harnesses=(fuzz_request_decode fuzz_solver fuzz_mesh_load fuzz_scheduler fuzz_upload
               fuzz_map_decode fuzz_session_decode)
fi
batches=$(((${#harnesses[@]} + jobs - 1) / jobs))
if [[ -n ${LIXEL_FUZZ_TOTAL_SECONDS:-} ]] && ((LIXEL_FUZZ_TOTAL_SECONDS / batches < seconds)); then
    seconds=$((LIXEL_FUZZ_TOTAL_SECONDS / batches > 10 ? LIXEL_FUZZ_TOTAL_SECONDS / batches : 10))
    echo "lixel fuzz: ${LIXEL_FUZZ_TOTAL_SECONDS} s for $batches batches: $seconds s a harness"
fi
source "$root/scripts/lib/asan_build.sh"

"$root/scripts/install_deps.sh"
configure_asan_build "$root" "$build_dir"
cmake --build "$build_dir" --parallel "$jobs" --target "${harnesses[@]}"

mkdir -p "$build_dir/artifacts"

# One harness for the bounded time; its exit status is the fuzzer's.
fuzz_one() {
    local h=$1
    # A dictionary (fuzz/<harness>.dict) lets libFuzzer splice in the tokens that reach the
    # refusal paths (mtllib, uri, \u escapes, data: URIs) instead of guessing them byte by byte.
    local dict=()
    if [[ -f "$root/fuzz/$h.dict" ]]; then dict=(-dict="$root/fuzz/$h.dict"); fi
    # UBSan aborts (halt_on_error) so libFuzzer records the input; leaks are failures too.
    ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 \
    UBSAN_OPTIONS=halt_on_error=1:abort_on_error=1:print_stacktrace=1 \
        "$build_dir/fuzz/$h" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
        -max_len=4096 "${dict[@]}" -print_final_stats=1 -artifact_prefix="$build_dir/artifacts/$h-" \
        "$build_dir/corpus/$h" "$root/fuzz/corpus/$h" >"$build_dir/$h.log" 2>&1
}

# libFuzzer runs on one core: the harnesses run $jobs at a time, each for its full time.
summary=()
failed=()
for ((first = 0; first < ${#harnesses[@]}; first += jobs)); do
    batch=("${harnesses[@]:first:jobs}")
    pids=()
    for h in "${batch[@]}"; do
        mkdir -p "$build_dir/corpus/$h"
        echo "lixel fuzz: $h for ${seconds} s"
        fuzz_one "$h" &
        pids+=($!)
    done
    for i in "${!batch[@]}"; do
        h=${batch[$i]}
        log="$build_dir/$h.log"
        status=0
        wait "${pids[$i]}" || status=$?
        runs=$(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
        secs=$(grep -m1 -o 'Done [0-9]* runs in [0-9]* second' "$log" | awk '{print $5}' || true)
        summary+=("$h: ${runs:-?} inputs in ${secs:-$seconds} s, exit $status")
        if ((status != 0)); then
            tail -n 60 "$log"
            failed+=("$h")
        fi
    done
    if ((${#failed[@]} > 0)); then
        printf '%s\n' "${summary[@]}"
        echo "lixel fuzz: ${failed[*]} failed; the input is in $build_dir/artifacts/ (logs:" \
             "$build_dir/<harness>.log)" >&2
        exit 1
    fi
done
printf '%s\n' "${summary[@]}"
