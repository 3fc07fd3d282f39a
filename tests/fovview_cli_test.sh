#!/usr/bin/env bash
# fovview: bad input gives one line and a non-zero exit; the frame loop runs headless under
# Xvfb with a replayed gaze trace, and its screenshot is foveated where the gaze was.
set -uo pipefail
fovview=$1
fovgen=$2
fovrender=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
tool=fovview
source "$(dirname "$0")/cli_check.sh"
export XDG_RUNTIME_DIR=$dir

"$fovgen" --width 256 --height 288 --k 8 -o "$dir/set.fovset" >/dev/null
printf 't_ms,x_norm,y_norm\n0,0.5,0.5\n50,0.3,0.4\n' > "$dir/gaze.csv"
printf 't_ms,x,y\n10,1,1\n5,1,1\n' > "$dir/backwards.csv"
set=(--points "$dir/set.fovset")
check "no points"          2 -- "$fovview"
check "both point flags"   2 -- "$fovview" "${set[@]}" --points-dir "$dir"
check "unknown method"     2 -- "$fovview" "${set[@]}" --method cubic
check "k above the set"    2 -- "$fovview" "${set[@]}" --k 9
check "two gaze sources"   2 -- "$fovview" "${set[@]}" --gaze-trace "$dir/gaze.csv" --gaze centre
check "bad port"           2 -- "$fovview" "${set[@]}" --gaze-udp 70000
check "pupil not a URL"     2 -- "$fovview" "${set[@]}" --gaze-pupil 127.0.0.1:50020
check "pupil and udp"      2 -- "$fovview" "${set[@]}" --gaze-pupil tcp://127.0.0.1:50020 --gaze-udp 47000
check "pupil topic"        2 -- "$fovview" "${set[@]}" --gaze-pupil tcp://127.0.0.1:50020 --gaze-pupil-topic pupil.
check "calibration alone"  2 -- "$fovview" "${set[@]}" --gaze-calibration "$dir/gaze.csv"
check "filter one number"  2 -- "$fovview" "${set[@]}" --gaze-filter 1
check "filter beta alone"  2 -- "$fovview" "${set[@]}" --gaze-filter 0,1
check "confidence > 1"     2 -- "$fovview" "${set[@]}" --gaze-min-confidence 2
check "negative saccade"   2 -- "$fovview" "${set[@]}" --saccade-deg-s -1
check "hold not a number"  2 -- "$fovview" "${set[@]}" --gaze-hold-ms soon
check "gaze log exists"    2 -- "$fovview" "${set[@]}" --gaze-log "$dir/gaze.csv"
check "bad calibration"    1 -- "$fovview" "${set[@]}" --gaze-udp 47999 --gaze-calibration "$dir/gaze.csv"
mkfifo "$dir/cal.fifo"  # read as a calibration it would block forever: refused
check "calibration FIFO"   1 -- timeout 20 "$fovview" "${set[@]}" --gaze-udp 47999 --gaze-calibration "$dir/cal.fifo"
check "no Pupil Remote"    1 -- env -u DISPLAY -u WAYLAND_DISPLAY "$fovview" "${set[@]}" --gaze-pupil tcp://127.0.0.1:1
check "exit without frames" 2 -- "$fovview" "${set[@]}" --exit
check "ipd negative"       2 -- "$fovview" "${set[@]}" --stereo --ipd -1
check "stereo pipeline"    2 -- "$fovview" "${set[@]}" --stereo --pipeline
check "eyes without stereo" 2 -- "$fovview" "${set[@]}" --reuse eyes
check "replay and a trace"  2 -- "$fovview" "${set[@]}" --gaze-replay "$dir/gaze.csv" --gaze-trace "$dir/gaze.csv"
check "replay adapting"    2 -- "$fovview" "${set[@]}" --gaze-replay "$dir/gaze.csv" --target-fps 60
check "replay not a log"   1 -- "$fovview" "${set[@]}" --gaze-replay "$dir/gaze.csv" --frames 1 --exit
check "bad screenshot frame" 2 -- "$fovview" "${set[@]}" --screenshot-at x "$dir/a.png"
check "missing set"        1 -- "$fovview" --points "$dir/none.fovset"
check "columns without a trace" 2 -- "$fovview" "${set[@]}" --gaze-trace-columns pupil
check "bad trace columns"  2 -- "$fovview" "${set[@]}" --gaze-trace "$dir/gaze.csv" --gaze-trace-columns "t,x"
check "missing export column" 1 -- "$fovview" "${set[@]}" --gaze-trace "$dir/gaze.csv" --gaze-trace-columns pupil
check "backwards trace"    1 -- "$fovview" "${set[@]}" --gaze-trace "$dir/backwards.csv"
check "empty points dir"   1 -- "$fovview" --points-dir "$dir/none"
# A directory holding two displays' families: fovview asks which (once it has one, the
# missing X display is the next thing it meets: exit 1).
mkdir -p "$dir/fam"
"$fovgen" --display 64x72 --k 4 --saturation 500 -o "$dir/fam/64x72-v1-s1.00.fovset" >/dev/null
"$fovgen" --display 48x40 --k 4 --saturation 500 --scale 1.5 -o "$dir/fam/48x40-v1-s1.50.fovset" >/dev/null
fam=(env -u DISPLAY -u WAYLAND_DISPLAY "$fovview" --points-dir "$dir/fam" --k 4 --frames 1 --exit)
check "two displays' sets"  2 -- "${fam[@]}"
check "the display chosen"  1 -- "${fam[@]}" --display 64x72
check "the scale chooses"   1 -- "${fam[@]}" --scale 1.5
check "no such scale"       2 -- "${fam[@]}" --scale 1.75
check "bad display spec"    2 -- "${fam[@]}" --display 64x72@0ppd
check "display with --points" 2 -- "$fovview" "${set[@]}" --display 64x72
check "no display"         1 -- env -u DISPLAY -u WAYLAND_DISPLAY "$fovview" "${set[@]}" --frames 1 --exit
# DISPLAY set but nothing there: Qt aborted (exit 134, six lines); now one line, before Qt starts.
check "unreachable display" 1 -- env -u WAYLAND_DISPLAY DISPLAY=:987 timeout 20 "$fovview" "${set[@]}" --frames 1 --exit
check "malformed display"  1 -- env -u WAYLAND_DISPLAY DISPLAY=nonsense timeout 20 "$fovview" "${set[@]}" --frames 1 --exit
check "remote display"     1 -- env -u WAYLAND_DISPLAY DISPLAY=127.0.0.1:987 timeout 20 "$fovview" "${set[@]}" --frames 1 --exit

