#!/usr/bin/env bash
# Every field of the seeded plans of tools/plan_dump, this working tree against a revision
# (default HEAD), bit for bit: the check a change that must not move a plan passes (a refactor of
# the scheduler, an index over the objects). Builds the dump here (build/) and, in a worktree of
# the revision, the solver and scene libraries it links, then compiles this tree's dump against
# them; a revision whose plan fields differ from this tree's will not compile, and says so.
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

echo "compare_plans: this tree" >&2
cmake --build "$root/build" --target lixel_plan_dump --parallel "$(nproc)" > "$work/build.log" 2>&1 ||
    { tail -40 "$work/build.log" >&2; exit 1; }
"$root/build/tools/plan_dump/lixel_plan_dump" "$rounds" > "$work/new.txt"

echo "compare_plans: $rev" >&2
git -C "$root" worktree add --detach "$work/old" "$rev" >/dev/null
cmake -S "$work/old" -B "$work/old/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DLIXEL_BUILD_TESTS=OFF -DLIXEL_BUILD_BENCH=OFF -DLIXEL_BUILD_EXAMPLES=OFF >/dev/null
cmake --build "$work/old/build" --target lixel_solver lixel_scene --parallel "$(nproc)" \
    > "$work/old_build.log" 2>&1 || { tail -40 "$work/old_build.log" >&2; exit 1; }
c++ -std=c++20 -O2 -I "$work/old/solver/include" -I "$work/old/server/scene/include" \
    -I /usr/include/eigen3 "$root/tools/plan_dump/plan_dump.cc" \
    "$work/old/build/server/scene/liblixel_scene.a" "$work/old/build/solver/liblixel_solver.a" \
    -o "$work/old_dump" || { echo "compare_plans: the dump does not build against $rev" >&2; exit 1; }
"$work/old_dump" "$rounds" > "$work/old.txt"

plans=$(grep -c '^== ' "$work/new.txt")
if cmp -s "$work/old.txt" "$work/new.txt"; then
    echo "compare_plans: $plans plans, every field the same as at $rev ($(md5sum < "$work/new.txt" | cut -c1-32))"
else
    echo "compare_plans: plans differ from $rev (first differences below)" >&2
    diff "$work/old.txt" "$work/new.txt" | head -40 >&2
    exit 1
fi
