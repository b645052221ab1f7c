// Intel Open Image Denoise, loaded at run time (dlopen) so that Tessera builds and runs without
// it and only `--denoise` needs it. OIDN 2.x (Apache-2.0) comes from scripts/install-deps.sh,
// which installs its release binaries under a fixed prefix; CMake records the library found
// there (TESSERA_OIDN_LIBRARY).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "denoise/oidn_api.h"

namespace tessera {

/// The library's file name (its soname), as the dynamic loader searches for it.
inline constexpr const char* kOidnSoname = "libOpenImageDenoise.so.2";

/// Open Image Denoise cannot be used: no library found, or the one named fails to load. what()
/// is one line that says what was tried and how to install it.
class DenoiserUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Where the library is looked for, in order. `named` (the --oidn-library flag, else the
/// TESSERA_OIDN_LIBRARY environment variable; "" = neither) is the only candidate when given: a
/// path the user names is never passed over for another. Otherwise `configured` (the path CMake
/// found at configure time; "" = none), then kOidnSoname (the system's search path).
std::vector<std::string> oidn_library_candidates(const std::string& named,
                                                 const std::string& configured);

/// The library named by `flag` (--oidn-library; "" = not given), else by TESSERA_OIDN_LIBRARY.
std::string named_oidn_library(const std::string& flag);

/// The path recorded at configure time ("" when CMake found none).
std::string configured_oidn_library();

/// The candidates a program's `--oidn-library` flag (`flag`; "" = not given) stands for:
/// oidn_library_candidates of named_oidn_library(flag) and configured_oidn_library().
std::vector<std::string> oidn_library_candidates_for_flag(const std::string& flag);

/// One loaded library: its functions, never unloaded (OIDN's threads may outlive a device).
class OidnLibrary {
 public:
  /// Loads the first candidate that loads and has every function of oidn::Api. Throws
  /// DenoiserUnavailable naming each candidate tried and why it failed.
  static std::shared_ptr<const OidnLibrary> load(const std::vector<std::string>& candidates);
  /// The library a program's `--oidn-library` flag (`flag`; "" = not given) stands for: load()
  /// of oidn_library_candidates_for_flag(flag).
  static std::shared_ptr<const OidnLibrary> load_for_flag(const std::string& flag);

  /// What load() returns: `api` resolved from the library at `path`.
  OidnLibrary(const oidn::Api& api, std::string path) : api_(api), path_(std::move(path)) {}

  const oidn::Api& api() const { return api_; }
  /// The candidate that loaded.
  const std::string& path() const { return path_; }

 private:
  oidn::Api api_;
  std::string path_;
};

}  // namespace tessera
