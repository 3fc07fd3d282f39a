#!/usr/bin/env python3
"""The tables of docs/adaptive.md from what scripts/adaptive-study.sh wrote: per scene and
gaze, every frame (fixed levels, adaptive thresholds, full resolution, the reference's noise
floor); then each adaptive frame against the fixed sets at its rays (their JOD and per-band
FLIP interpolated linearly in log rays between the two levels around it) and at its quality
(the rays the fixed sets need for its JOD, interpolated the same way, and the finest level).
Usage: scripts/adaptive_tables.py OUT SPP REFERENCE_SPP [SCENE...]"""
import json
import math
import os
import sys

THRESHOLDS = ["1", "0.5", "0.25"]
GAZES = ["centre", "320-1080"]


def band(j, name):
    return next(b for b in j["bands"] if b["band"] == name)["flip"]


def load(d, name):
    with open(os.path.join(d, name + ".json")) as f:
        return json.load(f)


def interpolate(xs, ys, x):
    """y at x on the polyline through (xs, ys), xs increasing; None outside it."""
    for i in range(len(xs) - 1):
        if xs[i] <= x <= xs[i + 1]:
            t = 0 if xs[i + 1] == xs[i] else (x - xs[i]) / (xs[i + 1] - xs[i])
            return ys[i] + t * (ys[i + 1] - ys[i])
    return None


def frames_table(d, names):
    floor, full = load(d, "floor"), load(d, "full")
    full["flicker"] = {"raw": load(d, "level0")["flicker"]["full_resolution"], "taa": None}
    print("| frame | rays | frame ms (min-max) | speedup over full res. (95 % interval) | flicker raw / TAA | JOD | FLIP | "
          "foveated FLIP | " + " | ".join(f"FLIP {n}" for n in names) + " |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|" + "---:|" * len(names))

    def row(label, j, m):
        timed = j is not None and "speedup" in j
        fl = j.get("flicker") if j else None
        cells = [label, f"{j['rays']:,}" if j else "",
                 f"{j['frame_ms']:.0f} ({j['frame_ms_lo']:.0f}-{j['frame_ms_hi']:.0f})" if timed
                 else (f"{j['total_ms']:.0f}" if j else ""),
                 f"{j['speedup']:.2f} ({j['speedup_interval'][0]:.2f}-{j['speedup_interval'][1]:.2f})" if timed else "",
                 (f"{fl['raw']:.4f}" + (f" / {fl['taa']:.4f}" if fl["taa"] is not None else "")) if fl else "",
                 f"{m['jod']:.3f}", f"{m['flip']:.4f}", f"{m['foveated_flip']:.4f}"]
        cells += [f"{band(m, n):.4f}" if band(m, n) is not None else "" for n in names]
        print("| " + " | ".join(cells) + " |")

    row("noise floor (second reference)", None, floor)
    row("full resolution (its flicker measured beside level 0's)", full, full["metrics"])
    for lv in range(5):
        j = load(d, f"level{lv}")
        row(f"fixed, level {lv} (s = {j['scale']:.2f})", j, j["metrics"])
    for t in THRESHOLDS:
        j = load(d, f"adaptive{t}")
        per = ", ".join(str(lv["blocks"]) for lv in j["adaptive"]["levels"])
        row(f"adaptive, threshold {t} (blocks per level {per})", j, j["metrics"])


def comparison_tables(d, names):
    fixed = sorted((load(d, f"level{lv}") for lv in range(5)), key=lambda j: j["rays"])
    log_rays = [math.log(j["rays"]) for j in fixed]
    finest = max(fixed, key=lambda j: j["metrics"]["jod"])
    print("Equal rays: the fixed sets at the adaptive frame's rays (interpolated in log rays between "
          "the levels around it) against the adaptive frame; FLIP per band (lower is better).")
    print()
    print("| adaptive | rays | JOD fixed / adaptive | FLIP fixed / adaptive | " +
          " | ".join(f"FLIP {n} fixed / adaptive" for n in names) + " |")
    print("|---|---:|---:|---:|" + "---:|" * len(names))
    for t in THRESHOLDS:
        a = load(d, f"adaptive{t}")
        x = math.log(a["rays"])

        def at(value):
            v = interpolate(log_rays, [value(j) for j in fixed], x)
            return "-" if v is None else v

        def pair(f, v, digits):
            return f"{f:.{digits}f} / {v:.{digits}f}" if f != "-" else f"- / {v:.{digits}f}"
        cells = [f"threshold {t}", f"{a['rays']:,}", pair(at(lambda j: j["metrics"]["jod"]), a["metrics"]["jod"], 3),
                 pair(at(lambda j: j["metrics"]["flip"]), a["metrics"]["flip"], 4)]
        for n in names:
            vals = [band(j["metrics"], n) for j in fixed]
            if any(v is None for v in vals) or band(a["metrics"], n) is None:
                cells.append("")
                continue
            v = interpolate(log_rays, vals, x)
            cells.append(pair("-" if v is None else v, band(a["metrics"], n), 4))
        print("| " + " | ".join(cells) + " |")
    print()
    print(f"Equal quality: the rays the fixed sets need for the adaptive frame's JOD (interpolated in log rays; "
          f"'-' beyond the finest level's), and the adaptive frame against the finest fixed level "
          f"(s = {finest['scale']:.2f}, JOD {finest['metrics']['jod']:.3f}, {finest['rays']:,} rays, "
          f"{finest['frame_ms']:.0f} ms).")
    print()
    print("| adaptive | JOD | rays | fixed rays at its JOD | rays / fixed at its JOD | rays / finest's | "
          "JOD - finest's | frame ms / finest's |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    by_jod = sorted(fixed, key=lambda j: j["metrics"]["jod"])
    for t in THRESHOLDS:
        a = load(d, f"adaptive{t}")
        jod = a["metrics"]["jod"]
        v = interpolate([j["metrics"]["jod"] for j in by_jod], [math.log(j["rays"]) for j in by_jod], jod)
        need = None if v is None else math.exp(v)
        need_text = "-" if need is None else f"{need:,.0f}"
        ratio_text = "-" if need is None else f"{a['rays'] / need:.2f}"
        print(f"| threshold {t} | {jod:.3f} | {a['rays']:,} | {need_text} | {ratio_text} | "
              f"{a['rays'] / finest['rays']:.2f} | {jod - finest['metrics']['jod']:+.3f} | "
              f"{a['frame_ms'] / finest['frame_ms']:.2f} |")


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__.splitlines()[-1])
    out, spp, ref_spp = sys.argv[1], sys.argv[2], sys.argv[3]
    for scene in sys.argv[4:] or ["builtin", "helmet", "env"]:
        for gaze in GAZES:
            d = os.path.join(out, scene, gaze)
            if not os.path.exists(os.path.join(d, "adaptive0.25.json")):
                continue
            names = [b["band"] for b in load(d, "floor")["bands"]]
            print(f"### {scene}, gaze {gaze.replace('-', ',')} (FOVE, {spp} rays per sample, against a {ref_spp}-spp reference)")
            print()
            frames_table(d, names)
            print()
            comparison_tables(d, names)
            print()


if __name__ == "__main__":
    main()
