// Test support: small images encoded in memory with OpenImageIO (or written to a file), and a
// FileReader over them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "scene/scene_error.h"
#include "scene/loader/scene_loader.h"

namespace tessera::test {

/// The bytes of an image file named `name` (its extension picks the format) holding `values`
/// (row-major from the top row, `channels` per pixel) stored as `format`.
template <typename T>
std::string encode_image(const std::string& name, int width, int height, int channels,
                         const std::vector<T>& values, OIIO::TypeDesc format) {
  OIIO::Filesystem::IOVecOutput out_bytes;
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(name, &out_bytes);
  if (!out) throw std::runtime_error("no writer for " + name + ": " + OIIO::geterror());
  OIIO::ImageSpec spec(width, height, channels, format);
  spec.attribute("oiio:UnassociatedAlpha", 1);  // store colours as given, whatever the alpha
  if (!out->open(name, spec) ||
      !out->write_image(OIIO::TypeDesc(OIIO::BaseTypeFromC<T>::value), values.data()) ||
      !out->close()) {
    throw std::runtime_error("cannot write " + name + ": " + out->geterror());
  }
  const std::vector<unsigned char>& b = out_bytes.buffer();
  return std::string(b.begin(), b.end());
}

/// An RGB float EXR of `width` x `height` texels (row-major from the top row) written to `path`.
inline void write_exr(const std::filesystem::path& path, int width, int height, const std::vector<float>& rgb) {
  const std::string bytes = encode_image(path.filename().string(), width, height, 3, rgb, OIIO::TypeDesc::FLOAT);
  std::ofstream out(path, std::ios::binary);
  out << bytes;
  if (!out.good()) throw std::runtime_error("cannot write " + path.string());
}

/// A FileReader over files held in memory; a missing one is a SceneError naming it, as the
/// bundle readers do.
inline FileReader memory_reader(std::map<std::string, std::string> files) {
  return [files = std::move(files)](const std::string& path) {
    const auto it = files.find(path);
    if (it == files.end()) throw SceneError(path + ": no such file in the bundle");
    return it->second;
  };
}

}  // namespace tessera::test
