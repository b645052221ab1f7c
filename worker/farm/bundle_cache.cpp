#include "bundle_cache.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <system_error>

#include "wire/sha256.h"

namespace tessera::farm {

BundleCache::BundleCache(std::filesystem::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw std::runtime_error("bundle cache " + dir_.string() + ": " + ec.message());
}

std::filesystem::path BundleCache::default_dir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) {
    return std::filesystem::path(xdg) / "tessera" / "bundles";
  }
  if (const char* home = std::getenv("HOME"); home && *home) {
    return std::filesystem::path(home) / ".cache" / "tessera" / "bundles";
  }
  return std::filesystem::temp_directory_path() / ("tessera-" + std::to_string(getuid())) /
         "bundles";
}

std::filesystem::path BundleCache::path_of(const std::string& sha256) const {
  if (!wire::is_sha256_hex(sha256)) throw wire::BundleError("bad bundle hash \"" + sha256 + "\"");
  return dir_ / (sha256 + ".bundle");
}

std::optional<wire::BundleContents> BundleCache::get(const std::string& sha256) const {
  const std::filesystem::path path = path_of(sha256);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string bytes = std::move(ss).str();
  try {
    if (wire::sha256_hex(bytes) == sha256) return wire::parse_canonical(bytes);
  } catch (const wire::BundleError&) {
    // Damaged: fall through, remove it, fetch again.
  }
  std::error_code ec;
  std::filesystem::remove(path, ec);
  return std::nullopt;
}

void BundleCache::put(const std::string& sha256, const wire::BundleContents& bundle) const {
  const std::string bytes = wire::canonical_bytes(bundle);
  const std::string got = wire::sha256_hex(bytes);
  if (got != sha256) {
    throw wire::BundleError("bundle hashes to " + got + ", not the requested " + sha256);
  }
  const std::filesystem::path path = path_of(sha256);
  // A per-writer temporary name: several workers may share a cache folder.
  std::filesystem::path temp = path;
  temp += ".partial-" + std::to_string(getpid()) + "-" + std::to_string(std::random_device{}());
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.flush();
    if (!out) throw std::runtime_error(temp.string() + ": cannot write");
  }
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) {
    std::filesystem::remove(temp, ec);
    throw std::runtime_error(path.string() + ": cannot rename into place");
  }
}

}  // namespace tessera::farm
