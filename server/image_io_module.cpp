// The image module of tessera-server (server/image_io_table.h): core's OpenImageIO code, built
// into a shared object that the server loads on first use. Only this function is exported.
#include "image_io_table.h"

namespace {

using tessera::ImageFileStream;

void* stream_open(const std::filesystem::path& path, int width, int height, const tessera::ImageWriteOptions& options) {
  return new ImageFileStream(path, width, height, options);
}
void* stream_open_in_memory(const std::string& format, int width, int height,
                            const tessera::ImageWriteOptions& options) {
  return new ImageFileStream(ImageFileStream::in_memory(format, width, height, options));
}
void stream_write_rows(void* stream, const tessera::RgbImage& band, const std::vector<tessera::ExtraChannel>& extra) {
  static_cast<ImageFileStream*>(stream)->write_rows(band, extra);
}
std::string stream_finish(void* stream) {
  static_cast<ImageFileStream*>(stream)->finish();
  return static_cast<ImageFileStream*>(stream)->take_bytes();
}
void stream_delete(void* stream) { delete static_cast<ImageFileStream*>(stream); }

}  // namespace

extern "C" __attribute__((visibility("default"))) const tessera::server::ImageIoTable*
tessera_image_io_table() {
  static const tessera::server::ImageIoTable table{
      tessera::server::kImageIoTableVersion, &tessera::write_image,
      &tessera::encode_image,               &tessera::read_image,
      &tessera::linear_to_srgb,             &tessera::check_image_bytes,
      &tessera::scene_image_files,          &stream_open,
      &stream_open_in_memory,               &stream_write_rows,
      &stream_finish,                       &stream_delete};
  return &table;
}
