// The image functions' one seam: what image_output.h's functions and ImageFileStream call. Its
// one implementation is OpenImageIO's (oiio_image_io.cpp), which each executable reaches in one
// of two ways, chosen by the library it links (core/CMakeLists.txt):
//   - linked in (tessera_image_oiio: linked_image_io.cpp): the worker, the local renderer and
//     the tests;
//   - as the image module (image_module.h): tessera-server and the tessera client, which load
//     OpenImageIO's ~250 libraries at their first image, not at start (BENCHMARKS.md,
//     "Server start-up time").
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "image/image_output.h"
#include "scene/image_check.h"

namespace tessera {

/// The image functions as a table of pointers, with image_output.h's contracts.
struct ImageIo {
  void (*write_image)(const RgbImage&, const std::filesystem::path&, const ImageWriteOptions&);
  std::string (*encode_image)(const RgbImage&, const std::string&, const ImageWriteOptions&);
  RgbImage (*read_image)(const std::filesystem::path&);
  // ImageFileStream, through an opaque handle (the implementation's own stream): open on a
  // file or in memory, write_rows, finish (returning an in-memory stream's bytes, "" for a
  // file), and delete (of a finished or unfinished one).
  void* (*stream_open)(const std::filesystem::path&, int, int, const ImageWriteOptions&);
  void* (*stream_open_in_memory)(const std::string&, int, int, const ImageWriteOptions&);
  void (*stream_write_rows)(void*, const RgbImage&, const std::vector<ExtraChannel>&);
  std::string (*stream_finish)(void*);
  void (*stream_delete)(void*);
  // The checks of scene/image_check.h (check_image_bytes and probe_image_bytes call these).
  ImageCheck (*check_image_bytes)(const std::string&, std::string_view, uint64_t);
  ImageHeader (*probe_image_bytes)(const std::string&, std::string_view);
};

/// OpenImageIO's table (oiio_image_io.cpp, its checks in oiio_image_check.cpp).
const ImageIo& oiio_image_io();
ImageCheck oiio_check_image_bytes(const std::string& path, std::string_view bytes, uint64_t max_values);
ImageHeader oiio_probe_image_bytes(const std::string& path, std::string_view bytes);

/// The table the image functions call: oiio_image_io() where OpenImageIO is linked in
/// (linked_image_io.cpp), the image module's copy of it elsewhere (image_module_loader.cpp,
/// which loads the module at the first call). An executable links exactly one of the two.
const ImageIo& image_io();

}  // namespace tessera
