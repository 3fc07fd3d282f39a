#!/usr/bin/env bash
# Installs every Debian package fovray builds, tests and benchmarks with.
# Idempotent: packages already present are skipped by apt-get; run as root
# (or with sudo available). Set FOV_SKIP_DEPS=1 to skip entirely.
set -euo pipefail

[[ "${FOV_SKIP_DEPS:-0}" == "1" ]] && exit 0

packages=(
  build-essential cmake pkg-config
  libembree-dev              # tracer: BVH build and ray intersection
  libflann-dev               # distgen: exact kd-tree k-nearest-neighbour tables
  libopenimageio-dev         # image I/O and filtered texture lookups
  libglm-dev                 # small vector maths
  libopencv-dev libopencv-contrib-dev   # plots, drawing; quality module (PSNR/SSIM)
  pocl-opencl-icd ocl-icd-opencl-dev opencl-c-headers opencl-clhpp-headers clinfo
  libtbb-dev                 # parallel loops
  libassimp-dev              # glTF/OBJ loading
  libcli11-dev               # command lines
  nlohmann-json3-dev         # --json output, protocol files
  libfmt-dev                 # formatting
  libgtest-dev libbenchmark-dev
  assimp-testmodels          # tests: every glTF2/OBJ sample must load or fail cleanly
  python3                    # scripts/demo.sh writes its summary table with it
  python3-matplotlib         # fovbench's figures (PNG and SVG): labels placed apart, error bars, one colour per scheme
  libzstd-dev                # k-NN table compression on disk (see README, Dependencies)
  libzmq3-dev libmsgpack-dev # --gaze-pupil: Pupil Labs' network API is ZeroMQ sockets carrying msgpack
  blender-data               # CC0 HDR environment maps: the env: stimulus of fovstair's thesis protocol
  xvfb xauth                 # tests: fovview and fovstair windows run headless under xvfb-run
  clang libclang-rt-dev      # scripts/fuzz.sh: libFuzzer and the sanitizers' runtimes for clang
  time                       # scripts/cells-bench.sh: GNU time's wall time and peak memory per run
  libcgal-dev                # interp: Delaunay triangulation and Sibson's natural-neighbour coordinates (header-only)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

sudo=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps.sh: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
