#!/usr/bin/env bash
# `pmcr --help`, `--version`, `--list-devices`, `--device` and `render --stats` (issue 2):
# help and version exit 0, the device list names a usable device that `--device` accepts by
# index and by name, `--stats` prints the per-kernel GPU time, and `render --help` marks the
# biased options.
#   help_devices_stats.sh PMCR SOURCE_DIR
set -eu
pmcr="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$pmcr" --help >"$tmp/help" || fail "pmcr --help exited with $?"
grep -q "pmcr render SCENE" "$tmp/help" || fail "pmcr --help does not show the render usage"
"$pmcr" --version >"$tmp/version" || fail "pmcr --version exited with $?"
grep -qE '^pmcr [0-9]+\.[0-9]+' "$tmp/version" || fail "pmcr --version printed: $(cat "$tmp/version")"

"$pmcr" render --help >"$tmp/render-help" || fail "pmcr render --help exited with $?"
for opt in --spp --time --device --stats --method; do
    grep -q -- "$opt" "$tmp/render-help" || fail "render --help lacks $opt"
done
# ERPT's noise filters are biased and must say so.
grep -E -- '--filter-(proposals|consecutive)' "$tmp/render-help" | grep -q BIASED ||
    fail "render --help does not mark ERPT's filters as biased"
[ "$(grep -cE -- '--filter-(proposals|consecutive).*\[BIASED\]' "$tmp/render-help")" -eq 2 ] ||
    fail "both ERPT filters must be marked [BIASED]"
# The papers' baselines are labelled as such wherever a method lists them (docs/paper-baselines.md).
for opt in pixel-sampler mis; do
    listed=$(grep -cE -- "^ +--$opt " "$tmp/render-help")
    labelled=$(grep -cE -- "^ +--$opt .*\[PAPER BASELINE [a-z]+: " "$tmp/render-help")
    [ "$listed" -gt 0 ] && [ "$listed" -eq "$labelled" ] ||
        fail "--$opt: listed $listed times, labelled [PAPER BASELINE] $labelled times"
done

"$pmcr" --list-devices >"$tmp/devices" || fail "pmcr --list-devices exited with $?"
line=$(grep -m1 -- '- usable$' "$tmp/devices") || fail "no usable device listed: $(cat "$tmp/devices")"
index=${line%%:*}
name=$(echo "$line" | sed 's/^[0-9]*: \([^ (]*\).*/\1/')

# --device by index and by name substring; the chosen device is printed.
"$pmcr" render "$src/scenes/furnace.glb" --spp 1 --width 16 --height 16 --device "$index" \
    --no-png -o "$tmp/a.exr" 2>"$tmp/a.err" >/dev/null || fail "--device $index failed: $(cat "$tmp/a.err")"
grep -q "^device: " "$tmp/a.err" || fail "the chosen device is not printed"
"$pmcr" render "$src/scenes/furnace.glb" --spp 1 --width 16 --height 16 --device "$name" -q \
    --no-png -o "$tmp/b.exr" || fail "--device $name failed"

# --stats: timings, rays and one line per kernel with its GPU time.
"$pmcr" render "$src/scenes/furnace.glb" --spp 2 --width 16 --height 16 -q --stats \
    --no-png -o "$tmp/s.exr" >"$tmp/stats" || fail "--stats render failed"
for key in "render time" "rays traced" "NaN/Inf dropped" "GPU time"; do
    grep -q "^$key" "$tmp/stats" || fail "--stats lacks '$key': $(cat "$tmp/stats")"
done
grep -qE '^  methods/pt/pt +[0-9.]+ ms +[0-9]+ dispatches' "$tmp/stats" ||
    fail "--stats lacks the pt kernel's GPU time: $(cat "$tmp/stats")"
# ERPT's --stats add its own figures: chains, proposals and acceptance per mutation type.
"$pmcr" render "$src/scenes/cornell-glass.glb" --method erpt --spp 1 --chain-length 4 \
    --width 16 --height 16 -q --stats --no-png -o "$tmp/e.exr" >"$tmp/erpt-stats" || fail "erpt --stats render failed"
for key in chains_started lens_proposed lens_acceptance caustic_proposed caustic_acceptance \
           invalid_proposals deposits_dropped energy_not_deposited deposited_vs_seed_energy; do
    grep -qE "^  $key +[0-9.e+-]+$" "$tmp/erpt-stats" || fail "erpt --stats lacks $key: $(cat "$tmp/erpt-stats")"
done
grep -qE '^  methods/erpt/erpt_chains +[0-9.]+ ms' "$tmp/erpt-stats" || fail "erpt --stats lacks the chain kernel's GPU time"
# PSSMLT's: mutations proposed and accepted, acceptance per step type, the bootstrap's b_hat.
"$pmcr" render "$src/scenes/cornell-glass.glb" --method pssmlt --spp 1 \
    --width 16 --height 16 -q --stats --no-png -o "$tmp/p.exr" >"$tmp/pssmlt-stats" || fail "pssmlt --stats render failed"
for key in passes bootstrap_samples normalization chains mutations acceptance large_step_proposed \
           large_step_acceptance small_step_proposed small_step_acceptance deposit_energy; do
    grep -qE "^  $key +[0-9.e+-]+$" "$tmp/pssmlt-stats" || fail "pssmlt --stats lacks $key: $(cat "$tmp/pssmlt-stats")"
done
grep -qE '^  methods/pssmlt/pssmlt_bdpt_connect +[0-9.]+ ms' "$tmp/pssmlt-stats" || fail "pssmlt --stats lacks the connect kernel's GPU time"
# MLT's: proposals and acceptance per mutation type, b_hat.
"$pmcr" render "$src/scenes/cornell-glass.glb" --method mlt --spp 1 \
    --width 16 --height 16 -q --stats --no-png -o "$tmp/m.exr" >"$tmp/mlt-stats" || fail "mlt --stats render failed"
for key in passes bootstrap_samples normalization chains mutations_per_pixel acceptance lens_proposed \
           lens_acceptance caustic_proposed caustic_acceptance large_step_proposed large_step_acceptance deposit_energy; do
    grep -qE "^  $key +[0-9.e+-]+$" "$tmp/mlt-stats" || fail "mlt --stats lacks $key: $(cat "$tmp/mlt-stats")"
done
grep -qE '^  methods/mlt/mlt_chains +[0-9.]+ ms' "$tmp/mlt-stats" || fail "mlt --stats lacks the chain kernel's GPU time"
echo ok
