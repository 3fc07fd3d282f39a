# Sourced by the study scripts (hybrid-displays.sh, steady-state.sh, per-display.sh): the fovbench flags of
# one of the study's scenes as the study renders it on a display. study_scene NAME DISPLAY
# sets the array `scene`: builtin (whites unclipped, the display's field of view), helmet
# (the close-up, 60°), env (the forest map, the display's field of view) or cornell (the
# built-in room lit by one downlight, the display's field of view); exits 2 on
# another NAME. Sourcing also sets the tools (FOV_BENCH, FOV_GEN, FOV_RENDER; default build/apps/) and
# the scene's name (SCENE; default builtin).
bench=${FOV_BENCH:-build/apps/fovbench}
fovgen=${FOV_GEN:-build/apps/fovgen}
render=${FOV_RENDER:-build/apps/fovrender}
scene_name=${SCENE:-builtin}
study_scene() {
  local name=$1 display=$2 hfov
  hfov=$("$fovgen" displays --display "$display" --json | python3 -c 'import json, sys; print("%.4f" % json.load(sys.stdin)[0]["fov_deg"][0])')
  case $name in
    builtin) scene=(--scene builtin --sun-irradiance 0.8,0.77,0.7 --hfov "$hfov") ;;
    helmet) scene=(--scene ../shared/scenes/flight-helmet/FlightHelmet.gltf --eye 0.1,0.28,0.22 --look-at 0,0.3,0 --hfov 60) ;;
    env) scene=(--scene env:/usr/share/blender/datafiles/studiolights/world/forest.exr --hfov "$hfov") ;;
    cornell) scene=(--scene builtin:cornell --hfov "$hfov") ;;
    *) echo "SCENE must be builtin, helmet, env or cornell (got $name)" >&2; exit 2 ;;
  esac
}
# stereo_set DISPLAY: sets `set_file` to the s = 1.0 set the stereo studies share
# (out/stereo/DISPLAY-s1.0.fovset), generating it when it is missing.
stereo_set() {
  set_file=out/stereo/$1-s1.0.fovset
  mkdir -p out/stereo
  [[ -s $set_file ]] || "$fovgen" --display "$1" --scale 1.0 -o "$set_file" > /dev/null
}
