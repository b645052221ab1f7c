#include "scene/mesh/serialized_loader.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "scene/mesh/mesh_limits.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

constexpr uint16_t kMagic = 0x041C;
constexpr uint16_t kVersion3 = 3;
constexpr uint16_t kVersion4 = 4;
constexpr uint32_t kHasNormals = 0x0001;
constexpr uint32_t kHasUvs = 0x0002;
constexpr uint32_t kHasColors = 0x0008;
constexpr uint32_t kDoublePrecision = 0x2000;
/// The most bytes a shape's arrays may declare per compressed byte. Deflate can expand zeros
/// about 1032:1, so a 0.5 MB file could declare 20M zero vertices and triangles (0.5 GB of
/// arrays, 1.8 GB of server memory while checked); real meshes inflate 2-3:1 (the shapes of
/// tests/data/mitsuba/common/meshes/matpreview.serialized: 2.0, 2.4 and 3.0).
constexpr uint64_t kMaxInflateRatio = kMaxSerializedInflateRatio;
constexpr size_t kMaxShapeName = 4096;

template <typename T>
T little_endian(const unsigned char* p) {
  uint64_t value = 0;
  for (size_t i = 0; i < sizeof(T); ++i) value |= uint64_t(p[i]) << (8 * i);
  return static_cast<T>(value);
}

/// Reads exactly the requested number of bytes from one zlib stream, or throws.
class ZlibReader {
 public:
  ZlibReader(std::string_view compressed, const std::string& name) : name_(name) {
    stream_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data()));
    stream_.avail_in = static_cast<uInt>(std::min<size_t>(compressed.size(), UINT32_MAX));
    if (inflateInit(&stream_) != Z_OK) throw SceneError(name_ + ": cannot start zlib");
  }
  ~ZlibReader() { inflateEnd(&stream_); }
  ZlibReader(const ZlibReader&) = delete;
  ZlibReader& operator=(const ZlibReader&) = delete;

  void read(void* out, size_t size, const char* what) {
    auto* dst = static_cast<Bytef*>(out);
    while (size > 0) {
      if (ended_) fail(what);
      uInt chunk = static_cast<uInt>(std::min<size_t>(size, 1u << 30));
      stream_.next_out = dst;
      stream_.avail_out = chunk;
      int status = inflate(&stream_, Z_NO_FLUSH);
      size_t produced = chunk - stream_.avail_out;
      dst += produced;
      size -= produced;
      if (status == Z_STREAM_END) {
        ended_ = true;
      } else if (status != Z_OK || (produced == 0 && stream_.avail_in == 0)) {
        if (status == Z_DATA_ERROR) {
          throw SceneError(name_ + ": corrupt compressed data while reading the " + what);
        }
        fail(what);
      }
    }
  }

  template <typename T>
  T value(const char* what) {
    unsigned char bytes[sizeof(T)];
    read(bytes, sizeof(T), what);
    return little_endian<T>(bytes);
  }

  void skip(uint64_t size, const char* what) {
    std::vector<unsigned char> scratch(1 << 16);
    while (size > 0) {
      size_t chunk = std::min<uint64_t>(size, scratch.size());
      read(scratch.data(), chunk, what);
      size -= chunk;
    }
  }

 private:
  [[noreturn]] void fail(const char* what) {
    throw SceneError(name_ + ": truncated: the compressed data ends in the " + what);
  }

  std::string name_;
  z_stream stream_{};
  bool ended_ = false;
};

/// The byte offset of shape `shape_index`, from the dictionary at the end of the file.
uint64_t shape_offset(std::string_view bytes, uint16_t version, int shape_index,
                      const std::string& name) {
  if (shape_index == 0) return 0;
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < 8) throw SceneError(name + ": truncated: no shape dictionary at the end");
  uint32_t count = little_endian<uint32_t>(data + bytes.size() - 4);
  if (static_cast<uint64_t>(shape_index) >= count) {
    throw SceneError(name + ": shape_index " + std::to_string(shape_index) +
                     " out of range (the file holds " + std::to_string(count) + " shapes)");
  }
  uint64_t entry = version == kVersion4 ? 8 : 4;
  if (uint64_t(count) * entry + 4 > bytes.size()) {
    throw SceneError(name + ": shape dictionary of " + std::to_string(count) +
                     " shapes does not fit in the file");
  }
  uint64_t at = bytes.size() - 4 - entry * (count - static_cast<uint64_t>(shape_index));
  uint64_t offset = version == kVersion4 ? little_endian<uint64_t>(data + at)
                                         : little_endian<uint32_t>(data + at);
  if (offset > bytes.size() - 4) {
    throw SceneError(name + ": shape " + std::to_string(shape_index) + " at offset " +
                     std::to_string(offset) + " lies beyond the end of the file");
  }
  return offset;
}

