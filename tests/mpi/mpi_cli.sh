#!/usr/bin/env bash
# `mpirun -n 2 pmcr render` as a user runs it (issue 25): one image whose stats JSON says
# "ranks": 2 and sums the ranks' samples; Ctrl-C still leaves a complete image; a rank that fails
# ends the job with one line naming it and writes nothing; bad input is reported once.
#   mpi_cli.sh PMCR SOURCE_DIR MPIEXEC
set -eu
pmcr="$1"
src="$2"
mpirun=("$3" --allow-run-as-root --oversubscribe)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scene="$src/scenes/cornell-glass.glb"
json() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"; }

# The issue's command: 16 spp in total over two ranks, one image, the stats summed.
"${mpirun[@]}" -n 2 "$pmcr" render "$scene" --spp 16 --validate -q -o "$tmp/x.exr"
for f in x.exr x.png x.json; do [ -s "$tmp/$f" ] || { echo "missing $f"; exit 1; }; done
[ "$(json "$tmp/x.json" 'j["ranks"]')" = 2 ] || { echo "stats lack \"ranks\": 2"; exit 1; }
[ "$(json "$tmp/x.json" 'j["spp"]')" = 16.0 ] || { echo "not 16 spp in total"; exit 1; }
[ "$(json "$tmp/x.json" 'j["samples"] == sum(r["samples"] for r in j["rank_stats"]) and j["rays"] == sum(r["rays"] for r in j["rank_stats"])')" = True ] ||
    { echo "samples or rays are not the sum of the ranks'"; exit 1; }
[ "$(json "$tmp/x.json" 'sorted(r["spp"] for r in j["rank_stats"]) == [8.0, 8.0] and len({r["seed"] for r in j["rank_stats"]}) == 2')" = True ] ||
    { echo "the ranks did not each render 8 spp with their own seed"; exit 1; }
[ -z "$(ls -A "$tmp" | grep tmp-)" ] || { echo "temporary files left behind"; exit 1; }

# Ctrl-C: SIGINT to mpirun stops every rank; rank 0 writes the image so far. (Open MPI sends
# the ranks SIGTERM odls_base_sigkill_timeout seconds after Ctrl-C and SIGKILL as long again
# later, 1 s by default; 3 s here so that a loaded CI machine finishes its batch: docs/mpi.md.)
"${mpirun[@]}" --mca odls_base_sigkill_timeout 3 -n 2 "$pmcr" render "$scene" --method pmc-ip --time 600 -q \
    --width 64 --height 48 -o "$tmp/long.exr" --no-png &
pid=$!
sleep 6
kill -INT $pid
set +e
wait $pid
set -e
[ -s "$tmp/long.exr" ] && [ -s "$tmp/long.json" ] || { echo "interrupted render wrote no image"; exit 1; }
[ "$(json "$tmp/long.json" 'j["interrupted"] and j["ranks"] == 2 and all(r["samples"] > 0 for r in j["rank_stats"])')" = True ] ||
    { echo "interrupted render: stats do not show two ranks' samples and the interruption"; exit 1; }

# A rank that fails (rank 1 asks for a device that does not exist): one line naming the rank
# and the cause, a non-zero status, no output.
set +e
"${mpirun[@]}" -n 1 "$pmcr" render "$scene" --spp 4 -q -o "$tmp/bad.exr" : \
    -n 1 "$pmcr" render "$scene" --spp 4 -q -o "$tmp/bad.exr" --device 99 2>"$tmp/err"
rc=$?
set -e
[ $rc -ne 0 ] || { echo "a failing rank exited 0"; exit 1; }
[ "$(grep -c '^pmcr: error' "$tmp/err")" = 1 ] && grep -q '^pmcr: error: rank 1: --device 99' "$tmp/err" ||
    { echo "failing rank: expected one 'pmcr: error: rank 1: --device 99' line:"; cat "$tmp/err"; exit 1; }
[ -z "$(ls "$tmp" | grep '^bad')" ] || { echo "failing rank left output"; exit 1; }

# Bad input: reported once, by rank 0, before anything renders.
for args in "$src/scenes/missing.glb --spp 4" "$scene --spp 4 --no-such-option" "$scene --spp 1"; do
    set +e
    # shellcheck disable=SC2086
    "${mpirun[@]}" -n 2 "$pmcr" render $args -q -o "$tmp/bad.exr" 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -ne 0 ] || { echo "bad input ($args) exited 0"; exit 1; }
    [ "$(grep -c '^pmcr: error' "$tmp/err")" = 1 ] || { echo "bad input ($args) not reported once:"; cat "$tmp/err"; exit 1; }
    [ -z "$(ls "$tmp" | grep '^bad')" ] || { echo "bad input ($args) left output"; exit 1; }
done
echo ok
