#include "wire/scene_bundle.h"

#include <cstdint>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>

#include "scene/image_check.h"
#include "scene/scene_error.h"
#include "wire/sha256.h"


namespace tessera::wire {
namespace {

constexpr std::string_view kMagic = "tessera-bundle-v1\n";

std::string checked_path(const std::string& path, const std::string& context) {
  try {
    return check_bundle_path(path, context);
  } catch (const SceneError& e) {
    throw BundleError(e.what());
  }
}

void put_u64(std::string& out, uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(char((v >> (8 * i)) & 0xff));
}

void put_string(std::string& out, std::string_view s) {
  put_u64(out, s.size());
  out.append(s);
}

/// Reads length-prefixed fields, never past the end.
class Reader {
 public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}

  uint64_t u64() {
    if (bytes_.size() - pos_ < 8) throw BundleError("bundle: truncated");
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(uint8_t(bytes_[pos_ + i])) << (8 * i);
    pos_ += 8;
    return v;
  }

  std::string string() {
    const uint64_t n = u64();
    if (n > bytes_.size() - pos_) throw BundleError("bundle: truncated");
    std::string s(bytes_.substr(pos_, n));
    pos_ += n;
    return s;
  }

  bool expect(std::string_view literal) {
    if (bytes_.substr(pos_, literal.size()) != literal) return false;
    pos_ += literal.size();
    return true;
  }

  bool at_end() const { return pos_ == bytes_.size(); }

 private:
  std::string_view bytes_;
  size_t pos_ = 0;
};

}  // namespace

BundleContents bundle_from_proto(const v1::SceneBundle& bundle) {
  BundleContents out;
  if (bundle.scene_file().empty()) throw BundleError("bundle: scene_file is empty");
  out.scene_file = checked_path(bundle.scene_file(), "bundle scene_file");
  for (int i = 0; i < bundle.files_size(); ++i) {
    const auto& f = bundle.files(i);
    const std::string path =
        checked_path(f.path(), "bundle files[" + std::to_string(i) + "] \"" + f.path() + "\"");
    if (!out.files.emplace(path, f.data()).second) {
      throw BundleError("bundle files[" + std::to_string(i) + "]: duplicate path \"" + path + "\"");
    }
  }
  if (!out.files.contains(out.scene_file)) {
    throw BundleError("bundle: scene file \"" + out.scene_file + "\" is not among its files");
  }
  return out;
}

v1::SceneBundle bundle_to_proto(const BundleContents& bundle) {
  v1::SceneBundle out;
  out.set_scene_file(bundle.scene_file);
  for (const auto& [path, data] : bundle.files) {
    auto* f = out.add_files();
    f->set_path(path);
    f->set_data(data);
  }
  return out;
}

std::string canonical_bytes(const BundleContents& bundle) {
  size_t size = kMagic.size() + 16 + bundle.scene_file.size();
  for (const auto& [path, data] : bundle.files) size += 16 + path.size() + data.size();
  std::string out;
  out.reserve(size);
  out.append(kMagic);
  put_string(out, bundle.scene_file);
  put_u64(out, bundle.files.size());
  for (const auto& [path, data] : bundle.files) {  // std::map: sorted by path bytes
    put_string(out, path);
    put_string(out, data);
  }
  return out;
}

BundleContents parse_canonical(std::string_view bytes) {
  Reader in(bytes);
  if (!in.expect(kMagic)) throw BundleError("bundle: not a tessera bundle (bad magic)");
  v1::SceneBundle proto;
  proto.set_scene_file(in.string());
  const uint64_t count = in.u64();
  std::string previous;
  for (uint64_t i = 0; i < count; ++i) {
    auto* f = proto.add_files();
    f->set_path(in.string());
    if (i > 0 && f->path() <= previous) throw BundleError("bundle: files not in canonical order");
    previous = f->path();
    f->set_data(in.string());
  }
  if (!in.at_end()) throw BundleError("bundle: trailing bytes");
  return bundle_from_proto(proto);
}

std::string bundle_sha256(const BundleContents& bundle) {
  return sha256_hex(canonical_bytes(bundle));
}

FileReader bundle_reader(const BundleContents& bundle) {
  auto files = std::make_shared<const std::map<std::string, std::string>>(bundle.files);
  return [files](const std::string& bundle_path) -> std::string {
    // The parser checks paths before it asks; checking again keeps this reader safe on its own.
    const std::string path = check_bundle_path(bundle_path, bundle_path);
    const auto it = files->find(path);
    if (it == files->end()) throw SceneError(bundle_path + ": not in the scene bundle");
    return it->second;
  };
}

Scene parse_bundle_scene(const BundleContents& bundle) {
  return parse_scene_any(bundle.scene_file, bundle.files.at(bundle.scene_file),
                         bundle_reader(bundle));
}

void check_scene_images(const Scene& scene) {
  std::set<std::string> checked;
  auto check = [&](const std::string& file, const std::string& origin) {
    if (file.empty() || !checked.insert(file).second) return;
    try {
      if (!scene.files) throw SceneError(file + ": the scene has no file reader");
      check_image_bytes(file, scene.files(file));
    } catch (const SceneError& e) {
      throw SceneError(origin + ": " + e.what());
    }
  };
  for (const Texture& texture : scene.textures) {
    if (texture.kind == TextureKind::bitmap) check(texture.file, texture.origin);
  }
  for (const Light& light : scene.lights) {
    if (light.kind == LightKind::envmap) check(light.file, light.origin);
  }
}

BundleContents bundle_from_disk(const std::filesystem::path& scene_file, Scene* scene_out,
                                const std::optional<std::filesystem::path>& root,
                                const MitsubaParameters& parameters) {
  // A bundle holds files, never links: a linked scene file could pull in anything readable.
  std::error_code error;
  if (std::filesystem::is_symlink(std::filesystem::symlink_status(scene_file, error))) {
    throw SceneError(scene_file.string() +
                     ": is a symbolic link; bundles take regular files only (submit the file it"
                     " points to)");
  }
  SceneOnDisk loaded = load_scene_bundle(scene_file, root, parameters);
  BundleContents out;
  out.scene_file = loaded.scene_path;
  out.files.emplace(out.scene_file, std::move(loaded.scene_text));
  const FileReader reader = folder_reader(loaded.root);
  for (const std::string& rel : loaded.scene.referenced_files) {
    const std::string path = check_bundle_path(rel, "referenced file");
    if (path == out.scene_file) continue;
    out.files.emplace(path, reader(path));
  }
  check_scene_images(loaded.scene);
  if (scene_out) *scene_out = std::move(loaded.scene);
  return out;
}

}  // namespace tessera::wire
