// The camera flags every rendering tool binds (--eye, --look-at, --up, --hfov): the input's
// lines are their values. Each is refused with one usage line (CLI11's or fovray's), or the
// camera set up from them is finite and within the world bound Embree needs.
#include <cmath>
#include <sstream>
#include <vector>

#include "fov/scene.h"
#include "fuzz_input.h"
#include "render_flags.h"

using namespace fov;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::unique_ptr<scene> builtin = load_scene("builtin");
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::vector<std::string> args = {"fuzz"};
  const char* flags[] = {"--eye", "--look-at", "--up", "--hfov"};
  std::string value;
  for (const char* flag : flags) {
    if (!std::getline(in, value)) break;
    if (value.empty()) continue;  // this flag not given
    args.push_back(flag), args.push_back(value);
  }
  CLI::App app;
  render_params p;
  add_render_flags(app, p, flags_view);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  try {
    app.parse(int(argv.size()), argv.data());
    const camera cam = setup_camera(*builtin, p.view);
    const glm::vec3 f = cam.forward;
    fuzz::require(world_point_problem(cam.position.x, cam.position.y, cam.position.z).empty(), "the eye within range");
    fuzz::require(std::isfinite(f.x + f.y + f.z) && std::fabs(glm::length(f) - 1) < 1e-3f, "a unit view direction");
    fuzz::require(cam.hfov_deg > 0 && cam.hfov_deg < 180, "a field of view in (0, 180)");
  } catch (const CLI::ParseError& e) {
    if (std::string(e.what()).find('\n') != std::string::npos) fuzz::finding("a flag message spans lines", e.what());
  } catch (const usage_error& e) {
    if (std::string(e.what()).find('\n') != std::string::npos) fuzz::finding("a flag message spans lines", e.what());
  } catch (const std::exception& e) {
    fuzz::finding("a camera flag error that is not a usage error", e.what());
  }
  return 0;
}
