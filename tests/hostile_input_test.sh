#!/usr/bin/env bash
# Hostile input, second round (issue 30): each reproduction the issue lists, as a careless or
# hostile user would type it. Every command runs under a time limit (a hang is a failure,
# exit 124) and must answer one line naming the flag or file, exit 2 for flags or 1 for
# files, never crash (134, 139) and never change an input. The cases the command line
# cannot reach (FIFO reference sidecars, symlinked results.csv, another subject's resume,
# resumed rows, a .fovset declaring a huge canvas) are in fovbench_tests, fovstair_tests
# and distgen_tests.
set -uo pipefail
fovrender=$1 fovgen=$2 fovbench=$3 fovstair=$4 source_dir=$5
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
source "$(dirname "$0")/cli_check.sh"
limited() { timeout 60 "$@"; }  # a hang fails as exit 124
unchanged() {  # unchanged FILE SUM: the file's bytes are what they were
  [[ "$(sha256sum < "$1")" == "$2" ]] || fail "$1 was changed"
}

python3 "$source_dir/tests/hostile_inputs.py" "$dir"
mkfifo "$dir/fifo.bin" "$dir/fifo.json"
"$fovgen" --width 64 --height 72 --k 8 --saturation 500 -o "$dir/set.fovset" >/dev/null
R=(limited "$fovrender" --points "$dir/set.fovset" --spp 1)

tool=fovrender
# Crashes: coordinates beyond Embree's range, degenerate files.
check "eye 1e20"              2 -- "${R[@]}" --eye 1e20,0,0 -o "$dir/x.png"
check "reference eye 1e20"    2 -- limited "$fovrender" --reference --width 64 --height 72 --spp 1 --eye 1e20,0,0 -o "$dir/x.png"
check "eye overflows"         2 -- "${R[@]}" --eye 3e38,0,0 --look-at -3e38,0,0 -o "$dir/x.png"
err=$("${R[@]}" --eye 3e38,0,0 --look-at -3e38,0,0 -o "$dir/x.png" 2>&1)
[[ "$err" == *"--eye: a coordinate beyond"* ]] || fail "--eye 3e38 said: $err"
check "scene fine"            0 -- "${R[@]}" --scene "$dir/ok.gltf" -o "$dir/ok.png"
for bad in deep-nodes deep-json inf-vertex huge-vertex tiny-scale fifo-buffer empty-buffer sparse-huge long-buffer infinite-light; do
  check "scene $bad"          1 -- "${R[@]}" --scene "$dir/$bad.gltf" -o "$dir/x.png"
  err=$("${R[@]}" --scene "$dir/$bad.gltf" -o "$dir/x.png" 2>&1)
  [[ "$err" == "fovrender: $dir/$bad.gltf: "* ]] || fail "$bad: the message does not begin with the scene: $err"
done
check "glb chunk past the end" 1 -- "${R[@]}" --scene "$dir/chunk-past-end.glb" -o "$dir/x.png"
[[ "$("${R[@]}" --scene "$dir/chunk-past-end.glb" -o "$dir/x.png" 2>&1)" == \
  "fovrender: $dir/chunk-past-end.glb: its JSON chunk claims 3808429344 bytes, more than the 49-byte file holds (refused)" ]] \
  || fail "a glb chunk past the end is not refused with its length"
[[ "$("${R[@]}" --scene "$dir/sparse-huge.gltf" -o "$dir/x.png" 2>&1)" == \
  *": accessor 2: sparse accessors are not supported (refused: Assimp writes where their indices point without a check)" ]] \
  || fail "a 3.4 GB sparse accessor is not refused naming the accessor"
[[ "$("${R[@]}" --scene "$dir/long-buffer.gltf" -o "$dir/x.png" 2>&1)" == *"buffer 0: claims 2000000000 bytes, more than the "*" bytes of "*"tex.png (refused)" ]] \
  || fail "a buffer longer than its file is not refused with both lengths"
[[ "$("${R[@]}" --scene "$dir/infinite-light.gltf" -o "$dir/x.png" 2>&1)" == *"infinite-light.gltf: light '"*"': a colour, intensity"* ]] \
  || fail "a light of infinite intensity is not refused naming the light"
[[ "$("${R[@]}" --scene "$dir/fifo-buffer.gltf" -o "$dir/x.png" 2>&1)" == *"fifo.bin: not a regular file"* ]] \
  || fail "a FIFO buffer is not named"
[[ "$("${R[@]}" --scene "$dir/empty-buffer.gltf" -o "$dir/x.png" 2>&1)" == *"empty.bin: is empty"* ]] \
  || fail "an empty buffer is not named"
# Inputs overwritten: an output naming a file the scene reads.
sum=$(sha256sum < "$dir/tex.png")
check "-o the scene's texture" 2 -- "${R[@]}" --scene "$dir/textured.gltf" -o "$dir/tex.png"
unchanged "$dir/tex.png" "$sum"
check "-o an unknown format"  2 -- "${R[@]}" -o "$dir/x.xyz"
check "-o twice"              2 -- "${R[@]}" -o "$dir/a.png" -o "$dir/a.png"
check "--width with --points" 2 -- "${R[@]}" --width 100 -o "$dir/x.png"
# env: images with negative and huge texels: read as documented, and said once.
err=$("${R[@]}" --scene "env:$dir/negative-sky.exr" -o "$dir/sky.png" 2>&1 >/dev/null)
[[ "$err" == *"1 texel values are negative; read as 0"* && "$err" == *"exceed 65504"* ]] || fail "env: texels not reported: $err"

