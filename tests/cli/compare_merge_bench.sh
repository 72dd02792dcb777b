#!/usr/bin/env bash
# `pmcr compare`, `pmcr merge` and `pmcr bench` from the command line: their outputs, and bad
# input getting one line naming the file and the problem, a non-zero exit and no output file.
#   compare_merge_bench.sh PMCR SOURCE_DIR
set -u
pmcr="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
furnace="$src/scenes/furnace.glb"

fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect_error DESCRIPTION PATTERN -- ARGS...: as in bad_input.sh.
expect_error() {
    local what="$1" pattern="$2"
    shift 3
    rm -rf "$tmp/out"
    mkdir -p "$tmp/out"
    "$pmcr" "$@" >"$tmp/stdout" 2>"$tmp/stderr"
    local rc=$?
    local lines
    lines=$(grep -vc '^warning: ' "$tmp/stderr")
    if [ $rc -eq 0 ]; then fail "$what: exit status 0"; return; fi
    if [ "$lines" -ne 1 ] || ! grep -v '^warning: ' "$tmp/stderr" | grep -qE -e "$pattern"; then
        fail "$what: expected one line matching /$pattern/, got:"; cat "$tmp/stderr"; return
    fi
    if [ -n "$(ls -A "$tmp/out")" ]; then fail "$what: left files: $(ls -A "$tmp/out")"; return; fi
    echo "ok   ($what): $(grep -v '^warning: ' "$tmp/stderr")"
}

render() { "$pmcr" render "$furnace" --width 16 --height 16 -q --no-png "$@" || fail "render $*"; }
render --spp 2 --seed 2 -o "$tmp/a.exr"
render --spp 6 --seed 3 -o "$tmp/b.exr"
render --spp 16 --seed 4 -o "$tmp/ref.exr"
render --spp 2 --seed 3 --max-depth 2 -o "$tmp/shallow.exr"
"$pmcr" render "$furnace" --width 8 --height 8 --spp 1 -q --no-png -o "$tmp/small.exr"
cp "$tmp/a.exr" "$tmp/nostats.exr"

# merge: the image, its preview and stats with the samples summed (16 x 16 x (2 + 6)).
"$pmcr" merge "$tmp/a.exr" "$tmp/b.exr" -o "$tmp/m.exr" -q || fail "merge"
for f in m.exr m.png m.json; do [ -s "$tmp/$f" ] || fail "merge wrote no $f"; done
grep -q '"samples": 2048' "$tmp/m.json" || fail "merged stats lack the summed samples"
grep -q '"merged_from"' "$tmp/m.json" || fail "merged stats lack merged_from"

# compare: the JSON keys, the time read from the stats beside the image, an error image.
"$pmcr" compare "$tmp/m.exr" "$tmp/ref.exr" --json >"$tmp/c.json" || fail "compare --json"
for key in mse mse_rgb rmse relmse pmse time eff peff; do
    grep -q "\"$key\":" "$tmp/c.json" || fail "compare --json lacks $key"
done
"$pmcr" compare "$tmp/nostats.exr" "$tmp/ref.exr" --json >"$tmp/c2.json" || fail "compare no stats"
grep -q '"eff"' "$tmp/c2.json" && fail "compare invented a time for an image without stats"
"$pmcr" compare "$tmp/nostats.exr" "$tmp/ref.exr" --time 2 --crop 2,2,4,4 \
    --error-image "$tmp/err.png" >"$tmp/c.txt" || fail "compare --time --crop --error-image"
grep -q '^Eff ' "$tmp/c.txt" || fail "compare --time printed no Eff"
grep -q '4x4 at (2, 2)' "$tmp/c.txt" || fail "compare --crop did not measure the crop"
[ -s "$tmp/err.png" ] || fail "no error image"

# bench: the report, and a method not implemented yet (if any is left) listed as such.
planned=$("$pmcr" render --help | grep 'not implemented yet' | head -n 1 | awk '{print $1}')
"$pmcr" bench "$furnace" --methods "pt,direct${planned:+,$planned}" --time 0.2 \
    --reference "$tmp/ref.exr" --seed 9 --out "$tmp/rep" -q >"$tmp/bench.txt" || fail "bench"
for f in report.html report.md results.json convergence-err.svg convergence-perr.svg \
    reference.png images/pt.png images/pt-error.png images/direct.png; do
    [ -s "$tmp/rep/$f" ] || fail "bench wrote no $f"
done
grep -q '^method | time (s) | samples (spp) |' "$tmp/bench.txt" || fail "bench table header"
if [ -n "$planned" ]; then
    grep -qE "^$planned +\| not implemented yet" "$tmp/bench.txt" || fail "bench row of $planned"
fi
[ -z "$(ls -A "$tmp" | grep tmp-)" ] || fail "temporary files left behind"

for cmd in compare merge bench; do
    "$pmcr" $cmd --help | grep -q "usage: pmcr $cmd" || fail "$cmd --help"
done

mkdir -p "$tmp/foreign" && touch "$tmp/foreign/notes.txt"
expect_error "compare sizes" "small\.exr.*ref\.exr|ref\.exr.*small\.exr" -- compare "$tmp/small.exr" "$tmp/ref.exr"
expect_error "compare missing" "no-such\.exr" -- compare "$tmp/no-such.exr" "$tmp/ref.exr" --error-image "$tmp/out/e.png"
expect_error "compare crop" "crop 10,10,8,8" -- compare "$tmp/a.exr" "$tmp/ref.exr" --crop 10,10,8,8 --error-image "$tmp/out/e.png"
expect_error "compare one file" "REFERENCE" -- compare "$tmp/a.exr"
expect_error "merge same seed" "seed 2" -- merge "$tmp/a.exr" "$tmp/a.exr" -o "$tmp/out/x.exr"
expect_error "merge settings" "shallow\.exr.*max_depth" -- merge "$tmp/a.exr" "$tmp/shallow.exr" -o "$tmp/out/x.exr"
expect_error "merge no stats" "nostats\.json" -- merge "$tmp/b.exr" "$tmp/nostats.exr" -o "$tmp/out/x.exr"
expect_error "merge no output" "-o" -- merge "$tmp/a.exr" "$tmp/b.exr"
expect_error "bench unknown method" "no-such-method" -- bench "$furnace" --methods pt,no-such-method --time 1 --reference "$tmp/ref.exr" --out "$tmp/out/r"
expect_error "bench reference seed" "ref\.exr.*seed 4" -- bench "$furnace" --methods pt --time 1 --reference "$tmp/ref.exr" --seed 4 --out "$tmp/out/r"
expect_error "bench reference size" "ref\.exr.*16x16" -- bench "$furnace" --methods pt --time 1 --reference "$tmp/ref.exr" --width 32 --height 32 --out "$tmp/out/r"
expect_error "bench no budget" "budget" -- bench "$furnace" --methods pt --reference "$tmp/ref.exr" --out "$tmp/out/r"
expect_error "bench foreign dir" "foreign" -- bench "$furnace" --methods pt --time 1 --reference "$tmp/ref.exr" --out "$tmp/foreign"
[ -f "$tmp/foreign/notes.txt" ] || fail "bench touched a foreign directory"

[ $failures -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo ok
