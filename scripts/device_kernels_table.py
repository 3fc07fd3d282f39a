#!/usr/bin/env python3
"""One markdown table from reconstruct_bench JSON files (scripts/device-kernels.sh): per set
and benchmark, the wall time per frame the kernels' device times and the host's upload and read-back times, as the median and
(min-max) of the repetitions, and the device the run found."""
import json
import statistics
import sys


def spread(values):
    if not values:
        return ""
    return f"{statistics.median(values):.2f} ({min(values):.2f}-{max(values):.2f})"


def main(paths):
    rows = []
    devices = set()
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        ctx = data["context"]
        devices.add(ctx.get("opencl_device", "?"))
        runs = {}
        for b in data["benchmarks"]:
            if b.get("run_type") != "iteration" or b.get("error_occurred"):
                continue
            runs.setdefault(b["run_name"], []).append(b)
        for name, reps in runs.items():
            unit = {"ms": 1.0, "us": 1e-3, "ns": 1e-6, "s": 1e3}[reps[0]["time_unit"]]
            col = lambda key: [r[key] for r in reps if key in r]
            rows.append([
                ctx.get("set", "?").split("/")[-1], ctx.get("display", "?"),
                name.replace("BM_", "").replace("/real_time", ""), str(len(reps)),
                spread([r["real_time"] * unit for r in reps]), spread(col("kernel_ms")),
                spread(col("taa_kernel_ms")), spread(col("upload_ms")), spread(col("read_back_ms")),
                spread(col("bound_ms")), spread(col("kernel_over_bound")),
                spread(col("copy_GBps")),
            ])
    print("OpenCL device: " + "; ".join(sorted(devices)))
    print()
    head = ["set", "display", "benchmark", "reps", "frame ms", "kernel ms", "TAA kernel ms", "upload ms",
            "read-back ms", "bound ms",
            "kernel / bound", "copy GB/s"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for r in rows:
        print("| " + " | ".join(r) + " |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: device_kernels_table.py BENCH.json ...")
    main(sys.argv[1:])
