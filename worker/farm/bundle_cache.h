// Scene bundles cached on disk by SHA-256, so a worker fetches each bundle once (per cache
// folder). Each bundle is one file, <dir>/<sha256>.bundle, holding its canonical serialization;
// it is written to a temporary name and renamed, and its hash is checked on every read, so a
// torn or corrupted file is fetched again rather than rendered.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "wire/scene_bundle.h"

namespace tessera::farm {

class BundleCache {
 public:
  /// Creates `dir` if needed. Throws std::runtime_error naming it when it cannot.
  explicit BundleCache(std::filesystem::path dir);

  /// The cached bundle, or nullopt when absent or damaged (a damaged file is removed).
  std::optional<wire::BundleContents> get(const std::string& sha256) const;

  /// Checks that `bundle` hashes to `sha256`, then stores it. Throws wire::BundleError on a
  /// mismatch, std::runtime_error when the file cannot be written.
  void put(const std::string& sha256, const wire::BundleContents& bundle) const;

  const std::filesystem::path& dir() const { return dir_; }

  /// The default folder: $XDG_CACHE_HOME/tessera/bundles, ~/.cache/tessera/bundles, or
  /// <temp>/tessera-<uid>/bundles.
  static std::filesystem::path default_dir();

 private:
  std::filesystem::path path_of(const std::string& sha256) const;

  std::filesystem::path dir_;
};

}  // namespace tessera::farm
