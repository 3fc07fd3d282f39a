#!/usr/bin/env bash
# k-NN cells against the k-NN table (issue 24; docs/benchmarks.md "k-NN cells"): the same
# darts kept both ways at FOVE (22 ppd) and on the 70-ppd retinal panel, and cells for
# Vision Pro and Varjo XR-4 (docs/displays.md). Measures, per set: generation (wall, peak
# memory), the file, the neighbours' bytes in memory, loading (fovgen info: read, check,
# build the cells; wall, peak memory); per method and device (OpenCL, C++), the
# reconstruction time of a centred frame (fovrender), table and cells interleaved run by
# run; and on the retinal panel a foveated frame's speedup over the full-resolution frame
# at the same spp (fovrender --speedup: paired, interleaved). Frames from table and cells
# are compared byte for byte (they must be equal).
#   out/cells/summary.md  the tables docs/benchmarks.md quotes; raw logs beside it
# FOV_REPS (default 5) repetitions; sets already in out/cells are reused.
set -euo pipefail
cd "$(dirname "$0")/.."
fovgen=${FOV_GEN:-build/apps/fovgen}
render=${FOV_RENDER:-build/apps/fovrender}
out=${FOV_OUT:-out/cells}
reps=${FOV_REPS:-5}
mkdir -p "$out"
timed() {  # timed LABEL COMMAND...: wall seconds and peak kB to LABEL.time, its output to LABEL.log
  local label=$1
  shift
  /usr/bin/time -f "%e %M" -o "$out/$label.time" "$@" > "$out/$label.log" 2>&1
}
generate() {  # generate NAME FLAGS...
  local name=$1
  shift
  [[ -s "$out/$name.fovset" ]] || timed "$name.gen" "$fovgen" "$@" -o "$out/$name.fovset"
  timed "$name.load" "$fovgen" info "$out/$name.fovset" --json
}
generate fove-table --display fove
generate fove-cells --display fove --encoding cells
generate retinal-table --display retinal
generate retinal-cells --display retinal --encoding cells
generate vision-pro-cells --display vision-pro --encoding cells
generate varjo-xr4-cells --display varjo-xr4 --encoding cells

# The retinal panel's table does not fit in an OpenCL buffer on PoCL here (fovrender falls
# back to C++ with a warning, kept in retinal-table-opencl.log): there the table is timed on
# the C++ path only, beside the cells on both; RBF and the extra repetitions are left out
# of the retinal panel for time (a run loads a 4.7 GB table).
timed retinal-table-opencl "$render" --points "$out/retinal-table.fovset" --gaze centre --spp 1 --method nn \
  -o "$out/retinal-table-probe.exr"
for display in fove retinal; do
  display_reps=$reps methods=(nn shepard rbf)
  [[ $display == retinal ]] && display_reps=3 methods=(nn shepard)
  for rep in $(seq 1 "$display_reps"); do
    for device in opencl cpp; do
      for method in "${methods[@]}"; do
        for storage in table cells; do
          [[ $display == retinal && $device == opencl && $storage == table ]] && continue
          label="$display-$storage-$device-$method-$rep"
          timed "$label.render" "$render" --points "$out/$display-$storage.fovset" --gaze centre --spp 1 --method "$method" \
            --device "$device" -o "$out/$display-$storage-$device-$method.exr"
        done
        # The same frame from either: EXR headers hold their capture date; the pixels must match.
        [[ -e "$out/$display-table-$device-$method.exr" ]] || continue
        { cmp -l "$out/$display-table-$device-$method.exr" "$out/$display-cells-$device-$method.exr" || true; } | wc -l \
          > "$out/$display-$device-$method.differing-bytes"
      done
    done
  done
done
for storage in table cells; do
  for spp in 1 4; do
    timed "retinal-$storage-speedup-$spp" "$render" --points "$out/retinal-$storage.fovset" --gaze centre --spp "$spp" \
      --method shepard --speedup "$reps" -o "$out/retinal-$storage-speedup.exr"
  done
done

/usr/bin/python3 - "$out" "$reps" <<'PY'
import json, os, re, statistics, sys
out, reps = sys.argv[1], int(sys.argv[2])
def timing(label):
    wall, kb = open(os.path.join(out, label + ".time")).read().split()[-2:]
    return float(wall), int(kb) / 1024
lines = ["| set | points | generation (s) | generation peak (MB) | file (MB) | neighbours in memory (MB) | load: fovgen info (s) | load peak (MB) |",
         "|---|---:|---:|---:|---:|---:|---:|---:|"]
