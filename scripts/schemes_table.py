#!/usr/bin/python3
"""The schemes study's tables (docs/schemes.md) from scripts/schemes-study.sh's runs:
one Markdown table per display of every scheme's rows, the full-resolution rows and any
lower-resolution rows (fovbench --baselines uniform, named by pixel fraction), and with
--figure STEM a figure of JOD against frame time, one line per scheme (STEM.png).
Usage: scripts/schemes_table.py [--figure STEM] out/schemes/DISPLAY [...] (Debian's python3 and
python3-matplotlib, as the tools' figures use)"""
import csv
import glob
import os
import sys


def rows_of(run):
    with open(os.path.join(run, "results.csv"), newline="") as f:
        return list(csv.DictReader(f))


def name_of(r, explicit=False):
    """A row's scheme, with its reconstruction where it is not the study's default (Shepard,
    k = 5) or where the rows beside it differ in reconstruction (explicit)."""
    if r["kind"] == "uniform":  # fovbench's lower-resolution baseline: a uniform set of that pixel fraction
        return f'lower resolution, 1/{round(1 / float(r["pixel_fraction"]))} of the pixels'
    scheme = f'{r["acuity"]} + {r["sampler"]}'
    if not explicit and (r["method"], r["k"]) == ("shepard", "5"):
        return scheme
    return f'{scheme}, {r["method"]} k = {r["k"]}'


def all_rows(display_dir):
    return [r for run in sorted(glob.glob(os.path.join(display_dir, "*", "results.csv")))
            for r in rows_of(os.path.dirname(run))]


def mixed_methods(display_dir):
    """Whether a display's runs hold more than one reconstruction (then every row names its own)."""
    return len({(r["method"], r["k"]) for r in all_rows(display_dir) if r["kind"] != "full"}) > 1


def num(r, key, fmt="{:.2f}"):
    v = r.get(key, "")
    return fmt.format(float(v)) if v not in ("", None) else ""


def scene_of(display_dir):
    """The scene a study folder's runs rendered, as results.csv names it."""
    for run in sorted(glob.glob(os.path.join(display_dir, "*"))):
        if os.path.exists(os.path.join(run, "results.csv")):
            rows = rows_of(run)
            if rows:
                return os.path.basename(rows[0]["scene"])
    return "?"


