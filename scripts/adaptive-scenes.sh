# Sourced by adaptive-study.sh and detail-noise-study.sh: the three scenes as they render them
# (fovrender's own defaults: the built-in scene with its light, the helmet close-up, the
# forest map) and their converged references. Needs $render (fovrender).
#   scene_flags NAME           prints NAME's flags (builtin, helmet, env)
#   scene_missing NAME         true (with a line on stderr) for the helmet without ../shared
#   converged_pair DIR SPP F.. DIR/ref-a.exr and DIR/ref-b.exr at SPP rays a pixel, seeds 1001
#                              and 1002 (the reference and its noise floor), unless there
scene_flags() {
  case $1 in
    builtin) echo "--scene builtin" ;;
    helmet) echo "--scene ../shared/scenes/flight-helmet/FlightHelmet.gltf --eye 0.1,0.28,0.22 --look-at 0,0.3,0 --hfov 60" ;;
    env) echo "--scene env:/usr/share/blender/datafiles/studiolights/world/forest.exr" ;;
    *) echo "scene must be builtin, helmet or env (got $1)" >&2; exit 2 ;;
  esac
}
scene_missing() {
  [[ $1 == helmet && ! -f ../shared/scenes/flight-helmet/FlightHelmet.gltf ]] || return 1
  echo "(no helmet: ../shared absent)" >&2
}
converged_pair() {
  local dir=$1 spp=$2
  shift 2
  mkdir -p "$dir"
  [[ -f $dir/ref-a.exr ]] || "$render" "$@" --display fove --reference --spp "$spp" --seed 1001 -o "$dir/ref-a.exr" > /dev/null
  [[ -f $dir/ref-b.exr ]] || "$render" "$@" --display fove --reference --spp "$spp" --seed 1002 -o "$dir/ref-b.exr" > /dev/null
}