if ! command -v xvfb-run >/dev/null; then
  echo "SKIP the windowed run: xvfb-run is not installed (scripts/install-deps.sh installs it)"
else
  "$fovrender" --reference "${set[@]}" --spp 16 -o "$dir/ref.exr" >/dev/null || fail "reference"
  xvfb-run -a -s "-screen 0 1024x768x24" "$fovview" "${set[@]}" --gaze-trace "$dir/gaze.csv" --frames 30 \
    --screenshot-at 29 "$dir/out.png" --exit --compare "$dir/ref.exr" --json --target-fps 1000 --gaze-log "$dir/log.csv" \
    >"$dir/stats.json" 2>"$dir/err.txt" || fail "windowed run: $(cat "$dir/err.txt")"
  python3 - "$dir/out.png" "$dir/stats.json" "$dir/log.csv" <<'PY' || fail "screenshot checks"
import json, struct, sys
png = open(sys.argv[1], "rb").read()
assert png[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
w, h = struct.unpack(">II", png[16:24])
assert (w, h) == (256, 288), (w, h)
j = json.load(open(sys.argv[1] + ".json"))
assert j["frame"] == 29 and j["method"] == "shepard" and j["k"] == 5, j
assert abs(j["gaze"][0] - 0.3 * 256) < 1e-6 and abs(j["gaze"][1] - 0.4 * 288) < 1e-6, j["gaze"]  # the traced gaze
m = j["metrics"]
# Foveated where the gaze is: the fovea is closer to the reference than the periphery.
assert m["psnr_fovea"] > m["psnr_periphery"] + 2, m
assert [b["band"] for b in m["bands"]] == ["<5", "5-10", "10-20", "20-30", ">30"], m  # fovrender's schema
c = j["camera"]
assert c["hfov_deg"] > 0 and c["vfov_deg"] > 0 and abs(c["vfov_deg"] / c["hfov_deg"] - 1) < 0.3, c  # both fields of view
# --json: the frame-time distribution and the frames dropped against --target-fps.
s = json.load(open(sys.argv[2]))
f = s["distribution_ms"]["frame"]
assert 0 < f["median"] <= f["p95"] <= f["p99"] <= f["max"], f
assert s["dropped"]["target_fps"] == 1000 and 0 < s["dropped"]["late_frames"] <= s["measured_frames"], s["dropped"]
assert s["gaze"]["samples"] == 2 and s["gaze"]["malformed"] == 0, s["gaze"]
# --gaze-log: one row per frame, the gaze used and the trace's sample behind it.
rows = open(sys.argv[3]).read().splitlines()
assert rows[0].startswith("frame,local_ms,x,y,state,"), rows[0]
assert len(rows) == 31, len(rows)
last = dict(zip(rows[0].split(","), rows[-1].split(",")))
assert last["frame"] == "29" and abs(float(last["x"]) - 0.3 * 256) < 1e-3 and last["state"] == "tracking", last
assert float(last["age_ms"]) >= 0 and float(last["shown_ms"]) >= float(last["local_ms"]), last
PY
  # --gaze-replay: a saccade-bearing trace logged, then replayed frame for frame: the same
  # gaze, state, saccade landings and times in the new log, and the same last frame, byte
  # for byte; one gaze moved by 8 pixels in the log changes the frame.
  printf 't_ms,x_norm,y_norm\n0,0.3,0.3\n100,0.3,0.3\n200,0.8,0.7\n400,0.8,0.7\n500,0.2,0.8\n' > "$dir/saccades.csv"
  xvfb-run -a -s "-screen 0 1024x768x24" "$fovview" "${set[@]}" --gaze-trace "$dir/saccades.csv" --frames 60 \
    --screenshot-at 59 "$dir/live.png" --exit --gaze-log "$dir/live-log.csv" 2>"$dir/err.txt" || fail "logged run: $(cat "$dir/err.txt")"
  xvfb-run -a -s "-screen 0 1024x768x24" "$fovview" "${set[@]}" --gaze-replay "$dir/live-log.csv" \
    --screenshot-at 59 "$dir/replay.png" --exit --gaze-log "$dir/replay-log.csv" 2>"$dir/err.txt" || fail "replay: $(cat "$dir/err.txt")"
  cmp -s <(cut -d, -f1-15 "$dir/live-log.csv") <(cut -d, -f1-15 "$dir/replay-log.csv") || fail "the replay's gaze log differs"
  [[ $(awk -F, '$6 == 1' "$dir/live-log.csv" | wc -l) -ge 1 ]] || fail "the logged trace held no saccade landing"
  python3 - "$dir/live.png" "$dir/replay.png" <<'PY' || fail "the replayed frame differs"
import sys
assert open(sys.argv[1], "rb").read() == open(sys.argv[2], "rb").read()
PY
  python3 - "$dir/live-log.csv" "$dir/moved-log.csv" <<'PY'
import sys
rows = open(sys.argv[1]).read().splitlines()
c = rows[56].split(","); c[2] = str(float(c[2]) + 8); rows[56] = ",".join(c)
open(sys.argv[2], "w").write("\n".join(rows) + "\n")
PY
  xvfb-run -a -s "-screen 0 1024x768x24" "$fovview" "${set[@]}" --gaze-replay "$dir/moved-log.csv" \
    --screenshot-at 59 "$dir/moved.png" --exit 2>/dev/null || fail "moved replay"
  ! cmp -s "$dir/live.png" "$dir/moved.png" || fail "a moved gaze replayed the same frame"
  # --pipeline (the next frame traced while one is shown) shows the same frames: without
  # TAA the ray pattern is fixed, so frame 5 at a fixed gaze is the same image either way.
  for mode in plain pipeline; do
    flags=(); [[ $mode == pipeline ]] && flags=(--pipeline)
    xvfb-run -a -s "-screen 0 1024x768x24" "$fovview" "${set[@]}" --gaze 90,100 --no-taa --frames 6 \
      --screenshot-at 5 "$dir/$mode.png" --exit "${flags[@]}" 2>"$dir/err.txt" || fail "$mode run: $(cat "$dir/err.txt")"
  done
  cmp -s "$dir/plain.png" "$dir/pipeline.png" || fail "--pipeline changed the frame"
  # Two eyes side by side: at zero IPD both eyes see the head's view at the same gaze; with
  # --reuse eyes the right eye keeps samples of the left.
  for mode in ipd0 eyes; do
    flags=(--stereo --ipd 0); [[ $mode == eyes ]] && flags=(--stereo --reuse eyes --reuse-fovea 0)
    xvfb-run -a -s "-screen 0 1024x768x24" "$fovview" "${set[@]}" --gaze 90,100 --no-taa --frames 3 \
      --screenshot-at 2 "$dir/$mode.png" --exit "${flags[@]}" 2>"$dir/err.txt" || fail "stereo $mode run: $(cat "$dir/err.txt")"
  done
  python3 - "$dir" <<'PY' || fail "stereo screenshots"
import json, struct, sys
d = sys.argv[1]
for mode in ("ipd0", "eyes"):
    w, h = struct.unpack(">II", open(f"{d}/{mode}.png", "rb").read(24)[16:24])
    assert (w, h) == (512, 288), (mode, w, h)
    j = json.load(open(f"{d}/{mode}.png.json"))
    assert j["stereo"] and j["eye_width"] == 256, j
a, b = (json.load(open(f"{d}/{m}.png.json"))["eyes"] for m in ("ipd0", "eyes"))
assert a["left"]["rays"] == a["right"]["rays"] > 0, a
assert 0 < b["right"]["rays"] < b["left"]["rays"], b
PY
fi

echo "$passes passed, $failures failed"
[[ $failures -eq 0 ]]