void check_header(std::string_view bytes, uint64_t offset, const std::string& name,
                  uint16_t expected_version) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data()) + offset;
  uint16_t magic = little_endian<uint16_t>(data);
  uint16_t version = little_endian<uint16_t>(data + 2);
  if (magic != kMagic || version != expected_version) {
    throw SceneError(name + ": no shape header at offset " + std::to_string(offset) +
                     " (bad shape dictionary)");
  }
}

std::string read_shape_name(ZlibReader& in, const std::string& name) {
  std::string shape_name;
  for (;;) {
    char c = in.value<char>("shape name");
    if (c == 0) return shape_name;
    if (shape_name.size() == kMaxShapeName) {
      throw SceneError(name + ": shape name longer than " + std::to_string(kMaxShapeName) +
                       " bytes (corrupt file?)");
    }
    shape_name += c;
  }
}

/// Reads `count` reals (float or double) a chunk at a time and hands each to `take(index,
/// value)`: no array of the whole stream's bytes is held beside the mesh being filled (a 20M
/// vertex mesh read into raw and converted arrays first took 3x its final size).
template <typename Take>
void read_reals(ZlibReader& in, uint64_t count, bool doubles, const char* what, Take take) {
  const size_t size = doubles ? 8 : 4;
  constexpr uint64_t kChunk = 1 << 14;
  std::vector<unsigned char> raw(size_t(std::min(count, kChunk)) * size);
  for (uint64_t first = 0; first < count; first += kChunk) {
    const uint64_t n = std::min(kChunk, count - first);
    in.read(raw.data(), size_t(n) * size, what);
    for (uint64_t i = 0; i < n; ++i) {
      double value;
      if (doubles) {
        uint64_t bits = little_endian<uint64_t>(raw.data() + 8 * i);
        std::memcpy(&value, &bits, 8);
      } else {
        uint32_t bits = little_endian<uint32_t>(raw.data() + 4 * i);
        float f;
        std::memcpy(&f, &bits, 4);
        value = f;
      }
      take(first + i, value);
    }
  }
}

uint64_t bytes_per_vertex(uint32_t flags) {
  uint64_t real = (flags & kDoublePrecision) ? 8 : 4;
  return real * (3 + ((flags & kHasNormals) ? 3 : 0) + ((flags & kHasUvs) ? 2 : 0) +
                 ((flags & kHasColors) ? 3 : 0));
}

void check_counts(uint64_t vertices, uint64_t triangles, uint64_t bytes_per_vertex,
                  uint64_t compressed, const std::string& name) {
  if (vertices > kMaxMeshElements) {
    throw SceneError(name + ": " + std::to_string(vertices) + " vertices (at most " +
                     std::to_string(kMaxMeshElements) + ")");
  }
  if (triangles > kMaxMeshElements) {
    throw SceneError(name + ": " + std::to_string(triangles) + " triangles (at most " +
                     std::to_string(kMaxMeshElements) + ")");
  }
  uint64_t declared = vertices * bytes_per_vertex + triangles * 12;
  if (declared > compressed * kMaxInflateRatio) {
    throw SceneError(name + ": " + std::to_string(vertices) + " vertices and " +
                     std::to_string(triangles) + " triangles (" + std::to_string(declared) +
                     " bytes) declared in " + std::to_string(compressed) +
                     " compressed bytes, more than " + std::to_string(kMaxInflateRatio) +
                     " times as many (truncated, or a decompression bomb)");
  }
}

/// What a shape's stream holds before its arrays, read and checked (check_counts).
struct ShapeHeader {
  uint32_t flags = 0;
  std::string shape_name;
  uint64_t vertices = 0;
  uint64_t triangles = 0;
};

ShapeHeader read_shape_header(ZlibReader& in, uint16_t version, uint64_t compressed,
                              const std::string& name) {
  ShapeHeader header;
  header.flags = in.value<uint32_t>("flags");
  if (version == kVersion4) header.shape_name = read_shape_name(in, name);
  header.vertices = in.value<uint64_t>("vertex count");
  header.triangles = in.value<uint64_t>("triangle count");
  check_counts(header.vertices, header.triangles, bytes_per_vertex(header.flags), compressed,
               name);
  return header;
}

/// The file's version, after its magic number and version are checked.
uint16_t file_version(std::string_view bytes, const std::string& name) {
  if (bytes.size() < 4) throw SceneError(name + ": truncated: no serialized file header");
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  uint16_t magic = little_endian<uint16_t>(data);
  uint16_t version = little_endian<uint16_t>(data + 2);
  if (magic != kMagic) {
    throw SceneError(name + ": not a Mitsuba serialized mesh (bad magic number)");
  }
  if (version != kVersion3 && version != kVersion4) {
    throw SceneError(name + ": unsupported serialized format version " + std::to_string(version) +
                     " (expected 3 or 4)");
  }
  return version;
}

