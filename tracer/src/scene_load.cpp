// Scene files: glTF 2.0 and OBJ through Assimp; env:FILE image scenes; the built-in scene.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>

#include <sys/stat.h>

#include <cctype>
#include <cerrno>
#include <cstring>

#include <assimp/DefaultIOSystem.h>
#include <assimp/DefaultLogger.hpp>
#include <assimp/GltfMaterial.h>
#include <assimp/LogStream.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <OpenImageIO/imageio.h>

#include "fov/files.h"
#include "fov/json_scan.h"
#include "fov/scene.h"

namespace fov {

namespace fs = std::filesystem;

namespace {


std::string lowercase(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

glm::mat4 to_glm(const aiMatrix4x4& m) {
  // Assimp is row-major with translation in the last column; glm is column-major.
  return glm::mat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4, m.b4, m.c4, m.d4);
}

// The node tree walked without recursion, parents before children: f(node, depth).
template <class F>
void walk_nodes(const aiNode* root, F&& f) {
  std::vector<std::pair<const aiNode*, int>> stack{{root, 1}};
  while (!stack.empty()) {
    const auto [node, depth] = stack.back();
    stack.pop_back();
    if (!f(node, depth)) return;
    for (unsigned i = node->mNumChildren; i-- > 0;) stack.emplace_back(node->mChildren[i], depth + 1);
  }
}

const aiNode* find_node(const aiNode* root, const aiString& name) {
  const aiNode* found = nullptr;
  walk_nodes(root, [&](const aiNode* n, int) { return n->mName == name ? (found = n, false) : true; });
  return found;
}

glm::mat4 world_transform(const aiNode* node) {
  glm::mat4 t(1.0f);
  for (; node; node = node->mParent) t = to_glm(node->mTransformation) * t;
  return t;
}

// The node hierarchy as instances (world transforms), without recursion. A placement that
// scales its mesh to (almost) nothing draws nothing: skipped, with a warning.
void flatten(const aiNode* root, std::vector<instance>& out, const std::vector<int>& mesh_map,
             std::vector<std::string>& warnings) {
  walk_nodes(root, [&](const aiNode* node, int) {
    const glm::mat4 t = world_transform(node);
    const bool vanishes = classify_placement(t) == placement_scale::vanishing;
    for (unsigned i = 0; i < node->mNumMeshes; ++i) {
      if (node->mMeshes[i] >= mesh_map.size() || mesh_map[node->mMeshes[i]] < 0) continue;
      if (vanishes) {
        warnings.push_back(fmt::format("node '{}' scales its mesh below {:g}: not drawn", printable(node->mName.C_Str()),
                                       1 / max_transform_scale));
        break;
      }
      out.push_back({uint32_t(mesh_map[node->mMeshes[i]]), t, node->mName.C_Str()});
    }
    return true;
  });
}

// Every file Assimp opens for a scene (the scene file, a glTF's buffers, an OBJ's .mtl) is
// checked first: a regular file (a FIFO would block forever) of at most
// max_scene_file_bytes. Refused files are remembered with the reason, so the error names
// them; missing and empty ones are left to Assimp (an OBJ's missing .mtl is not an error),
// and named when the import fails; the files read are the scene's inputs.
class checked_io : public Assimp::DefaultIOSystem {
 public:
  bool Exists(const char* file) const override {
    struct stat st {};
    return ::stat(file, &st) == 0;  // the default opens the file, which blocks on a FIFO
  }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (std::strchr(mode, 'w') || std::strchr(mode, 'a') || std::strchr(mode, '+')) {
      refused.push_back(fmt::format("{}: the importer asked to write it (refused)", file));
      return nullptr;
    }
    struct stat st {};
    if (::stat(file, &st) != 0) {
      unusable.push_back(fmt::format("{}: cannot open: {}", file, std::strerror(errno)));
      return nullptr;
    }
    if (const std::string why = input_file_problem(file, max_scene_file_bytes, "scene file"); !why.empty()) {
      refused.push_back(fmt::format("{}: {}", file, why));
      return nullptr;
    }
    if (st.st_size == 0) unusable.push_back(fmt::format("{}: is empty (0 bytes)", file));
    read.emplace_back(file);
    return Assimp::DefaultIOSystem::Open(file, mode);
  }
  std::vector<std::string> refused, unusable, read;  // unusable: missing or empty
};

// What a glTF's buffers claim, held to the bytes the scene has, and its accessors: Assimp
// allocates a buffer's stated byteLength before reading its file, so a file of a few
// hundred bytes could ask for gigabytes; a buffer may not claim more bytes than the file it
// names holds. "" when fine; what Assimp refuses anyway (a missing file) is left to it.
std::string gltf_data_problem(const nlohmann::json& j, const fs::path& dir) {
  if (j.contains("buffers") && j["buffers"].is_array()) {
    const nlohmann::json& buffers = j["buffers"];
    for (size_t i = 0; i < buffers.size(); ++i) {
      const nlohmann::json& b = buffers[i];
      if (!b.is_object() || !b.contains("uri") || !b["uri"].is_string()) continue;
      const std::string uri = b["uri"].get<std::string>();
      if (uri.rfind("data:", 0) == 0) continue;  // inside the scene file
      const fs::path file = dir / uri;
      std::error_code ec;
      if (!fs::is_regular_file(file, ec)) continue;  // missing or special: the checked IOSystem names it
      const uintmax_t bytes = fs::file_size(file, ec);
      if (ec) continue;
      if (!b.contains("byteLength") || !b["byteLength"].is_number_unsigned()) continue;
      const uint64_t claimed = b["byteLength"].get<uint64_t>();
      if (claimed > bytes && bytes == 0)
        return fmt::format("buffer {}: {}: is empty (0 bytes), but the buffer claims {} bytes (refused)", i,
                           file.string(), claimed);
      if (claimed > bytes)
        return fmt::format("buffer {}: claims {} bytes, more than the {} bytes of {} (refused)", i, claimed, bytes,
                           file.string());
    }
  }
  // Sparse accessors are refused. Debian's Assimp 5.2.5 allocates their dense array from
  // the count alone (3.4 GB from a file of 1 KB), dereferences a missing indices or values
  // bufferView (a crash), and writes each value where its index points, unchecked against
  // the count: two fuzz findings and a write out of bounds.
  if (!j.contains("accessors") || !j["accessors"].is_array()) return "";
  const nlohmann::json& accessors = j["accessors"];
  for (size_t i = 0; i < accessors.size(); ++i)
    if (accessors[i].is_object() && accessors[i].contains("sparse"))
      return fmt::format("accessor {}: sparse accessors are not supported (refused: Assimp writes where their indices "
                         "point without a check)", i);
  return "";
}

// What the check of a glTF's JSON found: why it is refused ("" when it is not), the
// extensions it declares (extensionsUsed) that fovray does not implement, and each
// material's emissiveStrength (KHR_materials_emissive_strength, which Debian's Assimp does
// not read; 1 where absent), by glTF material index.
constexpr size_t max_extension_warnings = 16;
// The largest emissiveStrength a material may give: far past any lamp authored in glTF.
constexpr double max_emissive_strength = 1e6;

struct gltf_check {
  gltf_check(std::string why = "") : problem(std::move(why)) {}  // (every early return is a refusal)
  std::string problem;
  std::vector<std::string> unsupported;
  std::vector<float> emissive_strength;
};

// Each material's emissiveStrength into `out`, or why the file is refused.
std::string read_emissive_strengths(const nlohmann::json& j, std::vector<float>& out) {
  if (!j.contains("materials") || !j["materials"].is_array()) return "";
  const nlohmann::json& materials = j["materials"];
  out.assign(materials.size(), 1.0f);
  for (size_t i = 0; i < materials.size(); ++i) {
    const nlohmann::json& m = materials[i];
    if (!m.is_object() || !m.contains("extensions") || !m["extensions"].is_object() ||
        !m["extensions"].contains("KHR_materials_emissive_strength"))
      continue;
    const nlohmann::json& e = m["extensions"]["KHR_materials_emissive_strength"];
    if (!e.is_object() || !e.contains("emissiveStrength")) continue;  // the default, 1
    const nlohmann::json& v = e["emissiveStrength"];
    const std::string name = m.contains("name") && m["name"].is_string() ? m["name"].get<std::string>() : "";
    if (!v.is_number() || !(v.get<double>() >= 0 && v.get<double>() <= max_emissive_strength))
      return fmt::format("material {} '{}': emissiveStrength {} not a number within 0..{:g} (refused)", i,
                         printable(name, 80), printable(v.dump(), 40), max_emissive_strength);
    out[i] = float(v.get<double>());
  }
  return "";
}

// The glTF extensions fovray implements: KHR_lights_punctual and
// KHR_materials_emissive_strength. Every other one a file declares is warned about
// (KHR_materials_* change how a material shades).
std::vector<std::string> unsupported_extensions(const nlohmann::json& j) {
  std::vector<std::string> out;
  if (!j.contains("extensionsUsed") || !j["extensionsUsed"].is_array()) return out;
  for (const nlohmann::json& e : j["extensionsUsed"]) {
    const std::string name = e.is_string() ? e.get<std::string>() : e.dump();
    const bool supported = name == "KHR_lights_punctual" || name == "KHR_materials_emissive_strength";
    if (!supported && std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
  }
  return out;
}

// A glTF's JSON (a .gltf file, a .glb's first chunk), checked before Assimp parses it:
// nesting at most max_gltf_json_depth, and a node tree (children by index) at most
// max_node_depth deep in which every node has at most one parent and no node is its own
// ancestor; a .glb's chunks end within the file. No problem when fine, or when a .glb's
// header cannot be read (Assimp's error then says why).
gltf_check check_gltf(const std::string& path, const std::string& extension) {
  std::string text;
  if (extension == ".glb") {  // only the JSON chunk is read (the binary one follows it)
    std::ifstream in(path, std::ios::binary);  // (load_file has checked it is a regular file)
    char head[20] = {};
    uint32_t length = 0, type = 0;
    // Not a binary glTF at all: refused here, since Assimp, its glTF readers failing, tries
    // its other readers on the content (OBJ text in a .glb: a fuzz finding, see obj_problem).
    if (!in.read(head, sizeof head)) return std::string("is too short for a binary glTF (a 20-byte header) (refused)");
    if (std::memcmp(head, "glTF", 4) != 0) return std::string("is not a binary glTF: no 'glTF' at its start (refused)");
    std::memcpy(&length, head + 12, 4), std::memcpy(&type, head + 16, 4);
    if (type != 0x4E4F534Au) return {};
    // Assimp allocates what a chunk's length says before reading it: a length past the
    // file's end would be an allocation of up to 4 GiB for a file of a few bytes.
    const uintmax_t size = std::filesystem::file_size(path);
    if (length > size - sizeof head)
      return fmt::format("its JSON chunk claims {} bytes, more than the {}-byte file holds (refused)", length, size);
    text.resize(length);
    if (!in.read(text.data(), std::streamsize(length))) return {};
    // The binary chunk, when one follows: Assimp reads its header after padding the JSON
    // chunk to 4 bytes.
    const uintmax_t padding = (4 - length % 4) % 4;
    char bin[8] = {};
    if (in.seekg(std::streamoff(padding), std::ios::cur) && in.read(bin, sizeof bin)) {
      uint32_t bin_length = 0;
      std::memcpy(&bin_length, bin, 4);
      if (bin_length > size - sizeof head - length - padding - sizeof bin)
        return fmt::format("its binary chunk claims {} bytes, more than the {}-byte file holds (refused)", bin_length, size);
    }
  } else {
    text = read_input_file(path, max_scene_file_bytes, "scene file");
  }
  if (const int line = json_too_deep_line(text, max_gltf_json_depth))
    return fmt::format("line {}: JSON nested deeper than {} levels (refused)", line, max_gltf_json_depth);
  // JSON that does not parse here is refused, not left to Assimp: its reader takes what
  // this one does not (ill-formed UTF-8 in a key: a fuzz finding), and every check here
  // would then be skipped. So is an object with a key twice: this reader keeps the last
  // value, Assimp's the first, and the checks would read another file than Assimp.
  nlohmann::json j;
  std::vector<std::set<std::string>> keys;  // the keys of each object being read
  std::string repeated;
  const auto track = [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    if (event == nlohmann::json::parse_event_t::object_start) keys.emplace_back();
    if (event == nlohmann::json::parse_event_t::object_end && !keys.empty()) keys.pop_back();
    if (event == nlohmann::json::parse_event_t::key && !keys.empty() && !keys.back().insert(parsed.get<std::string>()).second &&
        repeated.empty())
      repeated = parsed.get<std::string>();
    return true;
  };
  try {
    j = nlohmann::json::parse(text, track);
  } catch (const nlohmann::json::exception& e) {
    const std::string what = e.what(), at = what.find("parse error") != std::string::npos ? what.substr(what.find("parse error")) : what;
    return fmt::format("its JSON does not parse (refused): {}", printable(first_line(at), 120));
  }
  if (!repeated.empty())
    return fmt::format("its JSON has an object with the key \"{}\" twice (refused: readers differ on which counts)",
                       printable(repeated));
  if (!j.is_object()) return {};
  if (std::string why = gltf_data_problem(j, fs::path(path).parent_path()); !why.empty())
    return why;
  gltf_check fine;
  fine.unsupported = unsupported_extensions(j);
  if (std::string why = read_emissive_strengths(j, fine.emissive_strength); !why.empty()) return why;
  if (!j.contains("nodes") || !j["nodes"].is_array()) return fine;
  const nlohmann::json& nodes = j["nodes"];
  std::vector<long> parent(nodes.size(), -1);
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (!nodes[i].is_object() || !nodes[i].contains("children") || !nodes[i]["children"].is_array()) continue;
    for (const nlohmann::json& c : nodes[i]["children"]) {
      if (!c.is_number_unsigned() || c.get<uint64_t>() >= nodes.size())
        return fmt::format("node {}: a child that is not a node index (refused)", i);
      const size_t child = c.get<size_t>();
      if (parent[child] >= 0 || child == i)
        return fmt::format("node {}: the child of more than one node, or of itself (refused: glTF nodes form trees)", child);
      parent[child] = long(i);
    }
  }
  std::vector<int> depth(nodes.size(), 0);  // 0: not known yet
  for (size_t i = 0; i < nodes.size(); ++i) {
    std::vector<size_t> chain;  // up to a node whose depth is known, or the root
    size_t n = i;
    while (depth[n] == 0) {
      chain.push_back(n);
      if (chain.size() > size_t(max_node_depth))
        return fmt::format("node {}: nested deeper than {} levels, or in a cycle (refused)", i, max_node_depth);
      if (parent[n] < 0) break;
      n = size_t(parent[n]);
    }
    int d = depth[n];  // 0 when the walk stopped at the root (which is in the chain)
    for (size_t c = chain.size(); c-- > 0;) depth[chain[c]] = ++d;
    if (d > max_node_depth) return fmt::format("node {}: nested deeper than {} levels (refused)", i, max_node_depth);
  }
  return fine;
}

class texture_resolver {
 public:
  texture_resolver(fs::path dir, std::vector<std::string>& warnings) : dir_(std::move(dir)), warnings_(warnings) {}
  // The texture of this type, when it names a file that exists; warns once per missing file.
  texture_ref find(const aiMaterial* m, aiTextureType type, bool srgb) {
    if (m->GetTextureCount(type) == 0) return {};
    return check(m, type, 0, srgb);
  }
  texture_ref check(const aiMaterial* m, aiTextureType type, unsigned index, bool srgb = false) {
    aiString path;
    if (m->GetTexture(type, index, &path) != AI_SUCCESS) return {};
    const std::string name = path.C_Str();
    if (!name.empty() && name[0] == '*') {
      warn_once(name, fmt::format("embedded texture {} is not supported; using the material's factors", name));
      return {};
    }
    const fs::path file = dir_ / name;
    std::error_code ec;
    if (!fs::exists(file, ec) && !ec) {
      warn_once(name, fmt::format("texture {} is missing; using the material's factors", file.string()));
      return {};
    }
    // Whatever keeps a texture from being read is said once, naming the file: a directory
    // or special file (a FIFO or /dev/zero would block or never end), an empty file (what
    // a failed download leaves), or an image its reader refuses.
    std::string why = input_file_problem(file.string());
    if (why.empty() && fs::file_size(file) == 0) why = "is empty (0 bytes)";
    if (why.empty()) {
      if (auto in = OIIO::ImageInput::open(file.string())) in->close();
      else why = fmt::format("cannot be read: {}", first_line(OIIO::geterror()));
    }
    if (!why.empty()) {
      warn_once(name, fmt::format("texture {} {}; using the material's factors", file.string(), why));
      return {};
    }
    if (seen_files_.insert(file.string()).second) files_.push_back(file.string());
    return {file.string(), srgb};
  }
  const std::vector<std::string>& files() const { return files_; }

