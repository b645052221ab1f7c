// The image module of tessera-server (server/image_io_table.h): core's OpenImageIO code, built
// into a shared object that the server loads on first use. Only this function is exported.
#include "image_io_table.h"

extern "C" __attribute__((visibility("default"))) const tessera::server::ImageIoTable*
tessera_image_io_table() {
  static const tessera::server::ImageIoTable table{
      tessera::server::kImageIoTableVersion, &tessera::write_image,
      &tessera::encode_image,               &tessera::read_image,
      &tessera::linear_to_srgb,             &tessera::check_image_bytes,
      &tessera::scene_image_files};
  return &table;
}
