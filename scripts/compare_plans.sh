#!/usr/bin/env bash
# Every field of the seeded plans of tools/plan_dump, this working tree against a revision
# (default HEAD), bit for bit: the check a change that must not move a plan passes (a refactor of
# the scheduler, an index over the objects). Builds the solver and scene libraries here (build/,
# configured by scripts/build.sh) and in a worktree of the revision, and compiles this tree's
# dump the same way against each; a revision whose plan fields differ from this tree's will not
# compile, and says so.
#   scripts/compare_plans.sh [REV] [--rounds=N]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rev=HEAD
rounds=--rounds=200
for arg in "$@"; do
    case "$arg" in
        --rounds=*) rounds=$arg ;;
        -*) echo "usage: scripts/compare_plans.sh [REV] [--rounds=N]" >&2; exit 2 ;;
        *) rev=$arg ;;
    esac
done
work=$(mktemp -d /tmp/lixel_compare_plans.XXXXXX)
trap 'git -C "$root" worktree remove --force "$work/old" >/dev/null 2>&1 || true; rm -rf "$work"' EXIT

# Both dumps are compiled the same way, each against its own tree's solver and scene libraries
# (built by CMake, Release), so only the libraries differ.
dump_of() {  # dump_of SOURCE_ROOT BUILD_DIR OUTPUT
    cmake --build "$2" --target lixel_solver lixel_scene --parallel "$(nproc)" \
        > "$work/build.log" 2>&1 || { tail -40 "$work/build.log" >&2; return 1; }
    c++ -std=gnu++20 -O2 -I "$1/solver/include" -I "$1/server/scene/include" \
        -I /usr/include/eigen3 "$root/tools/plan_dump/plan_dump.cc" \
        "$2/server/scene/liblixel_scene.a" "$2/solver/liblixel_solver.a" -o "$work/dump" \
        > "$work/build.log" 2>&1 || { tail -20 "$work/build.log" >&2; return 1; }
    "$work/dump" "$rounds" > "$3"
}

echo "compare_plans: this tree" >&2
if [[ ! -f "$root/build/build.ninja" ]]; then
    cmake -S "$root" -B "$root/build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
dump_of "$root" "$root/build" "$work/new.txt"

echo "compare_plans: $rev" >&2
git -C "$root" worktree add --detach "$work/old" "$rev" >/dev/null
cmake -S "$work/old" -B "$work/old/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DLIXEL_BUILD_TESTS=OFF -DLIXEL_BUILD_BENCH=OFF -DLIXEL_BUILD_EXAMPLES=OFF >/dev/null
dump_of "$work/old" "$work/old/build" "$work/old.txt" ||
    { echo "compare_plans: the dump does not build or link against $rev (its plan fields or" \
           "libraries differ from this tree's)" >&2; exit 1; }

plans=$(grep -c '^== ' "$work/new.txt" || true)
if cmp -s "$work/old.txt" "$work/new.txt"; then
    echo "compare_plans: $plans plans, every field the same as at $rev ($(md5sum < "$work/new.txt" | cut -c1-32))"
else
    echo "compare_plans: plans differ from $rev (first differences below)" >&2
    diff "$work/old.txt" "$work/new.txt" | head -40 >&2
    exit 1
fi