 private:
  void warn_once(const std::string& key, std::string message) {
    if (seen_.insert(key).second) warnings_.push_back(std::move(message));
  }
  fs::path dir_;
  std::vector<std::string>& warnings_;
  std::set<std::string> seen_, seen_files_;
  std::vector<std::string> files_;
};

material convert_material(const aiMaterial* m, texture_resolver& textures) {
  material out;
  aiString name;
  if (m->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) out.name = name.C_Str();
  aiColor4D c;
  if (m->Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS || m->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS)
    out.base_colour = {c.r, c.g, c.b, c.a};
  float opacity = 1;
  if (m->Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS && opacity < 1) out.base_colour.a *= opacity;
  out.base_texture = textures.find(m, aiTextureType_BASE_COLOR, true);
  if (out.base_texture.file.empty()) out.base_texture = textures.find(m, aiTextureType_DIFFUSE, true);
  aiColor3D e;
  if (m->Get(AI_MATKEY_COLOR_EMISSIVE, e) == AI_SUCCESS) out.emissive = {e.r, e.g, e.b};
  out.emissive_texture = textures.find(m, aiTextureType_EMISSIVE, true);
  out.normal_texture = textures.find(m, aiTextureType_NORMALS, false);
  // glTF's metallic-roughness model: Assimp's glTF 2.0 reader sets the metallic factor on
  // every material it makes (OBJ materials have none and stay Lambertian).
  if (m->Get(AI_MATKEY_METALLIC_FACTOR, out.metallic) == AI_SUCCESS) {
    out.model = shading_model::metallic_roughness;
    m->Get(AI_MATKEY_ROUGHNESS_FACTOR, out.roughness);
    out.metallic = std::isfinite(out.metallic) ? std::clamp(out.metallic, 0.0f, 1.0f) : 1.0f;
    out.roughness = std::isfinite(out.roughness) ? std::clamp(out.roughness, 0.0f, 1.0f) : 1.0f;
    out.metallic_roughness_texture = textures.find(m, aiTextureType_UNKNOWN, false);  // (Assimp's glTF slot)
    out.occlusion_texture = textures.find(m, aiTextureType_LIGHTMAP, false);
    if (!out.occlusion_texture.file.empty()) {
      m->Get(AI_MATKEY_GLTF_TEXTURE_STRENGTH(aiTextureType_LIGHTMAP, 0), out.occlusion_strength);
      out.occlusion_strength = std::isfinite(out.occlusion_strength) ? std::clamp(out.occlusion_strength, 0.0f, 1.0f) : 1.0f;
    }
  }
  aiString mode;
  if (m->Get(AI_MATKEY_GLTF_ALPHAMODE, mode) == AI_SUCCESS && std::string(mode.C_Str()) == "MASK") {
    out.alpha = alpha_mode::mask;
    m->Get(AI_MATKEY_GLTF_ALPHACUTOFF, out.alpha_cutoff);
  }
  if (m->Get(AI_MATKEY_GLTF_ALPHAMODE, mode) == AI_SUCCESS && std::string(mode.C_Str()) == "BLEND") out.alpha = alpha_mode::blend;
  if (textures.find(m, aiTextureType_OPACITY, false).file.size()) out.alpha = alpha_mode::mask;  // OBJ map_d
  // Every other texture the file names is checked too, so each missing file is reported.
  for (int type = aiTextureType_NONE + 1; type <= AI_TEXTURE_TYPE_MAX; ++type)
    for (unsigned i = 0; i < m->GetTextureCount(aiTextureType(type)); ++i) textures.check(m, aiTextureType(type), i);
  return out;
}

// Assimp's warnings and errors while one file loads. Assimp drops faces whose vertex
// indices are out of range with nothing but a log line (a changed image, silently), so the
// loader listens to its log. Assimp's logger is process-wide: one import at a time.
class assimp_log : public Assimp::LogStream {
 public:
  assimp_log() {
    Assimp::DefaultLogger::create(nullptr, Assimp::Logger::NORMAL, 0);
    Assimp::DefaultLogger::get()->attachStream(this, severities);
  }
  ~assimp_log() override {
    Assimp::DefaultLogger::get()->detachStream(this, severities);
    Assimp::DefaultLogger::kill();
  }
  void write(const char* message) override { messages.emplace_back(first_line(message)); }
  std::vector<std::string> messages;

