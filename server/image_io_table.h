// The image functions of core (image/image_output.h, scene/image_check.h) as a table of
// pointers: what the tessera-server executable gets from its image module, which holds the real
// ones and links OpenImageIO. Loading OpenImageIO maps about 260 shared libraries (its codecs'
// dependencies: GDAL, OpenCV, GDCM, ffmpeg ...), about 0.5 s of CPU and most of the server's
// start-up (BENCHMARKS.md, "Start-up: where the time goes (branch dash8)"); the server needs it
// only for a job's images and a bundle's textures, so it loads it after it listens, on a thread
// of its own, or at the first image call if that comes first (server/lazy_image_io.cpp).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "image/image_output.h"
#include "scene/image_check.h"

namespace tessera::server {

/// Bumped with any change of the table; the executable refuses a module of another version.
inline constexpr uint32_t kImageIoTableVersion = 2;

struct ImageIoTable {
  uint32_t version = kImageIoTableVersion;
  void (*write_image)(const RgbImage&, const std::filesystem::path&, const ImageWriteOptions&);
  std::string (*encode_image)(const RgbImage&, const std::string&, const ImageWriteOptions&);
  RgbImage (*read_image)(const std::filesystem::path&);
  float (*linear_to_srgb)(float);
  ImageCheck (*check_image_bytes)(const std::string&, std::string_view);
  std::vector<std::string> (*scene_image_files)(const Scene&);
  // ImageFileStream, through an opaque handle (the module's own ImageFileStream object): open
  // on a file or in memory, write_rows, finish (returning take_bytes()), and delete (of a
  // finished or unfinished one).
  void* (*stream_open)(const std::filesystem::path&, int, int, const ImageWriteOptions&);
  void* (*stream_open_in_memory)(const std::string&, int, int, const ImageWriteOptions&);
  void (*stream_write_rows)(void*, const RgbImage&, const std::vector<ExtraChannel>&);
  std::string (*stream_finish)(void*);
  void (*stream_delete)(void*);
};

}  // namespace tessera::server

/// The module's one exported symbol (server/image_io_module.cpp).
extern "C" const tessera::server::ImageIoTable* tessera_image_io_table();