for name in ("fove-table", "fove-cells", "retinal-table", "retinal-cells", "vision-pro-cells", "varjo-xr4-cells"):
    info = json.load(open(os.path.join(out, name + ".load.log")))
    gen = timing(name + ".gen") if os.path.exists(os.path.join(out, name + ".gen.time")) else (float("nan"), float("nan"))
    load = timing(name + ".load")
    lines.append(f"| `{name}` | {info['points_total']:,} | {gen[0]:.1f} | {gen[1]:.0f} | {info['file_bytes'] / 1e6:.1f} | "
                 f"{info['knn_memory_bytes'] / 1e6:.0f} | {load[0]:.1f} | {load[1]:.0f} |")
lines += ["", "Reconstruction of a centred 1-spp frame (fovrender's `reconstruct` ms; median, min-max of the runs, "
          "table and cells interleaved run by run), the ratio cells / table per run (median, min-max), and the bytes in "
          "which the two frames' EXR files differ (the header's capture date only when the pixels are equal). `fallback`: "
          "the OpenCL device refused the set's buffer and fovrender ran the C++ path instead:", "",
          "| display | device | method | runs | table (ms) | cells (ms) | cells / table | differing bytes |",
          "|---|---|---|---:|---:|---:|---:|---:|"]
pattern = re.compile(r"reconstruct ([0-9.]+) ms")
def run(display, storage, device, method, r):
    text = open(os.path.join(out, f"{display}-{storage}-{device}-{method}-{r}.render.log")).read()
    return float(pattern.search(text).group(1)), "using the C++ path" in text
for display, display_reps, methods in (("fove", reps, ("nn", "shepard", "rbf")), ("retinal", 3, ("nn", "shepard"))):
    for device in ("opencl", "cpp"):
        for method in methods:
            f = lambda v: f"{statistics.median(v):.1f} ({min(v):.1f}-{max(v):.1f})"
            runs = {s: [run(display, s, device, method, r) for r in range(1, display_reps + 1)]
                    for s in ("table", "cells") if os.path.exists(os.path.join(out, f"{display}-{s}-{device}-{method}-1.render.log"))}
            ms = {s: [v for v, _ in runs[s]] for s in runs}
            fell = {s: any(x for _, x in runs[s]) for s in runs}
            cell = lambda s: (f(ms[s]) + (" fallback" if fell[s] else "")) if s in ms else "not run"
            if "table" in ms:
                ratio = [c / t for c, t in zip(ms["cells"], ms["table"])]
                ratio_text = f"{statistics.median(ratio):.2f} ({min(ratio):.2f}-{max(ratio):.2f})"
                diff = open(os.path.join(out, f"{display}-{device}-{method}.differing-bytes")).read().strip()
            else:
                ratio_text, diff = "", ""
            lines.append(f"| {display} | {device} | {method} | {display_reps} | {cell('table')} | {cell('cells')} | {ratio_text} | {diff} |")
probe = open(os.path.join(out, "retinal-table-opencl.log")).read()
lines += ["", "The retinal table on the OpenCL device: " +
          (next((l.strip() for l in probe.splitlines() if "warning" in l), "accepted") )]
lines += ["", "Retinal panel, Shepard k = 5, centred gaze: the foveated frame against the full-resolution frame at the same "
          f"spp, {reps} interleaved pairs (fovrender --speedup; time only, no quality):", "",
          "| neighbours | spp | speedup (95 % interval) | full frame (ms) | foveated frame (ms) | process peak (MB) |",
          "|---|---:|---|---:|---:|---:|"]
sp = re.compile(r"speedup over full resolution at (\d+) spp: ([0-9.]+)x \(95 % interval ([0-9.]+)-([0-9.]+);.*full ([0-9.]+) ms, foveated ([0-9.]+) ms")
for storage in ("table", "cells"):
    for spp in (1, 4):
        label = f"retinal-{storage}-speedup-{spp}"
        text = open(os.path.join(out, label + ".log")).read()
        m = sp.search(text)
        lines.append(f"| {storage}{' (C++ fallback)' if 'using the C++ path' in text else ''} | {m.group(1)} | {m.group(2)}x ({m.group(3)}-{m.group(4)}) | {m.group(5)} | {m.group(6)} | "
                     f"{timing(label)[1]:.0f} |")
open(os.path.join(out, "summary.md"), "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