 private:
  static constexpr unsigned severities = Assimp::Logger::Warn | Assimp::Logger::Err;
};

// An OBJ's face, line and point elements ('f', 'l', 'p'), checked before Assimp parses them:
// every vertex reference one of v, v/vt, v//vn or v/vt/vn (whole numbers, signed). Debian's
// Assimp misreads others: "f 1 1/1//31/ 3" sent its strtol past the end of the file's
// buffer (a heap overflow the scene fuzz target found). Returns "line N: ..." or "".
std::string obj_problem(const std::string& path) {
  const std::string text = read_input_file(path, max_scene_file_bytes, "scene file");
  auto number = [](const std::string& t, size_t& i) {  // [+-]digits from i; false if none
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    const size_t start = i;
    while (i < t.size() && std::isdigit(static_cast<unsigned char>(t[i]))) ++i;
    return i > start;
  };
  auto reference = [&](const std::string& t) {
    size_t i = 0;
    if (!number(t, i)) return false;
    if (i == t.size()) return true;            // v
    if (t[i++] != '/') return false;
    if (i < t.size() && t[i] == '/') {          // v//vn
      ++i;
      return number(t, i) && i == t.size();
    }
    if (!number(t, i)) return false;            // v/vt
    if (i == t.size()) return true;
    if (t[i++] != '/') return false;            // v/vt/vn
    return number(t, i) && i == t.size();
  };
  size_t line = 0, at = 0;
  while (at < text.size()) {
    const size_t end = std::min(text.find('\n', at), text.size());
    const std::string l = text.substr(at, end - at);  // (Assimp reads a '#' after a face as part of it)
    at = end + 1, ++line;
    std::vector<std::string> tokens;
    size_t i = 0;
    while (i < l.size()) {
      while (i < l.size() && std::isspace(static_cast<unsigned char>(l[i]))) ++i;
      const size_t start = i;
      while (i < l.size() && !std::isspace(static_cast<unsigned char>(l[i]))) ++i;
      if (i > start) tokens.push_back(l.substr(start, i - start));
    }
    if (tokens.empty() || (tokens[0] != "f" && tokens[0] != "l" && tokens[0] != "p")) continue;
    for (size_t k = 1; k < tokens.size(); ++k)
      if (!reference(tokens[k]))
        return fmt::format("line {}: vertex reference '{}' is not v, v/vt, v//vn or v/vt/vn (refused before Assimp "
                           "parses it)", line, printable(tokens[k], 40));
  }
  return {};
}

std::mutex& assimp_mutex() {
  static std::mutex m;
  return m;
}

scene_description load_file(const std::string& path) {
  std::error_code ec;  // (a loop of links is an error code, not an exception)
  if (!fs::exists(path, ec) && !ec) throw std::runtime_error(fmt::format("{}: no such file", path));
  if (const std::string why = input_file_problem(path, max_scene_file_bytes, "scene file"); !why.empty())
    throw std::runtime_error(fmt::format("{}: {}", path, why));
  const std::string extension = lowercase(fs::path(path).extension().string());
  gltf_check checked;
  if (extension == ".gltf" || extension == ".glb") {
    checked = check_gltf(path, extension);
    if (!checked.problem.empty()) throw std::runtime_error(fmt::format("{}: {}", path, checked.problem));
  }
  Assimp::Importer importer;
  // OBJ, by its extension or by its content where Assimp does not know the extension (it
  // then tries its readers on the content).
  if (extension == ".obj" || !importer.IsExtensionSupported(extension))
    if (const std::string why = obj_problem(path); !why.empty()) throw std::runtime_error(fmt::format("{}: {}", path, why));
  auto* io = new checked_io;  // the importer owns it
  importer.SetIOHandler(io);
  const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals |
                         aiProcess_CalcTangentSpace | aiProcess_FlipUVs | aiProcess_SortByPType;
  const aiScene* ai = nullptr;
  {
    const std::lock_guard<std::mutex> one_import(assimp_mutex());
    const assimp_log log;
    ai = importer.ReadFile(path, flags);
    for (const std::string& m : log.messages)
      if (m.find("out-of-range ind") != std::string::npos)
        throw std::runtime_error(fmt::format("{}: faces with vertex indices out of range (refused; Assimp: {})", path,
                                             m.substr(m.find(':') == std::string::npos ? 0 : m.find(':') + 2)));
  }
  auto name_it = [&](const std::string& problem) {  // "PATH: FILE: why", or "PATH: why" for the scene itself
    return problem.rfind(path + ": ", 0) == 0 ? problem : fmt::format("{}: {}", path, problem);
  };
  if (!io->refused.empty())  // a file the scene refers to, named with the reason
    throw std::runtime_error(name_it(io->refused.front()));
  if (!ai || !ai->mRootNode) {
    if (!io->unusable.empty()) throw std::runtime_error(name_it(io->unusable.front()) + " (cannot load the scene)");
    throw std::runtime_error(fmt::format("{}: cannot load scene: {}", path, first_line(importer.GetErrorString())));
  }
  int deepest = 0;
  walk_nodes(ai->mRootNode, [&](const aiNode*, int depth) { return (deepest = std::max(deepest, depth)) <= max_node_depth; });
  if (deepest > max_node_depth)
    throw std::runtime_error(fmt::format("{}: nodes nested deeper than {} levels (refused)", path, max_node_depth));

  scene_description d;
  d.files = io->read;
  // Extensions the file declares that fovray does not implement: one warning each (at
  // most max_extension_warnings, then how many more).
  for (size_t i = 0; i < checked.unsupported.size() && i < max_extension_warnings; ++i)
    d.warnings.push_back(fmt::format("{}: uses the glTF extension {}, which fovray does not support: ignored{}", path,
                                     printable(checked.unsupported[i], 80),
                                     checked.unsupported[i].rfind("KHR_materials_", 0) == 0
                                         ? " (its materials shade by the core metallic-roughness model)"
                                         : ""));
  if (checked.unsupported.size() > max_extension_warnings)
    d.warnings.push_back(fmt::format("{}: uses {} more glTF extensions fovray does not support: ignored", path,
                                     checked.unsupported.size() - max_extension_warnings));
  texture_resolver textures(fs::path(path).parent_path(), d.warnings);
  for (unsigned i = 0; i < ai->mNumMaterials; ++i) d.materials.push_back(convert_material(ai->mMaterials[i], textures));
  // Assimp keeps glTF's material order (and appends its default material after them).
  for (size_t i = 0; i < checked.emissive_strength.size() && i < d.materials.size(); ++i)
    d.materials[i].emissive *= checked.emissive_strength[i];

  d.files.insert(d.files.end(), textures.files().begin(), textures.files().end());
  std::vector<int> mesh_map(ai->mNumMeshes, -1);
  for (unsigned i = 0; i < ai->mNumMeshes; ++i) {
    const aiMesh* am = ai->mMeshes[i];
    mesh m;
    m.material = am->mMaterialIndex;
    m.positions.reserve(am->mNumVertices);
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
      m.positions.push_back({am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z});
      if (am->HasNormals()) m.normals.push_back({am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z});
      if (am->HasTextureCoords(0)) m.uvs.push_back({am->mTextureCoords[0][v].x, am->mTextureCoords[0][v].y});
      if (am->HasTangentsAndBitangents()) {
        const aiVector3D t = am->mTangents[v], b = am->mBitangents[v];
        const glm::vec3 n = am->HasNormals() ? glm::vec3(am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z)
                                             : glm::vec3(0, 0, 1);
        const float hand = glm::dot(glm::cross(n, glm::vec3(t.x, t.y, t.z)), glm::vec3(b.x, b.y, b.z)) < 0 ? -1.f : 1.f;
        m.tangents.push_back({t.x, t.y, t.z, hand});
      }
    }
    size_t degenerate = 0;
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines
      const glm::uvec3 t(face.mIndices[0], face.mIndices[1], face.mIndices[2]);
      if (std::max({t.x, t.y, t.z}) >= m.positions.size())
        throw std::runtime_error(fmt::format("{}: mesh '{}': a face's vertex index is out of range ({} vertices)", path,
                                             printable(am->mName.C_Str()), m.positions.size()));
      const glm::vec3 n = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
      if (!(glm::dot(n, n) > 0) || !std::isfinite(n.x + n.y + n.z)) {
        ++degenerate;
        continue;
      }
      m.triangles.push_back(t);
    }
    if (degenerate)
      d.warnings.push_back(fmt::format("mesh '{}': skipped {} degenerate triangle{}", am->mName.C_Str(), degenerate,
                                       degenerate == 1 ? "" : "s"));
    if (m.triangles.empty()) {
      if (am->mNumFaces) d.warnings.push_back(fmt::format("mesh '{}' has no usable triangles", am->mName.C_Str()));
      continue;
    }
    mesh_map[i] = int(d.meshes.size());
    d.meshes.push_back(std::move(m));
  }
  flatten(ai->mRootNode, d.instances, mesh_map, d.warnings);
  if (d.instances.empty())
    throw std::runtime_error(fmt::format("{}: the scene has no triangles{}", path, d.warnings.empty() ? "" : " (" + d.warnings.back() + ")"));

  if (ai->mNumCameras > 0) {
    const aiCamera* c = ai->mCameras[0];
    const glm::mat4 t = world_transform(find_node(ai->mRootNode, c->mName));
    // Assimp's camera is relative to its node, with half the horizontal field of view,
    // except from its glTF 2.0 importer (5.2), which copies the node's own translation into
    // mPosition (so the node's transform applied it twice) and stores yfov x aspect in
    // mHorizontalFOV (the full angle's linear approximation, not half an angle). For glTF
    // the node alone places the camera, and the vertical field of view is kept as the
    // file states it: yfov = mHorizontalFOV / mAspect (mAspect 0 when the file gives none).
    const bool gltf = extension == ".gltf" || extension == ".glb";
    const glm::vec3 local = gltf ? glm::vec3(0) : glm::vec3(c->mPosition.x, c->mPosition.y, c->mPosition.z);
    const glm::vec3 eye = glm::vec3(t * glm::vec4(local, 1));
    const glm::vec3 look = glm::mat3(t) * glm::vec3(c->mLookAt.x, c->mLookAt.y, c->mLookAt.z);
    const glm::vec3 up = glm::mat3(t) * glm::vec3(c->mUp.x, c->mUp.y, c->mUp.z);
    if (gltf) {
      const float yfov = c->mAspect > 0 ? c->mHorizontalFOV / c->mAspect : c->mHorizontalFOV;
      const float aspect = c->mAspect > 0 ? c->mAspect : 1.0f;
      camera cam = look_at(eye, eye + look, glm::degrees(2 * std::atan(aspect * std::tan(0.5f * yfov))), up);
      cam.vfov_deg = glm::degrees(yfov);
      d.scene_camera = cam;
    } else {
      d.scene_camera = look_at(eye, eye + look, 2 * glm::degrees(c->mHorizontalFOV), up);
    }
    const camera& cam = *d.scene_camera;
    const bool in_range = cam.hfov_deg > 0 && cam.hfov_deg < 180 && (gltf ? cam.vfov_deg > 0 && cam.vfov_deg < 180 : true);
    if (!in_range || !std::isfinite(glm::dot(cam.position, cam.forward)) ||
        !world_point_problem(cam.position.x, cam.position.y, cam.position.z).empty()) {
      d.warnings.push_back(fmt::format("camera '{}': field of view or placement out of range; framing the scene instead",
                                       c->mName.C_Str()));
      d.scene_camera.reset();
    }
  }
  // Every directional, point and spot light (KHR_lights_punctual; Assimp gives glTF's
  // colour x intensity in lux or candela), divided by pi: fovray's light colour is what a
  // white Lambertian surface facing it shows. A file with lights replaces the default sun.
  std::vector<light> lights;
  const bool from_gltf = extension == ".gltf" || extension == ".glb";
  for (unsigned i = 0; i < ai->mNumLights; ++i) {
    const aiLight* l = ai->mLights[i];
    const std::string name = printable(l->mName.C_Str());
    if (l->mType != aiLightSource_DIRECTIONAL && l->mType != aiLightSource_POINT && l->mType != aiLightSource_SPOT) {
      d.warnings.push_back(fmt::format("light '{}': not a directional, point or spot light; skipped", name));
      continue;
    }
    const glm::mat4 t = world_transform(find_node(ai->mRootNode, l->mName));
    light out;
    out.colour = glm::vec3(l->mColorDiffuse.r, l->mColorDiffuse.g, l->mColorDiffuse.b) * (from_gltf ? 0.318309886f : 1.0f);
    const glm::vec3 towards = glm::mat3(t) * glm::vec3(l->mDirection.x, l->mDirection.y, l->mDirection.z);
    out.position = glm::vec3(t * glm::vec4(l->mPosition.x, l->mPosition.y, l->mPosition.z, 1));
    if (l->mType == aiLightSource_DIRECTIONAL) {
      out.type = light::kind::directional;
      out.direction = -glm::normalize(towards);
    } else if (l->mType == aiLightSource_POINT) {
      out.type = light::kind::point;
    } else {
      out.type = light::kind::spot;
      out.axis = glm::normalize(towards);
      out.inner_cone = l->mAngleInnerCone, out.outer_cone = l->mAngleOuterCone;
    }
    const bool finite = std::isfinite(glm::dot(out.colour, out.colour)) && std::isfinite(glm::dot(out.position, out.position)) &&
                        std::isfinite(glm::dot(out.direction, out.direction)) && std::isfinite(glm::dot(out.axis, out.axis));
    if (!finite || glm::any(glm::lessThan(out.colour, glm::vec3(0))) ||
        !world_point_problem(out.position.x, out.position.y, out.position.z).empty())
      throw std::runtime_error(fmt::format("{}: light '{}': a colour, intensity, position or direction that is not finite, "
                                           "negative or out of range (refused)", path, name));
    if (out.type == light::kind::spot &&
        !(std::isfinite(out.inner_cone) && std::isfinite(out.outer_cone) && out.inner_cone >= 0 &&
          out.outer_cone > out.inner_cone && out.outer_cone <= 1.5707964f))
      throw std::runtime_error(fmt::format("{}: light '{}': spot cone angles {:g} and {:g} not within 0 <= inner < outer <= "
                                           "pi/2 (refused)", path, name, out.inner_cone, out.outer_cone));
    lights.push_back(out);
  }
  if (!lights.empty()) d.lights = std::move(lights);
  return d;
}

}  // namespace

