#!/usr/bin/env bash
# A render writes the EXR, the PNG and the stats JSON, with the documented fields, and an
# interrupted render (SIGINT) still writes the image so far and exits with status 130.
#   render_outputs.sh PMCR SOURCE_DIR
set -eu
pmcr="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

"$pmcr" render "$src/scenes/furnace.glb" --spp 2 -q --validate -o "$tmp/f.exr"
for f in f.exr f.png f.json; do [ -s "$tmp/$f" ] || { echo "missing $f"; exit 1; }; done
for key in method device width height samples spp render_seconds gpu_kernels rays nan_samples_dropped seed; do
    grep -q "\"$key\"" "$tmp/f.json" || { echo "stats JSON lacks $key"; exit 1; }
done
[ -z "$(ls -A "$tmp" | grep tmp-)" ] || { echo "temporary files left behind"; exit 1; }

# --paper-size takes the size the scene's paper used from the file.
"$pmcr" render "$src/scenes/cornell-glass.glb" --paper-size --spp 1 -q -o "$tmp/paper.exr" --no-png
grep -q '"width": 640' "$tmp/paper.json" && grep -q '"height": 480' "$tmp/paper.json" ||
    { echo "--paper-size did not render 640x480"; exit 1; }

# Same seed, same image, bit for bit.
"$pmcr" render "$src/scenes/furnace.glb" --spp 2 -q -o "$tmp/g.exr" --no-png
cmp "$tmp/f.exr" "$tmp/g.exr" || { echo "same seed gave a different image"; exit 1; }

# Interrupt a long render: the image so far is written, exit status 130.
"$pmcr" render "$src/scenes/cornell-spheres.glb" --time 600 -q -o "$tmp/long.exr" --no-png &
pid=$!
sleep 4
kill -INT $pid
set +e
wait $pid
rc=$?
set -e
[ $rc -eq 130 ] || { echo "interrupted render exited with $rc, expected 130"; exit 1; }
[ -s "$tmp/long.exr" ] && [ -s "$tmp/long.json" ] || { echo "interrupted render wrote no image"; exit 1; }
grep -q '"interrupted": true' "$tmp/long.json" || { echo "stats do not record the interruption"; exit 1; }
echo ok