tool=fovbench
B=(limited "$fovbench" --display 64x72 --scales 1.0 --methods nn --spp 1 --reference-spp 2 --baselines full --gazes centre)
check "fovbench eye 1e20"     2 -- "${B[@]}" --eye 1e20,0,0 -o "$dir/bench1"
mkdir -p "$dir/bench2" && touch "$dir/bench2/references"
check "-o with references a file" 2 -- "${B[@]}" -o "$dir/bench2"
for image in grey nan huge; do cp "$dir/$image.exr" "$dir/copy-$image.exr"; done
sum=$(sha256sum < "$dir/grey.exr")
check "compare --flip-map TEST" 2 -- limited "$fovbench" compare "$dir/grey.exr" "$dir/copy-grey.exr" --flip-map "$dir/grey.exr"
check "compare --foveated-flip-map REF" 2 -- limited "$fovbench" compare "$dir/grey.exr" "$dir/copy-grey.exr" --foveated-flip-map "$dir/copy-grey.exr"
unchanged "$dir/grey.exr" "$sum"
check "compare NaN image"     1 -- limited "$fovbench" compare "$dir/nan.exr" "$dir/grey.exr"
check "compare 3e38 pixel"    1 -- limited "$fovbench" compare "$dir/grey.exr" "$dir/huge.exr"
check "compare negative pixel" 1 -- limited "$fovbench" compare "$dir/negative.exr" "$dir/grey.exr"
err=$(limited "$fovbench" compare "$dir/negative.exr" "$dir/grey.exr" 2>&1)
[[ "$err" == *"negative.exr: 1 pixel is NaN, infinite, negative or above 65504 (first at x = 0, y = 0)"* ]] || fail "compare said: $err"
check "compare v 1e-300"      2 -- limited "$fovbench" compare "$dir/grey.exr" "$dir/copy-grey.exr" --viewing-distance 1e-300

tool=fovstair
protocol="$source_dir/apps/fovstair/protocols/thesis.json"
observer=logistic:threshold=1.7,slope=8
check "run --protocol FIFO"   1 -- limited "$fovstair" run --protocol "$dir/fifo.json" --subject S1 --observer "$observer" --out "$dir/s1"
check "run --protocol /dev/zero" 1 -- limited "$fovstair" run --protocol /dev/zero --subject S1 --observer "$observer" --out "$dir/s1"
head -c $((2 << 20)) /dev/zero | tr '\0' ' ' > "$dir/big.json"
check "run a 2 MiB protocol"  1 -- limited "$fovstair" run --protocol "$dir/big.json" --subject S1 --observer "$observer" --out "$dir/s1"
[[ -e "$dir/s1" ]] && fail "a run that could not start left --out behind"
mkdir -p "$dir/data" && touch "$dir/data/S1-99999999999999999999.jsonl"
check "a stray session name"  0 -- limited "$fovstair" run --protocol "$protocol" --subject S1 --observer "$observer" --out "$dir/data"
session="$dir/data/S1-1.jsonl"
sum=$(sha256sum < "$session")
check "analyze --out-csv its input" 2 -- limited "$fovstair" analyze "$session" --out-csv "$session"
unchanged "$session" "$sum"
touch "$dir/plots-file"
check "analyze --plots a file" 2 -- limited "$fovstair" analyze "$session" --plots "$dir/plots-file"
truncate -s 2G "$dir/sparse.csv"
check "thresholds 2 GB"       1 -- limited "$fovstair" analyze --thresholds "$dir/sparse.csv"
{ echo subject,condition,threshold; for c in $(seq 1 2000); do echo "S1,c$c,1.5"; done; } > "$dir/many.csv"
check "thresholds 2000 conditions" 1 -- limited "$fovstair" analyze --thresholds "$dir/many.csv"
check "simulate unreachable threshold" 2 -- limited "$fovstair" simulate --protocol "$protocol" --observer logistic:threshold=20,slope=8 --runs 5
check "simulate --step nan"   2 -- limited "$fovstair" simulate --protocol "$protocol" --observer "$observer" --runs 5 --step nan

tool=fovgen
err=$("$fovgen" sweep --width 64 --height 72 --k 4 --saturation 200 --scales 1.0:1.0:0.1 -o "$dir/sweep" 2>&1 >/dev/null)
[[ "$err" == *"["* ]] && fail "fovgen sweep drew a progress bar on a non-terminal: $err"
[[ "$err" == *"fovgen: 1/1"* ]] || fail "fovgen sweep said no progress line: $err"

ls "$dir" | grep -q 'tmp-' && fail "temporary files left: $(ls "$dir")"
echo "hostile input: $passes passed, $failures failed"
[[ $failures -eq 0 ]]