def temporal_table(display_dir):
    """Flicker and video JOD along fovbench's temporal path (runs with --temporal-frames)."""
    out = ["| scheme | spp | points traced | flicker | flicker through TAA | full resolution's flicker | video JOD | through TAA | full resolution's video JOD |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    floors = set()
    explicit = mixed_methods(display_dir)
    for r in all_rows(display_dir):
        if r["kind"] != "foveated" or r["flicker"] == "":
            continue
        floors.add(num(r, "noise_floor_video_jod"))
        out.append(f'| {name_of(r, explicit)} | {r["spp"]} | {int(r["points_traced"]):,} | ' +
                   " | ".join(num(r, k, "{:.4f}") for k in ("flicker", "flicker_taa", "flicker_reference")) + " | " +
                   " | ".join(num(r, k) for k in ("video_jod", "video_jod_taa", "video_jod_full")) + " |")
    out.append("")
    out.append("The converged path's own floor (video JOD): " + ", ".join(sorted(floors)) + ".")
    return "\n".join(out)


def table(display_dir):
    runs = sorted(d for d in glob.glob(os.path.join(display_dir, "*")) if os.path.exists(os.path.join(d, "results.csv")))
    out = ["| scheme | spp | points traced | rays (M) | frame ms (min-max) | same-spp speedup (min-max) | JOD | PSNR | FLIP | FLIP < 5° | 5-10° | 10-20° | 20-30° | > 30° |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    full = {}
    floors = set()
    explicit = mixed_methods(display_dir)
    for run in runs:
        for r in rows_of(run):
            floors.add((r["noise_floor_jod"], r["noise_floor_flip"]))
            if r["kind"] == "full":
                full.setdefault(r["spp"], []).append(r)
                continue
            name = name_of(r, explicit)
            out.append(f'| {name} | {r["spp"]} | {int(r["points_traced"]):,} | {float(r["rays"]) / 1e6:.2f} | '
                       f'{num(r, "frame_ms", "{:.0f}")} ({num(r, "frame_ms_lo", "{:.0f}")}-{num(r, "frame_ms_hi", "{:.0f}")}) | '
                       f'{num(r, "speedup")} ({num(r, "speedup_lo")}-{num(r, "speedup_hi")}) | {num(r, "jod")} | {num(r, "psnr")} | '
                       + " | ".join(num(r, k, "{:.3f}") for k in ("flip", "flip_fovea", "flip_5_10", "flip_10_20", "flip_20_30", "flip_periphery")) + " |")
    for spp in sorted(full, key=int):
        rs = full[spp]  # one per run, each timed beside its own sweep: the JOD is the same frame's
        jods = sorted(float(r["jod"]) for r in rs)
        ms = sorted(float(r["full_ms"]) for r in rs)
        r = rs[0]
        out.append(f'| full resolution ({len(rs)} runs) | {spp} |  | {float(r["rays"]) / 1e6:.2f} | '
                   f'{ms[len(ms) // 2]:.0f} ({ms[0]:.0f}-{ms[-1]:.0f}) | 1 | {jods[len(jods) // 2]:.2f} | {num(r, "psnr")} | '
                   + " | ".join(num(r, k, "{:.3f}") for k in ("flip", "flip_fovea", "flip_5_10", "flip_10_20", "flip_20_30", "flip_periphery")) + " |")
    out.append("")
    floors = sorted({f"{float(j):.2f}, {float(fl):.4f}" for j, fl in floors})
    out.append("Reference noise floor (JOD, FLIP), " + ("the same in every run: " if len(floors) == 1 else "per run: ")
               + "; ".join(floors) + ".")
    return "\n".join(out)


# One colour per scheme in every figure.
COLOURS = {"csf + poisson": "tab:blue", "linear-mar + poisson": "tab:orange", "linear-mar + polar": "tab:green",
           "piecewise-mar + log-polar": "tab:red", "piecewise-mar + poisson": "tab:purple",
           "csf + polar": "tab:olive", "csf + log-polar": "tab:cyan"}

# One marker and line style per reconstruction (colour stays the scheme's).
METHOD_MARKERS = {"shepard": "o", "rbf": "s", "barycentric": "^", "natural": "D", "nn": "x"}
METHOD_LINES = {"shepard": "-", "rbf": "-.", "barycentric": "--", "natural": ":", "nn": "-"}


def lower_colour(fraction):
    """A lower resolution's grey, darker for more pixels (1/4: 0.15, 1/16: 0.3, 1/64: 0.6)."""
    return str(min(0.75, 0.075 / fraction ** 0.5))


def figure(display_dirs, stem):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cols = min(2, len(display_dirs))
    rows = (len(display_dirs) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(6.5 * cols, 4.8 * rows), squeeze=False)
    for ax in axes.flat[len(display_dirs):]:
        ax.set_visible(False)
    for ax, d in zip(axes.flat, display_dirs):
        series, full = {}, {}
        explicit = mixed_methods(d)
        for r in all_rows(d):
            if r["kind"] == "full":
                full.setdefault(int(r["spp"]), []).append((float(r["full_ms"]), float(r["jod"])))
            else:
                # Lower-resolution rows (uniform sets) are keyed by their pixel fraction, "" otherwise.
                fraction = r["pixel_fraction"] if r["kind"] == "uniform" else ""
                scheme = name_of(r) if fraction else f'{r["acuity"]} + {r["sampler"]}'
                key = (scheme, r["method"], r["k"], fraction)
                series.setdefault(key, []).append((float(r["frame_ms"]), float(r["jod"]), r["spp"], name_of(r, explicit)))
        # Where a run swept several k, the smaller k's markers are hollow.
        widest = max((int(k) for _, _, k, _ in series), default=0)
        for (scheme, method, k, fraction), pts in sorted(series.items()):
            pts.sort()
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="v" if fraction else METHOD_MARKERS.get(method, "o"),
                    label=pts[0][3], color=lower_colour(float(fraction)) if fraction else COLOURS.get(scheme),
                    linestyle=":" if fraction else METHOD_LINES.get(method, "-"),
                    fillstyle="full" if int(k) == widest else "none", linewidth=1.2)
            for x, y, spp, _ in pts:
                ax.annotate(spp, (x, y), textcoords="offset points", xytext=(4, -10), fontsize=7)
        fpts = sorted((sorted(v)[len(v) // 2][0], v[0][1], spp) for spp, v in full.items())
        ax.plot([p[0] for p in fpts], [p[1] for p in fpts], marker="s", color="black", linestyle="--", label="full resolution")
        for x, y, spp in fpts:
            ax.annotate(str(spp), (x, y), textcoords="offset points", xytext=(4, -10), fontsize=7)
        ax.set_xscale("log")
        ax.set_xlabel("frame time (ms, median of 3; labels: rays per point or pixel)")
        ax.set_ylabel("JOD (FovVideoVDP, foveated, centred gaze)")
        ax.set_title(f"{scene_of(d)}, {os.path.basename(os.path.normpath(d)).split('-')[0]}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8 if len(series) <= 9 else 6, ncol=1 if len(series) <= 9 else 2)
    fig.tight_layout()
    fig.savefig(stem + ".png", dpi=110)


if __name__ == "__main__":
    args = sys.argv[1:]
    if len(args) >= 2 and args[0] == "--figure":
        figure(args[2:], args[1])
        args = args[2:]
    for d in args:
        print(f"### {os.path.basename(os.path.normpath(d))}\n")
        print(table(d))
        print()
        if any(r["flicker"] for run in glob.glob(os.path.join(d, "*", "results.csv")) for r in rows_of(os.path.dirname(run))):
            print(temporal_table(d))
            print()