void read_arrays(ZlibReader& in, uint32_t flags, uint64_t vertices, uint64_t triangles,
                 bool read_normals, const std::string& name, TriangleMesh& mesh) {
  bool doubles = (flags & kDoublePrecision) != 0;
  mesh.positions.resize(vertices);
  read_reals(in, 3 * vertices, doubles, "vertex positions", [&](uint64_t i, double v) {
    if (!std::isfinite(v)) {
      throw SceneError(name + ": vertex " + std::to_string(i / 3) + ": position is not finite");
    }
    mesh.positions[i / 3][int(i % 3)] = v;
  });
  if (flags & kHasNormals) {
    if (read_normals) mesh.normals.resize(vertices);
    read_reals(in, 3 * vertices, doubles, "vertex normals", [&](uint64_t i, double v) {
      if (read_normals) mesh.normals[i / 3][int(i % 3)] = v;
    });
  }
  if (flags & kHasUvs) {
    mesh.uvs.resize(vertices);
    read_reals(in, 2 * vertices, doubles, "texture coordinates", [&](uint64_t i, double v) {
      if (!std::isfinite(v)) {
        throw SceneError(name + ": vertex " + std::to_string(i / 2) +
                         ": texture coordinate is not finite");
      }
      mesh.uvs[i / 2][int(i % 2)] = v;
    });
  }
  if (flags & kHasColors) in.skip(3 * vertices * (doubles ? 8 : 4), "vertex colours");
  mesh.indices.resize(triangles);
  constexpr uint64_t kChunk = 1 << 14;
  std::vector<unsigned char> raw(12 * size_t(std::min(triangles, kChunk)));
  for (uint64_t first = 0; first < triangles; first += kChunk) {
    const uint64_t n = std::min(kChunk, triangles - first);
    in.read(raw.data(), 12 * size_t(n), "triangle indices");
    for (uint64_t t = first; t < first + n; ++t) {
      for (int k = 0; k < 3; ++k) {
        uint32_t index = little_endian<uint32_t>(raw.data() + 12 * (t - first) + 4 * k);
        if (index >= vertices) {
          throw SceneError(name + ": triangle " + std::to_string(t) + ": vertex index " +
                           std::to_string(index) + " out of range (" + std::to_string(vertices) +
                           " vertices)");
        }
        mesh.indices[t][k] = index;
      }
    }
  }
  if (!normals_usable(mesh)) mesh.normals.clear();
}

}  // namespace

SerializedMesh load_serialized_mesh(std::string_view bytes, const std::string& name,
                                    int shape_index, bool read_normals) {
  const uint16_t version = file_version(bytes, name);
  if (shape_index < 0) {
    throw SceneError(name + ": shape_index must be >= 0 (got " + std::to_string(shape_index) + ")");
  }
  uint64_t offset = shape_offset(bytes, version, shape_index, name);
  check_header(bytes, offset, name, version);
  std::string_view compressed = bytes.substr(offset + 4);
  ZlibReader in(compressed, name);
  const ShapeHeader header = read_shape_header(in, version, compressed.size(), name);
  SerializedMesh out;
  out.shape_name = header.shape_name;
  read_arrays(in, header.flags, header.vertices, header.triangles, read_normals, name, out.mesh);
  return out;
}

uint64_t serialized_load_bytes(std::string_view bytes, const std::string& name) {
  uint16_t version = 0;
  uint64_t shapes = 1;
  try {
    version = file_version(bytes, name);
    if (bytes.size() >= 8) {
      const auto* end = reinterpret_cast<const unsigned char*>(bytes.data()) + bytes.size();
      shapes = std::max<uint64_t>(1, little_endian<uint32_t>(end - 4));
    }
  } catch (const SceneError&) {
    return 0;  // refused before anything is allocated
  }
  uint64_t total = 0;
  for (uint64_t index = 0; index < shapes; ++index) {
    try {
      const int shape_index = int(std::min<uint64_t>(index, INT32_MAX));
      const uint64_t offset = shape_offset(bytes, version, shape_index, name);
      check_header(bytes, offset, name, version);
      std::string_view compressed = bytes.substr(offset + 4);
      ZlibReader in(compressed, name);
      const ShapeHeader header = read_shape_header(in, version, compressed.size(), name);
      // TriangleMesh: dvec3 positions and normals, dvec2 uvs, u32vec3 triangles.
      total += header.vertices * (24 + ((header.flags & kHasNormals) ? 24 : 0) +
                                  ((header.flags & kHasUvs) ? 16 : 0)) +
               header.triangles * 12;
    } catch (const SceneError&) {
      if (index == 0) return 0;
      break;  // a bad dictionary: only the shapes before it can be loaded
    }
  }
  return total;
}

}  // namespace tessera
