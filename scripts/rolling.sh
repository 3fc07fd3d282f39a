#!/usr/bin/env bash
# Rolling display time (issue 28; docs/reuse.md "Rolling display time"): the built-in scene on a
# display (default fove) seen from a head turning right about its eye at each speed given
# (SPEEDS, degrees a second, default "100 300"), shown by a display that scans its lines in
# ORDERS (default "top-down left-right") over PERIOD ms (default 14.3: the FOVE 0's 70 Hz).
# The truth is the rolling frame at full resolution with TRUTH_SPP Sobol rays a pixel (default
# 256): each line traced from the camera when it is shown. Its noise floor is a second truth
# with another seed. Against it: full resolution and a foveated set (s = 1.0, Shepard k = 5)
# at SPP rays (default 4), each rendered three ways: global at the scanout's start (what a
# renderer without rolling time shows), global at its middle (the best single instant), and
# rolling. fovrender --compare gives JOD (FovVideoVDP's image model, the gaze at the centre),
# FLIP and PSNR, and from each FLIP map the mean FLIP of the first and the last quarter of
# the lines shown. Results in out/rolling/DISPLAY: the frames' JSON, FLIP maps and summary.md.
set -euo pipefail
cd "$(dirname "$0")/.."
render=${FOV_RENDER:-build/apps/fovrender}
fovgen=${FOV_GEN:-build/apps/fovgen}
display=${1:-fove}
read -r -a speeds <<< "${SPEEDS:-100 300}"
read -r -a orders <<< "${ORDERS:-top-down left-right}"
period=${PERIOD:-14.3}
truth_spp=${TRUTH_SPP:-256}
spp=${SPP:-4}
out=out/rolling/$display
mkdir -p "$out"
hfov=$("$fovgen" displays --display "$display" --json | python3 -c 'import json, sys; print("%.4f" % json.load(sys.stdin)[0]["fov_deg"][0])')
set_file=out/rolling/$display-s1.0.fovset
[[ -s $set_file ]] || "$fovgen" --display "$display" --scale 1.0 -o "$set_file" > /dev/null
scene=(--scene builtin --sun-irradiance 0.8,0.77,0.7 --hfov "$hfov")
for speed in "${speeds[@]}"; do
  # The built-in scene's camera (eye 0,1.6,4 looking at 0,0.6,-10) turning right at `speed`
  # degrees a second about its eye, keyed every millisecond for 40 ms.
  path=$out/turn-$speed.csv
  python3 - "$speed" > "$path" <<'PY'
import math, sys
speed = float(sys.argv[1])
eye = (0.0, 1.6, 4.0)
ahead = (0.0, -1.0, -14.0)
n = math.sqrt(sum(a * a for a in ahead))
ahead = tuple(a / n for a in ahead)
right = (1.0, 0.0, 0.0)  # ahead x up, normalised: the view's right
print("t_ms,x,y,z,tx,ty,tz")
for t in range(41):
    a = math.radians(speed * t / 1000)
    target = [eye[i] + math.cos(a) * ahead[i] + math.sin(a) * right[i] for i in range(3)]
    print("%d,%g,%g,%g,%.9f,%.9f,%.9f" % (t, *eye, *target))
PY
  for order in "${orders[@]}"; do
    tag=$speed-$order
    roll=(--camera "$path" --camera-time 0 --frame-period "$period")
    truth=$out/truth-$tag.exr
    [[ -s $truth ]] || "$render" "${scene[@]}" --reference --display "$display" --spp "$truth_spp" "${roll[@]}" \
      --rolling "$order" -o "$truth" > /dev/null
    [[ -s $out/floor-$tag.json ]] || "$render" "${scene[@]}" --reference --display "$display" --spp "$truth_spp" \
      --seed 2 "${roll[@]}" --rolling "$order" --compare "$truth" --json > "$out/floor-$tag.json"
    mid=$(python3 -c "print($period / 2)")
    for frame in full foveated; do
      if [[ $frame == full ]]; then what=(--reference --display "$display"); else what=(--points "$set_file" --device cpp); fi
      for timing in start middle rolling; do
        case $timing in
          start) when=(--camera "$path" --camera-time 0) ;;
          middle) when=(--camera "$path" --camera-time "$mid") ;;
          rolling) when=("${roll[@]}" --rolling "$order") ;;
        esac
        json=$out/$frame-$timing-$tag.json
        [[ -s $json ]] || "$render" "${scene[@]}" "${what[@]}" --spp "$spp" "${when[@]}" --compare "$truth" --json \
          --flip-map "$out/$frame-$timing-$tag-flip.png" > "$json"
      done
    done
  done
done
python3 - "$out" "$period" "$truth_spp" "$spp" <<'PY' > "$out/summary.md"
import glob, json, os, struct, sys, zlib
out, period, truth_spp, spp = sys.argv[1:]

def png_grey(path):  # an 8-bit RGB(A) or grey PNG's first channel, rows of bytes
    data = open(path, "rb").read()
    pos, idat, width, height, channels = 8, b"", 0, 0, 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8, path
            channels = {0: 1, 2: 3, 4: 2, 6: 4}[colour]
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride, rows, prev = zlib.decompress(idat), width * channels, [], bytearray(width * channels)
    for y in range(height):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = prev[i], prev[i - channels] if i >= channels else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line[::channels])
        prev = line
    return rows

def quarters(path, order):  # mean FLIP of the first and the last quarter of the lines shown
    rows = png_grey(path)
    h, w = len(rows), len(rows[0])
    if order in ("top-down", "bottom-up"):
        lines = [sum(r) / w for r in rows]
    else:
        lines = [sum(r[x] for r in rows) / h for x in range(w)]
    if order in ("bottom-up", "right-left"):
        lines.reverse()
    q = len(lines) // 4
    return sum(lines[:q]) / q / 255, sum(lines[-q:]) / q / 255

print(f"Scanout {period} ms; truth {truth_spp} spp (its floor: a second seed against it); frames {spp} spp; "
      "JOD / mean FLIP / PSNR against the truth; FLIP first -> last: the mean FLIP of the first and the last "
      "quarter of the lines shown.\n")
print("| turn (deg/s) | order | truth floor JOD / FLIP | frame | instant | JOD | mean FLIP | PSNR (dB) | FLIP first -> last quarter |")
print("|---|---|---|---|---|---|---|---|---|")
tags = sorted({os.path.basename(p)[len("floor-"):-len(".json")] for p in glob.glob(out + "/floor-*.json")},
              key=lambda t: (float(t.split("-", 1)[0]), t))
for tag in tags:
    speed, order = tag.split("-", 1)
    floor = json.load(open(f"{out}/floor-{tag}.json"))["metrics"]
    for frame in ("full", "foveated"):
        for when in ("start", "middle", "rolling"):
            m = json.load(open(f"{out}/{frame}-{when}-{tag}.json"))["metrics"]
            first, last = quarters(f"{out}/{frame}-{when}-{tag}-flip.png", order)
            print(f"| {speed} | {order} | {floor['jod']:.2f} / {floor['flip']:.4f} | {frame} | {when} | {m['jod']:.2f} | "
                  f"{m['flip']:.4f} | {m['psnr']:.1f} | {first:.4f} -> {last:.4f} |")
PY
cat "$out/summary.md"