namespace {

// env_image_problem, keeping the header it read in `spec`.
std::string env_image_header(const std::string& file, OIIO::ImageSpec& spec) {
  if (std::string why = input_file_problem(file); !why.empty()) return why;
  auto in = OIIO::ImageInput::open(file);
  if (!in) return fmt::format("cannot read environment image: {}", first_line(OIIO::geterror()));
  spec = in->spec();
  if (spec.width < 2 || spec.height < 1) return "image too small";
  if (uint64_t(spec.width) * uint64_t(spec.height) > max_env_pixels)
    return fmt::format("{}x{} is larger than an environment image may be ({} pixels, e.g. {}x{})", spec.width, spec.height,
                       max_env_pixels, 2 * max_env_height, max_env_height);
  return "";
}

// The description of `spec` (see load_scene).
scene_description load_description(const std::string& spec) {
  if (spec == "builtin") return builtin_scene();
  if (spec == "builtin:cornell") return cornell_scene();
  if (spec.rfind("env:", 0) == 0) {
    const std::string file = spec.substr(4);
    OIIO::ImageSpec s;
    if (const std::string why = env_image_header(file, s); !why.empty()) throw std::runtime_error(fmt::format("{}: {}", file, why));
    scene_description d;
    d.env.latlong_file = file;
    d.files = {file};
    d.env.colour = glm::vec3(0);
    if (std::abs(s.width - 2 * s.height) > s.height / 8)
      d.warnings.push_back(fmt::format("{}: {}x{} is not 2:1; reading it as lat-long anyway", file, s.width, s.height));
    d.scene_camera = look_at({0, 0, 0}, {0, 0, -1}, 90);
    return d;
  }
  return load_file(spec);
}

std::unique_ptr<scene> load_scene_checked(const std::string& spec, const std::string& env_light) {
  scene_description d = load_description(spec);
  if (!env_light.empty()) {
    if (const std::string why = env_image_problem(env_light); !why.empty())
      throw std::runtime_error(fmt::format("{}: {}", env_light, why));
    d.env.latlong_file = env_light;
    d.env.intensity = 1;
    d.files.push_back(env_light);
  }
  try {
    return std::make_unique<scene>(std::move(d));
  } catch (const std::invalid_argument& e) {  // the scene refuses geometry Embree must not see (geometry_problem)
    throw std::runtime_error(fmt::format("{}: {}", spec, e.what()));
  }
}

}  // namespace

std::string env_image_problem(const std::string& file) {
  OIIO::ImageSpec spec;
  return env_image_header(file, spec);
}

std::unique_ptr<scene> load_scene(const std::string& spec, const std::string& env_light) {
  try {
    return load_scene_checked(spec, env_light);
  } catch (const std::bad_alloc&) {  // what no size check foresaw (a process limit): the file named
    throw std::runtime_error(fmt::format("{}: out of memory while loading the scene", spec));
  }
}

std::unique_ptr<scene> load_scene(const std::string& spec) { return load_scene(spec, ""); }

}  // namespace fov
