// image_io() where OpenImageIO is linked into the executable (the library tessera_image_oiio).
#include "image/image_io.h"

namespace tessera {

const ImageIo& image_io() { return oiio_image_io(); }

}  // namespace tessera
